//! The corrector both integrators share: the step's state ([`Step`]), the buffers of a step
//! ([`Workspace`]) and the modified-Newton iteration on the accelerations and multipliers
//! ([`correct`]). What differs between HHT-α and BDF is only how positions and velocities
//! follow from the accelerations (a placement closure) and the coefficients in [`Scheme`].

use crate::constraints::drivers::MotionError;
use crate::constraints::rows::{RowGradient, Velocities};
use crate::constraints::system::RowUnit;
use crate::kernel::error::{IntegrationError, SingularSolve};
use crate::kernel::matrix::{Iterate, IterationMatrix, MatrixCoefficients};
use crate::kernel::output::ConsistentSolve;
use crate::kernel::problem::{unflat_into, Problem};
use crate::physics::mass::{self, SingularInertia};
use crate::state::State;
use crate::tolerances::{
    CORRECTOR_ACCELERATION_MIN, CORRECTOR_CONSTRAINT, CORRECTOR_ERROR_FRACTION, CORRECTOR_NOISE,
    CORRECTOR_RELATIVE, CORRECTOR_ROUNDING, MATRIX_REFRESH_RATE, MATRIX_REUSE_BACKOFF,
};
use glam::DVec3;
use linkage_model::frames::exp_so3;
use linkage_model::settings::IntegratorSettings;

/// The weight of coordinate `i` (6 per part) in the convergence test and the error estimate:
/// `1/length` for translations (so they count relative to the characteristic length), 1 for
/// rotations (radians).
#[inline]
pub(super) fn reciprocal_length_weight(i: usize, length: f64) -> f64 {
    if i % 6 < 3 {
        1.0 / length
    } else {
        1.0
    }
}

/// What one step of size h may leave undone, in the error test's scaling (translations over
/// the characteristic length, rotations in radians): the bound of its local truncation-error
/// estimate, and what the corrector may leave unconverged in its positions and velocities.
///
/// The corrector's allowance is the step's share of ERROR over the run, `s = ERROR·h/T` (T the
/// run's span; at least the rounding floor), times [`CORRECTOR_ERROR_FRACTION`]: positions
/// `f·s`, velocities `f·s/T`. A velocity left wrong by δv is a state of its own (the BDF
/// carries the velocities' history, HHT's velocity update its last value): it moves the
/// positions by up to δv·T over the rest of the run, so the allowances of all steps add up to
/// `f·ERROR` of position error whatever the number of steps. An allowance per step (as
/// before issue 31) accepted corrections whose velocity error did not shrink with the step,
/// so capping the step (HMAX) multiplied the accepted error by the number of steps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepTolerance {
    /// Bound of the local error estimate (BDF: `s`; HHT: ERROR, as in Adams).
    pub local: f64,
    /// What the corrector may leave in the positions …
    pub position: f64,
    /// … and in the velocities (per time unit).
    pub velocity: f64,
}

impl StepTolerance {
    /// The tolerances of a step of size `h` in a run of span `span` with INTEGRATOR ERROR
    /// `error`: the local error bound is the step's share `error·h/span` (at least `floor`)
    /// when `per_run` (BDF), `error` otherwise (HHT).
    pub fn new(error: f64, per_run: bool, h: f64, span: f64, floor: f64) -> StepTolerance {
        let share = (error * h / span).max(floor);
        StepTolerance {
            local: if per_run { share } else { error },
            position: CORRECTOR_ERROR_FRACTION * share,
            velocity: CORRECTOR_ERROR_FRACTION * share / span,
        }
    }
}

/// Integrator state at one time.
#[derive(Clone, Debug)]
pub(super) struct Step {
    /// Positions and the time.
    pub s: State,
    /// Velocities and accelerations, 6 per part (CM then angular, ground axes).
    pub v: Vec<f64>,
    pub a: Vec<f64>,
    /// `Jᵀλ − Q` at the step (mass × acceleration units).
    pub force_term: Vec<f64>,
    pub lambda: Vec<f64>,
}

