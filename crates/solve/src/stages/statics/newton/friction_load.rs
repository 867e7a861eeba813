//! Joint friction in the static Newton iteration: each FRICTION's normal load is taken from its
//! joint's reaction at the current iterate, and the Newton matrix carries the coupling.
//!
//! The reaction on the joint's I marker (force and torque about its origin) is linear in the
//! joint's multipliers, `w(q, λ) = Σ_k λ_k u_k(q)` over the joint's rows k in the solve
//! (`u_k`: minus row k's gradient block on I's part, moved to the I marker; with I on ground,
//! the sum of its blocks on the parts — as `physics::reactions` computes reactions). The
//! normal load is `N(w)` ([`crate::physics::forces::friction::load`]) and the friction is
//! linear in it, `Q_f = μ(s)·N·(direction)`, so the residual and its multiplier columns are
//!
//! ```text
//! F(q, λ) = Q(q, N(w(q, λ))) − Jᵀλ
//! −∂F/∂λ_k = J_kᵀ − (∂Q_f/∂N)·(∇_w N · u_k)        (the block this module adds)
//! ```
//!
//! The dependence of `u_k` and of the load's geometry on q is left out of `K_T` (it is the
//! reaction's lever arm, of the order of the friction force times a rotation): the Newton
//! iteration converges to the same equilibrium, in which the friction acts with the normal
//! load of the final reactions. Joints whose rows were all removed as redundant carry no
//! reaction (as in Adams): their load is the preload alone and adds no coupling.
//!
//! Buffers are sized once per solve; an update and a fill allocate nothing.

use super::Problem;
use crate::constraints::rows::{RowGradient, Velocities};
use crate::physics::applied::Regime;
use crate::state::State;
use glam::DVec3;
use linkage_model::bodies::Body;

/// A Newton step takes a friction from well inside its stiction band (deformation below
/// MAX_STICTION_DEFORMATION) at most to this fraction of the band: beyond it the stiction
/// spring ends and the friction is a constant μs·N, so a step that overshoots (its normal
/// load not yet the final one) would lose the equilibrium the friction holds.
const STICTION_REACH: f64 = 0.9;

/// One active friction and its joint's rows in the solve.
struct Coupled {
    /// Index in the force set's frictions.
    friction: usize,
    /// Indices into the solve's rows (and multipliers) of the joint's rows.
    rows: Vec<usize>,
    /// `∂N/∂λ` of each of them at the last update.
    dn: Vec<f64>,
}

/// The frictions of one static solve whose normal loads follow the multipliers.
pub(super) struct FrictionLoads {
    coupled: Vec<Coupled>,
    /// The configuration a step would reach (sized once).
    trial: State,
}

impl FrictionLoads {
    /// The active frictions of `p` (none inactive in statics); `None` without frictions.
    pub fn new(p: &Problem, start: &State) -> Option<FrictionLoads> {
        let set = p.forces.joint_frictions()?;
        let coupled = set
            .laws()
            .iter()
            .enumerate()
            .filter(|(k, _)| set.acts(Regime::Static, *k))
            .map(|(k, law)| {
                let rows: Vec<usize> = p
                    .used
                    .iter()
                    .enumerate()
                    .filter(|(_, (r, _))| p.sys.rows[*r].element == law.friction.joint)
                    .map(|(i, _)| i)
                    .collect();
                Coupled {
                    friction: k,
                    dn: vec![0.0; rows.len()],
                    rows,
                }
            })
            .collect();
        Some(FrictionLoads {
            coupled,
            trial: start.clone(),
        })
    }

