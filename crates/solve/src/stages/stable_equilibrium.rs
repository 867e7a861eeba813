//! The static analysis's search for a stable equilibrium: Adams' modified Newton–Raphson with
//! the EQUILIBRIUM settings first, then, when it does not converge or converges to an unstable
//! equilibrium, the descent ([`crate::stages::statics::Solver::descend`]: pseudo-transient
//! continuation steered by the lowest mode, kicked off unstable equilibria), then damped
//! settling with damping chosen from the model ([`crate::stages::settle`]). Each path is tried
//! only when the one before it failed; the search says which one found the equilibrium.
//!
//! A Newton iteration that runs away along a free motion nothing resists (`unbounded`: a body
//! falling, a block sliding down a ramp steeper than its friction angle) has no equilibrium to
//! find: the search stops there with that reason.

use crate::pipeline::Assembled;
use crate::stages::settle::{settle_until, SettleOutcome};
use crate::stages::statics::{Equilibrium, Solver, StaticsError};
use crate::state::State;

/// Which path found an equilibrium (or was tried).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Path {
    /// Adams' modified Newton–Raphson with the EQUILIBRIUM settings.
    Newton,
    /// Pseudo-transient continuation downhill from the input or off an unstable equilibrium.
    Descent,
    /// Damped dynamics, then a Newton polish.
    Settling,
}

impl Path {
    /// `newton`, `descent`, `settling`.
    pub fn name(self) -> &'static str {
        match self {
            Path::Newton => "newton",
            Path::Descent => "descent",
            Path::Settling => "settling",
        }
    }
}

/// One path tried.
#[derive(Clone, Debug, PartialEq)]
pub struct Attempt {
    pub path: Path,
    /// Newton iterations, descent steps, or settling outputs integrated.
    pub iterations: usize,
    /// Whether it ended at an equilibrium, and that equilibrium's stability (`None`: not
    /// evaluated).
    pub converged: bool,
    pub stable: Option<bool>,
    /// What happened, in a few words (`converged to an unstable equilibrium`, the failure).
    pub outcome: String,
}

/// What the search found.
#[derive(Debug)]
pub struct Search {
    /// The equilibrium accepted; otherwise the first Newton solve (whose failure, or
    /// unstable equilibrium, the report states).
    pub result: Result<Equilibrium, StaticsError>,
    /// The path that gave `result`.
    pub path: Path,
    /// Every path tried, in order.
    pub attempts: Vec<Attempt>,
    /// The settling, when it was tried.
    pub settling: Option<SettleOutcome>,
    /// The model has no equilibrium near: Newton ran away along a free motion nothing resists.
    pub no_equilibrium: bool,
}

impl Search {
    /// Whether `result` is an equilibrium the search accepts (converged; stable unless
    /// `allow_unstable`).
    pub fn found(&self, allow_unstable: bool) -> bool {
        accepted(&self.result, allow_unstable)
    }
}

fn accepted(r: &Result<Equilibrium, StaticsError>, allow_unstable: bool) -> bool {
    r.as_ref()
        .is_ok_and(|e| e.converged && (allow_unstable || e.stability.is_none_or(|s| s.0)))
}

fn attempt(path: Path, r: &Result<Equilibrium, StaticsError>, iterations: usize) -> Attempt {
    let (converged, stable, outcome) = match r {
        Ok(e) if e.converged => (
            true,
            e.stability.map(|s| s.0),
            match e.stability {
                Some((false, _)) => "converged to an unstable equilibrium".to_string(),
                Some((true, _)) => "converged to a stable equilibrium".to_string(),
                None => "converged".to_string(),
            },
        ),
        Ok(e) if e.unbounded => (
            false,
            None,
            "ran away along an unresisted free motion".into(),
        ),
        Ok(e) => (
            false,
            None,
            format!("did not converge in {} iterations", e.iterations),
        ),
        Err(err) => (false, None, err.to_string()),
    };
    Attempt {
        path,
        iterations,
        converged,
        stable,
        outcome,
    }
}

/// Searches for a stable equilibrium of `a` from `start` (module docs). With
/// `allow_unstable`, Newton's first equilibrium is accepted whatever its stability. Settling
/// integrates from the assembled configuration and stops between two steps when `stop_now`
/// says so.
pub fn search(
    a: &Assembled,
    start: &State,
    allow_unstable: bool,
    stop_now: &dyn Fn() -> bool,
) -> Search {
    let solver = Solver {
        model: a.model,
        sys: &a.system,
        rows: &a.kept,
        drivers: &a.drivers,
        forces: a.forces,
        settings: &a.model.equilibrium,
    };
    let newton = solver.newton(start);
    let iterations = newton.as_ref().map_or(0, |e| e.iterations);
    let mut attempts = vec![attempt(Path::Newton, &newton, iterations)];
    let done = |result, path, attempts, settling, no_equilibrium| Search {
        result,
        path,
        attempts,
        settling,
        no_equilibrium,
    };
    let unbounded = newton.as_ref().is_ok_and(|e| !e.converged && e.unbounded);
    let input_error = matches!(
        newton,
        Err(StaticsError::Motion(_) | StaticsError::Force(_) | StaticsError::Sensor(_))
    );
    if accepted(&newton, allow_unstable) || input_error {
        return done(newton, Path::Newton, attempts, None, false);
    }
    let unstable = newton.as_ref().ok().filter(|e| e.converged);
    let mut descent_unbounded = false;
    match solver.descend(start, unstable) {
        Ok(Some(d)) => {
            descent_unbounded = d.equilibrium.unbounded;
            let r = Ok(d.equilibrium);
            attempts.push(attempt(Path::Descent, &r, d.steps));
            if accepted(&r, false) {
                return done(r, Path::Descent, attempts, None, false);
            }
        }
        Ok(None) => attempts.push(Attempt {
            path: Path::Descent,
            iterations: 0,
            converged: false,
            stable: None,
            outcome: "not tried: the modes of the free motions cannot be computed (more than DESCENT_MAX_DIM part coordinates, or a force Jacobian that cannot be evaluated)".into(),
        }),
        Err(e) => attempts.push(attempt(Path::Descent, &Err(e), 0)),
    }
    // Newton ran away along a free motion, and so did the Newton solve where the descent
    // ended: the loads act along a motion nothing resists, where damped dynamics would only
    // fall for ever.
    if unbounded && descent_unbounded {
        return done(newton, Path::Newton, attempts, None, true);
    }
    let Ok(settled) = settle_until(a, |_| {}, stop_now) else {
        return done(newton, Path::Newton, attempts, None, false);
    };
    let r = match (&settled.equilibrium, settled.settled_equilibrium()) {
        (_, Some(e)) => Ok(e.clone()),
        (Some(Err(e)), _) => Err(e.clone()),
        _ => Err(StaticsError::NotSettled(
            settled
                .failure(a.model, &a.system)
                .unwrap_or_else(|| "the model did not settle".into()),
        )),
    };
    let mut tried = attempt(Path::Settling, &r, 0);
    tried.iterations = settled
        .equilibrium
        .as_ref()
        .map_or(0, |e| e.as_ref().map_or(0, |e| e.iterations));
    attempts.push(tried);
    if accepted(&r, false) {
        return done(r, Path::Settling, attempts, Some(settled), false);
    }
    done(newton, Path::Newton, attempts, Some(settled), false)
}
