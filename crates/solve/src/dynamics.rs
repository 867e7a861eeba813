//! Dynamic simulation (DESIGN §8, ADM-REFERENCE §8.5): the index-3 DAE integrated with the
//! HHT-α method (Negrut, Rampalli, Ottarsson, Sajdak 2007) on the part configuration manifold.
//!
//! Per step the unknowns are the accelerations `a` (CM acceleration and angular acceleration of
//! every part, ground axes) and the multipliers `λ` of the independent constraint rows:
//!
//! ```text
//! M a_{n+1} + UCF·[(1+α)(Jᵀλ − Q)_{n+1} − α (Jᵀλ − Q)_n] = 0
//! Φ(q_{n+1}, t_{n+1}) / (β h²) = 0
//! q_{n+1} = q_n ⊕ (h v_n + h²/2 ((1−2β) a_n + 2β a_{n+1})),   v_{n+1} = v_n + h((1−γ) a_n + γ a_{n+1})
//! ```
//!
//! with `β = (1−α)²/4`, `γ = 1/2 − α`, `α ∈ [−1/3, 0]` (⊕: translation added, rotation applied
//! with the exponential map). Newton uses the scaled iteration matrix
//! `[M + (1+α)(βh² K_T + γh C_T), (1+α)Jᵀ; J, 0]` (K_T with the geometric stiffness), kept
//! across iterations and steps while it converges well (modified Newton). The step size is
//! controlled with the local error estimate `h²|β − 1/6|·‖a_{n+1} − a_n‖` against the
//! INTEGRATOR ERROR. Output times are hit exactly; at each output the velocities and
//! accelerations are made consistent with the constraints (projection and the acceleration/
//! force solve), which also gives the reactions. Redundant rows (removed as in verify) are
//! checked every step; one that becomes violated stops the run.

use crate::applied::AppliedForces;
use crate::hessian::HessianBlocks;
use crate::ic::{element_reactions, Reaction};
use crate::linear::SparseLu;
use crate::rows::RowGradient;
use crate::state::State;
use crate::system::System;
use crate::verify::{report_residual, within_tolerance, Drivers};
use glam::DVec3;
use linkage_model::Model;

/// Integrator settings (INTEGRATOR statement; Adams names are accepted by the caller and mapped
/// to HHT).
#[derive(Clone, Debug, PartialEq)]
pub struct IntegratorSettings {
    /// Local error tolerance (relative to the characteristic length for translations).
    pub error: f64,
    pub hmax: Option<f64>,
    pub hinit: Option<f64>,
    pub hmin: f64,
    /// HHT α in [−1/3, 0].
    pub alpha: f64,
    /// Newton iterations per step before the step is retried smaller.
    pub maxit: usize,
}

impl Default for IntegratorSettings {
    fn default() -> Self {
        IntegratorSettings {
            error: 1e-3,
            hmax: None,
            hinit: None,
            hmin: 1e-10,
            alpha: -0.3,
            maxit: 10,
        }
    }
}

/// Part state at an output time.
#[derive(Clone, Debug, PartialEq)]
pub struct Output {
    pub time: f64,
    pub state: State,
    /// CM velocity and angular velocity (ground).
    pub velocities: Vec<(DVec3, DVec3)>,
    pub accelerations: Vec<(DVec3, DVec3)>,
    pub reactions: Vec<Reaction>,
}

/// Why a simulation stopped early.
#[derive(Clone, Debug, PartialEq)]
pub struct Failure {
    pub time: f64,
    pub message: String,
}

/// Result of a simulation.
#[derive(Clone, Debug)]
pub struct Simulation {
    pub outputs: Vec<Output>,
    pub failure: Option<Failure>,
    pub steps: usize,
    pub rejected: usize,
    /// The model has no degrees of freedom: it was run kinematically.
    pub kinematic: bool,
}

/// Per-part damping added for dynamic settling: force `−c m v`, torque `−c I ω`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExtraDamping(pub f64);

/// Everything the step needs that does not change.
pub struct Problem<'a> {
    pub model: &'a Model,
    pub sys: &'a System,
    /// Independent rows.
    pub rows: &'a [usize],
    /// Redundant rows, checked every step.
    pub redundant: &'a [usize],
    pub drivers: &'a dyn Drivers,
    pub forces: &'a dyn AppliedForces,
    pub damping: Option<ExtraDamping>,
    /// Freeze time at this value (dynamic settling): motions and forces see it.
    pub frozen_time: Option<f64>,
}

