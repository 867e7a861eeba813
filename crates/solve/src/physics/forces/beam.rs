//! BEAM: a massless, uniform, linear Timoshenko beam from J (start) to I (end), undeformed
//! along J's x axis with I's axes parallel to J's.
//!
//! It is a [`SixDofLaw`] with `q₀ = [L, 0, 0, 0, 0, 0]`, no preload, and the stiffness of
//! the end node of a beam element clamped at its start (the lower-right 6×6 block of the
//! standard 12-DOF shear-deformable beam stiffness; e.g. Przemieniecki, *Theory of Matrix
//! Structural Analysis*, 1968, §5.6, or Cook et al., *Concepts and Applications of Finite
//! Element Analysis*, 4th ed., §2.4 and §10.3):
//!
//! ```text
//! Py = 12·E·Izz·ASY / (G·A·L²)        Pz = 12·E·Iyy·ASZ / (G·A·L²)   (shear parameters)
//!
//! K11 = E·A / L                       K44 = G·Ixx / L
//! K22 = 12·E·Izz / (L³·(1 + Py))      K26 = K62 = −6·E·Izz / (L²·(1 + Py))
//! K33 = 12·E·Iyy / (L³·(1 + Pz))      K35 = K53 = +6·E·Iyy / (L²·(1 + Pz))
//! K66 = (4 + Py)·E·Izz / (L·(1 + Py)) K55 = (4 + Pz)·E·Iyy / (L·(1 + Pz))
//! ```
//!
//! with rows/columns x, y, z, a, b, c (deflections along and rotations about J's axes).
//! Bending in the x–y plane (deflection y, rotation c about z) uses Izz; bending in the x–z
//! plane uses Iyy, with the opposite coupling sign because a positive z deflection along +x
//! is a negative rotation about y. ASY/ASZ are the shear area ratios (`A_shear = A / AS`);
//! 0 gives the Euler–Bernoulli beam. Check: a cantilever tip load P along y gives
//! `y = P·L³/(3·E·Izz) + P·L·ASY/(G·A)` and `c = P·L²/(2·E·Izz)`.
//!
//! Damping: `C = CRATIO·K`, or the symmetric `CMATRIX`.
//!
//! **Formulations.** Adams documents LINEAR as the linear Timoshenko beam, NONLINEAR as "a
//! full non linear Euler–Bernoulli theory" and STRING as "a simplified non linear theory",
//! without formulas; linkage decides [decided]:
//!
//! - `LINEAR`: the [`SixDofLaw`] above.
//! - `STRING`: the linear beam plus the second-order ("string") effect of the axial force —
//!   the geometric stiffness of the standard beam-column (McGuire, Gallagher & Ziemian,
//!   *Matrix Structural Analysis*, 2nd ed., 2000, §9.2; cubic shape functions), made
//!   consistent with an energy so that static, linear and dynamic analyses agree. With
//!   `δ = q − q₀` and `Γ = δᵀ·S·δ`, the (length-weighted) square of the axis' slope
//!   `∫(w′² + v′²)dx` plus the twist term:
//!
//!   ```text
//!   S(y,y) = S(z,z) = 6/(5L)   S(y,c) = −1/10   S(z,b) = +1/10   S(b,b) = S(c,c) = 2L/15
//!   S(a,a) = (IYY + IZZ)/(AREA·L)                                (polar radius of gyration)
//!   U = ½·δᵀ·K·δ + ½·(E·A/L)·(Γ/2)·(2δx + Γ/2)   i.e. the axial energy ½(E·A/L)·e²
//!   N = (E·A/L)·e,   e = δx + Γ/2                  (chord stretch + bow length)
//!   F = −∂U/∂δ − C·q̇:  Fx = −N,   F_bending = −K·δ − N·S·δ
//!   ```
//!
//!   A tensioned beam is laterally stiffer (`N > 0`), a compressed one softer, and bending
//!   shortens the chord under tension (the axial–bending coupling). Shear (ASY, ASZ) stays in
//!   K; S ignores it.
//! - `NONLINEAR`: the corotational Euler–Bernoulli element of [`super::corotational`] (the
//!   kernel FE_PART beams use) between J (end a, frame J) and I (end b, frame I), L₀ =
//!   LENGTH, `E·A`, `G·IXX`, `D = diag(E·IYY, E·IZZ)`; shear (ASY, ASZ) is not part of an
//!   Euler–Bernoulli theory and is ignored. Large rotations and displacements of the ends
//!   are exact (a rigid motion of both ends gives no load); strains are small. CRATIO is
//!   the kernel's `C = β·K` on the deformation rates; a CMATRIX acts, as in LINEAR, on the
//!   rates `q̇` of I relative to J in J's axes. For small deflections it equals LINEAR
//!   without shear.

