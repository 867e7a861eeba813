//! `linkage linear`: eigenvalues and modes about an operating point.

use crate::common::{applied_forces, input_error, load, print_json, Format};
use linkage_solve::coverage::Analysis;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::linearize::{run, EigenMethod, LinearOptions, LinearRun, DEFAULT_MODES};
use linkage_solve::tolerances::Tolerances;
use std::path::Path;
use std::process::ExitCode;

/// Options of `linkage linear`.
pub struct LinearArgs<'a> {
    pub model: &'a Path,
    pub format: Format,
    pub static_first: bool,
    pub damping: bool,
    pub vectors: bool,
    /// `--modes K`: the K modes nearest the shift, by shift-invert.
    pub modes: Option<usize>,
    /// `--shift F` in cycles per time unit.
    pub shift: Option<f64>,
    /// With `static_first`: accept an unstable equilibrium as the operating point.
    pub allow_unstable: bool,
    /// Statements to leave out (`--deactivate`).
    pub deactivate: &'a [String],
    /// Where to write the HTML page (`--html`).
    pub html: Option<&'a Path>,
}

/// The verdict on linearizing about an unstable static equilibrium, in one line with what to
/// try (`None` when the operating point is not a converged, unstable equilibrium).
fn unstable_operating_point(run: &LinearRun) -> Option<String> {
    let Some(Ok(eq)) = &run.equilibrium else {
        return None;
    };
    let (false, stiffness) = eq.stability? else {
        return None;
    };
    Some(format!(
        "the static equilibrium linearized about is UNSTABLE (negative stiffness {} along a \
         free motion): `linkage static --settle` finds a stable one by damped dynamics; \
         --allow-unstable accepts this one",
        linkage_adm::num::sci(stiffness, 4)
    ))
}

/// Most mode shapes a page animates.
const MODES_ANIMATED: usize = 12;

pub fn run_linear(args: &LinearArgs) -> ExitCode {
    let loaded = match load(args.model, args.deactivate, Some(Analysis::Linear)) {
        Ok(l) => l,
        Err(d) => return input_error(&d, args.format),
    };
    let forces = match applied_forces(&loaded, Analysis::Linear) {
        Ok(f) => f,
        Err(d) => return input_error(&d, args.format),
    };
    if args.shift.is_some_and(|f| !f.is_finite()) {
        eprintln!("error: --shift must be a finite frequency");
        return ExitCode::from(2);
    }
    let method = match (args.modes, args.shift) {
        (None, None) => EigenMethod::Auto,
        (modes, shift) => EigenMethod::ShiftInvert {
            modes: modes.unwrap_or(DEFAULT_MODES),
            shift: shift.map(|f| f * std::f64::consts::TAU),
        },
    };
    let opts = LinearOptions {
        damping: args.damping,
        vectors: args.vectors,
        method,
    };
    let assembled = Assembled::new(
        &loaded.model,
        &loaded.drivers,
        forces.as_ref(),
        &Tolerances::default(),
    );
    let result = run(&assembled, args.static_first, opts);
    let mut report = linkage_report::linear::to_json(
        &loaded.model,
        &result,
        args.static_first,
        &loaded.warnings,
    );
    (report.left_out, report.runs_without) =
        crate::common::coverage_json(&loaded, Analysis::Linear);
    if !args.allow_unstable && report.errors.is_empty() {
        report.errors.extend(unstable_operating_point(&result));
    }
    if let Some(out) = args.html {
        let mut page = crate::html_out::page(&loaded.model, "linear", &report, &[]);
        // The operating point: the static equilibrium, or the assembled configuration.
        let at = match &result.equilibrium {
            Some(Ok(eq)) => &eq.state,
            _ => &assembled.ic.assembly.state,
        };
        let base: Vec<_> = at.poses.iter().map(|p| (p.p, p.r)).collect();
        page.animations.extend(
            report
                .modes
                .iter()
                .filter(|m| m.frequency > 0.0)
                .take(MODES_ANIMATED)
                .filter_map(|m| {
                    linkage_html::series::mode_frames(&base, m, loaded.model.characteristic_length)
                }),
        );
        if page.animations.is_empty() {
            page.animations.push(crate::html_out::frames_of_states(
                "operating point",
                [at].into_iter(),
            ));
        } else {
            page.notes.push(format!(
                "Mode shapes of the first {} modes of nonzero frequency are animated over one \
                 cycle, scaled to be seen (the table gives their magnitudes).",
                page.animations.len()
            ));
        }
        if let Err(e) = crate::html_out::write(&page, out) {
            report.errors.push(e);
        }
    }
    match args.format {
        Format::Text => print!("{}", linkage_report::linear::to_text(&report)),
        Format::Json => {
            print_json(&report);
        }
    }
    crate::common::errors_to_stderr(&report.errors, crate::common::stdout_is_terminal());
    if report.errors.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}
