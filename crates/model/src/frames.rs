//! Orientation conventions of Adams datasets: body-fixed 3-1-3 Euler angles (REULER, PSI/THETA/
//! PHI), frames from a z-point and an x-point (ZP/XP, ZG/XG), and the exponential map used for
//! rotation increments.

use glam::{DMat3, DVec3};

/// `sin θ` below which [`matrix_to_euler313`] takes the pose at gimbal lock (θ = 0 or π, only
/// `ψ ± φ` determined): at 1e-12 the angles ψ and φ of the general formula would be
/// atan2 of rounding-level numbers, i.e. noise.
pub const EULER_GIMBAL_SINE: f64 = 1e-12;

/// Rotation angle (radians) below which [`exp_so3`] is the identity: the axis `θ/|θ|` is
/// undefined at 0, and a rotation this small moves no double-precision coordinate.
pub const NEGLIGIBLE_ROTATION_ANGLE: f64 = 1e-300;

/// `A(ψ,θ,φ) = Rz(ψ)·Rx(θ)·Rz(φ)`: columns are the rotated frame's axes in the parent frame
/// (ADM-REFERENCE §3.2).
pub fn euler313_to_matrix(a: [f64; 3]) -> DMat3 {
    DMat3::from_rotation_z(a[0]) * DMat3::from_rotation_x(a[1]) * DMat3::from_rotation_z(a[2])
}

/// Inverse of [`euler313_to_matrix`]: `θ = acos(A33)`, `ψ = atan2(A13, −A23)`,
/// `φ = atan2(A31, A32)`. At `sin θ = 0` only `ψ ± φ` is determined; then `φ = 0`.
pub fn matrix_to_euler313(r: &DMat3) -> [f64; 3] {
    // glam is column-major: r.col(j)[i] = A(i+1, j+1). θ from atan2 (not acos) so that a
    // rounding-level deviation of A33 from 1 does not create a spurious θ with noisy ψ, φ.
    let s = r.z_axis.x.hypot(r.z_axis.y);
    let theta = s.atan2(r.z_axis.z);
    if s > EULER_GIMBAL_SINE {
        let psi = r.z_axis.x.atan2(-r.z_axis.y);
        let phi = r.x_axis.z.atan2(r.y_axis.z);
        [psi, theta, phi]
    } else if r.z_axis.z > 0.0 {
        // θ = 0: A = Rz(ψ + φ); choose φ = 0.
        [r.x_axis.y.atan2(r.x_axis.x), 0.0, 0.0]
    } else {
        // θ = π: A = Rz(ψ)·Rx(π)·Rz(φ) = Rz(ψ − φ)·Rx(π); choose φ = 0.
        [r.x_axis.y.atan2(r.x_axis.x), std::f64::consts::PI, 0.0]
    }
}

/// The body 3-1-3 angles each of a set of frames (a run's parts, a request's pair of markers)
/// had at the last output, from which the next output continues the split of ψ and φ at
/// θ ≈ 0 or π ([`linkage_expr::orient::euler313_continued`]): the state an output writer
/// carries from output to output, so that the angles (and the Euler parameters written with
/// them) do not jump where the pose does not, as in Adams' output files.
#[derive(Clone, Debug)]
pub struct EulerHistory<K> {
    last: std::collections::HashMap<K, [f64; 3]>,
}

impl<K> Default for EulerHistory<K> {
    fn default() -> Self {
        EulerHistory {
            last: std::collections::HashMap::new(),
        }
    }
}

impl<K: Eq + std::hash::Hash + Copy> EulerHistory<K> {
    /// No output yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// The angles `[ψ, θ, φ]` (radians) of the rotation `r` of frame `key`, continued from
    /// its last output and kept as its last output.
    pub fn angles(&mut self, key: K, r: &DMat3) -> [f64; 3] {
        let a = linkage_expr::orient::euler313_continued(&r.to_cols_array(), self.previous(key));
        self.last.insert(key, a);
        a
    }

    /// The angles frame `key` had at the last output.
    pub fn previous(&self, key: K) -> Option<[f64; 3]> {
        self.last.get(&key).copied()
    }

    /// Keeps `angles` as frame `key`'s last output.
    pub fn record(&mut self, key: K, angles: [f64; 3]) {
        self.last.insert(key, angles);
    }
}

/// Frame whose +z axis points from `origin` towards `z_point` and whose x axis lies in the
/// half plane of `x_point` (Adams ZP/XP, ZG/XG). With `x_point` absent or on the z axis, x is
/// chosen as the ground axis least aligned with z, projected (a documented choice; Adams'
/// convention is not confirmed). Returns `None` when `z_point == origin`.
pub fn frame_from_points(
    origin: DVec3,
    z_point: Option<DVec3>,
    x_point: Option<DVec3>,
) -> Option<DMat3> {
    let z = match z_point {
        Some(zp) => (zp - origin).try_normalize()?,
        None => DVec3::Z,
    };
    let x_dir = x_point
        .map(|xp| xp - origin)
        .and_then(|v| (v - z * v.dot(z)).try_normalize());
    let x = match x_dir {
        Some(x) => x,
        None => {
            let a = z.abs();
            let pick = if a.x <= a.y && a.x <= a.z {
                DVec3::X
            } else if a.y <= a.z {
                DVec3::Y
            } else {
                DVec3::Z
            };
            (pick - z * pick.dot(z)).try_normalize()?
        }
    };
    let y = z.cross(x);
    Some(DMat3::from_cols(x, y, z))
}