impl Step {
    /// `Jᵀλ − Q` (mass × acceleration units) at this step's positions, velocities and
    /// multipliers, into `force_term`. Leaves the velocities as pairs in `w.twists` and the
    /// rows' gradients at `s` in `w.grads`.
    pub fn evaluate(&mut self, p: &Problem, w: &mut Workspace) -> Result<(), IntegrationError> {
        unflat_into(&self.v, &mut w.twists);
        p.gradients(&self.s, &mut w.grads);
        p.generalized_into(&self.s, &w.twists, &mut w.force_state, &mut w.q)?;
        let ucf = p.model.ucf();
        for (o, q) in self.force_term.iter_mut().zip(&w.q) {
            *o = -q;
        }
        for (g, l) in w.grads.iter().zip(&self.lambda) {
            for (body, b) in &g.blocks {
                let out = &mut self.force_term[6 * body..6 * body + 6];
                for (o, x) in out.iter_mut().zip(b) {
                    *o += ucf * l * x;
                }
            }
        }
        Ok(())
    }
}

/// Buffers of the corrector and of the consistent outputs, sized once per problem: a step
/// allocates nothing itself.
pub(super) struct Workspace {
    /// Drive values of the rows at the step's time (m).
    pub drives: Vec<f64>,
    /// Residual `[r₁; r₂; r₃]`, then the Newton correction (6n + m + nx: r₃ the control
    /// states' equations).
    pub rhs: Vec<f64>,
    /// Velocities as (CM, angular) pairs for the force elements (n).
    pub twists: Vec<(DVec3, DVec3)>,
    /// `UCF·Q` (6n).
    pub q: Vec<f64>,
    /// Gradients of the independent rows at the current iterate (m).
    pub grads: Vec<RowGradient>,
    /// The state force elements see when time is frozen.
    pub force_state: State,
    /// The scaled iteration matrix.
    pub matrix: IterationMatrix,
    /// `[M, Jᵀ; J, 0]` of the consistent velocity and acceleration solves.
    pub output: ConsistentSolve,
    /// Corrector iterations and iteration-matrix factorisations so far.
    pub newton_iterations: usize,
    pub factorisations: usize,
    /// How many coming steps refactorise at their first iteration instead of trying the
    /// previous step's matrix, and the length of that run after the next failure of a kept
    /// matrix (doubling, up to [`MATRIX_REUSE_BACKOFF`]; 0 once a kept matrix converged).
    refresh_first: usize,
    backoff: usize,
}

impl Workspace {
    /// Buffers for `p`, and the iteration matrix's pattern found by assembling it at `start`
    /// with velocities `v0` (n of them; see [`IterationMatrix::with_pattern`]).
    pub fn new(
        p: &Problem,
        start: &State,
        v0: &Velocities,
        coefficients: impl Fn(f64) -> MatrixCoefficients,
    ) -> Result<Workspace, IntegrationError> {
        let (n, m) = (p.n(), p.rows.len());
        let matrix = IterationMatrix::with_pattern(p, start, v0, coefficients)?;
        Ok(Workspace {
            drives: vec![0.0; m],
            rhs: vec![0.0; 6 * n + m + p.controls()],
            twists: v0.to_vec(),
            q: vec![0.0; 6 * n],
            grads: vec![RowGradient::default(); m],
            force_state: start.clone(),
            newton_iterations: 0,
            factorisations: 0,
            refresh_first: 0,
            backoff: 0,
            matrix,
            output: ConsistentSolve::new(p, start, SingularInertia::Regularise)?,
        })
    }
}

