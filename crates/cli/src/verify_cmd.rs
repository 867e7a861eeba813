//! `linkage verify` (with `--explain`, `--apply K --save OUT.adm`).

use crate::common::{input_error, load, print_json, Format, Loaded};
use linkage_report::explain::AppliedJson;
use linkage_solve::stages::explain::repair::realize;
use linkage_solve::stages::explain::{dense, explain, generic, Mobility, Proposal};
use linkage_solve::state::State;
use linkage_solve::tolerances::Tolerances;
use std::path::Path;
use std::process::ExitCode;

/// Options of `linkage verify`.
pub struct VerifyArgs<'a> {
    pub model: &'a Path,
    pub format: Format,
    /// Add the redundancy explanation (implied by `apply`).
    pub explain: bool,
    /// Proposal to apply (1-based).
    pub apply: Option<usize>,
    /// Where to write the changed dataset.
    pub save: Option<&'a Path>,
}

pub fn run(args: &VerifyArgs) -> ExitCode {
    let loaded = match load(args.model) {
        Ok(l) => l,
        Err(d) => return input_error(&d, args.format),
    };
    let tol = Tolerances::default();
    let v = linkage_solve::stages::verify::verify(&loaded.model, &loaded.drivers, &tol);
    let mut report = linkage_report::verify::to_json(&loaded.model, &v, &loaded.warnings);
    let mut failed = false;
    if args.explain || args.apply.is_some() {
        let ex = explain(&loaded.model, &loaded.drivers, &tol, &v);
        let mut j = linkage_report::explain::to_json(&loaded.model, &ex);
        if let Some(k) = args.apply {
            match apply(&loaded, &ex.suggestions, k, args.save, &tol) {
                Ok(a) => j.applied = Some(a),
                Err(e) => {
                    report.errors.push(e);
                    failed = true;
                }
            }
        }
        report.explain = Some(j);
    }
    match args.format {
        Format::Text => {
            print!("{}", linkage_report::verify::to_text(&report));
            if let Some(j) = &report.explain {
                print!("{}", linkage_report::explain::to_text(j));
            }
        }
        Format::Json => {
            if !print_json(&report) {
                return ExitCode::from(1);
            }
        }
    }
    for e in &report.errors {
        eprintln!("error: {e}");
    }
    if failed {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}

/// Writes the dataset with proposal `k` applied to `save`, then reads it back and verifies it:
/// the written model must have the DOF and redundancy the proposal promised.
fn apply(
    loaded: &Loaded,
    suggestions: &[Proposal],
    k: usize,
    save: Option<&Path>,
    tol: &Tolerances,
) -> Result<AppliedJson, String> {
    let Some(out) = save else {
        return Err("--apply needs --save OUT.adm".into());
    };
    let Some(p) = k.checked_sub(1).and_then(|i| suggestions.get(i)) else {
        return Err(format!(
            "--apply {k}: there {} {} proposal{} (numbered from 1); nothing written",
            if suggestions.len() == 1 { "is" } else { "are" },
            suggestions.len(),
            if suggestions.len() == 1 { "" } else { "s" }
        ));
    };
    let real = realize(&loaded.model, &p.changes);
    let text = linkage_adm::edit::apply_edits(&loaded.dataset, &real.edits)
        .map_err(|d| format!("cannot apply proposal {k}: {d}"))?;
    // Check what will be written before writing it.
    let ds = linkage_adm::parse_dataset(out.display().to_string().into(), &text)
        .map_err(|d| format!("internal error: the changed dataset does not read back: {d}"))?;
    let model = linkage_model::build_model(&ds)
        .map_err(|d| format!("internal error: the changed dataset does not build: {d}"))?
        .model;
    let drivers = linkage_solve::constraints::drivers::ExpressionDrivers::new(&model)
        .map_err(|d| format!("internal error: {d}"))?;
    let v = linkage_solve::stages::verify::verify(&model, &drivers, tol);
    let input = State::input(&model);
    let length = model.characteristic_length;
    let base = dense::analyse(&v.system, &input, &v.topology, length, tol);
    let at_input = Mobility::new(v.moving_parts, v.rows, base.rank);
    let g = generic::generic_mobility(&model, &v.system, &v.topology, &input, tol, at_input);
    let (want_dof, want_red) = match g.generic {
        Some(x) if g.singular => (x.dof, x.redundant),
        _ => (at_input.dof, at_input.redundant),
    };
    if (want_dof, want_red) != (p.dof_after, p.redundant_after) {
        return Err(format!(
            "internal error: proposal {k} promised {} DOF and {} redundant equations, the changed \
             dataset has {want_dof} and {want_red}; nothing written",
            p.dof_after, p.redundant_after
        ));
    }
    linkage_adm::writer::write_atomically(out, &text)
        .map_err(|e| format!("cannot write {}: {e}", out.display()))?;
    Ok(AppliedJson {
        number: k,
        file: out.display().to_string(),
        dof: v.dof,
        redundant: v.redundant.len(),
    })
}
