//! One linked subroutine: its entry point in either calling convention, the IFLAG pass, the
//! value call and the partial derivatives by central differences.

use crate::callbacks::{read, with_frame, Key};
use crate::kind::{CHead, Kind, Shape};
use linkage_expr::{Dual, Env, EvalError, EvalErrorKind, UserRoutine};
use std::ffi::c_int;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// Fortran, with a flag before IFLAG: `(ID, TIME, PAR, NPAR, DFLAG|IORD, IFLAG, OUT)`.
pub(crate) type FortranFlagged = unsafe extern "C" fn(
    *const c_int,
    *const f64,
    *const f64,
    *const c_int,
    *const c_int,
    *const c_int,
    *mut f64,
);
/// Fortran without: `(ID, TIME, PAR, NPAR, IFLAG, OUT)`.
pub(crate) type FortranPlain = unsafe extern "C" fn(
    *const c_int,
    *const f64,
    *const f64,
    *const c_int,
    *const c_int,
    *mut f64,
);
/// C style: `(const struct sAdams… *, double time, int dflag|iord, int iflag, double *out)`.
pub(crate) type CFlagged = unsafe extern "C" fn(*const CHead, f64, c_int, c_int, *mut f64);
/// C style without the flag: `(const struct sAdams… *, double time, int iflag, double *out)`.
pub(crate) type CPlain = unsafe extern "C" fn(*const CHead, f64, c_int, *mut f64);

/// An entry point and its convention.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Entry {
    FortranFlagged(FortranFlagged),
    FortranPlain(FortranPlain),
    CFlagged(CFlagged),
    CPlain(CPlain),
}

/// The relative step of the central differences that give a subroutine's partials:
/// ∛ε·max(1, |q|) balances truncation (∝ h²) against rounding (∝ ε/h), for an error near
/// ε^(2/3) ≈ 4e-11 relative — finer than Adams' default forward difference.
pub const DIFFERENCE_STEP: f64 = 6.055_454_452_393_343e-6;

/// Room for the values a subroutine writes (REQSUB writes 8; more for safety).
const OUT_LEN: usize = 32;

/// A subroutine linked to a statement's `USER(…)` call.
pub struct Linked {
    pub(crate) kind: Kind,
    /// The statement's id (the ID argument).
    pub(crate) id: c_int,
    /// Which value of the subroutine's output this call is.
    pub(crate) component: usize,
    pub(crate) entry: Entry,
    /// The symbol called and the library file that holds it.
    pub(crate) symbol: String,
    pub(crate) library: PathBuf,
    /// Keeps the library loaded while the routine can be called.
    pub(crate) _keep: Arc<libloading::os::unix::Library>,
    /// The statement, for messages (`SFORCE/3`).
    pub(crate) element: String,
    /// Set after the IFLAG call (the first one), shared by every value of the same statement's
    /// subroutine (a GFOSUB's six, a REQSUB's eight): Adams calls it once per statement.
    pub(crate) initialised: Arc<AtomicBool>,
}

impl Linked {
    /// Calls the subroutine once: `flag` is DFLAG (0/1) or IORD, `iflag` 1 in the
    /// initialisation pass. Returns the value of this call's component.
    fn invoke(&self, time: f64, params: &[f64], flag: c_int, iflag: c_int) -> f64 {
        let mut out = [0.0f64; OUT_LEN];
        let npar = params.len() as c_int;
        let par = if params.is_empty() {
            [0.0f64].as_ptr()
        } else {
            params.as_ptr()
        };
        let head = CHead {
            id: self.id,
            npar,
            par,
        };
        // SAFETY: the entry point has the convention `self.entry` says (chosen by its name,
        // as Adams does); every pointer is valid for the call, and `out` has room for more
        // values than any subroutine family writes.
        unsafe {
            match self.entry {
                Entry::FortranFlagged(f) => {
                    f(&self.id, &time, par, &npar, &flag, &iflag, out.as_mut_ptr())
                }
                Entry::FortranPlain(f) => f(&self.id, &time, par, &npar, &iflag, out.as_mut_ptr()),
                Entry::CFlagged(f) => f(&head, time, flag, iflag, out.as_mut_ptr()),
                Entry::CPlain(f) => f(&head, time, iflag, out.as_mut_ptr()),
            }
        }
        out[self.component]
    }

