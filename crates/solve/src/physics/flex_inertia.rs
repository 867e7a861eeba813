//! The inertia coupling of the flex bodies' rigid and modal coordinates in the mass matrix
//! (the model side and the kinetic energy in `linkage_model::flex_bodies`).
//!
//! A flex body is its reference body (6 coordinates: CM velocity `v`, angular velocity `ω`,
//! ground axes) and one mode body per mode, whose velocity along its guide's `axis` is
//! `q̇_j`. The analyses' mass matrix holds the blocks every part has (`I1·𝟙` and
//! `A I_cm Aᵀ` on the reference body, `I6_jj·𝟙` on mode body j); [`FlexCoupling`] adds the
//! rest of the flex body's mass matrix `ΔM(A, q)`, with `d = I3·q` and `c` the undeformed
//! centre of mass (BCS):
//!
//! ```text
//! (v, ω)    −[A d]×                (ω, v)    [A d]×
//! (v, q_j)  A I3_j · axisᵀ         (q_j, v)  axis · (A I3_j)ᵀ
//! (ω, ω)    A ΔJ(q) Aᵀ,            ΔJ = Σ_j q_j L_j − Σ_jk q_j q_k I9_jk,
//!                                   L_j = [c]×[I3_j]× + [I3_j]×[c]× − I8_j − I8_jᵀ
//! (ω, q_j)  A K_j(q) · axisᵀ,      K_j = I4_j − c × I3_j + Σ_k q_k I5_kj     (and transposed)
//! ```
//!
//! The mode bodies' generalized mass is diagonal (a full INVAR6 becomes the principal basis in
//! the model), so there is no mode–mode block. The matching quadratic velocity terms are a
//! force element (`physics::forces::flex_velocity`). Every analysis that uses the mass matrix
//! (the integrators' iteration matrix and residual, the consistent velocities, accelerations
//! and IC, linear's M, the kinetic energy, the constraint remainder of requests) adds
//! [`FlexCoupling`]'s blocks to its own.

use crate::state::State;
use glam::{DMat3, DVec3};
use linkage_model::frames::skew;
use linkage_model::Model;

/// The body-frame invariants of one coupled flex body, in the form the mass matrix and the
/// velocity terms use.
#[derive(Clone, Debug, PartialEq)]
pub struct FlexTerms {
    /// The reference body and the mode bodies (indices into the model's parts).
    pub reference: usize,
    pub modes: Vec<usize>,
    /// Ground direction of the mode bodies' guides and their point at q = 0.
    pub axis: DVec3,
    pub rest: DVec3,
    /// `I3_j` per mode (BCS).
    pub i3: Vec<DVec3>,
    /// `L_j = [c]×[I3_j]× + [I3_j]×[c]× − I8_j − I8_jᵀ`: ΔJ's first-order change with q_j.
    pub l: Vec<DMat3>,
    /// `K_j(0) = I4_j − c × I3_j`.
    pub k0: Vec<DVec3>,
    /// INVAR5 `i5[k][j]` (empty: zero).
    pub i5: Vec<Vec<DVec3>>,
    /// INVAR9 `i9[j][k]` (empty: zero).
    pub i9: Vec<Vec<DMat3>>,
}

impl FlexTerms {
    /// The terms of flex body `b`, or `None` when it is not coupled.
    pub fn of(b: &linkage_model::flex_bodies::FlexBody) -> Option<FlexTerms> {
        if !b.coupled() {
            return None;
        }
        let c = -b.bcs_in_body;
        let m = b.modes.len();
        let i3: Vec<DVec3> = b.modes.iter().map(|x| x.first_moment).collect();
        let inv = &b.inertia;
        let l = (0..m)
            .map(|j| {
                let s = skew(c) * skew(i3[j]) + skew(i3[j]) * skew(c);
                match inv.i8.get(j) {
                    Some(i8) => s - *i8 - i8.transpose(),
                    None => s,
                }
            })
            .collect();
        let k0 = (0..m)
            .map(|j| inv.i4.get(j).copied().unwrap_or(DVec3::ZERO) - c.cross(i3[j]))
            .collect();
        Some(FlexTerms {
            reference: b.reference,
            modes: b.modes.iter().map(|x| x.part).collect(),
            axis: b.axis,
            rest: b.rest,
            i3,
            l,
            k0,
            i5: inv.i5.clone(),
            i9: inv.i9.clone(),
        })
    }

    /// The modal coordinates `q_j = (p_j − rest)·axis` at `s`.
    pub fn coordinates(&self, s: &State) -> Vec<f64> {
        self.modes
            .iter()
            .map(|&p| (s.poses[p].p - self.rest).dot(self.axis))
            .collect()
    }

    /// `ΔJ(q) = Σ_j q_j L_j − Σ_jk q_j q_k I9_jk` (BCS).
    pub fn inertia_change(&self, q: &[f64]) -> DMat3 {
        let mut out = DMat3::ZERO;
        for (j, lj) in self.l.iter().enumerate() {
            out += *lj * q[j];
        }
        for (j, row) in self.i9.iter().enumerate() {
            for (k, x) in row.iter().enumerate() {
                out -= *x * (q[j] * q[k]);
            }
        }
        out
    }

    /// `K_j(q) = K_j(0) + Σ_k q_k I5_kj` (BCS).
    pub fn rotation_coupling(&self, q: &[f64], j: usize) -> DVec3 {
        let mut out = self.k0[j];
        for (k, row) in self.i5.iter().enumerate() {
            out += row[j] * q[k];
        }
        out
    }