impl Problem<'_> {
    fn n(&self) -> usize {
        self.model.parts.len()
    }

    fn time(&self, t: f64) -> f64 {
        self.frozen_time.unwrap_or(t)
    }

    /// `UCF·Q` (mass × acceleration units): gravity, applied forces, gyroscopic terms, extra
    /// damping.
    fn generalized(&self, s: &State, v: &[(DVec3, DVec3)]) -> Result<Vec<f64>, String> {
        let n = self.n();
        let ucf = self.model.ucf();
        let mut q = vec![0.0; 6 * n];
        let mut st = s.clone();
        st.time = self.time(s.time);
        self.forces.add_forces(&st, v, &mut q)?;
        for x in q.iter_mut() {
            *x *= ucf;
        }
        for (k, p) in self.model.parts.iter().enumerate() {
            let ig = s.poses[k].r * p.inertia * s.poses[k].r.transpose();
            let w = v[k].1;
            let gyro = -w.cross(ig * w);
            for c in 0..3 {
                q[6 * k + c] += p.mass * self.model.gravity[c];
                q[6 * k + 3 + c] += gyro[c];
            }
            if let Some(ExtraDamping(c)) = self.damping {
                let dv = v[k].0 * (-c * p.mass);
                let dw = ig * w * (-c);
                for i in 0..3 {
                    q[6 * k + i] += dv[i];
                    q[6 * k + 3 + i] += dw[i];
                }
            }
        }
        Ok(q)
    }

    /// Drive values of the rows (motions at time t).
    fn drives(&self, t: f64) -> Result<Vec<f64>, String> {
        self.rows
            .iter()
            .map(|&r| {
                let row = &self.sys.rows[r];
                if row.driven {
                    self.drivers
                        .value(row.element, self.time(t))
                        .ok_or_else(|| {
                            format!(
                                "{}: the motion cannot be evaluated at time {}",
                                self.model.constraints[row.element].origin.name, t
                            )
                        })
                } else {
                    Ok(0.0)
                }
            })
            .collect()
    }
}

fn apply(s: &State, d: &[f64]) -> State {
    let mut t = s.clone();
    for k in 0..s.poses.len() {
        t.increment(
            k,
            DVec3::new(d[6 * k], d[6 * k + 1], d[6 * k + 2]),
            DVec3::new(d[6 * k + 3], d[6 * k + 4], d[6 * k + 5]),
        );
    }
    t
}

fn flat(v: &[(DVec3, DVec3)]) -> Vec<f64> {
    v.iter()
        .flat_map(|(a, b)| [a.x, a.y, a.z, b.x, b.y, b.z])
        .collect()
}

fn unflat(x: &[f64]) -> Vec<(DVec3, DVec3)> {
    x.chunks(6)
        .map(|c| (DVec3::new(c[0], c[1], c[2]), DVec3::new(c[3], c[4], c[5])))
        .collect()
}

/// Integrator state between steps.
struct Step {
    s: State,
    v: Vec<f64>,
    a: Vec<f64>,
    /// `Jᵀλ − Q` at the step (mass × acceleration units), for the HHT α term.
    force_term: Vec<f64>,
    lambda: Vec<f64>,
}

