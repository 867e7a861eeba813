//! `linkage verify` (with `--explain`, `--apply K --save OUT.adm`).

use crate::common::{input_error, load, print_json, Format, Loaded};
use linkage_adm::Diagnostics;
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
    if args.explain || args.apply.is_some() {
        let ex = explain(&loaded.model, &loaded.drivers, &tol, &v);
        let mut j = linkage_report::explain::to_json(&loaded.model, &ex);
        if let Some(k) = args.apply {
            match apply(&loaded, &ex.suggestions, k, args.save, &tol) {
                Ok(a) => j.applied = Some(a),
                Err(e) => report.errors.push(e.to_string()),
            }
        }
        report.explain = Some(j);
    }
    match args.format {
        Format::Text => {
            print!("{}", linkage_report::verify::body_text(&report));
            if let Some(j) = &report.explain {
                print!("{}", linkage_report::explain::to_text(j));
            }
            print!("{}", linkage_report::verify::error_lines(&report.errors));
        }
        Format::Json => {
            if !print_json(&report) {
                return ExitCode::from(1);
            }
        }
    }
    crate::common::errors_to_stderr(&report.errors, crate::common::stdout_is_terminal());
    if !report.errors.is_empty() {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}

/// Why `--apply K --save OUT.adm` wrote nothing (or could not write).
#[derive(Debug, thiserror::Error)]
pub enum ApplyError {
    #[error("--apply needs --save OUT.adm")]
    NoSave,
    /// `number` is not between 1 and `count`.
    #[error(
        "--apply {number}: there {} {count} proposal{} (numbered from 1); nothing written",
        if *.count == 1 { "is" } else { "are" },
        if *.count == 1 { "" } else { "s" }
    )]
    NoSuchProposal { number: usize, count: usize },
    #[error("cannot apply proposal {number}: {source}")]
    Edit { number: usize, source: Diagnostics },
    #[error("internal error: the changed dataset does not read back: {0}")]
    ReadBack(Diagnostics),
    #[error("internal error: the changed dataset does not build: {0}")]
    Build(Diagnostics),
    #[error("internal error: {0}")]
    Functions(Diagnostics),
    /// The changed dataset does not have the mobility the proposal promised.
    #[error(
        "internal error: proposal {number} promised {promised_dof} DOF and {promised_redundant} \
         redundant equations, the changed dataset has {dof} and {redundant}; nothing written"
    )]
    BrokenPromise {
        number: usize,
        promised_dof: i64,
        promised_redundant: usize,
        dof: i64,
        redundant: usize,
    },
    #[error("cannot write {path}: {source}")]
    Write {
        path: String,
        source: std::io::Error,
    },
}

/// Writes the dataset with proposal `k` applied to `save`, then reads it back and verifies it:
/// the written model must have the DOF and redundancy the proposal promised.
fn apply(
    loaded: &Loaded,
    suggestions: &[Proposal],
    k: usize,
    save: Option<&Path>,
    tol: &Tolerances,
) -> Result<AppliedJson, ApplyError> {
    let Some(out) = save else {
        return Err(ApplyError::NoSave);
    };
    let Some(p) = k.checked_sub(1).and_then(|i| suggestions.get(i)) else {
        return Err(ApplyError::NoSuchProposal {
            number: k,
            count: suggestions.len(),
        });
    };
    let real = realize(&loaded.model, &p.changes);
    let text = linkage_adm::edit::apply_edits(&loaded.dataset, &real.edits)
        .map_err(|source| ApplyError::Edit { number: k, source })?;
    // Check what will be written before writing it.
    let ds = linkage_adm::parse_dataset(out.display().to_string().into(), &text)
        .map_err(ApplyError::ReadBack)?;
    let model = linkage_model::build_model(&ds)
        .map_err(ApplyError::Build)?
        .model;
    let drivers = linkage_solve::constraints::drivers::ExpressionDrivers::new(&model)
        .map_err(ApplyError::Functions)?;
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
        return Err(ApplyError::BrokenPromise {
            number: k,
            promised_dof: p.dof_after,
            promised_redundant: p.redundant_after,
            dof: want_dof,
            redundant: want_red,
        });
    }
    linkage_adm::writer::write_atomically(out, &text).map_err(|source| ApplyError::Write {
        path: out.display().to_string(),
        source,
    })?;
    Ok(AppliedJson {
        number: k,
        file: out.display().to_string(),
        dof: v.dof,
        redundant: v.redundant.len(),
    })
}
