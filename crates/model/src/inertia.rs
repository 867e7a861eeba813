//! Inertia tensors: Adams' `IP` convention, frame changes, the parallel-axis theorem, and the
//! physical-validity check.

use glam::{DMat3, DVec3};

/// Relative size (squared, against the squared diagonal) below which the off-diagonal terms
/// of a symmetric 3×3 matrix are taken as zero in [`symmetric_eigenvalues`], and the floor of
/// the scales there and in [`check_physical`]: near the smallest normal double, so only an
/// exactly diagonal (or zero) matrix takes that branch and no scale divides by zero.
pub const NEGLIGIBLE_RELATIVE_SIZE: f64 = 1e-300;

/// Tensor from `IP = Ixx, Iyy, Izz, Ixy, Ixz, Iyz`. Adams defines products as positive integrals
/// (`Ixy = ∫x·y dm`, ADM-REFERENCE §2.3), so the tensor holds their negatives off the diagonal.
pub fn tensor_from_ip(ip: [f64; 6]) -> DMat3 {
    let [xx, yy, zz, xy, xz, yz] = ip;
    DMat3::from_cols(
        DVec3::new(xx, -xy, -xz),
        DVec3::new(-xy, yy, -yz),
        DVec3::new(-xz, -yz, zz),
    )
}

/// Re-expresses a tensor given in frame A's axes in frame B's axes, where `r_ba` is the
/// orientation of A in B: `I_B = R·I_A·Rᵀ`.
pub fn rotate_tensor(i_a: &DMat3, r_ba: &DMat3) -> DMat3 {
    *r_ba * *i_a * r_ba.transpose()
}

/// Parallel-axis theorem: from a tensor about point P to the tensor about the centre of mass,
/// where `r` is the vector from the centre of mass to P: `I_cm = I_P − m(|r|²·1 − r rᵀ)`.
pub fn to_centre_of_mass(i_p: &DMat3, mass: f64, r: DVec3) -> DMat3 {
    let outer = DMat3::from_cols(r * r.x, r * r.y, r * r.z);
    *i_p - (DMat3::IDENTITY * r.length_squared() - outer) * mass
}

/// Eigenvalues of a symmetric 3×3 matrix, ascending (closed form, trigonometric method).
pub fn symmetric_eigenvalues(a: &DMat3) -> [f64; 3] {
    let (a11, a22, a33) = (a.x_axis.x, a.y_axis.y, a.z_axis.z);
    let (a12, a13, a23) = (a.y_axis.x, a.z_axis.x, a.z_axis.y);
    let p1 = a12 * a12 + a13 * a13 + a23 * a23;
    let diagonal = (a11 * a11 + a22 * a22 + a33 * a33).max(NEGLIGIBLE_RELATIVE_SIZE);
    let mut e = if p1 <= NEGLIGIBLE_RELATIVE_SIZE * diagonal {
        [a11, a22, a33]
    } else {
        let q = (a11 + a22 + a33) / 3.0;
        let p2 = (a11 - q).powi(2) + (a22 - q).powi(2) + (a33 - q).powi(2) + 2.0 * p1;
        let p = (p2 / 6.0).sqrt();
        let b = (*a - DMat3::IDENTITY * q) * (1.0 / p);
        let r = (b.determinant() / 2.0).clamp(-1.0, 1.0);
        let phi = r.acos() / 3.0;
        let e1 = q + 2.0 * p * phi.cos();
        let e3 = q + 2.0 * p * (phi + 2.0 * std::f64::consts::PI / 3.0).cos();
        [e1, 3.0 * q - e1 - e3, e3]
    };
    e.sort_by(|x, y| x.total_cmp(y));
    e
}

/// How an inertia tensor departs from a rigid body's.
#[derive(Debug, Clone, PartialEq)]
pub enum InertiaDefect {
    /// A negative principal moment: the kinetic energy could be negative, so no analysis
    /// can use it.
    Negative(String),
    /// The triangle inequality `I1 + I2 ≥ I3` fails: no rigid body has this inertia, but the
    /// tensor is positive (semi-)definite and the equations of motion stay well posed (Adams
    /// runs such models, e.g. the tiny transverse inertias of FAST's nacelle and generator).
    Triangle(String),
}

/// Whether an inertia tensor is a rigid body's: no negative principal moment and the
/// triangle inequality `I1 + I2 ≥ I3`, each beyond a relative tolerance `rel_tol`.
pub fn check_physical(i_cm: &DMat3, rel_tol: f64) -> Result<(), InertiaDefect> {
    let [a, b, c] = symmetric_eigenvalues(i_cm);
    let scale = c.abs().max(NEGLIGIBLE_RELATIVE_SIZE);
    if a < -rel_tol * scale {
        return Err(InertiaDefect::Negative(format!(
            "negative principal moment of inertia {} (principal moments {}, {}, {})",
            linkage_adm::num::sci(a, 7),
            linkage_adm::num::sci(a, 7),
            linkage_adm::num::sci(b, 7),
            linkage_adm::num::sci(c, 7)
        )));
    }
    if a + b < c - rel_tol * scale {
        return Err(InertiaDefect::Triangle(format!(
            "principal moments {}, {}, {} violate the triangle inequality (I1 + I2 < I3)",
            linkage_adm::num::sci(a, 7),
            linkage_adm::num::sci(b, 7),
            linkage_adm::num::sci(c, 7)
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn products_use_adams_sign() {
        let t = tensor_from_ip([2.0, 3.0, 4.0, 0.5, 0.25, 0.125]);
        assert_eq!(t.y_axis.x, -0.5);
        assert_eq!(t.z_axis.x, -0.25);
        assert_eq!(t.z_axis.y, -0.125);
    }

    #[test]
    fn point_mass_offset_has_the_expected_tensor() {
        // A point mass m at r from P: about P, I = m(|r|²1 − r rᵀ); about its own CM, zero.
        let m = 2.0;
        let r = DVec3::new(1.0, 2.0, -0.5);
        let outer = DMat3::from_cols(r * r.x, r * r.y, r * r.z);
        let i_p = (DMat3::IDENTITY * r.length_squared() - outer) * m;
        let i_cm = to_centre_of_mass(&i_p, m, r);
        assert!(i_cm.to_cols_array().iter().all(|v| v.abs() < 1e-12));
    }

    #[test]
    fn eigenvalues_of_rotated_diagonal_tensor() {
        let d = DMat3::from_diagonal(DVec3::new(1.0, 2.0, 2.5));
        let r = DMat3::from_axis_angle(DVec3::new(1.0, 1.0, 0.3).normalize(), 0.7);
        let e = symmetric_eigenvalues(&rotate_tensor(&d, &r));
        for (got, want) in e.iter().zip([1.0, 2.0, 2.5]) {
            assert!((got - want).abs() < 1e-12, "{e:?}");
        }
    }

    #[test]
    fn rejects_non_physical_tensors() {
        assert!(check_physical(&DMat3::from_diagonal(DVec3::new(1.0, 1.0, 1.5)), 1e-9).is_ok());
        assert!(matches!(
            check_physical(&DMat3::from_diagonal(DVec3::new(1.0, 1.0, 3.0)), 1e-9),
            Err(InertiaDefect::Triangle(_))
        ));
        assert!(matches!(
            check_physical(&DMat3::from_diagonal(DVec3::new(-1.0, 1.0, 1.0)), 1e-9),
            Err(InertiaDefect::Negative(_))
        ));
    }
}
