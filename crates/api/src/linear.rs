//! Linearization of a loaded model and its report.

use crate::source::{applied_forces, coverage_json, Loaded};
use linkage_adm::Diagnostics;
use linkage_report::linear::LinearJson;
use linkage_solve::coverage::Analysis;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::linearize::{run, EigenMethod, LinearOptions, LinearRun, DEFAULT_MODES};
use linkage_solve::state::State;
use linkage_solve::tolerances::Tolerances;

/// What `linkage linear` asks for.
#[derive(Clone, Copy, Debug)]
pub struct LinearArgs {
    /// Linearize about the static equilibrium rather than the assembled configuration.
    pub static_first: bool,
    /// Damping, mode shapes and the eigen method.
    pub options: LinearOptions,
    /// With `static_first`: accept an unstable equilibrium as the operating point.
    pub allow_unstable: bool,
}

/// The eigen method of `--modes K` and `--shift F` (F in cycles per time unit): every mode
/// (dense for small models) when neither is given, else the K (default [`DEFAULT_MODES`])
/// modes nearest F by shift-invert. An infinite or NaN shift is an input error.
pub fn eigen_method(modes: Option<usize>, shift: Option<f64>) -> Result<EigenMethod, String> {
    if shift.is_some_and(|f| !f.is_finite()) {
        return Err("--shift must be a finite frequency".into());
    }
    Ok(match (modes, shift) {
        (None, None) => EigenMethod::Auto,
        (modes, shift) => EigenMethod::ShiftInvert {
            modes: modes.unwrap_or(DEFAULT_MODES),
            shift: shift.map(|f| f * std::f64::consts::TAU),
        },
    })
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

/// `linkage linear --format json` of `loaded`: eigenvalues, frequencies, damping ratios and
/// mode shapes; its `errors` are the verdict.
pub fn linear(loaded: &Loaded, args: &LinearArgs) -> Result<LinearJson, Diagnostics> {
    linear_at(loaded, args).map(|(report, _)| report)
}

/// [`linear`] and its operating point: the static equilibrium (with `static_first`, when
/// found) or the assembled configuration.
pub fn linear_at(loaded: &Loaded, args: &LinearArgs) -> Result<(LinearJson, State), Diagnostics> {
    let forces = applied_forces(loaded, Analysis::Linear)?;
    let assembled = Assembled::new(
        &loaded.model,
        &loaded.drivers,
        forces.as_ref(),
        &Tolerances::default(),
    );
    let result = run(&assembled, args.static_first, args.options);
    let mut report = linkage_report::linear::to_json(
        &loaded.model,
        &result,
        args.static_first,
        &loaded.warnings,
    );
    (report.left_out, report.runs_without) = coverage_json(loaded, Analysis::Linear);
    if !args.allow_unstable && report.errors.is_empty() {
        report.errors.extend(unstable_operating_point(&result));
    }
    let at = match &result.equilibrium {
        Some(Ok(eq)) => eq.state.clone(),
        _ => assembled.ic.assembly.state.clone(),
    };
    Ok((report, at))
}