/// Simulates from `start` (assembled, with consistent velocities `v0`) to `end`, with output at
/// `times` (ascending, within [start.time, end]).
pub fn simulate(
    p: &Problem,
    start: &State,
    v0: &[(DVec3, DVec3)],
    times: &[f64],
    settings: &IntegratorSettings,
    mut progress: impl FnMut(f64),
) -> Simulation {
    let n = p.n();
    let m = p.rows.len();
    let mut sim = Simulation {
        outputs: Vec::new(),
        failure: None,
        steps: 0,
        rejected: 0,
        kinematic: m >= 6 * n && n > 0,
    };
    let length = p.model.characteristic_length;
    let t_end = times.last().copied().unwrap_or(start.time);
    // Consistent accelerations at the start.
    let first = match consistent_output(p, start, &flat(v0)) {
        Ok(o) => o,
        Err(e) => {
            sim.failure = Some(Failure {
                time: start.time,
                message: e,
            });
            return sim;
        }
    };
    let mut cur = Step {
        s: start.clone(),
        v: flat(&first.velocities),
        a: flat(&first.accelerations),
        force_term: Vec::new(),
        lambda: first.lambda.clone(),
    };
    cur.force_term = match force_term(p, &cur.s, &cur.v, &cur.lambda) {
        Ok(f) => f,
        Err(e) => {
            sim.failure = Some(Failure {
                time: start.time,
                message: e,
            });
            return sim;
        }
    };
    let mut next_output = 0;
    if times
        .first()
        .is_some_and(|t| (*t - start.time).abs() <= 1e-12 * t_end.abs().max(1.0))
    {
        sim.outputs.push(first.output);
        next_output = 1;
    }
    let span = (t_end - start.time).max(1e-300);
    let hmax = settings.hmax.unwrap_or(span / 10.0).min(span);
    let mut h = settings
        .hinit
        .unwrap_or((span / 1000.0).min(hmax))
        .min(hmax);
    let alpha = settings.alpha.clamp(-1.0 / 3.0, 0.0);
    let beta = (1.0 - alpha).powi(2) / 4.0;
    let gamma = 0.5 - alpha;
    let mut lu: Option<(SparseLu, f64)> = None;
    while next_output < times.len() {
        let target = times[next_output];
        let t = cur.s.time;
        let remaining = target - t;
        // Take the rest when it fits; split it in two rather than leave a sliver.
        let mut hs = if remaining <= h * (1.0 + 1e-9) {
            remaining
        } else if remaining < 2.0 * h {
            remaining / 2.0
        } else {
            h
        };
        let hit = hs >= remaining - 1e-12 * span;
        if hit {
            hs = remaining;
        }
        if hs <= 0.0 {
            next_output += 1;
            continue;
        }
        match hht_step(p, &cur, hs, alpha, beta, gamma, settings, &mut lu) {
            Ok((next, err)) => {
                let tol = settings.error;
                if err > tol && hs > settings.hmin * 1.0001 {
                    sim.rejected += 1;
                    h = (hs * (0.9 * (tol / err).powf(1.0 / 3.0)).clamp(0.2, 0.9))
                        .max(settings.hmin);
                    continue;
                }
                sim.steps += 1;
                cur = next;
                progress(cur.s.time);
                // Redundant rows must stay satisfied.
                for &r in p.redundant {
                    let row = &p.sys.rows[r];
                    let drive = if row.driven {
                        p.drivers.value(row.element, p.time(cur.s.time))
                    } else {
                        Some(0.0)
                    };
                    let Some(drive) = drive else { continue };
                    let val = p.sys.residual(r, &cur.s, drive);
                    let tol = crate::tolerances::Tolerances {
                        length: 1e-6,
                        angle: 1e-6,
                        ..Default::default()
                    };
                    if !within_tolerance(row.unit, val, &tol, length) {
                        let c = &p.model.constraints[row.element];
                        sim.failure = Some(Failure {
                            time: cur.s.time,
                            message: format!(
                                "the redundant equation {} of {} (removed as consistent) became inconsistent: residual {:.6e}{}",
                                row.label,
                                c.origin.name,
                                report_residual(row.unit, val),
                                if matches!(row.unit, crate::system::RowUnit::Direction | crate::system::RowUnit::Angle) { " deg" } else { "" }
                            ),
                        });
                        return sim;
                    }
                }
                let grow = if err > 0.0 {
                    (0.9 * (tol / err).powf(1.0 / 3.0)).clamp(0.2, 2.0)
                } else {
                    2.0
                };
                // A step shortened to hit an output does not shrink the step size.
                h = (hs * grow)
                    .max(if hit { h } else { 0.0 })
                    .min(hmax)
                    .max(settings.hmin);
                if hit {
                    match consistent_output(p, &cur.s, &cur.v) {
                        Ok(o) => sim.outputs.push(o.output),
                        Err(e) => {
                            sim.failure = Some(Failure {
                                time: cur.s.time,
                                message: e,
                            });
                            return sim;
                        }
                    }
                    next_output += 1;
                }
            }
            Err(e) => {
                if hs <= settings.hmin * 1.0001 {
                    sim.failure = Some(Failure {
                        time: t,
                        message: format!("{e} (step size {hs:.3e} at its minimum)"),
                    });
                    return sim;
                }
                sim.rejected += 1;
                lu = None;
                h = (hs * 0.25).max(settings.hmin);
            }
        }
    }
    sim
}

