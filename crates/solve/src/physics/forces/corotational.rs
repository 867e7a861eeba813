//! The corotational Euler–Bernoulli beam kernel shared by the FE_PART beam elements
//! ([`super::fe_beam`], between node bodies) and BEAM `FORMULATION = NONLINEAR`
//! ([`super::beam`], between the J and I markers).
//!
//! **Kinematics** (large rotations, small strains per element; Crisfield, *Non-linear Finite
//! Element Analysis of Solids and Structures*, vol. 2, 1997, ch. 17, the corotational idea).
//! Each end carries a frame `F = (f₁, f₂, f₃)` equal to the element's reference frame E₀ in
//! the undeformed state (f₁ along the axis). The corotated frame E follows the element:
//!
//! ```text
//! e₁ = (p_b − p_a)/l,   e₃ = e₁ × (f_a2 + f_b2) / |…|,   e₂ = e₃ × e₁
//! u  = l − L₀                                              (axial stretch)
//! θ  = ( e₃·f₂ − e₂·f₃ ,  e₁·f₃ − e₃·f₁ ,  e₂·f₁ − e₁·f₂ ) / 2   for F = F_a, F_b
//! ```
//!
//! θ is the rotation of the end frame relative to E (sin of the angle times the axis, exact
//! to O(θ³), so the element's own rotations stay small while it turns arbitrarily).
//!
//! **Local law** (the exact Euler–Bernoulli element, e.g. Przemieniecki 1968 §5.6), loads
//! the ends apply to the element, in E's axes; with `D = [[E·Iyy, −E·Iyz], [−E·Iyz, E·Izz]]`
//! on the (y, z) components:
//!
//! ```text
//! N   = E·A·u/L₀                 (tension-only elements: only when u > 0)
//! T   = G·J·(θ_bx − θ_ax)/L₀     M_a = D·(4θ_a + 2θ_b)/L₀,  M_b = D·(2θ_a + 4θ_b)/L₀
//! F_b = (N, −(M_az + M_bz)/l, (M_ay + M_by)/l),   F_a = −F_b
//! ```
//!
//! the shear forces from the element's moment equilibrium at its current length, so the
//! loads have zero net force and moment for any motion (objectivity: a rigid motion of both
//! ends gives no load). The loads on the ends are the opposites: `−F_b, −(T, M_b)` on b,
//! `−F_a, −(−T, M_a)` on a.
//!
//! **Stiffness-proportional damping** `C = β·K`: `u, θ` are replaced by `u + β·u̇, θ + β·θ̇`
//! with the deformation rates `u̇ = e₁·(v_b − v_a)`, `θ̇ = Eᵀ(ω − ω_E)`,
//! `ω_E = e₁ × (v_b − v_a)/l + e₁·(e₁·(ω_a + ω_b)/2)` (zero for a rigid motion).
//!
//! Generic over [`Real`]: with dual numbers the tangent stiffness is the exact derivative.
//! Cost: O(1) per element.

use super::algebra::{Real, V3};

/// Section and length of one corotational element.
#[derive(Clone, Debug, PartialEq)]
pub struct Section {
    /// L₀.
    pub length: f64,
    /// E·A.
    pub axial: f64,
    /// G·J (0 for a cable).
    pub torsion: f64,
    /// D = [[E·Iyy, −E·Iyz], [−E·Iyz, E·Izz]] (0 for a cable).
    pub bending: [[f64; 2]; 2],
    /// Tension only (3DCABLE): no axial force while `u < 0`.
    pub tension_only: bool,
    /// β of `C = β·K` (FE_PART CRATIOK, BEAM CRATIO).
    pub cratiok: f64,
}

/// One end of the element: its point and its frame `F` (columns in ground), both lifted.
pub struct End<R> {
    pub p: V3<R>,
    pub frame: [V3<R>; 3],
}

