//! `linkage ic`.

use crate::common::{input_error, load, print_json, Format};
use linkage_adm::Dataset;
use linkage_model::Model;
use linkage_solve::coverage::Analysis;
use linkage_solve::state::State;
use std::path::Path;
use std::process::ExitCode;

pub fn run(
    model: &Path,
    format: Format,
    save: Option<&Path>,
    html: Option<&Path>,
    deactivate: &[String],
) -> ExitCode {
    let loaded = match load(model, deactivate, Some(Analysis::Ic)) {
        Ok(l) => l,
        Err(d) => return input_error(&d, format),
    };
    let run = match linkage_api::ic::ic(&loaded) {
        Ok(r) => r,
        Err(e) => return crate::common::analysis_error(&e, format),
    };
    let (mut report, mut failed) = (run.report, run.failed);
    if let Some(out) = html {
        // The view moves from the input configuration to the assembled one.
        let mut page = crate::html_out::page(&loaded.model, "ic", &report, &[]);
        let states = [State::input(&loaded.model), run.state.clone()];
        page.animations.push(crate::html_out::frames_of_states(
            "input → assembled, time",
            states.iter(),
        ));
        if let Err(e) = crate::html_out::write(&page, out) {
            report.errors.push(e.to_string());
            failed = true;
        }
    }
    if let Some(out) = save {
        if failed {
            report.errors.push(format!(
                "{} not written: the model could not be assembled",
                out.display()
            ));
        } else if let Err(e) = save_configuration(&loaded.dataset, &loaded.model, &run.state, out) {
            report
                .errors
                .push(format!("cannot write {}: {e}", out.display()));
            emit(&report, format);
            return ExitCode::from(1);
        }
    }
    emit(&report, format);
    if failed {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}

fn emit(report: &linkage_report::ic::IcJson, format: Format) {
    match format {
        Format::Text => print!("{}", linkage_report::ic::to_text(report)),
        Format::Json => {
            print_json(report);
        }
    }
    crate::common::errors_to_stderr(&report.errors, crate::common::stdout_is_terminal());
}

/// Why a configuration could not be saved (shown after `cannot write OUT:`).
#[derive(Debug, thiserror::Error)]
pub enum SaveError {
    /// The dataset text could not be rewritten with the new poses.
    #[error("{0}")]
    Rewrite(linkage_adm::Diagnostics),
    #[error("{0}")]
    Write(std::io::Error),
}

/// Writes the dataset at configuration `state`: every moved part's QG/REULER (markers keep
/// their place on their part because they are given in the part's frame), an FE_PART's
/// COORDINATES and the markers on its nodes, a FLEX_BODY's QG/REULER and DMODE
/// (`linkage_model::saved` states what and why).
pub fn save_configuration(
    ds: &Dataset,
    model: &Model,
    state: &State,
    out: &Path,
) -> Result<(), SaveError> {
    let poses: Vec<_> = state.poses.iter().map(|s| (s.p, s.r)).collect();
    let changes = linkage_model::saved::saved_changes(ds, model, &poses);
    let text = linkage_adm::writer::write_changes(ds, &changes.parts, &changes.arguments)
        .map_err(SaveError::Rewrite)?;
    linkage_adm::writer::write_atomically(out, &text).map_err(SaveError::Write)
}