/// `Jᵀλ − Q` in mass × acceleration units.
fn force_term(p: &Problem, s: &State, v: &[f64], lambda: &[f64]) -> Result<Vec<f64>, String> {
    let q = p.generalized(s, &unflat(v))?;
    let ucf = p.model.ucf();
    let mut out: Vec<f64> = q.iter().map(|x| -x).collect();
    let mut g = RowGradient::default();
    for (k, &r) in p.rows.iter().enumerate() {
        p.sys.gradient(r, s, &mut g);
        for (body, b) in &g.blocks {
            for c in 0..6 {
                out[6 * body + c] += ucf * lambda[k] * b[c];
            }
        }
    }
    Ok(out)
}

#[allow(clippy::too_many_arguments)]
fn hht_step(
    p: &Problem,
    cur: &Step,
    h: f64,
    alpha: f64,
    beta: f64,
    gamma: f64,
    settings: &IntegratorSettings,
    lu: &mut Option<(SparseLu, f64)>,
) -> Result<(Step, f64), String> {
    let n = p.n();
    let m = p.rows.len();
    let dim = 6 * n + m;
    let ucf = p.model.ucf();
    let t1 = cur.s.time + h;
    let drives = p.drives(t1)?;
    let mut a = cur.a.clone();
    let mut lambda = cur.lambda.clone();
    let mut g = RowGradient::default();
    let mut converged = false;
    let mut da_prev = f64::INFINITY;
    let mut s1 = cur.s.clone();
    let mut v1 = cur.v.clone();
    let length = p.model.characteristic_length;
    for it in 0..settings.maxit {
        // Positions and velocities from the accelerations.
        let d: Vec<f64> = (0..6 * n)
            .map(|i| {
                h * cur.v[i] + h * h / 2.0 * ((1.0 - 2.0 * beta) * cur.a[i] + 2.0 * beta * a[i])
            })
            .collect();
        s1 = apply(&cur.s, &d);
        s1.time = t1;
        v1 = (0..6 * n)
            .map(|i| cur.v[i] + h * ((1.0 - gamma) * cur.a[i] + gamma * a[i]))
            .collect();
        // Residuals.
        let ft = force_term(p, &s1, &v1, &lambda)?;
        let mut r1 = vec![0.0; 6 * n];
        for (k, part) in p.model.parts.iter().enumerate() {
            let ig = s1.poses[k].r * part.inertia * s1.poses[k].r.transpose();
            let ang = ig * DVec3::new(a[6 * k + 3], a[6 * k + 4], a[6 * k + 5]);
            for c in 0..3 {
                r1[6 * k + c] = part.mass * a[6 * k + c];
                r1[6 * k + 3 + c] = ang[c];
            }
        }
        for i in 0..6 * n {
            r1[i] += (1.0 + alpha) * ft[i] - alpha * cur.force_term[i];
        }
        let r2: Vec<f64> = p
            .rows
            .iter()
            .zip(&drives)
            .map(|(&r, &dr)| p.sys.residual(r, &s1, dr) / (beta * h * h))
            .collect();
        // Convergence: position constraints to the assembly accuracy, dynamic residual small.
        let phi_ok = p.rows.iter().zip(&r2).all(|(&r, v)| {
            let raw = v * beta * h * h;
            match p.sys.rows[r].unit {
                crate::system::RowUnit::Length | crate::system::RowUnit::Mixed => {
                    raw.abs() <= 1e-9 * length
                }
                _ => raw.abs() <= 1e-9,
            }
        });
        // Newton matrix (refreshed when missing or built for another step size).
        let stale = lu.as_ref().is_none_or(|(_, hh)| (hh - h).abs() > 1e-12 * h) || it >= 3;
        if stale {
            let mut e: Vec<(usize, usize, f64)> = Vec::new();
            for (k, part) in p.model.parts.iter().enumerate() {
                let ig = s1.poses[k].r * part.inertia * s1.poses[k].r.transpose();
                for c in 0..3 {
                    e.push((6 * k + c, 6 * k + c, part.mass));
                    for dd in 0..3 {
                        let x = ig.col(dd)[c];
                        if x != 0.0 {
                            e.push((6 * k + 3 + c, 6 * k + 3 + dd, x));
                        }
                    }
                }
            }
            let kq = (1.0 + alpha) * beta * h * h;
            let kv = (1.0 + alpha) * gamma * h;
            let mut dq = Vec::new();
            let mut dv = Vec::new();
            let mut st = s1.clone();
            st.time = p.time(t1);
            p.forces
                .add_jacobians(&st, &unflat(&v1), &mut dq, Some(&mut dv))?;
            e.extend(dq.into_iter().map(|(i, j, x)| (i, j, -ucf * x * kq)));
            e.extend(dv.into_iter().map(|(i, j, x)| (i, j, -ucf * x * kv)));
            if let Some(ExtraDamping(c)) = p.damping {
                for (k, part) in p.model.parts.iter().enumerate() {
                    for i in 0..3 {
                        e.push((6 * k + i, 6 * k + i, c * part.mass * kv));
                    }
                    let ig = s1.poses[k].r * part.inertia * s1.poses[k].r.transpose();
                    for i in 0..3 {
                        for j in 0..3 {
                            e.push((6 * k + 3 + i, 6 * k + 3 + j, c * ig.col(j)[i] * kv));
                        }
                    }
                }
            }
            let mut hb = HessianBlocks::default();
            for (k, &r) in p.rows.iter().enumerate() {
                hb.clear();
                for (c, q) in &p.sys.rows[r].terms {
                    q.hessian(&s1, *c, &mut hb);
                }
                hb.triplets(ucf * lambda[k] * kq, &mut e);
                p.sys.gradient(r, &s1, &mut g);
                for (body, b) in &g.blocks {
                    for (c, x) in b.iter().enumerate() {
                        if *x != 0.0 {
                            e.push((6 * body + c, 6 * n + k, (1.0 + alpha) * ucf * x));
                            e.push((6 * n + k, 6 * body + c, *x));
                        }
                    }
                }
            }
            *lu = Some((
                SparseLu::factor(dim, &e).map_err(|err| {
                    format!("the integrator's Newton matrix cannot be factorised: {err}")
                })?,
                h,
            ));
        }
        let Some((f, _)) = lu.as_ref() else { break };
        let mut rhs: Vec<f64> = r1.iter().chain(r2.iter()).map(|x| -x).collect();
        f.solve(&mut rhs)
            .map_err(|_| "the integrator's Newton matrix is singular".to_string())?;
        let amax = (0..6 * n)
            .map(|i| a[i].abs() * if i % 6 < 3 { 1.0 / length } else { 1.0 })
            .fold(0.0, f64::max)
            .max(1.0 / (h * h) * 1e-12);
        let mut da = 0.0f64;
        for i in 0..6 * n {
            a[i] += rhs[i];
            da = da.max(rhs[i].abs() * if i % 6 < 3 { 1.0 / length } else { 1.0 });
        }
        for k in 0..m {
            lambda[k] += rhs[6 * n + k] / ucf;
        }
        // Converged when the constraints hold and the correction is negligible relative to the
        // accelerations, or its effect on positions is at rounding level. Coordinates far from
        // the origin (a 1000-loop chain reaches x = 1000 m) resolve positions to ε·|x| only, so
        // the residuals carry noise that the scaled matrix turns into corrections of
        // ε·|x|/(βh²) in the accelerations: a correction that no longer contracts (at least
        // halving) while moving positions by less than a tenth of the constraint tolerance is
        // that noise, and the iterate is as converged as the arithmetic allows.
        let stagnant = da >= 0.5 * da_prev && beta * h * h * da <= 1e-10;
        if phi_ok && (da <= 1e-8 * amax.max(1e-8) || beta * h * h * da <= 1e-14 || stagnant) {
            converged = true;
            break;
        }
        da_prev = da;
    }
    if !converged {
        return Err(format!(
            "the corrector did not converge in {} iterations at time {t1}",
            settings.maxit
        ));
    }
    // Final positions and velocities from the converged accelerations.
    let d: Vec<f64> = (0..6 * n)
        .map(|i| h * cur.v[i] + h * h / 2.0 * ((1.0 - 2.0 * beta) * cur.a[i] + 2.0 * beta * a[i]))
        .collect();
    let _ = (&s1, &v1);
    let mut s_new = apply(&cur.s, &d);
    s_new.time = t1;
    let v_new: Vec<f64> = (0..6 * n)
        .map(|i| cur.v[i] + h * ((1.0 - gamma) * cur.a[i] + gamma * a[i]))
        .collect();
    let force_term_new = force_term(p, &s_new, &v_new, &lambda)?;
    // Local error estimate (scaled: translations over the characteristic length).
    let err = (0..6 * n)
        .map(|i| {
            h * h
                * (beta - 1.0 / 6.0).abs()
                * (a[i] - cur.a[i]).abs()
                * if i % 6 < 3 { 1.0 / length } else { 1.0 }
        })
        .fold(0.0, f64::max);
    Ok((
        Step {
            s: s_new,
            v: v_new,
            a,
            force_term: force_term_new,
            lambda,
        },
        err,
    ))
}

