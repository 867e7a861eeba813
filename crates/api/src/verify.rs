//! The verify report of a loaded model (the CLI adds `--explain` and `--apply` to it).

use crate::source::Loaded;
use linkage_report::verify::VerifyJson;
use linkage_solve::pipeline::verify::Verification;
use linkage_solve::tolerances::Tolerances;

/// The verification of `loaded` (rank analysis at the input configuration).
pub fn verification(loaded: &Loaded, tol: &Tolerances) -> Verification {
    linkage_solve::pipeline::verify::verify(&loaded.model, &loaded.drivers, tol)
}

/// The verify report of `loaded` from its verification `v`: DOF, redundant and misaligned
/// equations, and what the dataset leaves out or later analyses refuse. Its `errors` are the
/// verdict (exit code 1 when not empty).
pub fn report(loaded: &Loaded, v: &Verification) -> VerifyJson {
    let mut report = linkage_report::verify::to_json(&loaded.model, v, &loaded.warnings);
    if !v.assembled || !v.idealized.is_empty() {
        // Not assembled at the input: also the counts at the pose the assembly reaches,
        // which every analysis uses (no forces are needed for the displacements).
        let input = linkage_solve::state::State::input(&loaded.model);
        let ic = linkage_solve::pipeline::ic::initial_conditions(
            &loaded.model,
            &linkage_solve::pipeline::verify::compile(&loaded.model, &input, &[]),
            &loaded.drivers,
            &linkage_solve::physics::applied::NoForces,
            &Tolerances::default(),
        );
        report.after_assembly = Some(linkage_report::verify::after_assembly_json(
            &loaded.model,
            ic.assembly.converged,
            &ic.analysis,
        ));
    }
    report.left_out = linkage_report::coverage::left_out_json(&loaded.left_out);
    report.not_run = loaded.findings.iter().map(Into::into).collect();
    report.later_refused_by = linkage_report::coverage::refusing_analyses(&loaded.findings);
    report
}

/// `linkage verify --format json` of `loaded`.
pub fn verify(loaded: &Loaded) -> VerifyJson {
    report(loaded, &verification(loaded, &Tolerances::default()))
}