    /// The factor (at most 1) on the step `scale·steps` from `s` that stops the frictions
    /// inside their stiction bands at [`STICTION_REACH`] of them: from the largest deformation
    /// fractions before (`f₀ < REACH`) and after the step (`f₁ > 1`), `(REACH − f₀)/(f₁ − f₀)`.
    /// The next step may leave the band (a friction can be stopped once), with the normal
    /// load of the new reactions.
    pub fn stiction_scale(
        &mut self,
        p: &Problem,
        s: &State,
        steps: &[(DVec3, DVec3)],
        scale: f64,
        rest: &Velocities,
    ) -> f64 {
        let Some(set) = p.forces.joint_frictions() else {
            return 1.0;
        };
        // A friction already at the reach (stopped there by the last step, or held near
        // its limit) may leave the band: its equilibrium can lie beyond, sliding at μs·N
        // with other loads taking the rest.
        let before = set.stiction_fraction(Regime::Static, s, rest);
        if before >= STICTION_REACH {
            return 1.0;
        }
        self.trial.poses.copy_from_slice(&s.poses);
        self.trial.elements.clone_from(&s.elements);
        for (k, &(dx, dth)) in steps.iter().enumerate() {
            self.trial.increment(k, dx * scale, dth * scale);
        }
        let after = set.stiction_fraction(Regime::Static, &self.trial, rest);
        if after <= 1.0 {
            return 1.0;
        }
        ((STICTION_REACH - before).max(0.0) / (after - before)).clamp(0.0, 1.0)
    }

    /// Sets each friction's normal load in `s` from the multipliers `lambda` there (the rows'
    /// gradients `grads` there) and keeps `∂N/∂λ` for the Newton matrix.
    pub fn update(&mut self, p: &Problem, s: &mut State, grads: &[RowGradient], lambda: &[f64]) {
        let Some(set) = p.forces.joint_frictions() else {
            return;
        };
        for c in &mut self.coupled {
            let law = &set.laws()[c.friction];
            let (body, p_i) = law.reaction_point(s);
            let (mut force, mut torque) = (DVec3::ZERO, DVec3::ZERO);
            for &row in &c.rows {
                let (f, t) = unit_reaction(body, p_i, s, &grads[row]);
                force += lambda[row] * f;
                torque += lambda[row] * t;
            }
            let (normal, dn_f, dn_t) = law.normal_gradient(s, force, torque);
            for (dn, &row) in c.dn.iter_mut().zip(&c.rows) {
                let (f, t) = unit_reaction(body, p_i, s, &grads[row]);
                *dn = dn_f.dot(f) + dn_t.dot(t);
            }
            set.set_normal(s, c.friction, normal);
        }
    }

    /// Adds `−(∂Q_f/∂N)(∂N/∂λ_k)` to the Newton matrix `out` (rows of the 6n balance
    /// equations, columns `6n + k` of the multipliers), at `s` with the parts at rest.
    pub fn fill(
        &self,
        p: &Problem,
        s: &State,
        rest: &Velocities,
        out: &mut Vec<(usize, usize, f64)>,
    ) {
        let Some(set) = p.forces.joint_frictions() else {
            return;
        };
        let n6 = 6 * p.parts();
        for c in &self.coupled {
            let law = &set.laws()[c.friction];
            let per_unit = law.per_unit_load(s, rest, &set.state(s, c.friction));
            for (part, dq) in per_unit.into_iter().flatten() {
                for (component, d) in dq.iter().enumerate() {
                    for (dn, &row) in c.dn.iter().zip(&c.rows) {
                        out.push((6 * part + component, n6 + row, -d * dn));
                    }
                }
            }
        }
    }
}

/// The reaction on the I marker (force, torque about its origin `p_i`, ground axes) per unit
/// multiplier of a row with gradient `g`: minus the row's block on I's part, or with I on
/// ground the sum of its blocks on the parts, each torque moved from the part's CM to `p_i`.
fn unit_reaction(body: Body, p_i: DVec3, s: &State, g: &RowGradient) -> (DVec3, DVec3) {
    let (mut force, mut torque) = (DVec3::ZERO, DVec3::ZERO);
    for (k, b) in &g.blocks {
        let sign = match body.part() {
            Some(i) if i == *k => -1.0,
            Some(_) => continue,
            None => 1.0,
        };
        let f = sign * DVec3::new(b[0], b[1], b[2]);
        let t = sign * DVec3::new(b[3], b[4], b[5]);
        force += f;
        torque += t + (s.poses[*k].p - p_i).cross(f);
    }
    (force, torque)
}
