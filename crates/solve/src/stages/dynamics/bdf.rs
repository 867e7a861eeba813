//! Variable-order, variable-step BDF (Adams' GSTIFF, WSTIFF and CONSTANT_BDF) in the index-3
//! form, on the part configuration manifold.
//!
//! The first-order system `q̇ = v`, `v̇ = a` is discretised with the backward differentiation
//! formula of order k through the new point and the k last accepted ones (coefficients from
//! the actual step sizes: "variable coefficient", so a change of step size needs no
//! interpolation of the history):
//!
//! ```text
//! Σⱼ cⱼ y_{n+1−j} = ẏ_{n+1},   cⱼ = L'ⱼ(t_{n+1})   (Lⱼ: Lagrange basis on t_{n+1}, …, t_{n+1−k})
//! v_{n+1} = ṽ + a_{n+1}/c₀,     x_{n+1} = x̃ + v_{n+1}/c₀,     ỹ = −Σ_{j≥1} (cⱼ/c₀) y_{n+1−j}
//! ```
//!
//! Rotations use the chart of the current orientation: `R = exp([θ]×) R_n`, the past
//! orientations as `θⱼ = log(Rⱼ R_nᵀ)`, and the kinematic equation in that chart,
//! `θ̇ = J_l(θ)⁻¹ ω` (`J_l`: the left Jacobian of SO(3); ω in ground axes), so the formula keeps
//! its order for 3-D rotation. The accelerations and multipliers are found by the shared
//! corrector ([`super::corrector::correct`]) with `∂q/∂a = 1/c₀²`, `∂v/∂a = 1/c₀`, the
//! constraints scaled by `c₀²`.
//!
//! Formulations (Adams' FORMULATION): I3 solves the position constraints with the equations
//! of motion, and the velocities are the BDF derivative of the positions. SI2 (stabilised
//! index 2, after Gear, Gupta and Leimkuhler) solves the velocity constraints `J v + Φ_t = 0`
//! instead, then projects the positions onto `Φ = 0` with multipliers of their own
//! ([`super::corrector`]'s `project`), so the position correction does not leak into the
//! velocities as its quotient by the step; its error test has the velocities too (times the
//! step). On IFToMM A02 with N = 40 at ERROR = 1e-6, I3 ends 8.1e-4 m off, SI2 1.25e-4 m, at
//! about the same number of steps (through the chain's flat poses both depend on rounding:
//! README, dynamics).
//!
//! The iteration matrix of I3 is refactorised with the pivot sequence of its last
//! factorisation with partial pivoting while those pivots stay within a factor 10 of their
//! columns' largest candidates ([`crate::linalg::refactor`]): on IFToMM A02 with N = 40 that
//! is 2.4k refactorisations of about 35 µs instead of pivoting factorisations of about
//! 0.2 ms, 78 of them falling back to a fresh pivot search. SI2 keeps partial pivoting at
//! every factorisation: its position projection uses the same matrix, and through A02's flat
//! poses it left the parallelogram branch with the kept pivots (measured at ERROR = 1e-6:
//! 2.0 m off, against 1.15e-4 m with partial pivoting).
//!
//! Local error (positions; translations over the characteristic length, rotations in
//! radians): with `y^P` the polynomial through the k+1 last accepted points, extrapolated to
//! `t_{n+1}`, the leading term of the local error is
//! `‖y_{n+1} − y^P(t_{n+1})‖ / (c₀ (t_{n+1} − t_{n−k}))` (exact to leading order for any step
//! sizes; `‖·‖/2`… `/(k+1)Σ1/j` at constant steps). The same estimate at orders k−1 and k+1
//! chooses the order after k+1 steps at the same order: the one that allows the longest next
//! step, up to KMAX. The run starts at order 1 with a Taylor predictor.
//!
//! Control states (DIFF, LSE, TFSISO) are first-order coordinates of the same formula:
//! `x_{n+1} = x̃ + ẋ_{n+1}/c₀`, their rates solved by the corrector with the mechanics; they
//! join the error test weighed by `1/max(1, |x|)` (absolute below 1, relative above), and
//! start from rates consistent with their equations
//! ([`crate::physics::controls::consistent_rates`]).

