//! `--html OUT.html`: the page of an analysis ([`linkage_html`]), written beside its report.
//!
//! Each command hands over its report (the JSON structure it prints) and what it has of the
//! motion: the frames of a run, the configurations of a series, the mode shapes. A page that
//! cannot be written is an error of the run (exit 1), named in its report.

use linkage_html::scene::{scene, Frames};
use linkage_html::Page;
use linkage_model::Model;
use linkage_solve::state::State;
use std::path::Path;

/// A page of `analysis` on `model` with its `report`; the constraint elements named in
/// `highlight` drawn in red. The view shows the input configuration until animations are
/// added.
pub fn page<T: serde::Serialize>(
    model: &Model,
    analysis: &str,
    report: &T,
    highlight: &[String],
) -> Page {
    Page {
        analysis: analysis.into(),
        report: serde_json::to_value(report).unwrap_or_default(),
        scene: scene(model, highlight),
        gravity: model.gravity,
        animations: Vec::new(),
        plots: Vec::new(),
        notes: Vec::new(),
    }
}

/// Frames named `label` through the configurations `states` (at their times).
pub fn frames_of_states<'s>(label: &str, states: impl Iterator<Item = &'s State>) -> Frames {
    let mut f = Frames {
        label: label.into(),
        ..Frames::default()
    };
    for s in states {
        f.push(s.time, s.poses.iter().map(|p| (p.p, p.r)));
    }
    f.total = f.times.len();
    f
}

/// A page that could not be written.
#[derive(Debug, thiserror::Error)]
#[error("cannot write {path}: {cause}")]
pub struct PageError {
    pub path: String,
    pub cause: std::io::Error,
}

/// Writes `page` to `out`; the error as the report states it.
pub fn write(page: &Page, out: &Path) -> Result<(), PageError> {
    linkage_html::write_page(page, out).map_err(|cause| PageError {
        path: out.display().to_string(),
        cause,
    })
}