/// Output values made consistent with the constraints at `s`.
struct Consistent {
    output: Output,
    velocities: Vec<(DVec3, DVec3)>,
    accelerations: Vec<(DVec3, DVec3)>,
    lambda: Vec<f64>,
}

/// Projects velocities onto `J v = ḟ` (least change, mass-weighted) and solves the
/// accelerations and multipliers (`M a + UCF·Jᵀλ = UCF·Q`, `J a = f̈ − γ`).
fn consistent_output(p: &Problem, s: &State, v: &[f64]) -> Result<Consistent, String> {
    let n = p.n();
    let m = p.rows.len();
    let dim = 6 * n + m;
    let ucf = p.model.ucf();
    let length = p.model.characteristic_length;
    let mut grads = vec![RowGradient::default(); m];
    for (k, &r) in p.rows.iter().enumerate() {
        p.sys.gradient(r, s, &mut grads[k]);
    }
    let mut mass_entries: Vec<(usize, usize, f64)> = Vec::new();
    for (k, part) in p.model.parts.iter().enumerate() {
        let ig = s.poses[k].r * part.inertia * s.poses[k].r.transpose();
        let mass = if part.mass > 0.0 { part.mass } else { 1e-12 };
        for c in 0..3 {
            mass_entries.push((6 * k + c, 6 * k + c, mass));
            for d in 0..3 {
                let x = ig.col(d)[c];
                if x != 0.0 {
                    mass_entries.push((6 * k + 3 + c, 6 * k + 3 + d, x));
                }
            }
            mass_entries.push((6 * k + 3 + c, 6 * k + 3 + c, 1e-12 * mass * length * length));
        }
    }
    let mut kkt = mass_entries.clone();
    for (k, g) in grads.iter().enumerate() {
        for (body, b) in &g.blocks {
            for (c, x) in b.iter().enumerate() {
                if *x != 0.0 {
                    kkt.push((6 * n + k, 6 * body + c, *x));
                    kkt.push((6 * body + c, 6 * n + k, *x));
                }
            }
        }
    }
    let lu = SparseLu::factor(dim, &kkt)
        .map_err(|e| format!("the consistent velocity/acceleration solve failed: {e}"))?;
    // Velocities.
    let mut rhs = vec![0.0; dim];
    let mut mv = vec![0.0; 6 * n];
    for &(i, j, x) in &mass_entries {
        mv[i] += x * v[j];
    }
    rhs[..6 * n].copy_from_slice(&mv);
    for (k, &r) in p.rows.iter().enumerate() {
        let row = &p.sys.rows[r];
        if row.driven {
            rhs[6 * n + k] = match drive_series(p, row.element, s.time) {
                Some(f) => f[1],
                None => rate_of(&grads[k], v),
            };
        }
    }
    lu.solve(&mut rhs)
        .map_err(|_| "the velocity projection is singular".to_string())?;
    let vel: Vec<f64> = rhs[..6 * n].to_vec();
    let velocities = unflat(&vel);
    // Accelerations and multipliers.
    let q = p.generalized(s, &velocities)?;
    let mut rhs = vec![0.0; dim];
    rhs[..6 * n].copy_from_slice(&q);
    for (k, &r) in p.rows.iter().enumerate() {
        let row = &p.sys.rows[r];
        let bias: f64 = row
            .terms
            .iter()
            .map(|(c, qq)| c * qq.rates(s, &velocities).1)
            .sum();
        let fdd = if row.driven {
            drive_series(p, row.element, s.time).map_or(0.0, |f| f[2])
        } else {
            0.0
        };
        rhs[6 * n + k] = fdd - bias;
    }
    lu.solve(&mut rhs)
        .map_err(|_| "the acceleration solve is singular".to_string())?;
    let accelerations = unflat(&rhs[..6 * n]);
    // Multipliers in force units (M a + Jᵀμ = UCF·Q → λ = μ/UCF).
    let lambda: Vec<f64> = rhs[6 * n..].iter().map(|x| x / ucf).collect();
    let rg: Vec<(usize, &RowGradient)> = p.rows.iter().copied().zip(grads.iter()).collect();
    let mut reactions = element_reactions(p.model, p.sys, &rg, &lambda, s);
    // A general constraint's velocity-product term needs second derivatives of its expression,
    // which linkage does not compute: the reported accelerations and reactions would be wrong,
    // so they are NaN (positions and velocities, which the integrator takes from the position
    // constraints, are right). The integrator's own accelerations are not affected.
    let unknown_accelerations = p.rows.iter().any(|&r| p.sys.rows[r].function.is_some());
    let mut reported = accelerations.clone();
    if unknown_accelerations {
        let nan = DVec3::splat(f64::NAN);
        reported.iter_mut().for_each(|a| *a = (nan, nan));
        reactions.iter_mut().for_each(|r| {
            r.force = nan;
            r.torque = nan;
        });
    }
    Ok(Consistent {
        output: Output {
            time: s.time,
            state: s.clone(),
            velocities: velocities.clone(),
            accelerations: reported,
            reactions,
        },
        velocities,
        accelerations,
        lambda,
    })
}