use super::corrector::{correct, reciprocal_length_weight, Scheme, Step, StepTolerance, Workspace};
use crate::constraints::rows::Velocities;
use crate::kernel::error::IntegrationError;
use crate::kernel::matrix::MatrixCoefficients;
use crate::kernel::output::Output;
use crate::kernel::problem::{flat, padded, Problem};
use crate::state::{ElementState, Pose, State};
use glam::{DMat3, DVec3};
use linkage_model::frames::{exp_so3, log_so3, skew};
use linkage_model::settings::{Formulation, IntegratorSettings};

/// The highest BDF order (KMAX is clamped to it): BDF is not zero-stable beyond 6.
pub const MAX_ORDER: usize = 6;

/// Points kept: the k past points of order k+1 and one more for the estimate at order k+1.
const KEPT: usize = MAX_ORDER + 2;

/// One accepted step: time, poses, velocities (6 per part).
#[derive(Clone, Debug)]
struct Point {
    time: f64,
    poses: Vec<Pose>,
    v: Vec<f64>,
    /// Control states and their rates.
    x: Vec<f64>,
    xd: Vec<f64>,
}

/// `J_l(θ)⁻¹`, the inverse of the left Jacobian of SO(3):
/// `I − ½[θ]× + (1/φ² − (1 + cos φ)/(2φ sin φ)) [θ]×²`, φ = |θ|.
fn left_jacobian_inverse(theta: DVec3) -> DMat3 {
    let phi2 = theta.length_squared();
    let k = skew(theta);
    let c = if phi2 < 1e-6 {
        1.0 / 12.0 + phi2 / 720.0
    } else {
        let phi = phi2.sqrt();
        1.0 / phi2 - (1.0 + phi.cos()) / (2.0 * phi * phi.sin())
    };
    DMat3::IDENTITY - k * 0.5 + k * k * c
}

/// The BDF coefficients `cⱼ = L'ⱼ(t)` on the nodes `t, past[0], …, past[k−1]` into
/// `out[0..=k]` (k = past.len()).
fn bdf_coefficients(t: f64, past: &[f64], out: &mut [f64]) {
    let k = past.len();
    let node = |j: usize| if j == 0 { t } else { past[j - 1] };
    out[0] = past.iter().map(|tp| 1.0 / (t - tp)).sum();
    for (j, o) in out.iter_mut().enumerate().take(k + 1).skip(1) {
        let mut c = 1.0 / (node(j) - t);
        for i in (1..=k).filter(|i| *i != j) {
            c *= (t - node(i)) / (node(j) - node(i));
        }
        *o = c;
    }
}

/// The weights of the polynomial through `nodes` evaluated at `t`: `Lⱼ(t)` into `out`.
fn extrapolation_weights(t: f64, nodes: &[f64], out: &mut [f64]) {
    for (j, o) in out.iter_mut().enumerate().take(nodes.len()) {
        let mut w = 1.0;
        for (i, ti) in nodes.iter().enumerate() {
            if i != j {
                w *= (t - ti) / (nodes[j] - ti);
            }
        }
        *o = w;
    }
}

