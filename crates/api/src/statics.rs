//! Static equilibrium of a loaded model (Newton, quasi-static series or damped settling) and
//! its report.

use crate::error::Error;
use crate::source::{applied_forces, coverage_json, Loaded};
use linkage_report::statics::StaticJson;
use linkage_solve::coverage::Analysis;
use linkage_solve::pipeline::Assembled;
use linkage_solve::state::State;
use linkage_solve::tolerances::Tolerances;
use std::time::{Duration, Instant};

/// Wall-clock seconds after which damped settling stops when no time limit is given (the
/// CLI's `static --settle` default).
pub const DEFAULT_SETTLE_TIME_LIMIT: f64 = 600.0;

/// What `linkage static` asks for.
#[derive(Clone, Copy, Debug, Default)]
pub struct StaticArgs {
    /// `(end time, steps)` of a quasi-static series.
    pub series: Option<(f64, usize)>,
    /// Find the equilibrium by damped dynamics (also when the dataset says
    /// EQUILIBRIUM/DYNAMIC and there is no series).
    pub settle: bool,
    /// Accept an unstable equilibrium; otherwise it is the run's failure.
    pub allow_unstable: bool,
    /// Wall-clock seconds after which damped settling stops (after the step it is in).
    pub time_limit: Option<f64>,
    /// Also give the CSV of the series (one row per output time).
    pub csv: bool,
}

/// What a static analysis gave.
pub struct StaticRun {
    /// `linkage static --format json`.
    pub report: StaticJson,
    /// The equilibrium was found (converged, no errors).
    pub ok: bool,
    /// Found by damped settling (rather than Newton statics).
    pub settled: bool,
    /// The (last) equilibrium configuration, when one was accepted.
    pub state: Option<State>,
    /// `--format csv` (Newton statics with `StaticArgs::csv` only).
    pub csv: Option<String>,
    /// Newton statics of one equilibrium: the largest force imbalance of each iteration.
    pub imbalance_history: Vec<f64>,
}

/// The analysis of `args`: quasi-static for a series, static otherwise.
pub fn analysis(args: &StaticArgs) -> Analysis {
    if args.series.is_some() {
        Analysis::QuasiStatic
    } else {
        Analysis::Static
    }
}

/// Adds the unstable-equilibrium verdict to `report` unless `allow` (see
/// [`linkage_report::statics::unstable_verdict`]).
fn judge_stability(report: &mut StaticJson, allow: bool) {
    if allow {
        return;
    }
    if let Some(why) = linkage_report::statics::unstable_verdict(report) {
        report.errors.push(why);
    }
}

/// The static equilibrium of `loaded` (see [`StaticArgs`]); `settling(elapsed, limit)` is
/// told how far damped settling has come.
pub fn statics(
    loaded: &Loaded,
    args: &StaticArgs,
    settling: &dyn Fn(f64, f64),
) -> Result<StaticRun, Error> {
    let analysis = analysis(args);
    let applied = applied_forces(loaded, analysis)?;
    let assemble = || {
        Assembled::new(
            &loaded.model,
            &loaded.drivers,
            applied.as_ref(),
            &Tolerances::default(),
        )
    };
    if args.settle || (loaded.model.equilibrium.dynamic && args.series.is_none()) {
        let assembled = assemble();
        let limit = loaded.model.equilibrium.settling_time;
        // Damped settling cannot bound its own wall-clock time: without a time limit, the
        // CLI's default guard stops it.
        let limit_secs = args.time_limit.unwrap_or(DEFAULT_SETTLE_TIME_LIMIT);
        let deadline = Instant::now() + Duration::from_secs_f64(limit_secs);
        let out_of_time = || Instant::now() >= deadline;
        let settled = linkage_solve::stages::settle::settle_until(
            &assembled,
            |elapsed| settling(elapsed, limit),
            &out_of_time,
        );
        let state = settled
            .as_ref()
            .ok()
            .and_then(|o| o.settled_equilibrium())
            .map(|e| e.state.clone());
        let mut report =
            linkage_report::statics::settling_json(&assembled, settled, &loaded.warnings);
        (report.left_out, report.runs_without) = coverage_json(loaded, analysis);
        judge_stability(&mut report, args.allow_unstable);
        if out_of_time() && !report.errors.is_empty() {
            report.errors.push(match args.time_limit {
                Some(secs) => format!("the time limit of {secs} s was reached while settling"),
                None => format!(
                    "the default wall-clock guard of {DEFAULT_SETTLE_TIME_LIMIT} s was reached \
                     while settling (time_limit sets another)"
                ),
            });
        }
        let ok = report.converged && report.errors.is_empty();
        return Ok(StaticRun {
            report,
            ok,
            settled: true,
            state,
            csv: None,
            imbalance_history: Vec::new(),
        });
    }
    let times = match args.series {
        Some((end, steps)) => crate::times::output_times(end, Some(steps), None)?,
        None => vec![0.0],
    };
    let assembled = assemble();
    let result = linkage_solve::stages::statics::run(&assembled, &times);
    let mut report = linkage_report::statics::to_json(&assembled, &result, &loaded.warnings);
    if let [(_, Ok(eq))] = result.steps.as_slice() {
        // The friction as the equilibrium had it (those inactive in statics off).
        let rest = assembled.rest();
        let values = applied.friction_values(
            linkage_solve::physics::applied::Regime::Static,
            &eq.state,
            &rest,
        );
        report.frictions = linkage_report::friction::frictions_json(&loaded.model, &values);
        let contacts = linkage_solve::constraints::curve_contacts::curve_contacts(
            &loaded.model,
            &assembled.system,
            &eq.state,
        );
        report.curve_contacts =
            linkage_report::curve_contacts::curve_contacts_json(&loaded.model, &contacts);
    }
    (report.left_out, report.runs_without) = coverage_json(loaded, analysis);
    judge_stability(&mut report, args.allow_unstable);
    let ok = result.converged() && report.errors.is_empty();
    let state = match result.steps.last() {
        Some((_, Ok(eq))) if ok => Some(eq.state.clone()),
        _ => None,
    };
    let csv = args
        .csv
        .then(|| linkage_report::statics::to_csv(&loaded.model, &result));
    let imbalance_history = match result.steps.as_slice() {
        [(_, Ok(eq))] => eq.imbalance_history.clone(),
        _ => Vec::new(),
    };
    Ok(StaticRun {
        report,
        ok,
        settled: false,
        state,
        csv,
        imbalance_history,
    })
}