/// The rates the damping needs: `v_b − v_a` (of the end points), `ω_a`, `ω_b`.
pub struct Rates<R> {
    pub dv: V3<R>,
    pub wa: V3<R>,
    pub wb: V3<R>,
}

/// The loads the element applies to its ends, in ground axes: the force on b (the force on
/// a is its opposite, at a's point) and the torques on a and b.
pub struct EndLoads<R> {
    pub force_b: V3<R>,
    pub torque_a: V3<R>,
    pub torque_b: V3<R>,
}

impl Section {
    /// The end loads for ends `a`, `b`; `rates` is called only when `cratiok > 0`.
    pub fn loads<R: Real>(
        &self,
        a: &End<R>,
        b: &End<R>,
        rates: impl FnOnce() -> Rates<R>,
    ) -> EndLoads<R> {
        let (fa, fb) = (&a.frame, &b.frame);
        let d = b.p.sub(&a.p);
        let l = d.norm();
        let inv_l = R::cst(1.0).div(&l);
        let e1 = d.times(&inv_l);
        let z = e1.cross(&fa[1].add(&fb[1]));
        let e3 = z.times(&R::cst(1.0).div(&z.norm()));
        let e2 = e3.cross(&e1);
        let e = [e1.clone(), e2.clone(), e3.clone()];
        let theta = |f: &[V3<R>; 3]| -> [R; 3] {
            [
                e[2].dot(&f[1]).sub(&e[1].dot(&f[2])).scale(0.5),
                e[0].dot(&f[2]).sub(&e[2].dot(&f[0])).scale(0.5),
                e[1].dot(&f[0]).sub(&e[0].dot(&f[1])).scale(0.5),
            ]
        };
        let mut u = l.shift(-self.length);
        let mut ta = theta(fa);
        let mut tb = theta(fb);
        if self.cratiok > 0.0 {
            let Rates { dv, wa, wb } = rates();
            let spin = e1.dot(&wa.add(&wb)).scale(0.5);
            let w_e = e1.cross(&dv).times(&inv_l).add(&e1.times(&spin));
            let rate = |w: &V3<R>| -> [R; 3] {
                let r = w.sub(&w_e);
                [e[0].dot(&r), e[1].dot(&r), e[2].dot(&r)]
            };
            let (ra, rb) = (rate(&wa), rate(&wb));
            let beta = self.cratiok;
            u = u.add(&e1.dot(&dv).scale(beta));
            for c in 0..3 {
                ta[c] = ta[c].add(&ra[c].scale(beta));
                tb[c] = tb[c].add(&rb[c].scale(beta));
            }
        }
        let l0 = self.length;
        let axial = if self.tension_only && u.value() < 0.0 {
            R::cst(0.0)
        } else {
            u.scale(self.axial / l0)
        };
        let torque_x = tb[0].sub(&ta[0]).scale(self.torsion / l0);
        let bend = |x: &[R; 3], y: &[R; 3], row: usize| -> R {
            // (D·(4x + 2y))_row / L₀ over the (y, z) components.
            let c = |k: usize| x[1 + k].scale(4.0).add(&y[1 + k].scale(2.0));
            c(0).scale(self.bending[row][0] / l0)
                .add(&c(1).scale(self.bending[row][1] / l0))
        };
        let (may, maz) = (bend(&ta, &tb, 0), bend(&ta, &tb, 1));
        let (mby, mbz) = (bend(&tb, &ta, 0), bend(&tb, &ta, 1));
        let fby = maz.add(&mbz).mul(&inv_l).neg();
        let fbz = may.add(&mby).mul(&inv_l);
        // Loads on the ends: the opposites of the element's end loads.
        EndLoads {
            force_b: V3::combine(&e, &[axial, fby, fbz]).neg(),
            torque_b: V3::combine(&e, &[torque_x.clone(), mby, mbz]).neg(),
            torque_a: V3::combine(&e, &[torque_x.neg(), may, maz]).neg(),
        }
    }
}
