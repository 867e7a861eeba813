//! What every builder shares: the diagnostics collected so far (errors and warnings, in the
//! order they are found) and the small conversions from dataset values.

use crate::bodies::Origin;
use glam::DVec3;
use linkage_adm::{Diagnostic, Header, Located, Span};
use std::collections::HashSet;
use std::sync::Arc;

/// The diagnostics of one build. Every problem is collected (not just the first); a build
/// with errors returns them all, in the order the builders found them.
pub(crate) struct Ctx {
    pub file: Arc<str>,
    /// The linker of `USER(…)` calls.
    pub user: crate::functions::UserRoutines,
    pub errors: Vec<Diagnostic>,
    pub warnings: Vec<Diagnostic>,
}

impl Ctx {
    /// An error at `span` of the dataset.
    pub fn error(&mut self, span: Span, msg: impl Into<String>) {
        self.errors
            .push(Diagnostic::error(self.file.clone(), Some(span), msg));
    }

    /// A warning at `span` of the dataset.
    pub fn warn(&mut self, span: Span, msg: impl Into<String>) {
        self.warnings
            .push(Diagnostic::warning(self.file.clone(), Some(span), msg));
    }

    /// The point `keyword` (QG, QP, ZP, …) of element `name` as a vector; an error, and the
    /// origin, when a coordinate is beyond [`MAX_COORDINATE`].
    pub fn point(&mut self, name: &str, keyword: &str, q: &Located<[f64; 3]>) -> DVec3 {
        match q.value.iter().find(|x| x.abs() > MAX_COORDINATE) {
            Some(x) => {
                self.error(
                    q.span,
                    format!(
                        "{name}: {keyword} coordinate {} is beyond ±{}, where the arithmetic \
                         of the analyses overflows (a digit astray?)",
                        linkage_adm::num::general(*x, 6),
                        linkage_adm::num::general(MAX_COORDINATE, 6)
                    ),
                );
                DVec3::ZERO
            }
            None => v3(q.value),
        }
    }

    /// False, after the error `duplicate STATEMENT id N`, when `h`'s id is already in `seen`
    /// (ids are unique within a statement type); true (and the id recorded) otherwise.
    pub fn unique(&mut self, seen: &mut HashSet<u64>, statement: &str, h: &Header) -> bool {
        if !seen.insert(h.id) {
            self.error(h.span, format!("duplicate {statement} id {}", h.id));
            return false;
        }
        true
    }
}

/// Where the element of header `h` (a `statement` statement) was defined.
pub(crate) fn origin(statement: &'static str, h: &Header) -> Origin {
    Origin {
        statement,
        id: h.id,
        name: h.name.clone(),
        span: h.span,
        statement_index: h.statement,
    }
}

/// The largest coordinate magnitude (model units) a point may have: no mechanism is that
/// large, and squares and differences of larger numbers overflow in the analyses (found by
/// fuzzing: a QG of -1E308 gave infinite residuals and a wrong DOF).
pub(crate) const MAX_COORDINATE: f64 = 1e60;

/// A dataset triple as a vector.
pub(crate) fn v3(a: [f64; 3]) -> DVec3 {
    DVec3::from_array(a)
}
