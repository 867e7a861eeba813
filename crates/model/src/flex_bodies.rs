//! Linear flexible bodies (FLEX_BODY, ADM-ELEMENTS §19) in the model.
//!
//! A flex body has six rigid coordinates (its reference frame, the BCS) and one modal
//! amplitude `q_j` per selected mode. A point P of the body (a node) is at
//! `r_P = x + A·(s_P + Φ_P·q)` and turned by the small rotation `θ_P = Φ*_P·q` (in BCS axes)
//! from the reference frame's axes [doc: adams_flex/flex_theory]. linkage keeps the solver's
//! six-columns-per-body layout and represents the body by ordinary bodies of the model, named
//! after it:
//!
//! - the **reference body** `<name>` (the dataset's FLEX_BODY as a part): mass INVAR1, centre
//!   of mass INVAR2/INVAR1, inertia INVAR7 moved to the centre of mass; its axes are the BCS;
//! - one **mode body** `<name>.mode_<label>` per selected mode: its translation along a fixed
//!   ground direction (`FlexBody::axis`, chosen normal to gravity so that weight does not act
//!   on it) *is* the modal coordinate, `q_j = (p − rest)·axis`; a hidden translational guide
//!   to ground holds its other five coordinates; its mass is the generalized mass (INVAR6's
//!   diagonal); the modal stiffness and damping act on it as a hidden bushing to ground
//!   (`k_j` = GENSTIFF's diagonal, `c_j = 2 ζ_j ω_j m_j`);
//! - one massless **node body** `<name>.node_<id>` per node markers use (`NODE_ID`): the six
//!   node equations (`ConstraintKind::FlexNode`) tie its frame to the reference body and the
//!   mode bodies: `(P_node − (x + A s_P))·A e_k − Σ_j Φ_Pj,k q_j = 0` for k = x, y, z, and
//!   `z_n·x_b − θ_y = 0`, `z_n·y_b + θ_x = 0`, `x_n·y_b − θ_z = 0` with `θ = Φ*_P·q`
//!   (first order in the node's rotation relative to the BCS axes, as the modal theory is).
//!
//! Each mode body adds 6 columns and 5 equations, each node body 6 and 6: the body
//! contributes `6 + modes` to the Gruebler count, as the chapter says, and its modal
//! coordinates are in the constraint Jacobian through the node equations.
//!
//! **The weight** acts on the reference body (INVAR1 at the centre of mass) and, through
//! INVAR3 `= Σ m_p Φ_p`, on the modes: from `V = −gᵀ(x·I1 + A·(I2 + I3·q))` the
//! generalized force on mode j is `gᵀ·A·I3_j` and the torque on the reference body
//! `(A·I3·q) × g` (the weight of the deformation's first moment), a force element of the
//! solver (`physics::forces::flex_weight`).
//!
//! **The inertia coupling** (`crate::flex_bodies::ModalInertia`, the solver's
//! `physics::flex_inertia` and `physics::forces::flex_velocity`): the kinetic energy of the
//! body, with `c` its undeformed centre of mass, `d = I3·q`, `v` the CM velocity and `ω` the
//! angular velocity in BCS axes,
//!
//! ```text
//! T = ½ I1 |v|² + vᵀ(ω × d + I3 q̇) + ½ ωᵀ J_c(q) ω + ωᵀ K(q) q̇ + ½ q̇ᵀ I6 q̇
//! J_c(q) = I_cm + [c]×[d]× + [d]×[c]× − Σ_j (I8_j + I8_jᵀ) q_j − Σ_jk I9_jk q_j q_k
//! K(q)   = I4 − [c]×·I3 + Σ_k q_k I5_k        (column j: I4_j − c × I3_j + Σ_k q_k I5_kj)
//! ```
//!
//! (`I_cm = I7 − I1 [c]×ᵀ[c]×`, the inertia about c at q = 0) gives the mass matrix (its rigid blocks `I1·𝟙`, `I_cm` on the reference body, `I6` on the
//! mode bodies; the rest is the coupling added by the solver) and the quadratic velocity
//! terms from Lagrange's equations in the body's axes. Invariants switched off by
//! `INVARIANTS` (or not listed) are zero; with 3, 4, 5, 8 and 9 off the mass matrix is block
//! diagonal, which is exact for a body whose reference frame is held and, at the
//! linearization about rest, for free-free modes orthogonal to the rigid-body motion
//! (mean-axis modes, for which invariants 3 and 4 vanish).

use crate::bodies::Origin;
use glam::{DMat3, DVec3};

/// Statement keyword of the flex bodies' parts, hidden markers, guides and bushings.
pub const FLEX_BODY_STATEMENT: &str = "FLEX_BODY";

/// One selected mode.
#[derive(Clone, Debug, PartialEq)]
pub struct FlexMode {
    /// The mode's number (SELMOD).
    pub label: u64,
    /// The mode body (index into [`crate::Model::parts`]).
    pub part: usize,
    /// Generalized mass `m_j` (INVAR6's diagonal).
    pub mass: f64,
    /// Modal stiffness `k_j` (GENSTIFF's diagonal).
    pub stiffness: f64,
    /// Damping ratio ζ_j (CRATIO, or Adams' default by frequency).
    pub damping_ratio: f64,
    /// Natural frequency `√(k_j/m_j)/2π` in cycles per model time unit.
    pub frequency: f64,
    /// First moment of mass of the mode, `Σ_p m_p Φ_pj` (INVAR3's column j, BCS axes; zero
    /// without INVAR3): the weight's generalized force on the mode is `gᵀ·A·first_moment`.
    pub first_moment: DVec3,
}