/// How a method's positions and velocities respond to its accelerations within one step.
#[derive(Clone, Copy, Debug)]
pub(super) struct Scheme {
    /// `∂q/∂a`: `βh²` for HHT-α, `(h/c₀)²` for BDF. The position constraints are scaled by
    /// its reciprocal.
    pub position: f64,
    /// `∂v/∂a`: `γh` for HHT-α, `h/c₀` for BDF.
    pub velocity: f64,
    /// The iteration matrix's coefficients (the step size the matrix is kept for is `h`).
    pub matrix: MatrixCoefficients,
    /// HHT's α (0 for BDF): forces and inertia are taken at `t_{n+1} + αh`.
    pub alpha: f64,
    /// SI2: the iteration holds the velocity constraints `J v + Φ_t = 0` (scaled by
    /// `1/velocity`), and the positions are then projected onto `Φ = 0` by [`project`]; I3
    /// (false): the position constraints (scaled by `1/position`).
    pub stabilised: bool,
}

/// Newton iteration on `trial`'s accelerations and multipliers for the step of size `h` from
/// `cur` (allowed a local error `tolerance`), with the scheme's positions and velocities set by `place(trial)` from
/// `trial.a`:
///
/// ```text
/// r₁ = M_{n+1+α} a + (1+α)(Jᵀλ − Q)_{n+1} − α(Jᵀλ − Q)_n = 0,    r₂ = Φ(q_{n+1}) / position = 0
/// ```
///
/// and the control states' equations `r₃ = r(q, v, x, ẋ, t_{n+1}) = 0`
/// ([`crate::physics::controls`]) for their rates ẋ, with the states placed by the scheme
/// from them (`∂x/∂ẋ` = `velocity`: the BDF formula, or HHT's `x = x_n + h((1−γ)ẋ_n + γẋ)`)
///
/// (`M_{n+1+α} = (1+α) M_{n+1} − α M_n`: the inertia about ground axes turns with the part, and
/// the accelerations of HHT belong to the shifted time; with `M_{n+1}` alone 3-D rotation would
/// be only first order). Modified Newton: the matrix is kept across iterations and steps, and
/// refreshed when there is none, when the step size is more than a factor 2 away from the one
/// it was built for, when the last correction contracted by less than `MATRIX_REFRESH_RATE`,
/// or when three iterations with a matrix from an earlier step did not converge. A kept matrix
/// that failed so makes the next steps refactorise at their first iteration (1, 2, 4, … up to
/// `MATRIX_REUSE_BACKOFF` steps after successive failures) before trying a kept one again: where
/// the matrix changes fast from step to step (IFToMM A02, a chain of 40 loops) the kept matrix
/// only costs two wasted iterations per step. Leaves
/// `trial` placed and evaluated at the converged accelerations.
#[allow(clippy::too_many_arguments)]
pub(super) fn correct(
    p: &Problem,
    settings: &IntegratorSettings,
    w: &mut Workspace,
    cur: &Step,
    trial: &mut Step,
    h: f64,
    tolerance: StepTolerance,
    scheme: Scheme,
    mut place: impl FnMut(&mut Step),
) -> Result<(), IntegrationError> {
    let Scheme {
        position,
        velocity,
        alpha,
        stabilised,
        ..
    } = scheme;
    let n6 = 6 * p.n();
    let m = p.rows.len();
    let nx = p.controls();
    let ucf = p.model.ucf();
    let length = p.model.characteristic_length;
    p.drives_into(cur.s.time + h, &mut w.drives)?;
    let mut converged = false;
    let mut da_prev = f64::INFINITY;
    // Contraction of the last correction relative to the one before (0: none yet).
    let mut rate = 0.0f64;
    // Whether the matrix was factorised during this step.
    let mut fresh = false;
    for it in 0..settings.maxit {
        w.newton_iterations += 1;
        place(trial);
        trial.evaluate(p, w)?;
        let (r1, r2) = w.rhs.split_at_mut(n6);
        for (k, part) in p.model.parts.iter().enumerate() {
            let mut ig = mass::ground_inertia(part, &trial.s.poses[k]);
            if alpha != 0.0 {
                ig = ig * (1.0 + alpha) - mass::ground_inertia(part, &cur.s.poses[k]) * alpha;
            }
            let a = &trial.a[6 * k..6 * k + 6];
            let ang = ig * DVec3::new(a[3], a[4], a[5]);
            for c in 0..3 {
                r1[6 * k + c] = part.mass * a[c];
                r1[6 * k + 3 + c] = ang[c];
            }
        }
        if !p.coupling.is_empty() {
            p.coupling.add_product(&trial.s, &trial.a, 1.0 + alpha, r1);
            if alpha != 0.0 {
                p.coupling.add_product(&cur.s, &trial.a, -alpha, r1);
            }
        }
        for ((r, ft), ft0) in r1.iter_mut().zip(&trial.force_term).zip(&cur.force_term) {
            *r += (1.0 + alpha) * ft - alpha * ft0;
        }
        // Position constraints to the assembly accuracy; they see the analysis time (frozen
        // when settling).
        let mut phi_ok = true;
        let constrained = p.force_state(&trial.s, &mut w.force_state);
        for (k, ((r, &row), &drive)) in r2.iter_mut().zip(p.rows).zip(&w.drives).enumerate() {
            // I3: Φ; SI2: the velocity constraint's residual times the step's `∂v/∂a`,
            // which is the drift of Φ it causes over the step (both in position units).
            let raw = if stabilised {
                let target = velocity_target(p, row, constrained)?;
                (w.grads[k].rate(&w.twists) - target) * velocity
            } else {
                p.sys.residual(row, constrained, drive)
            };
            *r = raw / position;
            phi_ok &= raw.abs() <= constraint_limit(p, row, length);
        }
        if nx > 0 {
            let fs = p.force_state(&trial.s, &mut w.force_state);
            p.forces
                .control_residuals(fs, &w.twists, &mut w.rhs[n6 + m..])?;
        }
        let kept_failed = it > 0 && !fresh && (rate > MATRIX_REFRESH_RATE || it >= 3);
        if kept_failed {
            w.backoff = (2 * w.backoff).clamp(1, MATRIX_REUSE_BACKOFF);
            w.refresh_first = w.backoff;
        }
        let first_fresh = it == 0 && w.refresh_first > 0;
        if first_fresh {
            w.refresh_first -= 1;
        }
        let stale = w.matrix.h.is_none_or(|hh| h > 2.0 * hh || h < 0.5 * hh)
            || rate > MATRIX_REFRESH_RATE
            || (it >= 3 && !fresh)
            || first_fresh;
        if stale {
            w.matrix.h = None;
            let at = Iterate {
                s: &trial.s,
                v: &w.twists,
                grads: &w.grads,
                lambda: &trial.lambda,
            };
            w.matrix.refresh(p, &at, scheme.matrix)?;
            w.matrix.h = Some(h);
            w.factorisations += 1;
            fresh = true;
        }
        for x in w.rhs.iter_mut() {
            *x = -*x;
        }
        w.matrix
            .lu
            .solve_in_place(&mut w.rhs)
            .map_err(|_| IntegrationError::Singular(SingularSolve::Newton))?;
        let amax = (0..n6)
            .map(|i| trial.a[i].abs() * reciprocal_length_weight(i, length))
            .fold(0.0, f64::max);
        let mut da = 0.0f64;
        for i in 0..n6 {
            trial.a[i] += w.rhs[i];
            da = da.max(w.rhs[i].abs() * reciprocal_length_weight(i, length));
        }
        for (l, d) in trial.lambda.iter_mut().zip(&w.rhs[n6..n6 + m]) {
            *l += d / ucf;
        }
        // The control rates; their states move by `velocity` times as much, weighed
        // absolutely below 1 and relatively above.
        let mut dx = 0.0f64;
        let c = &mut trial.s.controls;
        for ((xd, x), d) in c.xdot.iter_mut().zip(&c.x).zip(&w.rhs[n6 + m..]) {
            *xd += d;
            dx = dx.max(velocity * d.abs() / x.abs().max(1.0));
        }
        let states_ok = dx <= tolerance.position.max(CORRECTOR_ROUNDING);
        // Converged when the constraints hold and the correction's effect on the step is within
        // the corrector's allowance (see [`StepTolerance`]): on the positions directly and, for
        // the rest of the run, through the velocities. A test relative to the accelerations
        // (`|Δa| ≤ 1e-8·|a|`, before issue 31) left a velocity error of the same sign at every
        // step, which capped steps multiplied: a cart with an inverted pendulum in millimetres
        // ended 20 % of its velocity's range off at ERROR = 1e-7 with HMAX = 1e-4 (3e-9 now).
        // A correction that no longer contracts (at least halving) with a matrix built during
        // this step, or is still there at the last iteration MAXIT allows, is noise, and the iterate is as converged as the arithmetic allows (noise
        // has no sign to accumulate) when the correction moves the positions by less than a
        // tenth of the constraint tolerance or is below `CORRECTOR_RELATIVE` of the
        // accelerations: coordinates far from the origin resolve positions to ε·|x| only, and
        // the scaled matrix turns that into corrections of ε·|x|/position in the
        // accelerations; near a singular pose (IFToMM A02's flat chain) the multipliers
        // amplify it further.
        let moved = position * da;
        let noise = moved <= CORRECTOR_NOISE
            || da <= CORRECTOR_RELATIVE * amax.max(CORRECTOR_ACCELERATION_MIN);
        let stagnant = noise && ((fresh && da >= 0.5 * da_prev) || it + 1 == settings.maxit);
        let negligible = position * da <= tolerance.position && velocity * da <= tolerance.velocity;
        if phi_ok && states_ok && (negligible || stagnant) {
            converged = true;
            if !fresh {
                // The kept matrix did the job: keep trying it first.
                w.backoff = 0;
            }
            break;
        }
        // The rate compares two corrections made with the same matrix.
        rate = if !stale && da_prev.is_finite() && da_prev > 0.0 {
            da / da_prev
        } else {
            0.0
        };
        da_prev = da;
    }
    if !converged {
        return Err(IntegrationError::CorrectorNotConverged {
            iterations: settings.maxit,
            time: cur.s.time + h,
        });
    }
    // Final positions, velocities and force term from the converged accelerations.
    place(trial);
    if stabilised {
        project(p, settings, w, trial, position, tolerance)?;
    }
    trial.evaluate(p, w)
}

