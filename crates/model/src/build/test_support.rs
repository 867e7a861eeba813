//! Helpers of the builders' unit tests: build a dataset from text, read its diagnostics.

use super::{build_model, Built};
use std::sync::Arc;

/// Ground with two markers; PART/2 (CM 20, markers 20, 21 and floating 22) and PART/3 (CM 30,
/// floating 31), each of unit mass and inertia. Text appended to it starts at line 12.
pub(crate) const BASE: &str = "title\nPART/1, GROUND\nMARKER/1, PART = 1\nMARKER/2, PART = 1, QP = 1, 0, 0\nPART/2, MASS = 1, CM = 20, IP = 1, 1, 1\nMARKER/20, PART = 2, QP = 0, 2, 0\nMARKER/21, PART = 2, QP = 1, 2, 0\nMARKER/22, PART = 2, FLOATING\nPART/3, MASS = 1, CM = 30, IP = 1, 1, 1\nMARKER/30, PART = 3\nMARKER/31, PART = 3, FLOATING\n";

/// Builds [`BASE`] followed by `extra` and `END`.
pub(crate) fn build(extra: &str) -> Result<Built, linkage_adm::Diagnostics> {
    build_text(&format!("{BASE}{extra}\nEND\n"))
}

/// Builds a whole dataset text.
pub(crate) fn build_text(text: &str) -> Result<Built, linkage_adm::Diagnostics> {
    let ds = linkage_adm::parse_dataset(Arc::from("m.adm"), text).unwrap_or_else(|e| panic!("{e}"));
    build_model(&ds)
}

/// [`build`], which must succeed.
pub(crate) fn ok(extra: &str) -> Built {
    build(extra).unwrap_or_else(|e| panic!("{e}"))
}

/// The errors of [`build`] (which must fail) as `(line, col, message)`, sorted.
pub(crate) fn errors(extra: &str) -> Vec<(u32, u32, String)> {
    let mut e = errors_in_order(&format!("{BASE}{extra}\nEND\n"));
    e.sort();
    e
}

/// The errors of building `text` (which must fail) as `(line, col, message)`, in the order
/// they are reported.
pub(crate) fn errors_in_order(text: &str) -> Vec<(u32, u32, String)> {
    match build_text(text) {
        Ok(_) => panic!("expected errors"),
        Err(d) => {
            d.0.into_iter()
                .map(|d| {
                    let s = d.span.unwrap_or_default();
                    (s.line, s.col, d.message)
                })
                .collect()
        }
    }
}