use super::algebra::Real;
use super::corotational::{End, Rates, Section};
use super::six_dof::SixDofLaw;
use super::{Context, Load, Loads};
use crate::constraints::rows::BodyFrame;
use crate::physics::applied::LawError;
use linkage_adm::BeamFormulation;
use linkage_model::forces::{Beam, BeamDamping};

/// The 6×6 stiffness of the beam's free end (rows/columns x, y, z, a, b, c).
pub fn stiffness(b: &Beam) -> [[f64; 6]; 6] {
    let (e, g, a, l) = (b.emodulus, b.gmodulus, b.area, b.length);
    let py = 12.0 * e * b.izz * b.asy / (g * a * l * l);
    let pz = 12.0 * e * b.iyy * b.asz / (g * a * l * l);
    let mut k = [[0.0; 6]; 6];
    k[0][0] = e * a / l;
    k[1][1] = 12.0 * e * b.izz / (l.powi(3) * (1.0 + py));
    k[1][5] = -6.0 * e * b.izz / (l * l * (1.0 + py));
    k[5][1] = k[1][5];
    k[2][2] = 12.0 * e * b.iyy / (l.powi(3) * (1.0 + pz));
    k[2][4] = 6.0 * e * b.iyy / (l * l * (1.0 + pz));
    k[4][2] = k[2][4];
    k[3][3] = g * b.ixx / l;
    k[4][4] = (4.0 + pz) * e * b.iyy / (l * (1.0 + pz));
    k[5][5] = (4.0 + py) * e * b.izz / (l * (1.0 + py));
    k
}

/// The law of a BEAM, per its formulation.
#[derive(Clone, Debug, PartialEq)]
pub enum BeamLaw {
    Linear(SixDofLaw),
    String(StringLaw),
    Nonlinear(NonlinearLaw),
}

impl BeamLaw {
    pub fn loads<R: Real>(&self, cx: &Context) -> Result<Loads<R>, LawError> {
        match self {
            BeamLaw::Linear(l) => l.loads(cx),
            BeamLaw::String(l) => l.loads(cx),
            BeamLaw::Nonlinear(l) => l.loads(cx),
        }
    }
}

/// `FORMULATION = STRING`: the linear beam plus the axial force's geometric stiffness.
#[derive(Clone, Debug, PartialEq)]
pub struct StringLaw {
    /// The LINEAR beam (its K, C and `q₀`).
    pub linear: SixDofLaw,
    /// E·A/L.
    pub axial: f64,
    /// S of the module docs (rows/columns x, y, z, a, b, c; row and column x zero).
    pub slope: [[f64; 6]; 6],
}

impl StringLaw {
    pub fn loads<R: Real>(&self, cx: &Context) -> Result<Loads<R>, LawError> {
        let c = self.linear.coordinates::<R>(cx)?;
        let mut g = self.linear.generalised(&c);
        let d = &c.deflection;
        // S·δ and Γ = δᵀ·S·δ.
        let s_d: [R; 6] = std::array::from_fn(|r| {
            (1..6).fold(R::cst(0.0), |acc, k| {
                let s = self.slope[r][k];
                if s == 0.0 {
                    acc
                } else {
                    acc.add(&d[k].scale(s))
                }
            })
        });
        let gamma = (1..6).fold(R::cst(0.0), |acc, k| acc.add(&d[k].mul(&s_d[k])));
        let half = gamma.scale(0.5);
        let n = d[0].add(&half).scale(self.axial);
        // K·δ already holds (E·A/L)·δx in g[0]: add the bow term.
        g[0] = g[0].sub(&half.scale(self.axial));
        for r in 1..6 {
            g[r] = g[r].sub(&n.mul(&s_d[r]));
        }
        Ok(self.linear.apply(c, g))
    }
}

