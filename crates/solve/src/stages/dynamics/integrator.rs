//! The HHT-α integrator of a [`Problem`]: one step (predictor, modified-Newton corrector,
//! local error estimate) on the part configuration manifold, with every buffer it needs
//! allocated once (module docs of [`super`]).

use super::corrector::{
    correct, project_velocities, reciprocal_length_weight, Scheme, Step, StepTolerance, Workspace,
};
use super::hht::Hht;
use crate::constraints::rows::Velocities;
use crate::kernel::error::IntegrationError;
use crate::kernel::output::Output;
use crate::kernel::problem::{flat, padded, Problem};
use crate::state::{ElementState, State};
use glam::DVec3;
use linkage_model::settings::IntegratorSettings;

/// Positions and velocities of the step of size `h` from `from` with accelerations
/// `step.a`:
/// `q = q_n ⊕ (h v_n + h²/2 ((1−2β) a_n + 2β a))`, `v = v_n + h((1−γ) a_n + γ a)`, and the
/// control states `x = x_n + h((1−γ) ẋ_n + γ ẋ)` (HHT has no rule of its own for first-order
/// states: the velocity's keeps the numerical damping of α, and is the trapezoidal rule at
/// α = 0).
fn place(step: &mut Step, from: &Step, h: f64, hht: Hht) {
    let Hht { beta, gamma, .. } = hht;
    step.s.poses.copy_from_slice(&from.s.poses);
    step.s.time = from.s.time + h;
    for k in 0..step.s.poses.len() {
        let d = |i: usize| {
            let i = 6 * k + i;
            h * from.v[i] + h * h / 2.0 * ((1.0 - 2.0 * beta) * from.a[i] + 2.0 * beta * step.a[i])
        };
        step.s.increment(
            k,
            DVec3::new(d(0), d(1), d(2)),
            DVec3::new(d(3), d(4), d(5)),
        );
    }
    for ((v, (v0, a0)), a) in step
        .v
        .iter_mut()
        .zip(from.v.iter().zip(&from.a))
        .zip(&step.a)
    {
        *v = v0 + h * ((1.0 - gamma) * a0 + gamma * a);
    }
    // Control states by the same rule as the velocities (trapezoidal at α = 0).
    let (c, c0) = (&mut step.s.controls, &from.s.controls);
    for (((x, x0), xd0), xd) in c.x.iter_mut().zip(&c0.x).zip(&c0.xdot).zip(&c.xdot) {
        *x = x0 + h * ((1.0 - gamma) * xd0 + gamma * xd);
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
    /// The size of the step before that (`None` before the second step).
    prev_prev_h: Option<f64>,
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
        let mut start = start.clone();
        crate::physics::controls::consistent_rates(p.forces, &mut start, &v0)?;
        let start = &start;
        let hht = Hht::new(settings.alpha);
        let mut work = Workspace::new(p, start, &v0, |h| hht.matrix_coefficients(h))?;
        // Refactorisations keep their pivot sequence ([`crate::linalg::refactor`]).
        work.matrix.lu.keep_pivots();
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
                prev_prev_h: None,
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

    /// Replaces the force elements' state the next steps are solved with (joint friction
    /// after an accepted step: [`crate::physics::applied::AppliedForces::accept_state`]).
    pub fn set_elements(&mut self, elements: &ElementState) {
        self.cur.s.elements.clone_from(elements);
        self.trial.s.elements.clone_from(elements);
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
    pub fn try_step(&mut self, h: f64, tolerance: StepTolerance) -> Result<f64, IntegrationError> {
        let r = self.corrector(h, tolerance);
        if r.is_err() {
            self.work.matrix.h = None;
        }
        r
    }

    /// Makes the trial step (from the last successful [`Integrator::try_step`]) current.
    pub fn accept(&mut self) {
        self.prev_a.copy_from_slice(&self.cur.a);
        self.prev_lambda.copy_from_slice(&self.cur.lambda);
        self.prev_prev_h = self.prev_h;
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

    /// The HHT step (module docs) on the trial step: predictor, [`correct`], local error
    /// estimate.
    fn corrector(&mut self, h: f64, tolerance: StepTolerance) -> Result<f64, IntegrationError> {
        let Integrator {
            p,
            settings,
            hht,
            cur,
            trial,
            prev_a,
            prev_lambda,
            prev_h,
            prev_prev_h,
            work: w,
        } = self;
        let p: &Problem = p;
        let hht = *hht;
        let length = p.model.characteristic_length;
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
        trial.s.controls.xdot.copy_from_slice(&cur.s.controls.xdot);
        let scheme = Scheme {
            position: hht.beta * h * h,
            velocity: hht.gamma * h,
            matrix: hht.matrix_coefficients(h),
            alpha: hht.alpha,
            stabilised: false,
        };
        let from: &Step = cur;
        correct(p, settings, w, from, trial, h, tolerance, scheme, |t| {
            place(t, from, h, hht)
        })?;
        if hht.undamped() {
            project_velocities(p, w, trial)?;
        }
        // Local error estimate `h³|β − 1/6|·|ȧ|` (scaled: translations over the
        // characteristic length). HHT's accelerations belong to the shifted times
        // `t + αh` of their steps (the start's are at t₀ itself), so ȧ is a difference of
        // accelerations over the time between their shifted times: a plain `a_{n+1} − a_n`
        // would keep `α(h_prev − h)·ȧ` however small the step. The difference is taken over
        // two steps, `a_{n+1} − a_{n−1}`, once there are two: the index-3 HHT has a mode
        // alternating from step to step, `(−1)ⁿ ε`, in the accelerations (the discrete
        // velocity constraint `u_{n+1} = −ρ∞ u_n`, with ρ∞ = (1+α)/(1−α)), fed by the
        // corrector's constraint tolerance at every step and growing like its size over h²;
        // it is no truncation error, and it cancels over two steps. With α = 0 (ρ∞ = 1, the
        // mode undamped) a one-step difference made the estimate of A01 at ERROR = 1e-8
        // stay at 7e-9 however small the step, and the step shrank without end.
        let (older, span) = match (*prev_h, *prev_prev_h) {
            (Some(hp), hpp) => (
                &prev_a[..],
                (1.0 + hht.alpha) * h + hp - hht.alpha * hpp.unwrap_or(0.0),
            ),
            (None, _) => (&cur.a[..], h),
        };
        let err = (0..6 * p.n())
            .map(|i| {
                h * h * h / span
                    * (hht.beta - 1.0 / 6.0).abs()
                    * (trial.a[i] - older[i]).abs()
                    * reciprocal_length_weight(i, length)
            })
            .fold(0.0, f64::max);
        // Control states advance by the γ rule `x = x_n + h((1−γ)ẋ_n + γẋ)`: its local error
        // is `h²|γ − ½| ẍ + h³/12 x⃛`, bounded here by `h(|γ − ½| + 1/12)|ẋ_{n+1} − ẋ_n|`
        // (weighed by 1/max(1, |x|)).
        let c = &cur.s.controls;
        let err_x = trial
            .s
            .controls
            .xdot
            .iter()
            .zip(&c.xdot)
            .zip(&c.x)
            .map(|((a, b), x)| {
                h * ((hht.gamma - 0.5).abs() + 1.0 / 12.0) * (a - b).abs() / x.abs().max(1.0)
            })
            .fold(0.0, f64::max);
        Ok(err.max(err_x))
    }
}