/// `[v]×`, the matrix of `u ↦ v × u`.
pub fn skew(v: DVec3) -> DMat3 {
    DMat3::from_cols(
        DVec3::new(0.0, v.z, -v.y),
        DVec3::new(-v.z, 0.0, v.x),
        DVec3::new(v.y, -v.x, 0.0),
    )
}

/// Rotation `exp([θ]×)` by angle `|θ|` about `θ/|θ|` (Rodrigues).
pub fn exp_so3(theta: DVec3) -> DMat3 {
    let angle = theta.length();
    if angle < NEGLIGIBLE_ROTATION_ANGLE {
        return DMat3::IDENTITY;
    }
    DMat3::from_axis_angle(theta / angle, angle)
}

/// Rotation vector `θ` with `exp([θ]×) = r` (|θ| ≤ π), accurate to rounding for small
/// angles too: from the unit quaternion `(w, u)` of `r`, `|θ| = 2·atan2(|u|, |w|)` along
/// `±u` (an `acos(w)` would resolve angles only to about 1e-8).
pub fn log_so3(r: &DMat3) -> DVec3 {
    let q = glam::DQuat::from_mat3(r).normalize();
    // q and −q are the same rotation: take w ≥ 0 for the angle in [0, π].
    let (w, u) = if q.w < 0.0 {
        (-q.w, -DVec3::new(q.x, q.y, q.z))
    } else {
        (q.w, DVec3::new(q.x, q.y, q.z))
    };
    let s = u.length();
    if s == 0.0 {
        return DVec3::ZERO;
    }
    u * (2.0 * s.atan2(w) / s)
}

/// Re-orthonormalises a rotation matrix (polar factor via quaternion).
pub fn orthonormalize(r: &DMat3) -> DMat3 {
    DMat3::from_quat(glam::DQuat::from_mat3(r).normalize())
}

#[cfg(test)]
mod tests {
    use super::*;
    const D: f64 = std::f64::consts::PI / 180.0;

    fn close(a: &DMat3, b: &DMat3, tol: f64) -> bool {
        (0..3).all(|c| (a.col(c) - b.col(c)).abs().max_element() < tol)
    }

    #[test]
    fn reuler_180_90_180_is_minus_90_about_x() {
        // ADM-REFERENCE §12: A(180D,90D,180D) = [[1,0,0],[0,0,1],[0,-1,0]].
        let a = euler313_to_matrix([180.0 * D, 90.0 * D, 180.0 * D]);
        let expect = DMat3::from_cols(
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(0.0, 0.0, -1.0),
            DVec3::new(0.0, 1.0, 0.0),
        );
        assert!(close(&a, &expect, 1e-12), "{a:?}");
    }

    #[test]
    fn reuler_90_90_0_points_z_along_x() {
        let a = euler313_to_matrix([90.0 * D, 90.0 * D, 0.0]);
        assert!((a.z_axis - DVec3::X).length() < 1e-12);
    }

    #[test]
    fn euler_round_trip() {
        for angles in [
            [0.3, 1.1, -2.0],
            [-2.5, 0.2, 0.7],
            [1.0, 3.0, 0.1],
            [0.4, 0.0, 0.0],
        ] {
            let r = euler313_to_matrix(angles);
            let back = euler313_to_matrix(matrix_to_euler313(&r));
            assert!(close(&r, &back, 1e-12));
        }
    }

    #[test]
    fn rounding_noise_near_theta_zero_gives_no_spurious_angles() {
        // A rotation about z whose A33 is 1 − 1e-16 (rounding): ψ must be the z rotation.
        let mut r = DMat3::from_rotation_z(1.8);
        r.z_axis.z = 1.0 - 1.1e-16;
        r.z_axis.x = 1e-18;
        let e = matrix_to_euler313(&r);
        assert!((e[0] + e[2] - 1.8).abs() < 1e-9, "{e:?}");
    }

    #[test]
    fn frame_from_z_and_x_points() {
        let r = frame_from_points(
            DVec3::ZERO,
            Some(DVec3::new(0.0, 0.0, -2.0)),
            Some(DVec3::new(1.0, 1.0, 0.0)),
        )
        .unwrap();
        assert!((r.z_axis - DVec3::new(0.0, 0.0, -1.0)).length() < 1e-12);
        assert!((r.x_axis - DVec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-12);
        assert!((r.determinant() - 1.0).abs() < 1e-12);
        assert!(frame_from_points(DVec3::ONE, Some(DVec3::ONE), None).is_none());
    }

    #[test]
    fn exp_log_round_trip() {
        let t = DVec3::new(0.3, -0.2, 1.1);
        assert!((log_so3(&exp_so3(t)) - t).length() < 1e-12);
        // Small angles keep their relative accuracy.
        let tiny = DVec3::new(1.3e-9, -2.0e-10, 4.0e-9);
        assert!(
            (log_so3(&DMat3::from_axis_angle(tiny.normalize(), tiny.length())) - tiny).length()
                < 1e-15
        );
        let v = DVec3::new(1.0, 2.0, 3.0);
        assert!((skew(t) * v - t.cross(v)).length() < 1e-15);
    }
}