/// `FORMULATION = NONLINEAR`: the corotational Euler–Bernoulli element from J to I.
#[derive(Clone, Debug, PartialEq)]
pub struct NonlinearLaw {
    pub i: BodyFrame,
    pub j: BodyFrame,
    pub section: Section,
    /// A CMATRIX: `−C·q̇` on the rates of I relative to J (stiffness zero).
    pub cmatrix: Option<SixDofLaw>,
}

impl NonlinearLaw {
    pub fn loads<R: Real>(&self, cx: &Context) -> Result<Loads<R>, LawError> {
        let kin = &cx.kin;
        let end = |f: &BodyFrame| End {
            p: kin.point::<R>(&f.origin()),
            frame: [0, 1, 2].map(|k| kin.dir::<R>(&f.axis(k))),
        };
        let (a, b) = (end(&self.j), end(&self.i));
        let out = self.section.loads(&a, &b, || Rates {
            dv: kin
                .point_velocity::<R>(&self.i.origin())
                .sub(&kin.point_velocity::<R>(&self.j.origin())),
            wa: kin.omega::<R>(self.j.body),
            wb: kin.omega::<R>(self.i.body),
        });
        let (mut force_i, mut torque_i) = (out.force_b, out.torque_b);
        let mut force_j = force_i.neg();
        let mut torque_j = out.torque_a;
        if let Some(damper) = &self.cmatrix {
            // The damper's reaction on J acts at I's origin: moved to J's origin it adds
            // (P_i − P_j) × (−F_d).
            if let [Some(on_i), Some(on_j)] = damper.loads::<R>(cx)? {
                force_i = force_i.add(&on_i.force);
                torque_i = torque_i.add(&on_i.torque);
                force_j = force_j.add(&on_j.force);
                torque_j = torque_j
                    .add(&on_j.torque)
                    .add(&on_j.point.sub(&a.p).cross(&on_j.force));
            }
        }
        Ok([
            Some(Load {
                body: self.i.body,
                point: b.p,
                force: force_i,
                torque: torque_i,
            }),
            Some(Load {
                body: self.j.body,
                point: a.p,
                force: force_j,
                torque: torque_j,
            }),
        ])
    }
}

/// S of the STRING formulation (module docs).
fn slope_matrix(b: &Beam) -> [[f64; 6]; 6] {
    let l = b.length;
    let mut s = [[0.0; 6]; 6];
    s[1][1] = 6.0 / (5.0 * l);
    s[2][2] = s[1][1];
    s[1][5] = -0.1;
    s[5][1] = -0.1;
    s[2][4] = 0.1;
    s[4][2] = 0.1;
    s[4][4] = 2.0 * l / 15.0;
    s[5][5] = s[4][4];
    s[3][3] = (b.iyy + b.izz) / (b.area * l);
    s
}

/// The law of a BEAM between frames I and J.
pub fn law(i: BodyFrame, j: BodyFrame, b: &Beam) -> BeamLaw {
    let k = stiffness(b);
    let damping = match &b.damping {
        BeamDamping::Ratio(r) => k.map(|row| row.map(|x| x * r)),
        BeamDamping::Matrix(m) => **m,
    };
    let linear = SixDofLaw {
        i,
        j,
        stiffness: k,
        damping,
        reference: [b.length, 0.0, 0.0, 0.0, 0.0, 0.0],
        preload: [0.0; 6],
    };
    match b.formulation {
        BeamFormulation::Linear => BeamLaw::Linear(linear),
        BeamFormulation::String => BeamLaw::String(StringLaw {
            axial: b.emodulus * b.area / b.length,
            slope: slope_matrix(b),
            linear,
        }),
        BeamFormulation::Nonlinear => {
            let (cratiok, cmatrix) = match &b.damping {
                BeamDamping::Ratio(r) => (*r, None),
                BeamDamping::Matrix(m) => (
                    0.0,
                    Some(SixDofLaw {
                        stiffness: [[0.0; 6]; 6],
                        damping: **m,
                        ..linear
                    }),
                ),
            };
            BeamLaw::Nonlinear(NonlinearLaw {
                i,
                j,
                section: Section {
                    length: b.length,
                    axial: b.emodulus * b.area,
                    torsion: b.gmodulus * b.ixx,
                    bending: [[b.emodulus * b.iyy, 0.0], [0.0, b.emodulus * b.izz]],
                    tension_only: false,
                    cratiok,
                },
                cmatrix,
            })
        }
    }
}