/// The velocities of `trial` (placed and evaluated: `w.grads` and `w.twists` are its) moved
/// onto the velocity constraints `J v = ḟ − ∂Φ/∂t` with the factorised iteration matrix:
/// `[M + …, Jᵀ; J, 0] [Δv; μ] = [0; −(J v − target)]`, so `J Δv` cancels the violation and
/// `Δv` is the least change in the matrix's (mass-like) norm; then evaluated again. HHT with
/// α near 0 needs it (see [`super::integrator`]): its index-3 form leaves the velocity
/// violation `u` alternating undamped from step to step, fed by the corrector's tolerance.
pub(super) fn project_velocities(
    p: &Problem,
    w: &mut Workspace,
    trial: &mut Step,
) -> Result<(), IntegrationError> {
    let n6 = 6 * p.n();
    w.rhs.fill(0.0);
    let constrained = p.force_state(&trial.s, &mut w.force_state);
    for (k, &row) in p.rows.iter().enumerate() {
        let target = velocity_target(p, row, constrained)?;
        w.rhs[n6 + k] = target - w.grads[k].rate(&w.twists);
    }
    w.matrix
        .lu
        .solve_in_place(&mut w.rhs)
        .map_err(|_| IntegrationError::Singular(SingularSolve::Newton))?;
    for (v, d) in trial.v.iter_mut().zip(&w.rhs[..n6]) {
        *v += d;
    }
    trial.evaluate(p, w)
}