/// The BDF integrator of a [`Problem`] (module docs): the accepted points, the current step, a
/// trial step and every buffer a step needs, allocated once ([`Bdf::new`]).
pub struct Bdf<'p, 'a> {
    p: &'p Problem<'a>,
    settings: IntegratorSettings,
    kmax: usize,
    /// Accepted points, newest (the current step) first; `len` of them are valid.
    past: Vec<Point>,
    len: usize,
    order: usize,
    steps_at_order: usize,
    cur: Step,
    trial: Step,
    prev_lambda: Vec<f64>,
    prev_h: Option<f64>,
    work: Workspace,
    /// The past points' orientations in the chart of the current one (`len × n`).
    chart: Vec<DVec3>,
    /// Whether `chart` belongs to the current step (false after an accept).
    chart_fresh: bool,
    /// `ṽ` and `x̃`/`θ̃` (6 per part) of the trial step.
    v_tilde: Vec<f64>,
    q_tilde: Vec<f64>,
    /// `x̃` of the control states (nx).
    x_tilde: Vec<f64>,
    /// The trial's orientations in the chart (n).
    theta: Vec<DVec3>,
    /// Error estimates of the trial at orders k−1, k, k+1 (infinite: not available).
    estimates: [f64; 3],
    /// The order of the trial.
    trial_order: usize,
}