    /// Calls `block(row, column, B)` for every 3 × 3 block of `ΔM` at `s` (rows and
    /// columns in the 6-per-part layout).
    pub fn blocks(&self, s: &State, mut block: impl FnMut(usize, usize, DMat3)) {
        let a = s.poses[self.reference].r;
        let q = self.coordinates(s);
        let d: DVec3 = self.i3.iter().zip(&q).map(|(i, x)| *i * *x).sum();
        let r = 6 * self.reference;
        let ad = skew(a * d);
        block(r, r + 3, -ad);
        block(r + 3, r, ad);
        block(r + 3, r + 3, a * self.inertia_change(&q) * a.transpose());
        for (j, &p) in self.modes.iter().enumerate() {
            let pm = 6 * p;
            let t = outer(a * self.i3[j], self.axis);
            block(r, pm, t);
            block(pm, r, t.transpose());
            let w = outer(a * self.rotation_coupling(&q, j), self.axis);
            block(r + 3, pm, w);
            block(pm, r + 3, w.transpose());
        }
    }
}

/// `u wᵀ`.
fn outer(u: DVec3, w: DVec3) -> DMat3 {
    DMat3::from_cols(u * w.x, u * w.y, u * w.z)
}

/// The coupled flex bodies of a model.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FlexCoupling {
    pub bodies: Vec<FlexTerms>,
}

impl FlexCoupling {
    pub fn new(model: &Model) -> FlexCoupling {
        FlexCoupling {
            bodies: model.flex_bodies.iter().filter_map(FlexTerms::of).collect(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.bodies.is_empty()
    }

    /// Calls `block(row, column, B)` for every 3 × 3 block of `ΔM` at `s`.
    pub fn blocks(&self, s: &State, mut block: impl FnMut(usize, usize, DMat3)) {
        for b in &self.bodies {
            b.blocks(s, &mut block);
        }
    }

    /// Calls `add(row, column, value)` for every entry of `ΔM` at `s` (6-per-part layout).
    pub fn entries(&self, s: &State, mut add: impl FnMut(usize, usize, f64)) {
        for b in &self.bodies {
            b.blocks(s, |r, c, m| {
                for j in 0..3 {
                    for i in 0..3 {
                        add(r + i, c + j, m.col(j)[i]);
                    }
                }
            });
        }
    }

    /// `out += factor · ΔM(s)·x` (both 6 per part).
    pub fn add_product(&self, s: &State, x: &[f64], factor: f64, out: &mut [f64]) {
        self.entries(s, |i, j, m| out[i] += factor * m * x[j]);
    }

    /// `½ vᵀ ΔM v` (model mass × velocity², `v` 6 per part): the coupling's kinetic energy.
    pub fn kinetic_energy(&self, s: &State, v: &[f64]) -> f64 {
        let mut e = 0.0;
        self.entries(s, |i, j, m| e += 0.5 * v[i] * m * v[j]);
        e
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::state::Pose;

    /// One mode with a first moment along y and a rotation coupling about z: ΔM is symmetric
    /// and the coupling's kinetic energy is `v·(ω × A d) + (v·A I3 + ω·A K) q̇ + ½ ωᵀ A ΔJ Aᵀ ω`.
    #[test]
    fn coupling_blocks_are_symmetric_and_give_the_cross_kinetic_energy() {
        let terms = FlexTerms {
            reference: 0,
            modes: vec![1],
            axis: DVec3::X,
            rest: DVec3::ZERO,
            i3: vec![DVec3::new(0.0, 2.0, 0.0)],
            l: vec![DMat3::from_diagonal(DVec3::new(0.1, 0.2, 0.3))],
            k0: vec![DVec3::new(0.0, 0.0, 1.5)],
            i5: Vec::new(),
            i9: Vec::new(),
        };
        let a = DMat3::from_rotation_z(0.4) * DMat3::from_rotation_x(-0.3);
        let s = State {
            time: 0.0,
            poses: vec![
                Pose {
                    p: DVec3::ZERO,
                    r: a,
                },
                Pose {
                    p: DVec3::new(0.25, 7.0, 0.0),
                    r: DMat3::IDENTITY,
                },
            ],
            controls: Default::default(),
            elements: Default::default(),
        };
        let coupling = FlexCoupling {
            bodies: vec![terms.clone()],
        };
        let mut m = [[0.0; 12]; 12];
        coupling.entries(&s, |i, j, x| m[i][j] += x);
        for (i, row) in m.iter().enumerate() {
            for (j, x) in row.iter().enumerate() {
                assert!((x - m[j][i]).abs() < 1e-15, "{i} {j}");
            }
        }
        let (v, w, qd) = (DVec3::new(0.3, -1.0, 2.0), DVec3::new(0.5, 0.1, -0.7), 0.9);
        let x = [v.x, v.y, v.z, w.x, w.y, w.z, qd, 5.0, -3.0, 1.0, 1.0, 1.0];
        let q = 0.25;
        let d = terms.i3[0] * q;
        let expected = v.dot(w.cross(a * d))
            + (v.dot(a * terms.i3[0]) + w.dot(a * terms.k0[0])) * qd
            + 0.5 * w.dot(a * (terms.l[0] * q) * a.transpose() * w);
        let got = coupling.kinetic_energy(&s, &x);
        assert!((got - expected).abs() < 1e-13, "{got} {expected}");
    }
}