/// The corrector's bound on a row's residual: `CORRECTOR_CONSTRAINT × L` for lengths,
/// `CORRECTOR_CONSTRAINT` for dot products and angles.
fn constraint_limit(p: &Problem, row: usize, length: f64) -> f64 {
    match p.sys.rows[row].unit {
        RowUnit::Length | RowUnit::Mixed => CORRECTOR_CONSTRAINT * length,
        _ => CORRECTOR_CONSTRAINT,
    }
}

/// The rate row `row`'s velocity constraint asks for: `J v = ḟ` for a motion (0 when time is
/// frozen), `J v = −∂Φ/∂t` for a row that depends on time explicitly.
fn velocity_target(p: &Problem, row: usize, s: &State) -> Result<f64, IntegrationError> {
    let r = &p.sys.rows[row];
    if r.driven {
        p.drive_series(r.element, s.time)
            .map(|f| f[1])
            .ok_or_else(|| MotionError::at(p.model, p.drivers, r.element, s.time).into())
    } else {
        p.sys
            .explicit_rate(row, s, p.time_rate())
            .map(|x| -x)
            .map_err(|e| p.row_error(row, &e))
    }
}

/// SI2's position projection: `trial`'s positions moved onto `Φ = 0`, velocities untouched
/// (the correction has its own multipliers: `q ← q + Δq` with
/// `[M + c_K K_T + c_C C_T, Jᵀ; J, 0] [Δq/position; ν] = [0; −Φ/position]`, the factorised
/// iteration matrix, so `J Δq = −Φ` with `Δq` of least kinetic-energy-like norm), repeated
/// until `Φ` is within the corrector's bound and the last move is negligible against the
/// step's allowed local error, at most MAXIT times. Leaves `w.grads` stale (the caller
/// evaluates the trial again).
fn project(
    p: &Problem,
    settings: &IntegratorSettings,
    w: &mut Workspace,
    trial: &mut Step,
    position: f64,
    tolerance: StepTolerance,
) -> Result<(), IntegrationError> {
    let n6 = 6 * p.n();
    let length = p.model.characteristic_length;
    for _ in 0..settings.maxit {
        let constrained = p.force_state(&trial.s, &mut w.force_state);
        let mut within = true;
        w.rhs[..n6].fill(0.0);
        for ((r, &row), &drive) in w.rhs[n6..].iter_mut().zip(p.rows).zip(&w.drives) {
            let raw = p.sys.residual(row, constrained, drive);
            within &= raw.abs()
                <= tolerance.position.max(CORRECTOR_ROUNDING)
                    * if matches!(p.sys.rows[row].unit, RowUnit::Length | RowUnit::Mixed) {
                        length
                    } else {
                        1.0
                    };
            *r = -raw / position;
        }
        if within {
            return Ok(());
        }
        w.matrix
            .lu
            .solve_in_place(&mut w.rhs)
            .map_err(|_| IntegrationError::Singular(SingularSolve::Newton))?;
        for (k, pose) in trial.s.poses.iter_mut().enumerate() {
            let d = &w.rhs[6 * k..6 * k + 6];
            pose.p += DVec3::new(d[0], d[1], d[2]) * position;
            pose.r = exp_so3(DVec3::new(d[3], d[4], d[5]) * position) * pose.r;
        }
    }
    let worst = p
        .rows
        .iter()
        .zip(&w.drives)
        .map(|(&row, &drive)| {
            p.sys
                .residual(row, p.force_state(&trial.s, &mut w.force_state), drive)
                .abs()
                / constraint_limit(p, row, length)
        })
        .fold(0.0, f64::max);
    if worst <= 1.0 {
        Ok(())
    } else {
        Err(IntegrationError::CorrectorNotConverged {
            iterations: settings.maxit,
            time: trial.s.time,
        })
    }
}
