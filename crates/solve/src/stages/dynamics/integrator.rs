//! The HHT-α integrator of a [`Problem`]: one step (predictor, modified-Newton corrector,
//! local error estimate) on the part configuration manifold, with every buffer it needs
//! allocated once (module docs of [`super`]).

use super::error::{IntegrationError, SingularSolve};
use super::hht::Hht;
use super::matrix::{Iterate, IterationMatrix};
use super::output::{ConsistentSolve, Output};
use super::problem::{flat, padded, unflat_into, Problem};
use crate::constraints::rows::{RowGradient, Velocities};
use crate::constraints::system::RowUnit;
use crate::physics::mass::{self, SingularInertia};
use crate::state::State;
use crate::tolerances::{
    CORRECTOR_ACCELERATION_FLOOR, CORRECTOR_ACCELERATION_MIN, CORRECTOR_CONSTRAINT,
    CORRECTOR_ERROR_FRACTION, CORRECTOR_NOISE, CORRECTOR_RELATIVE, CORRECTOR_ROUNDING,
    MATRIX_REFRESH_RATE,
};
use glam::DVec3;
use linkage_model::settings::IntegratorSettings;

/// The weight of coordinate `i` (6 per part) in the convergence test and the error estimate:
/// `1/length` for translations (so they count relative to the characteristic length), 1 for
/// rotations (radians).
#[inline]
fn reciprocal_length_weight(i: usize, length: f64) -> f64 {
    if i % 6 < 3 {
        1.0 / length
    } else {
        1.0
    }
}

/// Integrator state at one time.
#[derive(Clone, Debug)]
struct Step {
    /// Positions and the time.
    s: State,
    /// Velocities and accelerations, 6 per part (CM then angular, ground axes).
    v: Vec<f64>,
    a: Vec<f64>,
    /// `Jᵀλ − Q` at the step (mass × acceleration units), for the HHT α term.
    force_term: Vec<f64>,
    lambda: Vec<f64>,
}

impl Step {
    /// Positions and velocities of the step of size `h` from `from` with accelerations
    /// `self.a`:
    /// `q = q_n ⊕ (h v_n + h²/2 ((1−2β) a_n + 2β a))`, `v = v_n + h((1−γ) a_n + γ a)`.
    fn place(&mut self, from: &Step, h: f64, hht: Hht) {
        let Hht { beta, gamma, .. } = hht;
        self.s.poses.copy_from_slice(&from.s.poses);
        self.s.time = from.s.time + h;
        for k in 0..self.s.poses.len() {
            let d = |i: usize| {
                let i = 6 * k + i;
                h * from.v[i]
                    + h * h / 2.0 * ((1.0 - 2.0 * beta) * from.a[i] + 2.0 * beta * self.a[i])
            };
            self.s.increment(
                k,
                DVec3::new(d(0), d(1), d(2)),
                DVec3::new(d(3), d(4), d(5)),
            );
        }
        for ((v, (v0, a0)), a) in self
            .v
            .iter_mut()
            .zip(from.v.iter().zip(&from.a))
            .zip(&self.a)
        {
            *v = v0 + h * ((1.0 - gamma) * a0 + gamma * a);
        }
    }