/// One node markers use.
#[derive(Clone, Debug, PartialEq)]
pub struct FlexNode {
    pub id: u64,
    /// The node body (index into [`crate::Model::parts`]).
    pub part: usize,
    /// Undeformed position `s_P` in the BCS.
    pub position: DVec3,
    /// Translational shape `Φ_P` of each mode (BCS axes), in the order of [`FlexBody::modes`].
    pub translation: Vec<DVec3>,
    /// Rotational shape `Φ*_P` of each mode (small rotation vector, BCS axes).
    pub rotation: Vec<DVec3>,
}

/// A FLEX_BODY.
#[derive(Clone, Debug, PartialEq)]
pub struct FlexBody {
    pub origin: Origin,
    /// The reference body (index into [`crate::Model::parts`]).
    pub reference: usize,
    /// The BCS origin in the reference body's frame (its frame is at the centre of mass, with
    /// the BCS axes).
    pub bcs_in_body: DVec3,
    pub modes: Vec<FlexMode>,
    pub nodes: Vec<FlexNode>,
    /// Ground direction along which each mode body moves (normal to gravity).
    pub axis: DVec3,
    /// Ground point of every mode body at q = 0 (the BCS origin at the input).
    pub rest: DVec3,
    /// The first FLEX_NODE constraint of this body (index into
    /// [`crate::Model::constraints`]); its nodes' equations follow in node order.
    pub first_node_constraint: usize,
    /// The dataset's mode numbers (SELMOD), one per modal coordinate q of the dataset.
    pub labels: Vec<u64>,
    /// The invariants of the inertia coupling beyond INVAR3 ([`FlexMode::first_moment`]).
    pub inertia: ModalInertia,
    /// The principal basis `V` (row-major m × m, `q = V·η`) when GENSTIFF or INVAR6 is not
    /// diagonal: [`FlexBody::modes`] are then the principal modes η
    /// (`crate::modal_basis`); `None`: the modes are the dataset's.
    pub basis: Option<Vec<f64>>,
}

/// The inertia invariants 4, 5, 8 and 9 of a flex body (BCS axes, in the order of
/// [`FlexBody::modes`]); an empty list is zero (switched off or not listed).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ModalInertia {
    /// INVAR4 per mode j: `Σ_p m_p s_p × Φ_pj + I_p Φ*_pj` (rotation–mode coupling).
    pub i4: Vec<DVec3>,
    /// INVAR5: `i5[k][j] = Σ_p m_p Φ_pk × Φ_pj` (its change with q_k).
    pub i5: Vec<Vec<DVec3>>,
    /// INVAR8 per mode j: `Σ_p m_p [s_p]×[Φ_pj]×` (the inertia's first-order change).
    pub i8: Vec<DMat3>,
    /// INVAR9: `i9[j][k] = Σ_p m_p [Φ_pj]×[Φ_pk]×` (its second-order change).
    pub i9: Vec<Vec<DMat3>>,
}

impl FlexBody {
    /// Whether the mass matrix couples the rigid and modal coordinates (some invariant 3,
    /// 4, 5, 8 or 9 is not zero).
    pub fn coupled(&self) -> bool {
        self.modes.iter().any(|m| m.first_moment != DVec3::ZERO)
            || !self.inertia.i4.is_empty()
            || !self.inertia.i5.is_empty()
            || !self.inertia.i8.is_empty()
            || !self.inertia.i9.is_empty()
    }

    /// Degrees of freedom in the Gruebler count: the modes + 6.
    pub fn gruebler_dof(&self) -> usize {
        self.modes.len() + 6
    }

    /// The dataset's modal coordinates `q` (in the order of [`FlexBody::labels`]) from the
    /// coordinates of the mode bodies `eta` (in the order of [`FlexBody::modes`]).
    pub fn coordinates(&self, eta: &[f64]) -> Vec<f64> {
        match &self.basis {
            None => eta.to_vec(),
            Some(v) => {
                let m = eta.len();
                (0..m)
                    .map(|i| (0..m).map(|j| v[i * m + j] * eta[j]).sum())
                    .collect()
            }
        }
    }

    /// Every part of this body: the reference, the mode bodies and the node bodies.
    pub fn parts(&self) -> impl Iterator<Item = usize> + '_ {
        std::iter::once(self.reference)
            .chain(self.modes.iter().map(|m| m.part))
            .chain(self.nodes.iter().map(|n| n.part))
    }
}

/// Adams' default modal damping ratio by natural frequency in Hz [doc: AS/state_flex_body]:
/// 1 % below 100 Hz, 10 % below 1 kHz, critical (100 %) above.
pub fn default_damping_ratio(frequency_hz: f64) -> f64 {
    if frequency_hz < 100.0 {
        0.01
    } else if frequency_hz < 1000.0 {
        0.1
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_damping_steps_at_100_hz_and_1_khz() {
        assert_eq!(default_damping_ratio(99.9), 0.01);
        assert_eq!(default_damping_ratio(100.0), 0.1);
        assert_eq!(default_damping_ratio(999.0), 0.1);
        assert_eq!(default_damping_ratio(1000.0), 1.0);
    }
}