impl<'p, 'a> Bdf<'p, 'a> {
    /// Starts at `start` (assembled) with velocities `v0`, projected onto the velocity
    /// constraints; accelerations and multipliers from the constraint-consistent solve.
    /// Returns the integrator and the output at the start.
    pub fn new(
        p: &'p Problem<'a>,
        start: &State,
        v0: &Velocities,
        settings: &IntegratorSettings,
        kmax: usize,
    ) -> Result<(Bdf<'p, 'a>, Output), IntegrationError> {
        if start.poses.len() != p.n() {
            return Err(IntegrationError::StartMismatch {
                state: start.poses.len(),
                model: p.n(),
            });
        }
        let n = p.n();
        let v0 = padded(p, v0);
        let mut start = start.clone();
        crate::physics::controls::consistent_rates(p.forces, &mut start, &v0)?;
        let start = &start;
        let mut work = Workspace::new(p, start, &v0, |h| scheme(h, false).matrix)?;
        if settings.formulation != Formulation::Si2 {
            // I3 refactorises with kept pivots (module docs); SI2 pivots afresh each time.
            work.matrix.lu.keep_pivots();
        }
        let first = work.output.solve(p, start, &flat(&v0), &work.matrix)?;
        let mut cur = Step {
            s: start.clone(),
            v: flat(&first.output.velocities),
            a: flat(&first.output.accelerations),
            force_term: vec![0.0; 6 * n],
            lambda: first.lambda,
        };
        cur.evaluate(p, &mut work)?;
        let point = Point {
            time: start.time,
            poses: start.poses.clone(),
            v: cur.v.clone(),
            x: start.controls.x.clone(),
            xd: start.controls.xdot.clone(),
        };
        let mut past = vec![point; KEPT];
        past[0].time = start.time;
        Ok((
            Bdf {
                p,
                settings: settings.clone(),
                kmax: kmax.clamp(1, MAX_ORDER),
                past,
                len: 1,
                order: 1,
                steps_at_order: 0,
                trial: cur.clone(),
                prev_lambda: cur.lambda.clone(),
                prev_h: None,
                cur,
                work,
                chart: vec![DVec3::ZERO; KEPT * n],
                chart_fresh: false,
                v_tilde: vec![0.0; 6 * n],
                q_tilde: vec![0.0; 6 * n],
                x_tilde: vec![0.0; p.controls()],
                theta: vec![DVec3::ZERO; n],
                estimates: [f64::INFINITY; 3],
                trial_order: 1,
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

    /// The order the next step will use.
    pub fn order(&self) -> usize {
        self.order.min(self.len)
    }

    /// The output at the current step (consistent velocities, accelerations, reactions).
    pub fn output(&mut self) -> Result<Output, IntegrationError> {
        let w = &mut self.work;
        w.output
            .solve(self.p, &self.cur.s, &self.cur.v, &w.matrix)
            .map(|c| c.output)
    }

    /// The 6 coordinates of past point `j`, part `k`: CM position and orientation in the
    /// chart of the current step.
    fn coordinate(&self, j: usize, k: usize, c: usize) -> f64 {
        if c < 3 {
            self.past[j].poses[k].p[c]
        } else {
            self.chart[j * self.p.n() + k][c - 3]
        }
    }

    /// Computes the step of size `h` (kept as the trial; see [`Bdf::accept`]) and returns its
    /// local error estimate (module docs). An error leaves the current step as it was and
    /// drops the iteration matrix.
    pub fn try_step(&mut self, h: f64, tolerance: StepTolerance) -> Result<f64, IntegrationError> {
        let r = self.step(h, tolerance);
        if r.is_err() {
            self.work.matrix.h = None;
        }
        r
    }

    fn step(&mut self, h: f64, tolerance: StepTolerance) -> Result<f64, IntegrationError> {
        let n = self.p.n();
        let t1 = self.cur.s.time + h;
        let k = self.order.min(self.len);
        self.trial_order = k;
        let mut times = [0.0; KEPT];
        for (t, point) in times.iter_mut().zip(&self.past).take(self.len) {
            *t = point.time;
        }
        // The past orientations in the current chart: they change only when a step is
        // accepted, so retries of the same step reuse them.
        if !self.chart_fresh {
            for j in 0..self.len {
                for part in 0..n {
                    self.chart[j * n + part] = if j == 0 {
                        DVec3::ZERO
                    } else {
                        let r = self.past[j].poses[part].r * self.cur.s.poses[part].r.transpose();
                        log_so3(&r)
                    };
                }
            }
            self.chart_fresh = true;
        }
        let mut c = [0.0; KEPT];
        bdf_coefficients(t1, &times[..k], &mut c);
        let hb = 1.0 / c[0];
        // ỹ = y_n − Σ_{j≥2} (c_{j}/c₀)(y_{n+1−j} − y_n) (Σ cⱼ = 0), for y = v and q.
        for part in 0..n {
            for comp in 0..6 {
                let i = 6 * part + comp;
                let (mut v, mut q) = (self.cur.v[i], self.coordinate(0, part, comp));
                let (v_n, q_n) = (v, q);
                for j in 2..=k {
                    let w = -c[j] / c[0];
                    v += w * (self.past[j - 1].v[i] - v_n);
                    q += w * (self.coordinate(j - 1, part, comp) - q_n);
                }
                self.v_tilde[i] = v;
                self.q_tilde[i] = q;
            }
        }
        for i in 0..self.x_tilde.len() {
            let x_n = self.cur.s.controls.x[i];
            let mut x = x_n;
            for j in 2..=k {
                x += -c[j] / c[0] * (self.past[j - 1].x[i] - x_n);
            }
            self.x_tilde[i] = x;
        }
        // Predictor: the velocities and orientations extrapolated by the polynomial through
        // the last k+1 points (a Taylor expansion at the first step); accelerations that give
        // those velocities; multipliers extrapolated linearly.
        let degree = k.min(self.len - 1);
        let mut w = [0.0; KEPT];
        extrapolation_weights(t1, &times[..=degree], &mut w);
        for part in 0..n {
            let mut theta = DVec3::ZERO;
            for comp in 0..6 {
                let i = 6 * part + comp;
                let v_pred = if degree == 0 {
                    self.cur.v[i] + h * self.cur.a[i]
                } else {
                    (0..=degree).map(|j| w[j] * self.past[j].v[i]).sum()
                };
                self.trial.a[i] = (v_pred - self.v_tilde[i]) / hb;
                if comp >= 3 {
                    theta[comp - 3] = if degree == 0 {
                        h * self.cur.v[i] + 0.5 * h * h * self.cur.a[i]
                    } else {
                        (0..=degree)
                            .map(|j| w[j] * self.coordinate(j, part, comp))
                            .sum()
                    };
                }
            }
            self.theta[part] = theta;
        }
        for (i, xd) in self.trial.s.controls.xdot.iter_mut().enumerate() {
            *xd = if degree == 0 {
                self.cur.s.controls.xdot[i]
            } else {
                (0..=degree).map(|j| w[j] * self.past[j].xd[i]).sum()
            };
        }
        let r = self
            .prev_h
            .filter(|hp| *hp > 0.0)
            .map_or(0.0, |hp| (h / hp).min(2.0));
        for ((x, now), before) in self
            .trial
            .lambda
            .iter_mut()
            .zip(&self.cur.lambda)
            .zip(&self.prev_lambda)
        {
            *x = now + r * (now - before);
        }
        let stabilised = self.settings.formulation == Formulation::Si2;
        let Bdf {
            p,
            settings,
            cur,
            trial,
            work,
            v_tilde,
            q_tilde,
            x_tilde,
            theta,
            ..
        } = self;
        let from: &Step = cur;
        let (v_tilde, q_tilde, x_tilde): (&[f64], &[f64], &[f64]) = (v_tilde, q_tilde, x_tilde);
        correct(
            p,
            settings,
            work,
            from,
            trial,
            h,
            tolerance,
            scheme(hb, stabilised),
            |t| {
                place(t, from, t1, hb, v_tilde, q_tilde, theta);
                for ((x, xt), xd) in
                    t.s.controls
                        .x
                        .iter_mut()
                        .zip(x_tilde)
                        .zip(&t.s.controls.xdot)
                {
                    *x = xt + hb * xd;
                }
            },
        )?;
        if stabilised {
            // The projection moved the orientations: their chart coordinates again.
            for (th, (pose, now)) in self
                .theta
                .iter_mut()
                .zip(self.trial.s.poses.iter().zip(&self.cur.s.poses))
            {
                *th = log_so3(&(pose.r * now.r.transpose()));
            }
        }
        // Error estimates at orders k−1, k, k+1 where the points allow.
        self.estimates = [f64::INFINITY; 3];
        for (slot, order) in [k.wrapping_sub(1), k, k + 1].into_iter().enumerate() {
            if order == 0 || order > MAX_ORDER {
                continue;
            }
            if order == 1 && self.len == 1 {
                self.estimates[slot] = self.taylor_estimate(h);
            } else if order < self.len {
                self.estimates[slot] = self.estimate(t1, &times, order);
            }
        }
        Ok(self.estimates[1])
    }

    /// The first step's estimate (order 1): `‖y_{n+1} − (y_n + h v_n + h²/2 a_n)‖`, the leading
    /// term of backward Euler's local error `h²/2 ÿ`.
    fn taylor_estimate(&self, h: f64) -> f64 {
        let length = self.p.model.characteristic_length;
        let mut err = 0.0f64;
        for part in 0..self.p.n() {
            for comp in 0..6 {
                let i = 6 * part + comp;
                let y = self.trial_coordinate(part, comp) - self.coordinate(0, part, comp);
                let pred = h * self.cur.v[i] + 0.5 * h * h * self.cur.a[i];
                err = err.max((y - pred).abs() * reciprocal_length_weight(i, length));
            }
        }
        let c = &self.cur.s.controls;
        for (i, x1) in self.trial.s.controls.x.iter().enumerate() {
            let y = x1 - c.x[i];
            err = err.max((y - h * c.xdot[i]).abs() / c.x[i].abs().max(1.0));
        }
        err
    }

    /// The trial's coordinate (CM position, orientation in the chart).
    fn trial_coordinate(&self, part: usize, comp: usize) -> f64 {
        if comp < 3 {
            self.trial.s.poses[part].p[comp]
        } else {
            self.theta[part][comp - 3]
        }
    }

    /// The local error estimate of order `order` (needs `order + 1` past points):
    /// `‖y_{n+1} − y^P‖ / (c₀ (t_{n+1} − t_{n−order}))` with `y^P` the extrapolation through
    /// `t_n … t_{n−order}` and `c₀ = Σ_{j<order} 1/(t_{n+1} − t_{n−j})`.
    fn estimate(&self, t1: f64, times: &[f64], order: usize) -> f64 {
        let length = self.p.model.characteristic_length;
        let mut w = [0.0; KEPT];
        extrapolation_weights(t1, &times[..=order], &mut w);
        let c0: f64 = times[..order].iter().map(|t| 1.0 / (t1 - t)).sum();
        let scale = 1.0 / (c0 * (t1 - times[order]));
        // SI2: velocities in the error test, weighted by the step (the position error a
        // velocity error makes over the step). I3's velocities are the BDF derivative of its
        // positions: their error is the positions' divided by the step, not an error of its own.
        let vw = if self.settings.formulation == Formulation::Si2 {
            t1 - times[0]
        } else {
            0.0
        };
        let mut err = 0.0f64;
        for part in 0..self.p.n() {
            for comp in 0..6 {
                let base = self.coordinate(0, part, comp);
                let pred: f64 = (0..=order)
                    .map(|j| w[j] * (self.coordinate(j, part, comp) - base))
                    .sum();
                let y = self.trial_coordinate(part, comp) - base;
                err = err.max((y - pred).abs() * reciprocal_length_weight(6 * part + comp, length));
                if vw > 0.0 {
                    let i = 6 * part + comp;
                    let pred: f64 = (0..=order).map(|j| w[j] * self.past[j].v[i]).sum();
                    err = err.max(
                        (self.trial.v[i] - pred).abs() * vw * reciprocal_length_weight(i, length),
                    );
                }
            }
        }
        for (i, x1) in self.trial.s.controls.x.iter().enumerate() {
            let base = self.past[0].x[i];
            let pred: f64 = (0..=order).map(|j| w[j] * (self.past[j].x[i] - base)).sum();
            err = err.max((x1 - base - pred).abs() / base.abs().max(1.0));
        }
        err * scale
    }

    /// Makes the trial step current, keeps it among the past points and chooses the order of
    /// the next step: after `k+1` steps at order k, the order among k−1, k, k+1 (within KMAX
    /// and the points kept) whose estimate allows the longest step for `tolerance`. Returns
    /// the error estimate and order the next step size is to be chosen with.
    pub fn accept(&mut self, tolerance: f64) -> (f64, usize) {
        self.prev_lambda.copy_from_slice(&self.cur.lambda);
        self.prev_h = Some(self.trial.s.time - self.cur.s.time);
        std::mem::swap(&mut self.cur, &mut self.trial);
        self.past.rotate_right(1);
        let newest = &mut self.past[0];
        newest.time = self.cur.s.time;
        newest.poses.copy_from_slice(&self.cur.s.poses);
        newest.v.copy_from_slice(&self.cur.v);
        newest.x.copy_from_slice(&self.cur.s.controls.x);
        newest.xd.copy_from_slice(&self.cur.s.controls.xdot);
        self.len = (self.len + 1).min(KEPT);
        self.chart_fresh = false;
        self.steps_at_order += 1;
        let k = self.trial_order;
        let mut chosen = (self.estimates[1], k);
        if self.steps_at_order > k {
            let ratio = |err: f64, order: usize| (tolerance / err).powf(1.0 / order as f64);
            let mut best = ratio(self.estimates[1], k);
            for (slot, order) in [(0, k.wrapping_sub(1)), (2, k + 1)] {
                let e = self.estimates[slot];
                if order == 0 || order > self.kmax || !e.is_finite() {
                    continue;
                }
                // Raising the order asks for a clearly longer step.
                let r = ratio(e, order) * if order > k { 1.0 / 1.2 } else { 1.0 };
                if r > best {
                    best = r;
                    chosen = (e, order);
                }
            }
            if chosen.1 != k {
                self.steps_at_order = 0;
            }
        }
        self.order = chosen.1;
        chosen
    }
}

/// The corrector's coefficients for a step with `1/c₀ = hb` (SI2 when `stabilised`).
fn scheme(hb: f64, stabilised: bool) -> Scheme {
    Scheme {
        position: hb * hb,
        velocity: hb,
        matrix: MatrixCoefficients {
            stiffness: hb * hb,
            damping: hb,
            multiplier: 1.0,
        },
        alpha: 0.0,
        stabilised,
    }
}

/// Positions and velocities of the trial step (time `t1`) from its accelerations (module
/// docs): `v = ṽ + a/c₀`, `x = x̃ + v/c₀`, `θ = θ̃ + J_l(θ)⁻¹ω/c₀` (fixed point from the last
/// θ, which is O(h)), `R = exp([θ]×) R_n`.
fn place(
    t: &mut Step,
    from: &Step,
    t1: f64,
    hb: f64,
    v_tilde: &[f64],
    q_tilde: &[f64],
    theta: &mut [DVec3],
) {
    t.s.time = t1;
    for ((v, vt), a) in t.v.iter_mut().zip(v_tilde).zip(&t.a) {
        *v = vt + hb * a;
    }
    for (k, th) in theta.iter_mut().enumerate() {
        let i = 6 * k;
        let v = &t.v[i..i + 6];
        let q = &q_tilde[i..i + 6];
        t.s.poses[k].p = DVec3::new(q[0] + hb * v[0], q[1] + hb * v[1], q[2] + hb * v[2]);
        let omega = DVec3::new(v[3], v[4], v[5]);
        let base = DVec3::new(q[3], q[4], q[5]);
        for _ in 0..3 {
            *th = base + left_jacobian_inverse(*th) * omega * hb;
        }
        t.s.poses[k].r = exp_so3(*th) * from.s.poses[k].r;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constant_step_coefficients_are_the_textbook_ones() {
        // BDF2 at h = 0.1: (3/2 y_{n+1} − 2 y_n + 1/2 y_{n−1}) / h.
        let mut c = [0.0; 3];
        bdf_coefficients(0.2, &[0.1, 0.0], &mut c);
        for (x, e) in c.iter().zip([15.0, -20.0, 5.0]) {
            assert!((x - e).abs() < 1e-12, "{c:?}");
        }
        // BDF3: (11/6, −3, 3/2, −1/3) / h.
        let mut c = [0.0; 4];
        bdf_coefficients(3.0, &[2.0, 1.0, 0.0], &mut c);
        for (x, e) in c.iter().zip([11.0 / 6.0, -3.0, 1.5, -1.0 / 3.0]) {
            assert!((x - e).abs() < 1e-12, "{c:?}");
        }
    }

    #[test]
    fn extrapolation_reproduces_polynomials_of_its_degree() {
        let nodes = [1.0, 0.7, 0.2, -0.5];
        let mut w = [0.0; 4];
        extrapolation_weights(1.3, &nodes, &mut w);
        let f = |t: f64| 2.0 - t + 0.5 * t * t - 0.25 * t * t * t;
        let p: f64 = nodes.iter().zip(&w).map(|(t, w)| w * f(*t)).sum();
        assert!((p - f(1.3)).abs() < 1e-12);
    }

    #[test]
    fn the_left_jacobian_inverse_maps_rates_of_the_rotation_vector() {
        // R(t) = exp(θ(t)) R₀: ω from finite differences equals J_l(θ) θ̇.
        let theta = DVec3::new(0.3, -0.8, 0.5);
        let rate = DVec3::new(0.2, 0.1, -0.4);
        let d = 1e-6;
        let r1 = exp_so3(theta + rate * d);
        let r0 = exp_so3(theta - rate * d);
        let w = log_so3(&(r1 * r0.transpose())) / (2.0 * d);
        let back = left_jacobian_inverse(theta) * w;
        assert!((back - rate).length() < 1e-8, "{back} vs {rate}");
    }
}
