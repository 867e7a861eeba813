//! Constraint rows: scalar equations Φ(q, t) = 0, their values and analytic Jacobians.
//!
//! Every row is a linear combination of a few geometric *quantities* of body-fixed points and
//! directions, minus a constant offset and (for motions) a function of time:
//!
//! ```text
//! Φ = Σ c_k · Q_k(q) − offset − f(t)
//! Q ∈ { a·b (two unit axes),  (P_i − P_j)·e,  atan2(x_i·y_r, x_i·x_r),  body 1-2-3 angle }
//! ```
//!
//! Tangent coordinates of a moving part are `(δx, δθ)`: the CM translation and a rotation
//! increment `R ← exp([δθ]×)·R`, both in ground axes. For a body-fixed point `P = x + R·p_b`
//! with arm `u = R·p_b`: `δP = δx + δθ × u`; for a body-fixed direction `e = R·v_b`:
//! `δe = δθ × e`. From these:
//!
//! * `a·b`: `∂/∂θ_A = a × b`, `∂/∂θ_B = b × a`;
//! * `d·e` with `d = P_i − P_j`: `∂/∂x_i = e`, `∂/∂θ_i = u_i × e`, `∂/∂x_j = −e`,
//!   `∂/∂θ_j = −u_j × e`, and `∂/∂θ_E = e × d` for the body carrying e;
//! * `atan2(s, c)`: `(c·ds − s·dc)/(s² + c²)`.

use crate::state::State;
use glam::{DMat3, DVec3};
use linkage_model::Body;

/// A point fixed on a body: `p_b` in the body frame (in ground for ground).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyPoint {
    pub body: Body,
    pub p_b: DVec3,
}

/// A unit direction fixed on a body.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyDir {
    pub body: Body,
    pub v_b: DVec3,
}

impl BodyPoint {
    /// Position in ground and the arm `R·p_b` from the body origin.
    #[inline]
    pub fn eval(&self, s: &State) -> (DVec3, DVec3) {
        let pose = s.pose(self.body);
        let u = pose.r * self.p_b;
        (pose.p + u, u)
    }
}

impl BodyDir {
    #[inline]
    pub fn eval(&self, s: &State) -> DVec3 {
        s.pose(self.body).r * self.v_b
    }
}

/// A frame fixed on a body (a marker, or an idealised marker of a broken joint).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyFrame {
    pub body: Body,
    pub p_b: DVec3,
    pub r_b: DMat3,
}

impl BodyFrame {
    pub fn origin(&self) -> BodyPoint {
        BodyPoint {
            body: self.body,
            p_b: self.p_b,
        }
    }
    /// Axis 0, 1, 2 = x, y, z.
    pub fn axis(&self, k: usize) -> BodyDir {
        BodyDir {
            body: self.body,
            v_b: self.r_b.col(k),
        }
    }
    /// Pose in ground.
    pub fn eval(&self, s: &State) -> (DVec3, DMat3) {
        let pose = s.pose(self.body);
        (pose.p + pose.r * self.p_b, pose.r * self.r_b)
    }
}

/// A geometric quantity of body-fixed points and directions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Quantity {
    /// `a·b`.
    Dot(BodyDir, BodyDir),
    /// `(P_i − P_j)·e`.
    Proj {
        i: BodyPoint,
        j: BodyPoint,
        e: BodyDir,
    },
    /// `atan2(x·y_ref, x·x_ref)`: the angle of `x` about the axis `x_ref × y_ref`, from `x_ref`.
    Angle {
        x: BodyDir,
        x_ref: BodyDir,
        y_ref: BodyDir,
    },
    /// Body 1-2-3 angle `k` (0, 1, 2 = B1, B2, B3) of frame `i` relative to frame `j`:
    /// `R_j^T R_i = Rx(b1)·Ry(b2)·Rz(b3)`.
    Body123 {
        i: BodyFrame,
        j: BodyFrame,
        k: usize,
    },
}

/// Gradient of one row: per-body 6-vectors `[∂/∂x; ∂/∂θ]`, bodies unique.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RowGradient {
    pub blocks: Vec<(usize, [f64; 6])>,
}

impl RowGradient {
    pub fn clear(&mut self) {
        self.blocks.clear();
    }
    fn add(&mut self, body: Body, c: f64, dx: DVec3, dth: DVec3) {
        let Body::Part(k) = body else { return };
        let v = [
            dx.x * c,
            dx.y * c,
            dx.z * c,
            dth.x * c,
            dth.y * c,
            dth.z * c,
        ];
        if let Some((_, b)) = self.blocks.iter_mut().find(|(kk, _)| *kk == k) {
            for (bi, vi) in b.iter_mut().zip(v) {
                *bi += vi;
            }
        } else {
            self.blocks.push((k, v));
        }
    }
}

