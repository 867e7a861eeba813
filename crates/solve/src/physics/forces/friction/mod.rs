//! FRICTION on joints (ADM-ELEMENTS §4): the stick-slip model of Adams as an applied force
//! element of the [`crate::physics::forces::ForceSet`], with a state of its own.
//!
//! **Slip.** Each joint type slips in 1 to 3 directions at its contact surface, measured in
//! J's axes, in length units (R = PIN_RADIUS, or BALL_RADIUS for a spherical joint):
//!
//! | joint | slip velocity `v` | stiction deformation `s` | friction load on I (−on J), at P_i |
//! |---|---|---|---|
//! | translational | `v_rel·z_j` | `(P_i − P_j)·z_j − a` | force `g₀·z_j` |
//! | revolute | `R·ω_rel·z_j` | `R·φ_z` | torque `R·g₀·z_j` |
//! | cylindrical | both of the above | both | force `g₀·z_j`, torque `R·g₁·z_j` |
//! | spherical, universal/hooke | `R·ω_rel` (J axes) | `R·φ` | torque `R·(g₀ x_j + g₁ y_j + g₂ z_j)` |
//!
//! `v_rel = v_Pi − v_Pj − ω_j × (P_i − P_j)` and `ω_rel = ω_i − ω_j` (as BUSHING measures
//! them); `φ` is the rotation of I relative to J since the *anchor* `A` (the relative
//! orientation `R_jᵀR_i` where the deformation is zero): `φ = vee(skew(R_jᵀR_i·Aᵀ))` for
//! spherical and universal joints — its direction is the rotation axis, its size `sin|φ|`,
//! which is all it needs: between steps `|R·φ| ≤ Δmax`, and while sliding the deformation is
//! saturated (right up to half a turn in one step) — and for revolute and cylindrical joints
//! `φ_z` the angle about z_j (atan2, to ±π), so that the axial and circumferential slip of a
//! cylindrical joint keep their proportion over a long step. `a` is the
//! anchor's travel. The friction `g = μ(s, v)·N` ([`regime`]) with the normal load `N`
//! ([`load`]).
//!
//! **State and the implicit coupling.** The friction depends on the joint's reaction, which
//! the analyses solve together with the motion. Outside statics linkage breaks the loop by
//! lagging the normal load: `N` and the anchor are a [`FrictionState`] per friction, data of the
//! run's [`State`] (`State::elements`), updated at accepted states only
//! ([`crate::physics::applied::AppliedForces::accept_state`]); the force set holds none:
//! - the IC sets the anchors at the assembled pose, solves the accelerations and reactions,
//!   takes `N` from them and solves again (`pipeline::ic`);
//! - statics takes `N` from the joint's multipliers at every Newton iterate, with the
//!   coupling `∂Q/∂λ` in the Newton matrix (`stages/statics/newton/friction_load.rs`), so the
//!   equilibrium holds with the load of its own reactions (the friction in statics is the
//!   stiction spring about the anchor at the start: a block on a ramp with `tan θ < μs` is
//!   held with a deformation below Δmax; `INACTIVE_DURING = STATIC` switches the friction off
//!   in statics and dynamic settling);
//! - a dynamic run takes `N` from the consistent output after every accepted step, and each
//!   step is solved with the friction's exact derivatives in `s` (positions) and `v` in the
//!   Newton matrix, `N` held at the last accepted step's value. With a normal load that
//!   changes slowly over a step (a block on a ramp, a disc on a pin, a brake) this is the
//!   implicit solution; where the reaction jumps the friction follows one step later.
//! - after each accepted state the anchor trails so that `|s| ≤ Δmax`: a sticking joint
//!   creeps by less than Δmax whatever the time, a sliding one carries `|s| = Δmax`.
//!
//! A joint row removed as redundant carries no reaction (as in Adams), so it feeds no load.

pub mod load;
pub mod regime;
mod set;

pub use set::FrictionSet;

use super::algebra::{Kinematics, Real, V3};
use super::{Context, Load, Loads};
use crate::constraints::rows::{BodyFrame, Velocities};
use crate::physics::reactions::Reaction;
pub use crate::state::FrictionState;
use crate::state::State;
use glam::{DMat3, DVec3};
use linkage_model::frames::{exp_so3, log_so3};
use linkage_model::friction::{Friction, FrictionJoint};
use regime::Regime;