    /// `Jᵀλ − Q` (mass × acceleration units) at this step's positions, velocities and
    /// multipliers, into `force_term`. Leaves the velocities as pairs in `w.twists` and the
    /// rows' gradients at `s` in `w.grads`.
    fn evaluate(&mut self, p: &Problem, w: &mut Workspace) -> Result<(), IntegrationError> {
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
/// allocates nothing itself (see [`Integrator`] for what the force elements may allocate).
struct Workspace {
    /// Drive values of the rows at the step's time (m).
    drives: Vec<f64>,
    /// Residual `[r₁; r₂]`, then the Newton correction (6n + m).
    rhs: Vec<f64>,
    /// Velocities as (CM, angular) pairs for the force elements (n).
    twists: Vec<(DVec3, DVec3)>,
    /// `UCF·Q` (6n).
    q: Vec<f64>,
    /// Gradients of the independent rows at the current iterate (m).
    grads: Vec<RowGradient>,
    /// The state force elements see when time is frozen.
    force_state: State,
    /// The scaled iteration matrix.
    matrix: IterationMatrix,
    /// `[M, Jᵀ; J, 0]` of the consistent velocity and acceleration solves.
    output: ConsistentSolve,
    /// Corrector iterations and iteration-matrix factorisations so far.
    newton_iterations: usize,
    factorisations: usize,
}

impl Workspace {
    /// Buffers for `p`, and the iteration matrix's pattern found by assembling it at `start`
    /// with velocities `v0` (n of them; see [`IterationMatrix::with_pattern`]).
    fn new(
        p: &Problem,
        start: &State,
        v0: &Velocities,
        hht: Hht,
    ) -> Result<Workspace, IntegrationError> {
        let (n, m) = (p.n(), p.rows.len());
        let matrix = IterationMatrix::with_pattern(p, start, v0, |h| hht.matrix_coefficients(h))?;
        Ok(Workspace {
            drives: vec![0.0; m],
            rhs: vec![0.0; 6 * n + m],
            twists: v0.to_vec(),
            q: vec![0.0; 6 * n],
            grads: vec![RowGradient::default(); m],
            force_state: start.clone(),
            newton_iterations: 0,
            factorisations: 0,
            matrix,
            output: ConsistentSolve::new(p, start, SingularInertia::Regularise)?,
        })
    }
}

/// The HHT-α integrator of a [`Problem`]: the current step, a trial step and every buffer
/// the corrector needs, allocated once ([`Integrator::new`]).
///
/// Allocation: [`Integrator::try_step`] and [`Integrator::accept`] allocate nothing
/// themselves once the iteration matrix's pattern has been found (the first factorisation,
/// and again only if a new nonzero appears). What they call may:
/// - faer's numeric LU grows its L and U storage if partial pivoting ever produces more fill
///   than any earlier factorisation (amortised doubling);
/// - force elements: the generalised forces of elements without expressions (SPRINGDAMPER,
///   BUSHING, FIELD, BEAM) allocate nothing; expressions (SFORCE, VFORCE, VTORQUE, GFORCE,
///   VARIABLEs) allocate in the evaluator at every evaluation; force Jacobians, evaluated at
///   each matrix refresh only, use dual numbers whose gradients are heap vectors;
/// - motions given by expressions allocate in the evaluator.
///
/// Models without expressions and force elements (e.g. the generated chains) step without a
/// single allocation; `tests/allocations.rs` counts them.
pub struct Integrator<'p, 'a> {
    p: &'p Problem<'a>,
    settings: IntegratorSettings,
    hht: Hht,
    cur: Step,
    trial: Step,
    /// Accelerations and multipliers of the step before `cur`, and the size of the step from
    /// there to `cur` (`None` before the first step): the corrector's predictor.
    prev_a: Vec<f64>,
    prev_lambda: Vec<f64>,
    prev_h: Option<f64>,
    work: Workspace,
}

impl<'p, 'a> Integrator<'p, 'a> {
    /// Starts at `start` (assembled) with velocities `v0` (one per part; missing ones are
    /// zero), projected onto the velocity constraints; accelerations and multipliers from the
    /// constraint-consistent solve. Returns the integrator and the output at the start.
    pub fn new(
        p: &'p Problem<'a>,
        start: &State,
        v0: &Velocities,
        settings: &IntegratorSettings,
    ) -> Result<(Integrator<'p, 'a>, Output), IntegrationError> {
        if start.poses.len() != p.n() {
            return Err(IntegrationError::StartMismatch {
                state: start.poses.len(),
                model: p.n(),
            });
        }
        let v0 = padded(p, v0);
        let hht = Hht::new(settings.alpha);
        let mut work = Workspace::new(p, start, &v0, hht)?;
        let first = work.output.solve(p, start, &flat(&v0), &work.matrix)?;
        let mut cur = Step {
            s: start.clone(),
            v: flat(&first.output.velocities),
            a: flat(&first.output.accelerations),
            force_term: vec![0.0; 6 * p.n()],
            lambda: first.lambda,
        };
        cur.evaluate(p, &mut work)?;
        let trial = cur.clone();
        Ok((
            Integrator {
                p,
                settings: settings.clone(),
                hht,
                prev_a: cur.a.clone(),
                prev_lambda: cur.lambda.clone(),
                prev_h: None,
                cur,
                trial,
                work,
            },
            first.output,
        ))
    }

    /// Corrector iterations and iteration-matrix factorisations since the start.
    pub fn statistics(&self) -> (usize, usize) {
        (self.work.newton_iterations, self.work.factorisations)
    }

    /// Time of the current step.
    pub fn time(&self) -> f64 {
        self.cur.s.time
    }

    /// Positions at the current step.
    pub fn state(&self) -> &State {
        &self.cur.s
    }

    /// Velocities at the current step, 6 per part (CM velocity, angular velocity; ground).
    pub fn velocities(&self) -> &[f64] {
        &self.cur.v
    }

    /// Computes the step of size `h` from the current one (kept as the trial; see
    /// [`Integrator::accept`]) and returns its local error estimate
    /// `max_i h²|β − 1/6|·|a_{n+1} − a_n|_i` (translations over the characteristic length).
    /// An error (corrector not converged, singular matrix, a force or motion that cannot be
    /// evaluated) leaves the current step as it was and drops the iteration matrix.
    pub fn try_step(&mut self, h: f64) -> Result<f64, IntegrationError> {
        let r = self.corrector(h);
        if r.is_err() {
            self.work.matrix.h = None;
        }
        r
    }

    /// Makes the trial step (from the last successful [`Integrator::try_step`]) current.
    pub fn accept(&mut self) {
        self.prev_a.copy_from_slice(&self.cur.a);
        self.prev_lambda.copy_from_slice(&self.cur.lambda);
        self.prev_h = Some(self.trial.s.time - self.cur.s.time);
        std::mem::swap(&mut self.cur, &mut self.trial);
    }

    /// The output at the current step: velocities and accelerations made consistent with the
    /// constraints, reactions.
    pub fn output(&mut self) -> Result<Output, IntegrationError> {
        let w = &mut self.work;
        w.output
            .solve(self.p, &self.cur.s, &self.cur.v, &w.matrix)
            .map(|c| c.output)
    }

    /// Newton iteration of the HHT step (module docs) on the trial step.
    fn corrector(&mut self, h: f64) -> Result<f64, IntegrationError> {
        let Integrator {
            p,
            settings,
            hht,
            cur,
            trial,
            prev_a,
            prev_lambda,
            prev_h,
            work: w,
        } = self;
        let p: &Problem = p;
        let Hht { alpha, beta, .. } = *hht;
        let n6 = 6 * p.n();
        let ucf = p.model.ucf();
        let length = p.model.characteristic_length;
        let t1 = cur.s.time + h;
        p.drives_into(t1, &mut w.drives)?;
        // Predictor: accelerations and multipliers extrapolated linearly from the last two
        // steps (the ratio of step sizes capped at 2), or the current ones.
        let r = prev_h
            .filter(|hp| *hp > 0.0)
            .map_or(0.0, |hp| (h / hp).min(2.0));
        for ((x, now), before) in trial.a.iter_mut().zip(&cur.a).zip(prev_a.iter()) {
            *x = now + r * (now - before);
        }
        for ((x, now), before) in trial
            .lambda
            .iter_mut()
            .zip(&cur.lambda)
            .zip(prev_lambda.iter())
        {
            *x = now + r * (now - before);
        }
        let mut converged = false;
        let mut da_prev = f64::INFINITY;
        // Contraction of the last correction relative to the one before (0: none yet).
        let mut rate = 0.0f64;
        // Whether the matrix was factorised during this step.
        let mut fresh = false;
        for it in 0..settings.maxit {
            w.newton_iterations += 1;
            trial.place(cur, h, *hht);
            trial.evaluate(p, w)?;
            // Residuals: r₁ = M a + (1+α)(Jᵀλ − Q) − α(Jᵀλ − Q)_n, r₂ = Φ/(βh²).
            let (r1, r2) = w.rhs.split_at_mut(n6);
            for (k, part) in p.model.parts.iter().enumerate() {
                let ig = mass::ground_inertia(part, &trial.s.poses[k]);
                let a = &trial.a[6 * k..6 * k + 6];
                let ang = ig * DVec3::new(a[3], a[4], a[5]);
                for c in 0..3 {
                    r1[6 * k + c] = part.mass * a[c];
                    r1[6 * k + 3 + c] = ang[c];
                }
            }
            for ((r, ft), ft0) in r1.iter_mut().zip(&trial.force_term).zip(&cur.force_term) {
                *r += (1.0 + alpha) * ft - alpha * ft0;
            }
            // Position constraints to the assembly accuracy.
            let mut phi_ok = true;
            // The constraints see the analysis time (frozen when settling).
            let constrained = p.force_state(&trial.s, &mut w.force_state);
            for ((r, &row), &drive) in r2.iter_mut().zip(p.rows).zip(&w.drives) {
                let raw = p.sys.residual(row, constrained, drive);
                *r = raw / (beta * h * h);
                let limit = match p.sys.rows[row].unit {
                    RowUnit::Length | RowUnit::Mixed => CORRECTOR_CONSTRAINT * length,
                    _ => CORRECTOR_CONSTRAINT,
                };
                phi_ok &= raw.abs() <= limit;
            }
            // Modified Newton: the matrix is kept across iterations and steps, and refreshed
            // when there is none, when the step size is more than a factor 2 away from the
            // one it was built for, when the last correction contracted by less than
            // `MATRIX_REFRESH_RATE` (the matrix no longer describes the iterate well), or
            // when three iterations with a matrix from an earlier step did not converge.
            let stale = w.matrix.h.is_none_or(|hh| h > 2.0 * hh || h < 0.5 * hh)
                || rate > MATRIX_REFRESH_RATE
                || (it >= 3 && !fresh);
            if stale {
                w.matrix.h = None;
                let at = Iterate {
                    s: &trial.s,
                    v: &w.twists,
                    grads: &w.grads,
                    lambda: &trial.lambda,
                };
                w.matrix.refresh(p, &at, hht.matrix_coefficients(h))?;
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
                .fold(0.0, f64::max)
                .max(1.0 / (h * h) * CORRECTOR_ACCELERATION_FLOOR);
            let mut da = 0.0f64;
            for i in 0..n6 {
                trial.a[i] += w.rhs[i];
                da = da.max(w.rhs[i].abs() * reciprocal_length_weight(i, length));
            }
            for (l, d) in trial.lambda.iter_mut().zip(&w.rhs[n6..]) {
                *l += d / ucf;
            }
            // Converged when the constraints hold and the correction is negligible relative
            // to the accelerations, or its effect on positions is at rounding level.
            // Coordinates far from the origin (a 1000-loop chain reaches x = 1000 m) resolve
            // positions to ε·|x| only, so the residuals carry noise that the scaled matrix
            // turns into corrections of ε·|x|/(βh²) in the accelerations: a correction that
            // no longer contracts (at least halving) with a matrix built during this step,
            // while moving positions by less than a tenth of the constraint tolerance, is
            // that noise, and the iterate is as converged as the arithmetic allows.
            let moved = beta * h * h * da;
            let stagnant = fresh && da >= 0.5 * da_prev && moved <= CORRECTOR_NOISE;
            // Parts with tiny inertia about some axis leave corrections at noise level too:
            // a correction whose effect on the rates of the positions and velocities
            // (`max(β, γ)·h·|Δa|`: what it changes per step, divided by the step) is a
            // negligible fraction of the integration ERROR is accepted. Per unit time, so
            // that what is accepted over a run does not grow as the steps shrink (HMAX = 1e-5
            // takes 500,000 steps over 5 s).
            let negligible =
                beta.max(hht.gamma) * h * da <= CORRECTOR_ERROR_FRACTION * settings.error;
            if phi_ok
                && (da <= CORRECTOR_RELATIVE * amax.max(CORRECTOR_ACCELERATION_MIN)
                    || moved <= CORRECTOR_ROUNDING
                    || stagnant
                    || negligible)
            {
                converged = true;
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
                time: t1,
            });
        }
        // Final positions, velocities and force term from the converged accelerations.
        trial.place(cur, h, *hht);
        trial.evaluate(p, w)?;
        // Local error estimate (scaled: translations over the characteristic length).
        let err = (0..n6)
            .map(|i| {
                h * h
                    * (beta - 1.0 / 6.0).abs()
                    * (trial.a[i] - cur.a[i]).abs()
                    * reciprocal_length_weight(i, length)
            })
            .fold(0.0, f64::max);
        Ok(err)
    }
}