    /// One call inside a frame: TIME is read (and perturbed) like any other quantity.
    fn call(
        &self,
        params: &[f64],
        env: &dyn Env,
        gradient: bool,
        perturb: Option<(Key, f64)>,
        flag: c_int,
        iflag: c_int,
    ) -> Result<(f64, Vec<(Key, Dual)>), EvalError> {
        let (value, frame) = with_frame(env, gradient, perturb, || {
            let time = read(Key::Time).unwrap_or(env.time());
            self.invoke(time, params, flag, iflag)
        });
        if let Some(msg) = frame.stop {
            return Err(EvalError::new(
                EvalErrorKind::UserSubroutine,
                format!(
                    "{} of {}: {} at time {}: {msg}",
                    self.symbol,
                    self.element,
                    linkage_expr::user::STOP,
                    env.time()
                ),
            ));
        }
        if let Some(why) = frame.failure {
            return Err(EvalError::invalid_argument(format!(
                "{} of {}: {why}",
                self.symbol, self.element
            )));
        }
        if !value.is_finite() {
            return Err(EvalError::domain(format!(
                "{} of {} returned {value}",
                self.symbol, self.element
            )));
        }
        Ok((value, frame.reads))
    }

    /// The IFLAG pass, once: the subroutine declares what it reads (Adams calls it with IFLAG
    /// true before any evaluation); its result is not used.
    fn initialise(&self, params: &[f64], env: &dyn Env) -> Result<(), EvalError> {
        if !self.initialised.swap(true, Ordering::AcqRel) {
            self.call(params, env, false, None, 0, 1)?;
        }
        Ok(())
    }

    fn flag_for_value(&self) -> c_int {
        0
    }
}

impl UserRoutine for Linked {
    /// The value; with `gradient`, the partials by central differences of the subroutine with
    /// respect to each quantity it read (DFLAG set on those calls), chained with that
    /// quantity's gradient: ∂f/∂x = Σ_q (∂f/∂q)·∂q/∂x.
    fn evaluate(&self, params: &[f64], env: &dyn Env, gradient: bool) -> Result<Dual, EvalError> {
        self.initialise(params, env)?;
        let flag = self.flag_for_value();
        let (f0, reads) = self.call(params, env, gradient, None, flag, 0)?;
        if !gradient {
            return Ok(Dual::constant(f0));
        }
        let dflag = if self.kind == Kind::Motsub { 0 } else { 1 };
        let mut grad = Vec::new();
        for (key, q) in reads.iter().filter(|(_, q)| !q.is_constant()) {
            let h = DIFFERENCE_STEP * q.value().abs().max(1.0);
            let (up, _) = self.call(params, env, false, Some((key.clone(), h)), dflag, 0)?;
            let (down, _) = self.call(params, env, false, Some((key.clone(), -h)), dflag, 0)?;
            let slope = (up - down) / (2.0 * h);
            grad.extend(q.gradient().iter().map(|&(i, g)| (i, slope * g)));
        }
        Ok(Dual::new(f0, grad))
    }

    /// A MOTSUB's displacement, velocity and acceleration (IORD = 0, 1, 2).
    fn series(&self, params: &[f64], env: &dyn Env) -> Result<[f64; 3], EvalError> {
        if self.kind != Kind::Motsub || self.kind.shape() != Shape::Flagged {
            return Err(EvalError::not_time_only(self.kind.name()));
        }
        self.initialise(params, env)?;
        let mut out = [0.0; 3];
        for (iord, v) in out.iter_mut().enumerate() {
            *v = self.call(params, env, false, None, iord as c_int, 0)?.0;
        }
        Ok(out)
    }

    fn describe(&self) -> String {
        format!(
            "{} ({}) in {}",
            self.kind.name(),
            self.symbol,
            self.library.display()
        )
    }
}
