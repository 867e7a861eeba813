//! Static equilibrium of a loaded model (Newton, quasi-static series or damped settling) and
//! its report.

use crate::error::Error;
use crate::sink::{Feed, NoSink, OutputSink, SinkError};
use crate::source::Loaded;
use crate::start::{assemble, input_model, Left, Start};
use linkage_report::statics::SearchJson;
use linkage_report::statics::StaticJson;
use linkage_solve::coverage::Analysis;
use linkage_solve::physics::applied::Regime;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::dynamics::Output;
use linkage_solve::stages::statics::{Equilibrium, StaticRun as SolveRun};
use linkage_solve::state::State;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

/// Wall-clock seconds after which damped settling stops when no time limit is given (the
/// CLI's `static --settle` default, and a command file's EQUILIBRIUM/DYNAMIC).
pub const DEFAULT_SETTLE_TIME_LIMIT: f64 = 600.0;

/// What a static analysis asks for.
#[derive(Clone, Debug, Default)]
pub struct StaticArgs {
    /// The output times of a quasi-static series (its first equilibrium at the first time).
    pub series: Option<Vec<f64>>,
    /// Find the equilibrium by damped dynamics (also when the dataset says
    /// EQUILIBRIUM/DYNAMIC and there is no series).
    pub settle: bool,
    /// Accept an unstable equilibrium; otherwise it is the run's failure.
    pub allow_unstable: bool,
    /// Wall-clock seconds after which damped settling stops (after the step it is in).
    pub time_limit: Option<f64>,
    /// Stops a quasi-static series after the equilibrium it is at when set (Ctrl-C); the
    /// sink keeps the equilibria before it.
    pub interrupt: Option<Arc<AtomicBool>>,
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
    /// The series was stopped by [`StaticArgs::interrupt`].
    pub interrupted: bool,
    /// Newton statics of one equilibrium: the largest force imbalance of each iteration.
    pub imbalance_history: Vec<f64>,
    /// Where the analysis leaves the model: the last equilibrium accepted, at rest.
    pub left: Option<Left>,
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

/// Each FRICTION at its static limit `|F| = μs·N` (within
/// [`linkage_solve::tolerances::FRICTION_AT_STATIC_LIMIT`]) in a failed equilibrium, as the
/// reason: the load along its joint is more than static friction holds.
fn frictions_at_limit(
    model: &linkage_model::Model,
    values: &[linkage_solve::physics::forces::friction::FrictionValue],
) -> Vec<String> {
    let at_limit = 1.0 - linkage_solve::tolerances::FRICTION_AT_STATIC_LIMIT;
    let num = |x: f64| linkage_adm::num::sci(x, 4);
    values
        .iter()
        .filter_map(|v| {
            let f = model.frictions.iter().find(|f| f.origin.name == v.name)?;
            let limit = f.mu_static * v.normal;
            (v.sticking && limit > 0.0 && v.force.length() >= at_limit * limit).then(|| {
                format!(
                    "{} is at its static limit μs·N = {} (μs = {}, N = {}): the load along {} \
                     is more than static friction holds (as a block on a ramp steeper than \
                     the friction angle), so there is no static equilibrium",
                    v.name,
                    num(limit),
                    f.mu_static,
                    num(v.normal),
                    model.constraints[f.joint].origin.name
                )
            })
        })
        .collect()
}

/// The output of an equilibrium `eq` of `a` at time `time`: at rest, with its reactions.
fn at_rest(a: &Assembled, time: f64, eq: &Equilibrium) -> Output {
    Output {
        time,
        state: eq.state.clone(),
        velocities: a.rest(),
        accelerations: a.rest(),
        reactions: eq.reactions.clone(),
    }
}

/// One equilibrium of `a` from `from` by the search for a stable one
/// ([`linkage_solve::stages::stable_equilibrium::search`]; its settling bounded by the
/// time limit or [`DEFAULT_SETTLE_TIME_LIMIT`]), as a run of one step, and the search's summary.
fn one_equilibrium(
    a: &Assembled,
    from: &State,
    args: &StaticArgs,
) -> Result<(SolveRun, Option<SearchJson>), Error> {
    let mut run = SolveRun {
        steps: Vec::new(),
        sensor_events: Vec::new(),
        stopped_by_sensor: None,
    };
    if a.failure().is_some() {
        return Ok((run, None));
    }
    let deadline = crate::budget::deadline(args.time_limit, DEFAULT_SETTLE_TIME_LIMIT)
        .map_err(crate::error::ArgumentError::from)?;
    let out_of_time = || Instant::now() >= deadline;
    let found = linkage_solve::stages::stable_equilibrium::search(
        a,
        from,
        args.allow_unstable,
        &out_of_time,
    );
    let summary = linkage_report::statics::search_json(&found, found.found(args.allow_unstable));
    run.steps.push((from.time, found.result));
    Ok((run, Some(summary)))
}

/// The static equilibrium of `loaded` from its input (see [`StaticArgs`]);
/// `settling(elapsed, limit)` is told how far damped settling has come.
pub fn statics(
    loaded: &Loaded,
    args: &StaticArgs,
    settling: &dyn Fn(f64, f64),
) -> Result<StaticRun, Error> {
    run(loaded, Start::Input, args, settling, &mut NoSink)
}

/// The static equilibrium of `loaded` from `start`: one equilibrium at the start time (by
/// Newton, or by damped settling with `args.settle` or the dataset's EQUILIBRIUM/DYNAMIC), or
/// a quasi-static series at `args.series`; each equilibrium accepted is handed to `sink`.
pub fn run(
    loaded: &Loaded,
    start: Start,
    args: &StaticArgs,
    settling: &dyn Fn(f64, f64),
    sink: &mut dyn OutputSink,
) -> Result<StaticRun, Error> {
    let analysis = analysis(args);
    let settle = args.settle || (loaded.model.equilibrium.dynamic && args.series.is_none());
    let mut start = start;
    if let (Start::Left(left), true) = (&mut start, settle) {
        // Settling integrates from the assembled configuration: assembled at the left state.
        left.assembly = None;
    }
    let mut feed = Feed::new(&loaded.model, sink)?;
    let model = input_model(loaded, &start);
    let begun = assemble(loaded, model.as_ref(), start, analysis)?;
    if begun.assembled.failure().is_none() {
        feed.assembled(&begun.assembled, begun.assembled_now())
            .map_err(Error::from)?;
    }
    if settle {
        let assembled = begun.assembled;
        let limit = loaded.model.equilibrium.settling_time;
        // Damped settling cannot bound its own wall-clock time: without a time limit, the
        // default guard stops it.
        let deadline = crate::budget::deadline(args.time_limit, DEFAULT_SETTLE_TIME_LIMIT)
            .map_err(crate::error::ArgumentError::from)?;
        let out_of_time = || Instant::now() >= deadline;
        let settled = linkage_solve::stages::settle::settle_until(
            &assembled,
            |elapsed| settling(elapsed, limit),
            &out_of_time,
        );
        let found = settled
            .as_ref()
            .ok()
            .and_then(|o| o.settled_equilibrium())
            .cloned();
        let mut report =
            linkage_report::statics::settling_json(&assembled, settled, &loaded.warnings);
        (report.left_out, report.runs_without) = loaded.coverage(analysis);
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
        let mut left = None;
        if let (Some(eq), true) = (&found, ok) {
            let o = at_rest(&assembled, assembled.state().time, eq);
            feed.output(&assembled, &o).map_err(Error::from)?;
            left = Some(Left {
                state: o.state,
                velocities: o.velocities,
                assembly: None,
            });
        }
        if let Some(l) = left.as_mut() {
            l.assembly = Some(assembled.into_assembly());
        }
        return Ok(StaticRun {
            report,
            ok,
            settled: true,
            state: found.map(|e| e.state),
            interrupted: false,
            imbalance_history: Vec::new(),
            left,
        });
    }
    let from = begun.state().clone();
    let assembled = begun.assembled;
    // Every equilibrium accepted goes to the sink as it is found, up to the first that
    // failed, the first the sink refused or the interruption.
    let mut last = None;
    let mut sink_error = None;
    let mut interrupted = false;
    let mut hand_on = |t: f64, step: &linkage_solve::stages::statics::StepResult| {
        let Some(eq) = step.as_ref().ok().filter(|eq| eq.converged) else {
            return false;
        };
        if assembled.failure().is_some() {
            return false;
        }
        let o = at_rest(&assembled, t, eq);
        if let Err(e) = feed.output(&assembled, &o) {
            sink_error = Some(e);
            return false;
        }
        last = Some(o);
        interrupted = args
            .interrupt
            .as_ref()
            .is_some_and(|i| i.load(Ordering::Relaxed));
        !interrupted
    };
    let (result, search) = match &args.series {
        Some(times) => (
            linkage_solve::stages::statics::run_from_streamed(
                &assembled,
                &from,
                times,
                &mut hand_on,
            ),
            None,
        ),
        None => {
            let (result, search) = one_equilibrium(&assembled, &from, args)?;
            if let [(t, step)] = result.steps.as_slice() {
                hand_on(*t, step);
            }
            (result, search)
        }
    };
    if let Some(e) = sink_error {
        return Err(Error::from(e));
    }
    let mut report = linkage_report::statics::to_json(&assembled, &result, &loaded.warnings);
    report.search = search;
    if let [(_, Ok(eq))] = result.steps.as_slice() {
        // The friction as the equilibrium had it (those inactive in statics off).
        let rest = assembled.rest();
        let values = assembled
            .forces
            .friction_values(Regime::Static, &eq.state, &rest);
        report.frictions = linkage_report::friction::frictions_json(&loaded.model, &values);
        if !eq.converged {
            report
                .errors
                .extend(frictions_at_limit(&loaded.model, &values));
        }
        let contacts = linkage_solve::constraints::curve_contacts::curve_contacts(
            &loaded.model,
            &assembled.system,
            &eq.state,
        );
        report.curve_contacts =
            linkage_report::curve_contacts::curve_contacts_json(&loaded.model, &contacts);
    }
    (report.left_out, report.runs_without) = loaded.coverage(analysis);
    judge_stability(&mut report, args.allow_unstable);
    if interrupted {
        if let Some(o) = &last {
            report.errors.push(
                SinkError::Interrupted { time: o.time }.to_string()
                    + "; the equilibria up to it are written",
            );
        }
    }
    let ok = result.converged() && report.errors.is_empty();
    let state = match result.steps.last() {
        Some((_, Ok(eq))) if ok => Some(eq.state.clone()),
        _ => None,
    };
    let imbalance_history = match result.steps.as_slice() {
        [(_, Ok(eq))] => eq.imbalance_history.clone(),
        _ => Vec::new(),
    };
    let left = match last {
        Some(o) if ok => Some(Left {
            state: o.state,
            velocities: o.velocities,
            assembly: Some(assembled.into_assembly()),
        }),
        _ => None,
    };
    Ok(StaticRun {
        report,
        ok,
        settled: false,
        state,
        interrupted,
        imbalance_history,
        left,
    })
}
