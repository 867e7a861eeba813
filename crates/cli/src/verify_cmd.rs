//! `linkage verify` (with `--explain`, `--apply K --save OUT.adm`).

use crate::common::{load, Format, Loaded};
use linkage_adm::Diagnostics;
use linkage_report::explain::AppliedJson;
use linkage_report::verify_stream::{write_documents, StreamedVerify, VerifyDocument};
use linkage_solve::stages::explain::repair::realize;
use linkage_solve::stages::explain::{dense, explain, generic, Mobility, Proposal};
use linkage_solve::state::State;
use linkage_solve::tolerances::Tolerances;
use std::path::Path;
use std::process::ExitCode;

/// Options of `linkage verify`.
pub struct VerifyArgs<'a> {
    /// One or more datasets, verified in turn.
    pub models: &'a [std::path::PathBuf],
    pub format: Format,
    /// Add the redundancy explanation (implied by `apply`).
    pub explain: bool,
    /// Proposal to apply (1-based).
    pub apply: Option<usize>,
    /// Where to write the changed dataset.
    pub save: Option<&'a Path>,
    /// Statements to leave out (`--deactivate`).
    pub deactivate: &'a [String],
    /// Where to write the HTML page (`--html`; one model).
    pub html: Option<&'a Path>,
}

/// What verifying one model gave: its report (`None` for an input error, already printed in
/// text) and its exit code.
struct Verified {
    report: Result<linkage_report::verify::VerifyJson, Diagnostics>,
    code: u8,
}

/// Verifies one model: the report and its verdict (1 when its `errors` list is not empty).
fn verify_one(args: &VerifyArgs, model: &Path) -> Verified {
    // Only --apply reads the dataset again; otherwise its text and statements (most of the
    // memory of a large model: about 8 kB per part of a four-bar chain) are freed as soon as
    // the model no longer needs them.
    let loaded = if args.apply.is_none() {
        crate::common::load_model(model, args.deactivate, None)
    } else {
        load(model, args.deactivate, None)
    };
    let loaded = match loaded {
        Ok(l) => l,
        Err(d) => {
            return Verified {
                report: Err(d),
                code: 2,
            }
        }
    };
    let tol = Tolerances::default();
    let v = linkage_api::verify::verification(&loaded, &tol);
    let mut report = linkage_api::verify::report(&loaded, &v);
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
    if let Some(out) = args.html {
        // The elements with redundant or misaligned equations are drawn in red.
        let mut highlight: Vec<String> = report
            .redundant
            .iter()
            .map(|r| r.equation.name.to_string())
            .chain(
                report
                    .misaligned
                    .iter()
                    .map(|m| m.equation.name.to_string()),
            )
            .collect();
        highlight.dedup();
        let mut page = crate::html_out::page(&loaded.model, "verify", &report, &highlight);
        page.animations.push(crate::html_out::frames_of_states(
            "input configuration, time",
            [State::input(&loaded.model)].iter(),
        ));
        if let Err(e) = crate::html_out::write(&page, out) {
            report.errors.push(e.to_string());
        }
    }
    let code = u8::from(!report.errors.is_empty());
    Verified {
        report: Ok(report),
        code,
    }
}

/// Prints one report as text.
fn print_text(report: &linkage_report::verify::VerifyJson) {
    print!("{}", linkage_report::verify::body_text(report));
    if let Some(j) = &report.explain {
        print!("{}", linkage_report::explain::to_text(j));
    }
    print!("{}", linkage_report::verify::error_lines(&report.errors));
}

/// Verifies every model of `args.models`, one report after the other (text: in sequence,
/// JSON: one document, an array when there are several models). The exit code is the worst:
/// 2 when a model has input errors, 1 when one fails, 0 otherwise.
pub fn run(args: &VerifyArgs) -> ExitCode {
    if args.models.len() > 1 && args.html.is_some() {
        eprintln!("error: --html writes the page of one model: give a single dataset");
        return ExitCode::from(2);
    }
    if args.models.len() > 1 && args.apply.is_some() {
        eprintln!("error: --apply changes one model: give a single dataset");
        return ExitCode::from(2);
    }
    let mut worst = 0u8;
    let mut documents = Vec::new();
    for (k, model) in args.models.iter().enumerate() {
        let one = verify_one(args, model);
        worst = worst.max(one.code);
        match (one.report, args.format) {
            (Err(d), Format::Text) => eprintln!("{d}"),
            (Err(d), Format::Json) => {
                eprintln!("{d}");
                let errors: Vec<String> = d.0.iter().map(|e| e.to_string()).collect();
                documents.push(VerifyDocument::InputErrors(serde_json::json!({
                    "file": model.display().to_string(),
                    "errors": errors,
                    "warnings": [],
                })));
            }
            (Ok(r), Format::Text) => {
                if k > 0 {
                    println!();
                }
                print_text(&r);
                crate::common::errors_to_stderr(&r.errors, crate::common::stdout_is_terminal());
            }
            (Ok(r), Format::Json) => {
                crate::common::errors_to_stderr(&r.errors, false);
                match StreamedVerify::new(r) {
                    Ok(s) => documents.push(VerifyDocument::Report(Box::new(s))),
                    Err(e) => {
                        eprintln!("error: cannot write JSON: {e}");
                        worst = worst.max(1);
                    }
                }
            }
        }
    }
    if args.format == Format::Json {
        // Streamed: the document is never held as a value tree or a string.
        if let Err(e) = write_documents(std::io::stdout().lock(), &documents) {
            eprintln!("error: cannot write JSON: {e}");
            worst = worst.max(1);
        }
    }
    ExitCode::from(worst)
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
    let v = linkage_solve::pipeline::verify::verify(&model, &drivers, tol);
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