/// One FRICTION, ready to evaluate.
#[derive(Clone, Debug)]
pub struct FrictionLaw {
    pub friction: Friction,
    pub i: BodyFrame,
    pub j: BodyFrame,
    pub regime: Regime,
}

/// The slip of a joint at a state (module docs), with what its loads need.
pub struct Slip<R> {
    /// Components used: 1 (translational, revolute), 2 (cylindrical), 3 (rotations).
    pub dims: usize,
    pub deformation: [R; 3],
    pub velocity: [R; 3],
    /// x_j, y_j, z_j in ground.
    pub axes: [V3<R>; 3],
    pub p_i: V3<R>,
    /// The travel along z_j and the relative orientation `R_jᵀR_i`.
    pub travel: f64,
    pub rotation: DMat3,
}

/// The value of one friction at a state, for the reports: the friction load on I's part in
/// J's axes (force and torque) and the normal load it came from.
#[derive(Clone, Debug, PartialEq)]
pub struct FrictionValue {
    /// The FRICTION's name.
    pub name: String,
    pub force: DVec3,
    pub torque: DVec3,
    pub normal: f64,
    /// The slip speed at the surface (length/time) and whether it is in the stiction regime.
    pub slip_speed: f64,
    pub sticking: bool,
}

impl FrictionLaw {
    pub fn new(friction: &Friction, i: BodyFrame, j: BodyFrame) -> FrictionLaw {
        FrictionLaw {
            i,
            j,
            regime: Regime {
                mu_static: friction.mu_static,
                mu_dynamic: friction.mu_dynamic,
                stiction_velocity: friction.stiction_velocity,
                transition_coefficient: friction.transition_coefficient,
                max_deformation: friction.max_stiction_deformation,
                effect: friction.effect,
            },
            friction: friction.clone(),
        }
    }

    /// The state with the anchor at `s` and the normal load of the preloads alone.
    pub fn start(&self, s: &State) -> FrictionState {
        let (travel, rotation) = self.relative(s);
        let preload_only = load::normal_load(
            &self.friction,
            &self.j.eval(s).1,
            travel,
            DVec3::ZERO,
            DVec3::ZERO,
        );
        FrictionState {
            anchor_travel: travel,
            anchor_rotation: rotation,
            normal: preload_only,
        }
    }

    /// The travel along z_j and `R_jᵀR_i` at `s`.
    fn relative(&self, s: &State) -> (f64, DMat3) {
        let (p_i, r_i) = self.i.eval(s);
        let (p_j, r_j) = self.j.eval(s);
        ((p_i - p_j).dot(r_j.col(2)), r_j.transpose() * r_i)
    }

    /// The slip at the kinematics of `kin` from the anchor of `st`.
    pub fn slip<R: Real>(&self, kin: &Kinematics, st: &FrictionState) -> Slip<R> {
        let (pi_b, pj_b) = (self.i.origin(), self.j.origin());
        let ej = [0, 1, 2].map(|k| kin.dir::<R>(&self.j.axis(k)));
        let p_i = kin.point::<R>(&pi_b);
        let d = p_i.sub(&kin.point::<R>(&pj_b));
        let wj = kin.omega::<R>(self.j.body);
        let v_rel = kin
            .point_velocity::<R>(&pi_b)
            .sub(&kin.point_velocity::<R>(&pj_b))
            .sub(&wj.cross(&d));
        let w_rel = kin.omega::<R>(self.i.body).sub(&wj);
        let travel = d.dot(&ej[2]);
        let radius = self.friction.radius();
        let rotational = !matches!(self.friction.kind, FrictionJoint::Translational);
        let phi = if rotational {
            let ei = [0, 1, 2].map(|k| kin.dir::<R>(&self.i.axis(k)));
            // E = (R_jᵀR_i)·Aᵀ: E[a][b] = Σ_c (e_j,a · e_i,c)·A[b][c].
            let rel: [[R; 3]; 3] =
                std::array::from_fn(|a| std::array::from_fn(|c| ej[a].dot(&ei[c])));
            let a = &st.anchor_rotation;
            let e = |r: usize, c: usize| -> R {
                (0..3).fold(R::cst(0.0), |acc, k| acc.add(&rel[r][k].scale(a.col(k)[c])))
            };
            let about_z = e(1, 0).sub(&e(0, 1));
            let cos_z = e(0, 0).add(&e(1, 1));
            let turning = matches!(
                self.friction.kind,
                FrictionJoint::Revolute | FrictionJoint::Cylindrical
            );
            let z = if turning && (about_z.value() != 0.0 || cos_z.value() != 0.0) {
                // The angle about z_j itself (to ±π): exact, so that a cylindrical joint's
                // slip keeps its direction however far it turns in a step.
                R::atan2(&about_z, &cos_z)
            } else {
                about_z.scale(0.5)
            };
            [
                e(2, 1).sub(&e(1, 2)).scale(0.5),
                e(0, 2).sub(&e(2, 0)).scale(0.5),
                z,
            ]
        } else {
            [R::cst(0.0), R::cst(0.0), R::cst(0.0)]
        };
        let zero = || R::cst(0.0);
        let axial_s = travel.shift(-st.anchor_travel);
        let axial_v = v_rel.dot(&ej[2]);
        let (dims, deformation, velocity) = match self.friction.kind {
            FrictionJoint::Translational => {
                (1, [axial_s, zero(), zero()], [axial_v, zero(), zero()])
            }
            FrictionJoint::Revolute => (
                1,
                [phi[2].scale(radius), zero(), zero()],
                [w_rel.dot(&ej[2]).scale(radius), zero(), zero()],
            ),
            FrictionJoint::Cylindrical => (
                2,
                [axial_s, phi[2].scale(radius), zero()],
                [axial_v, w_rel.dot(&ej[2]).scale(radius), zero()],
            ),
            FrictionJoint::Spherical | FrictionJoint::Universal => (
                3,
                phi.map(|x| x.scale(radius)),
                [0, 1, 2].map(|k| w_rel.dot(&ej[k]).scale(radius)),
            ),
        };
        let (travel_value, rotation) = self.relative(kin.state);
        Slip {
            dims,
            deformation,
            velocity,
            axes: ej,
            p_i,
            travel: travel_value,
            rotation,
        }
    }