/// `(s, c)` of an angle quantity.
fn angle_parts(x: DVec3, xr: DVec3, yr: DVec3) -> (f64, f64) {
    (x.dot(yr), x.dot(xr))
}

/// Body 1-2-3 angles of `R = Rx(b1)·Ry(b2)·Rz(b3)`.
pub fn body123_angles(r: &DMat3) -> [f64; 3] {
    // R(0,2) = sin b2; R(1,2) = −sin b1 cos b2; R(2,2) = cos b1 cos b2;
    // R(0,1) = −cos b2 sin b3; R(0,0) = cos b2 cos b3.
    let b2 = r.z_axis.x.clamp(-1.0, 1.0).asin();
    let b1 = (-r.z_axis.y).atan2(r.z_axis.z);
    let b3 = (-r.y_axis.x).atan2(r.x_axis.x);
    [b1, b2, b3]
}

/// Rows of `E⁻¹` where `ω = E·ḃ` for body 1-2-3 angles (ω the left angular velocity in the
/// reference frame): `E = [e1, Rx(b1)e2, Rx(b1)Ry(b2)e3]`. `None` at the singularity cos b2 = 0.
fn body123_rate_map(b: [f64; 3]) -> Option<DMat3> {
    let rx = DMat3::from_rotation_x(b[0]);
    let ry = DMat3::from_rotation_y(b[1]);
    let e = DMat3::from_cols(DVec3::X, rx * DVec3::Y, rx * ry * DVec3::Z);
    (e.determinant().abs() > 1e-12).then(|| e.inverse())
}

impl Quantity {
    /// Value at state `s`.
    pub fn value(&self, s: &State) -> f64 {
        match self {
            Quantity::Dot(a, b) => a.eval(s).dot(b.eval(s)),
            Quantity::Proj { i, j, e } => (i.eval(s).0 - j.eval(s).0).dot(e.eval(s)),
            Quantity::Angle { x, x_ref, y_ref } => {
                let (sn, c) = angle_parts(x.eval(s), x_ref.eval(s), y_ref.eval(s));
                sn.atan2(c)
            }
            Quantity::Body123 { i, j, k } => {
                let (_, ri) = i.eval(s);
                let (_, rj) = j.eval(s);
                body123_angles(&(rj.transpose() * ri))[*k]
            }
        }
    }

    /// Adds `c · ∂Q/∂q` to `g`.
    pub fn gradient(&self, s: &State, c: f64, g: &mut RowGradient) {
        match self {
            Quantity::Dot(a, b) => {
                let (va, vb) = (a.eval(s), b.eval(s));
                g.add(a.body, c, DVec3::ZERO, va.cross(vb));
                g.add(b.body, c, DVec3::ZERO, vb.cross(va));
            }
            Quantity::Proj { i, j, e } => {
                let (pi, ui) = i.eval(s);
                let (pj, uj) = j.eval(s);
                let ve = e.eval(s);
                let d = pi - pj;
                g.add(i.body, c, ve, ui.cross(ve));
                g.add(j.body, -c, ve, uj.cross(ve));
                g.add(e.body, c, DVec3::ZERO, ve.cross(d));
            }
            Quantity::Angle { x, x_ref, y_ref } => {
                let (vx, vxr, vyr) = (x.eval(s), x_ref.eval(s), y_ref.eval(s));
                let (sn, cs) = angle_parts(vx, vxr, vyr);
                let den = sn * sn + cs * cs;
                if den <= 1e-300 {
                    return;
                }
                // dθ = (cs·ds − sn·dc)/den; ds = d(x·y_ref), dc = d(x·x_ref).
                let (fs, fc) = (c * cs / den, -c * sn / den);
                g.add(x.body, fs, DVec3::ZERO, vx.cross(vyr));
                g.add(y_ref.body, fs, DVec3::ZERO, vyr.cross(vx));
                g.add(x.body, fc, DVec3::ZERO, vx.cross(vxr));
                g.add(x_ref.body, fc, DVec3::ZERO, vxr.cross(vx));
            }
            Quantity::Body123 { i, j, k } => {
                let (_, ri) = i.eval(s);
                let (_, rj) = j.eval(s);
                let b = body123_angles(&(rj.transpose() * ri));
                let Some(einv) = body123_rate_map(b) else {
                    return;
                };
                // ω (in J axes) = R_jᵀ(δθ_i − δθ_j); ḃ_k = row_k(E⁻¹)·ω.
                let row = DVec3::new(einv.col(0)[*k], einv.col(1)[*k], einv.col(2)[*k]);
                let w = rj * row;
                g.add(i.body, c, DVec3::ZERO, w);
                g.add(j.body, -c, DVec3::ZERO, w);
            }
        }
    }

    /// Whether the quantity is an angle (radians) rather than a dot product or a length.
    pub fn is_angle(&self) -> bool {
        matches!(self, Quantity::Angle { .. } | Quantity::Body123 { .. })
    }
}