fn rate_of(g: &RowGradient, v: &[f64]) -> f64 {
    g.blocks
        .iter()
        .map(|(k, b)| (0..6).map(|c| b[c] * v[6 * k + c]).sum::<f64>())
        .sum()
}

/// `[f, ḟ, f̈]` of a motion at time t (frozen time gives zero rates).
fn drive_series(p: &Problem, element: usize, t: f64) -> Option<[f64; 3]> {
    if let Some(t0) = p.frozen_time {
        return p.drivers.value(element, t0).map(|f| [f, 0.0, 0.0]);
    }
    p.drivers.rates(element, t)
}

/// A dynamic analysis from the dataset: initial conditions (or static equilibrium first), then
/// the simulation.
#[derive(Clone, Debug)]
pub struct DynamicRun {
    pub ic: crate::ic::InitialConditions,
    pub equilibrium: Option<Result<crate::statics::Equilibrium, String>>,
    pub simulation: Option<Simulation>,
    /// Why no simulation was run.
    pub error: Option<String>,
}

/// Runs initial conditions (and static equilibrium with `start_at_equilibrium`), then
/// integrates to the last of `times`.
#[allow(clippy::too_many_arguments)]
pub fn run(
    model: &Model,
    drivers: &crate::drivers::ExpressionDrivers,
    forces: &dyn AppliedForces,
    tol: &crate::tolerances::Tolerances,
    times: &[f64],
    settings: &IntegratorSettings,
    start_at_equilibrium: bool,
    progress: impl FnMut(f64),
) -> DynamicRun {
    let sys = System::new(model);
    let (ic, equilibrium, start, v0) = if start_at_equilibrium {
        let st = crate::statics::run(model, drivers, forces, tol, &[0.0]);
        let eq = st.steps.into_iter().next().map(|(_, e)| e);
        let start = match &eq {
            Some(Ok(e)) if e.converged => Some(e.state.clone()),
            _ => None,
        };
        (
            st.ic,
            eq,
            start,
            vec![(DVec3::ZERO, DVec3::ZERO); model.parts.len()],
        )
    } else {
        let ic = crate::ic::initial_conditions(model, drivers, forces, tol);
        let ok = ic.assembly.converged && !ic.inconsistent();
        let v0 = ic
            .velocity
            .as_ref()
            .map(|v| v.velocities.clone())
            .unwrap_or_default();
        let start = ok.then(|| ic.assembly.state.clone());
        (ic, None, start, v0)
    };
    let Some(start) = start else {
        let why = if start_at_equilibrium {
            "no static equilibrium was found"
        } else {
            "the model could not be assembled"
        };
        return DynamicRun {
            ic,
            equilibrium,
            simulation: None,
            error: Some(why.into()),
        };
    };
    let rows = crate::ic::admitted_rows(&ic.analysis);
    let redundant: Vec<usize> = ic.analysis.redundant.iter().map(|r| r.row).collect();
    let problem = Problem {
        model,
        sys: &sys,
        rows: &rows,
        redundant: &redundant,
        drivers,
        forces,
        damping: None,
        frozen_time: None,
    };
    let sim = simulate(&problem, &start, &v0, times, settings, progress);
    DynamicRun {
        ic,
        equilibrium,
        simulation: Some(sim),
        error: None,
    }
}