    /// The friction `g = μ(s, v)·N` in the slip components, and the slip.
    fn friction<R: Real>(&self, kin: &Kinematics, st: &FrictionState) -> ([R; 3], Slip<R>) {
        let slip = self.slip::<R>(kin, st);
        let n = slip.dims;
        let mut mu = [R::cst(0.0), R::cst(0.0), R::cst(0.0)];
        self.regime
            .coefficient(&slip.deformation[..n], &slip.velocity[..n], &mut mu[..n]);
        (mu.map(|m| m.scale(st.normal)), slip)
    }

    /// The friction's loads at `cx`: on I's part at P_i, and the opposite on J's part at the
    /// same point (module docs).
    pub fn loads<R: Real>(&self, cx: &Context, st: &FrictionState) -> Loads<R> {
        self.loads_at(&cx.kin, st)
    }

    /// [`FrictionLaw::loads`] at the kinematics `kin`.
    fn loads_at<R: Real>(&self, kin: &Kinematics, st: &FrictionState) -> Loads<R> {
        let (g, slip) = self.friction::<R>(kin, st);
        let radius = self.friction.radius();
        let [x, y, z] = &slip.axes;
        let zero = V3::zero;
        let (force, torque) = match self.friction.kind {
            FrictionJoint::Translational => (z.times(&g[0]), zero()),
            FrictionJoint::Revolute => (zero(), z.times(&g[0].scale(radius))),
            FrictionJoint::Cylindrical => (z.times(&g[0]), z.times(&g[1].scale(radius))),
            FrictionJoint::Spherical | FrictionJoint::Universal => {
                let [g0, g1, g2] = &g;
                let t = x.times(g0).add(&y.times(g1)).add(&z.times(g2));
                (zero(), t.times(&R::cst(radius)))
            }
        };
        let reaction = Load {
            body: self.j.body,
            point: slip.p_i.clone(),
            force: force.neg(),
            torque: torque.neg(),
        };
        [
            Some(Load {
                body: self.i.body,
                point: slip.p_i,
                force,
                torque,
            }),
            Some(reaction),
        ]
    }

    /// `∂Q/∂N`: the generalised force (force at the CM, torque about it, ground axes) on each
    /// of the two parts per unit of normal load at `(s, v)` from the anchor of `st` (the
    /// friction is `μ(s, v)·N`, linear in N); `None` for ground.
    pub fn per_unit_load(
        &self,
        s: &State,
        v: &Velocities,
        st: &FrictionState,
    ) -> [Option<(usize, [f64; 6])>; 2] {
        let kin = Kinematics {
            state: s,
            velocities: v,
        };
        let unit = FrictionState { normal: 1.0, ..*st };
        self.loads_at::<f64>(&kin, &unit).map(|load| {
            let load = load?;
            let linkage_model::bodies::Body::Part(k) = load.body else {
                return None;
            };
            let arm = load.point.value() - kin.cm::<f64>(load.body).value();
            let force = load.force.value();
            let moment = arm.cross(force) + load.torque.value();
            Some((k, [force.x, force.y, force.z, moment.x, moment.y, moment.z]))
        })
    }

