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
//! Damping: `C = CRATIO·K`, or the symmetric `CMATRIX`. Only `FORMULATION = LINEAR` is
//! implemented; STRING and NONLINEAR are refused rather than approximated.

use super::six_dof::SixDofLaw;
use crate::constraints::rows::BodyFrame;
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

/// A BEAM linkage cannot model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum BeamError {
    /// A formulation other than LINEAR (`STRING`, `NONLINEAR`).
    #[error("FORMULATION = {0} is not supported (linkage implements the LINEAR Timoshenko beam)")]
    Formulation(&'static str),
}

/// The law of a BEAM between frames I and J; an error for a formulation other than LINEAR.
pub fn law(i: BodyFrame, j: BodyFrame, b: &Beam) -> Result<SixDofLaw, BeamError> {
    match b.formulation {
        BeamFormulation::Linear => {}
        BeamFormulation::String => return Err(BeamError::Formulation("STRING")),
        BeamFormulation::Nonlinear => return Err(BeamError::Formulation("NONLINEAR")),
    }
    let k = stiffness(b);
    let damping = match &b.damping {
        BeamDamping::Ratio(r) => k.map(|row| row.map(|x| x * r)),
        BeamDamping::Matrix(m) => **m,
    };
    Ok(SixDofLaw {
        i,
        j,
        stiffness: k,
        damping,
        reference: [b.length, 0.0, 0.0, 0.0, 0.0, 0.0],
        preload: [0.0; 6],
    })
}
