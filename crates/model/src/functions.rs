//! Function expressions of the dataset's statements, parsed once here for every analysis.

use crate::bodies::Origin;
use linkage_adm::{Diagnostic, Function, Located};
use linkage_expr::{parse, Expr};
use std::sync::Arc;

/// Parses argument `what` (`FUNCTION`, `F3`, …) of the element `origin`. Errors, located in
/// the file: a `USER(…)` call (linkage cannot run user subroutines; the whole argument is the
/// place), a syntax error (its place inside the expression).
pub fn parse_function(
    file: &Arc<str>,
    f: &Located<Function>,
    origin: &Origin,
    what: &str,
) -> Result<Expr, Diagnostic> {
    let user = || {
        Diagnostic::error(
            file.clone(),
            Some(f.span),
            format!(
                "{} ({}, line {}): {what} calls a USER subroutine, which linkage cannot run",
                origin.name,
                origin.element(),
                origin.span.line
            ),
        )
        .with_hint("replace the USER(…) call by a function expression")
    };
    if f.value.user {
        return Err(user());
    }
    match parse(&f.value.expr.text) {
        Ok(e) if e.contains_user() => Err(user()),
        Ok(e) => Ok(e),
        Err(e) => Err(Diagnostic::error(
            file.clone(),
            Some(f.value.expr.span_at(e.offset)),
            format!("{}: syntax error in {what}: {}", origin.name, e.message),
        )),
    }
}