    /// The I marker's body and origin (ground) at `s`: where the joint's reaction that loads
    /// the friction is taken.
    pub fn reaction_point(&self, s: &State) -> (linkage_model::bodies::Body, DVec3) {
        (self.i.body, self.i.eval(s).0)
    }

    /// The normal load from the joint's reaction on I (`force`, `torque` about I's origin,
    /// ground axes) at `s`, with its gradient ([`load::normal_load_gradient`]).
    pub fn normal_gradient(&self, s: &State, force: DVec3, torque: DVec3) -> (f64, DVec3, DVec3) {
        let (travel, _) = self.relative(s);
        load::normal_load_gradient(&self.friction, &self.j.eval(s).1, travel, force, torque)
    }

    /// The value of the friction at `(s, v)` for the reports (see [`FrictionValue`]).
    pub fn value(&self, s: &State, v: &Velocities, st: &FrictionState, on: bool) -> FrictionValue {
        let kin = Kinematics {
            state: s,
            velocities: v,
        };
        let (g, slip) = self.friction::<f64>(&kin, st);
        let g = if on { g } else { [0.0; 3] };
        let radius = self.friction.radius();
        let (force, torque) = match self.friction.kind {
            FrictionJoint::Translational => (DVec3::Z * g[0], DVec3::ZERO),
            FrictionJoint::Revolute => (DVec3::ZERO, DVec3::Z * radius * g[0]),
            FrictionJoint::Cylindrical => (DVec3::Z * g[0], DVec3::Z * radius * g[1]),
            FrictionJoint::Spherical | FrictionJoint::Universal => {
                (DVec3::ZERO, DVec3::from_array(g) * radius)
            }
        };
        let speed = slip.velocity[..slip.dims]
            .iter()
            .map(|c| c * c)
            .sum::<f64>()
            .sqrt();
        FrictionValue {
            name: self.friction.origin.name.clone(),
            force,
            torque,
            normal: st.normal,
            slip_speed: speed,
            sticking: speed < self.regime.stiction_velocity,
        }
    }

    /// The state after an accepted state `(s, v)` with the constraint `reactions`: the normal
    /// load from the joint's reaction ([`load::normal_load`]; none when the joint has no
    /// reaction, its rows being redundant), and the anchor moved so that `|s| ≤ Δmax`.
    pub fn accept(
        &self,
        s: &State,
        v: &Velocities,
        reactions: &[Reaction],
        st: &FrictionState,
    ) -> FrictionState {
        let kin = Kinematics {
            state: s,
            velocities: v,
        };
        let slip = self.slip::<f64>(&kin, st);
        let (force, torque) = reactions
            .iter()
            .find(|r| r.element == self.friction.joint)
            .map_or((DVec3::ZERO, DVec3::ZERO), |r| (r.force, r.torque));
        let r_gj = self.j.eval(s).1;
        let mut next = *st;
        next.normal = load::normal_load(&self.friction, &r_gj, slip.travel, force, torque);
        let n = slip.dims;
        let size = slip.deformation[..n]
            .iter()
            .map(|c| c * c)
            .sum::<f64>()
            .sqrt();
        let dmax = self.regime.max_deformation;
        if size > dmax {
            let keep = dmax / size;
            // The axial part: s' = keep·s.
            if matches!(
                self.friction.kind,
                FrictionJoint::Translational | FrictionJoint::Cylindrical
            ) {
                let s_axial = slip.travel - st.anchor_travel;
                next.anchor_travel = slip.travel - keep * s_axial;
            }
            // The rotational part: E' = exp(keep·log E), A' = exp(φ')ᵀ·R_jᵀR_i.
            if !matches!(self.friction.kind, FrictionJoint::Translational) {
                let e = slip.rotation * st.anchor_rotation.transpose();
                let phi = log_so3(&e) * keep;
                next.anchor_rotation = exp_so3(phi).transpose() * slip.rotation;
            }
        }
        next
    }
}
