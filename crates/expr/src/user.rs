//! `USER(…)` calls linked to a subroutine: the contract between the evaluator and whatever
//! runs foreign code (the `linkage-usersub` crate).
//!
//! The parser leaves `USER(r1, …, rn)` unlinked ([`crate::Expr::User`]); the model builder
//! replaces it by [`crate::Expr::Linked`] with a [`Routine`] when the user gave a library
//! that holds the statement's subroutine. The evaluator evaluates the parameters to numbers
//! and hands them, with the environment, to [`UserRoutine::evaluate`]; the routine reads the
//! model back through the same [`Env`] (SYSFNC, SYSARY, TIMGET) and returns the value and,
//! when asked, its gradient with respect to the environment's variables.

use crate::dual::Dual;
use crate::env::Env;
use crate::error::EvalError;
use std::fmt;
use std::sync::Arc;

/// The words every error of a subroutine that ended the analysis (ERRMES with STOP) carries:
/// an analysis that meets them stops at once rather than retrying (a smaller step, another
/// iteration), since the subroutine asked to stop.
pub const STOP: &str = "ERRMES with STOP";

/// Whether an error message is a subroutine's request to stop ([`STOP`]).
pub fn is_stop(message: &str) -> bool {
    message.contains(STOP)
}

/// A subroutine that computes one value of an element from its parameters and the model.
pub trait UserRoutine: Send + Sync {
    /// The value for parameters `params` in `env`; with `gradient`, its partial derivatives
    /// with respect to `env`'s variables (how they are found belongs to the routine).
    fn evaluate(&self, params: &[f64], env: &dyn Env, gradient: bool) -> Result<Dual, EvalError>;

    /// `[f, df/dt, d²f/dt²]` along time (a MOTSUB's IORD = 0, 1, 2). Default: the routine
    /// gives no time derivatives ([`EvalError::not_time_only`]).
    fn series(&self, params: &[f64], env: &dyn Env) -> Result<[f64; 3], EvalError> {
        let _ = (params, env);
        Err(EvalError::not_time_only("USER"))
    }

    /// What is called, for messages and reports: `SFOSUB in /path/libforces.so`.
    fn describe(&self) -> String;
}

/// A shared handle on a [`UserRoutine`]; two handles are equal when they are the same routine.
#[derive(Clone)]
pub struct Routine(pub Arc<dyn UserRoutine>);

impl PartialEq for Routine {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

impl fmt::Debug for Routine {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Routine({})", self.0.describe())
    }
}

/// Forwards every [`Env`] method to `E`, so that a generic environment can be passed on as
/// `&dyn Env`.
pub(crate) struct Forward<'a, E: ?Sized>(pub &'a E);

impl<E: Env + ?Sized> Env for Forward<'_, E> {
    fn time(&self) -> f64 {
        self.0.time()
    }
    fn mode(&self) -> i32 {
        self.0.mode()
    }
    fn time_variable(&self) -> Option<u32> {
        self.0.time_variable()
    }
    fn measure(
        &self,
        kind: crate::MeasureKind,
        markers: crate::MarkerArgs,
        gradient: bool,
    ) -> Result<Dual, EvalError> {
        self.0.measure(kind, markers, gradient)
    }
    fn measure_series(
        &self,
        kind: crate::MeasureKind,
        markers: crate::MarkerArgs,
    ) -> Result<[f64; 3], EvalError> {
        self.0.measure_series(kind, markers)
    }
    fn rotation(&self, i: u32, j: u32, gradient: bool) -> Result<[Dual; 9], EvalError> {
        self.0.rotation(i, j, gradient)
    }
    fn euler313_previous(&self, i: u32, j: u32) -> Option<[f64; 3]> {
        self.0.euler313_previous(i, j)
    }
    fn rotation_series(&self, i: u32, j: u32) -> Result<[[f64; 3]; 9], EvalError> {
        self.0.rotation_series(i, j)
    }
    fn time_rate(&self) -> f64 {
        self.0.time_rate()
    }
    fn element_force(
        &self,
        kind: crate::ElementForce,
        args: crate::ElementForceArgs,
        gradient: bool,
    ) -> Result<Dual, EvalError> {
        self.0.element_force(kind, args, gradient)
    }
    fn state(&self, state: crate::StateRef, gradient: bool) -> Result<Dual, EvalError> {
        self.0.state(state, gradient)
    }
    fn spline(&self, id: u32) -> Option<&crate::SplineData> {
        self.0.spline(id)
    }
}
