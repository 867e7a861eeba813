//! Function expressions of the dataset's statements, parsed once here for every analysis, and
//! their `USER(…)` calls linked to the subroutines the user gave ([`UserRoutines`]).

use crate::bodies::Origin;
use linkage_adm::{Diagnostic, Function, Located};
use linkage_expr::{parse, Expr, Routine};
use std::fmt;
use std::sync::Arc;

/// One `USER(…)` call of the dataset: what a linker needs to find and call its subroutine.
#[derive(Clone, Copy, Debug)]
pub struct UserSite<'a> {
    /// The statement (`SFORCE/3`, …), which fixes the subroutine family (SFOSUB, …) and the ID
    /// argument.
    pub origin: &'a Origin,
    /// The argument (`FUNCTION`, `F3`, …).
    pub what: &'a str,
    /// The statement's `ROUTINE = lib::name`, as written.
    pub routine: Option<&'a str>,
    /// Which value of a subroutine that returns several (GFOSUB's 6, REQSUB's 8): 0-based.
    pub component: usize,
}

/// Links `USER(…)` calls to code. Implemented by `linkage-usersub`; the model only asks.
pub trait UserLinker: Send + Sync {
    /// The routine that computes `site`'s value, or why there is none (the message names
    /// what was looked for and where; the caller adds the statement and its place).
    fn link(
        &self,
        site: &UserSite<'_>,
    ) -> Result<Routine, Box<dyn std::error::Error + Send + Sync>>;

    /// The library files loaded so far, with their full paths (for every report).
    fn loaded(&self) -> Vec<String>;

    /// The subroutine a `USER(…)` call of a `keyword` statement with `routine` calls, as
    /// verify lists it (`SFOSUB as springs::sfosub`), or `None` when the statement's USER
    /// subroutines are not called (its family is not supported).
    fn calls(&self, keyword: &str, routine: Option<&str>) -> Option<String>;
}

/// The linker of a model's `USER(…)` calls: none (every USER call is refused, as before the
/// user gave a library) or the one the front end made from `--user-lib`.
#[derive(Clone, Default)]
pub struct UserRoutines(pub Option<Arc<dyn UserLinker>>);

impl fmt::Debug for UserRoutines {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.0 {
            None => f.write_str("UserRoutines(none)"),
            Some(l) => write!(f, "UserRoutines({:?})", l.loaded()),
        }
    }
}

impl UserRoutines {
    /// True when a linker is given (USER calls are linked rather than refused).
    pub fn given(&self) -> bool {
        self.0.is_some()
    }
}

/// Parses argument `what` (`FUNCTION`, `F3`, …) of the element `origin`, linking its
/// `USER(…)` call through `user` (value `component` of the subroutine). Errors, located in
/// the file: a `USER(…)` call without a linker, or whose subroutine cannot be found (the
/// whole argument is the place), a syntax error (its place inside the expression).
pub fn parse_function(
    file: &Arc<str>,
    f: &Located<Function>,
    origin: &Origin,
    what: &str,
    user: &UserRoutines,
) -> Result<Expr, Diagnostic> {
    parse_component(file, f, origin, what, user, 0)
}

/// [`parse_function`] for value `component` (0-based) of a subroutine that returns several.
pub fn parse_component(
    file: &Arc<str>,
    f: &Located<Function>,
    origin: &Origin,
    what: &str,
    user: &UserRoutines,
    component: usize,
) -> Result<Expr, Diagnostic> {
    let refuse = |why: &str, hint: &str| {
        Diagnostic::error(
            file.clone(),
            Some(f.span),
            format!(
                "{} ({}, line {}): {what} calls a USER subroutine{why}",
                origin.name,
                origin.element(),
                origin.span.line
            ),
        )
        .with_hint(hint)
    };
    let e = match parse(&f.value.expr.text) {
        Ok(e) => e,
        Err(e) => {
            return Err(Diagnostic::error(
                file.clone(),
                Some(f.value.expr.span_at(e.offset)),
                format!("{}: syntax error in {what}: {}", origin.name, e.message),
            ))
        }
    };
    if !e.contains_user() {
        return Ok(e);
    }
    let Some(linker) = &user.0 else {
        return Err(refuse(
            ", which linkage runs only from a library the user gives",
            "give the subroutine's library with --user-lib PATH, or replace the USER(…) call \
             by a function expression",
        ));
    };
    let site = UserSite {
        origin,
        what,
        routine: f.value.routine.as_deref(),
        component,
    };
    let mut failure = None;
    let linked = e.link_user(&mut |_| match linker.link(&site) {
        Ok(r) => Some(r),
        Err(why) => {
            failure.get_or_insert(why.to_string());
            None
        }
    });
    match failure {
        Some(why) => Err(refuse(
            &format!(": {why}"),
            "give the library that holds it with --user-lib PATH (a file or a folder)",
        )),
        None => Ok(linked),
    }
}
