//! The initial conditions of a loaded model and their report.

use crate::source::{applied_forces, coverage_json, Loaded};
use linkage_adm::Diagnostics;
use linkage_report::ic::IcJson;
use linkage_solve::coverage::Analysis;
use linkage_solve::pipeline::{Assembled, NotAssembled};
use linkage_solve::state::State;
use linkage_solve::tolerances::Tolerances;

/// What the initial conditions gave.
pub struct IcRun {
    /// `linkage ic --format json`.
    pub report: IcJson,
    /// The model could not be assembled (exit code 1).
    pub failed: bool,
    /// The assembled configuration (what `--save` writes).
    pub state: State,
}

/// Assembles `loaded` and solves its velocities, accelerations and forces at the start time.
/// An inconsistent redundant equation is the verdict's one line.
pub fn ic(loaded: &Loaded) -> Result<IcRun, Diagnostics> {
    let forces = applied_forces(loaded, Analysis::Ic)?;
    let assembled = Assembled::new(
        &loaded.model,
        &loaded.drivers,
        forces.as_ref(),
        &Tolerances::default(),
    );
    let ic = &assembled.ic;
    let mut report = linkage_report::ic::to_json(&loaded.model, ic, &loaded.warnings);
    if let Some(v) = &ic.velocity {
        let values = forces.friction_values(
            linkage_solve::physics::applied::Regime::Dynamic,
            &ic.assembly.state,
            &v.velocities,
        );
        report.frictions = linkage_report::friction::frictions_json(&loaded.model, &values);
    }
    if !matches!(
        assembled.failure(),
        Some(NotAssembled::DidNotConverge { .. })
    ) {
        let contacts = linkage_solve::constraints::curve_contacts::curve_contacts(
            &loaded.model,
            &assembled.system,
            &ic.assembly.state,
        );
        report.curve_contacts =
            linkage_report::curve_contacts::curve_contacts_json(&loaded.model, &contacts);
    }
    (report.left_out, report.runs_without) = coverage_json(loaded, Analysis::Ic);
    // An assembly that did not converge has its own error; an inconsistent redundancy is named
    // here, as the one line of the verdict.
    if let Some(why @ NotAssembled::Inconsistent { .. }) = assembled.failure() {
        report.errors.push(why.to_string());
    }
    let failed = assembled.failure().is_some() || !report.errors.is_empty();
    Ok(IcRun {
        report,
        failed,
        state: ic.assembly.state.clone(),
    })
}
