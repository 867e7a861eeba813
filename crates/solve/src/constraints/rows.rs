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

pub mod curve_curve;
pub mod curve_gap;

use crate::state::State;
use crate::tolerances::{ATAN2_DEGENERATE, EULER_RATE_SINGULAR};
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
///
/// The rare Euler-angle quantity is boxed: a row's term is as large as the largest variant,
/// and rows of joints (nearly all rows of a large model) hold dot products and projections.
#[derive(Clone, Debug, PartialEq)]
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
    /// Euler angle `k` (0, 1, 2) of frame `i` relative to frame `j` in sequence `seq`
    /// (`R_jᵀ R_i = Rx(b1)·Ry(b2)·Rz(b3)` for body 1-2-3, …).
    Euler(Box<EulerAngle>),
    /// A component of a PTCV's gap in the normal plane of its curve
    /// ([`curve_gap`]).
    CurveGap(Box<curve_gap::CurveGap>),
    /// A component of a CVCV's gap: along the common normal of its two curves, or out of
    /// their plane ([`curve_curve`]).
    CurveContact(Box<curve_curve::CurveContact>),
}

/// Euler angle `k` (0, 1, 2) of frame `i` relative to frame `j` in sequence `seq`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EulerAngle {
    pub i: BodyFrame,
    pub j: BodyFrame,
    pub seq: EulerSeq,
    pub k: usize,
}

impl Quantity {
    /// Euler angle `k` of frame `i` relative to frame `j` in sequence `seq`.
    pub fn euler(i: BodyFrame, j: BodyFrame, seq: EulerSeq, k: usize) -> Quantity {
        Quantity::Euler(Box::new(EulerAngle { i, j, seq, k }))
    }
}

/// Euler-angle sequences used by motions and measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EulerSeq {
    /// Body 1-2-3 (MOTION B1, B2, B3): `Rx(b1)·Ry(b2)·Rz(b3)`.
    Body123,
    /// Body 3-1-3 (PSI, THETA, PHI): `Rz(ψ)·Rx(θ)·Rz(φ)`.
    Body313,
    /// Body 3-2-1 (YAW, PITCH, ROLL): `Rz(y)·Ry(p)·Rx(r)`.
    Body321,
}

impl EulerSeq {
    /// The three angles of rotation `r`.
    pub fn angles(self, r: &DMat3) -> [f64; 3] {
        match self {
            EulerSeq::Body123 => body123_angles(r),
            EulerSeq::Body313 => linkage_model::frames::matrix_to_euler313(r),
            EulerSeq::Body321 => {
                let b = (-r.x_axis.z).clamp(-1.0, 1.0).asin();
                [
                    r.x_axis.y.atan2(r.x_axis.x),
                    b,
                    r.y_axis.z.atan2(r.z_axis.z),
                ]
            }
        }
    }

    /// Rotation axes of the sequence: `R = R_a1(b0)·R_a2(b1)·R_a3(b2)`.
    fn axes(self) -> [DVec3; 3] {
        match self {
            EulerSeq::Body123 => [DVec3::X, DVec3::Y, DVec3::Z],
            EulerSeq::Body313 => [DVec3::Z, DVec3::X, DVec3::Z],
            EulerSeq::Body321 => [DVec3::Z, DVec3::Y, DVec3::X],
        }
    }

    /// `E` with the left angular velocity `ω = E·ḃ`: `E = [a1, R1·a2, R1·R2·a3]`, and its
    /// partial derivatives with respect to b0 and b1.
    fn rate_matrix(self, b: [f64; 3]) -> (DMat3, DMat3, DMat3) {
        let [a1, a2, a3] = self.axes();
        let r1 = DMat3::from_axis_angle(a1, b[0]);
        let r2 = DMat3::from_axis_angle(a2, b[1]);
        let e = DMat3::from_cols(a1, r1 * a2, r1 * r2 * a3);
        let d0 = DMat3::from_cols(DVec3::ZERO, a1.cross(r1 * a2), a1.cross(r1 * r2 * a3));
        let d1 = DMat3::from_cols(DVec3::ZERO, DVec3::ZERO, r1 * a2.cross(r2 * a3));
        (e, d0, d1)
    }

    /// `E⁻¹` where the left angular velocity is `ω = E·(rates)`; `None` at a singular pose.
    fn rate_map(self, b: [f64; 3]) -> Option<DMat3> {
        let (e, _, _) = self.rate_matrix(b);
        (e.determinant().abs() > EULER_RATE_SINGULAR).then(|| e.inverse())
    }
}

/// Velocity of every moving part: centre-of-mass velocity and angular velocity, in ground.
pub type Velocities = [(DVec3, DVec3)];

pub(crate) fn twist(v: &Velocities, b: Body) -> (DVec3, DVec3) {
    match b {
        Body::Ground => (DVec3::ZERO, DVec3::ZERO),
        Body::Part(k) => v[k],
    }
}

/// Position, velocity and acceleration of a body-fixed point whose body moves with the twists
/// `v` and the accelerations `acc` (CM acceleration and angular acceleration, ground axes;
/// zero when `None`): `[P, v_c + ω×u, a_c + α×u + ω×(ω×u)]` with the arm `u = R·p_b`.
pub fn point_series(
    p: &BodyPoint,
    s: &State,
    v: &Velocities,
    acc: Option<&Velocities>,
) -> [DVec3; 3] {
    let (pos, u) = p.eval(s);
    let (vc, w) = twist(v, p.body);
    let (ac, al) = acc.map_or((DVec3::ZERO, DVec3::ZERO), |a| twist(a, p.body));
    [pos, vc + w.cross(u), ac + al.cross(u) + w.cross(w.cross(u))]
}

/// A body-fixed direction, its rate and its second derivative: `[e, ω×e, α×e + ω×(ω×e)]`
/// (α = 0 when `acc` is `None`).
pub fn dir_series(d: &BodyDir, s: &State, v: &Velocities, acc: Option<&Velocities>) -> [DVec3; 3] {
    let e = d.eval(s);
    let (_, w) = twist(v, d.body);
    let al = acc.map_or(DVec3::ZERO, |a| twist(a, d.body).1);
    [e, w.cross(e), al.cross(e) + w.cross(w.cross(e))]
}

/// `[a·b, (a·b)˙, (a·b)¨]` of two vector series.
pub fn dot_series(a: &[DVec3; 3], b: &[DVec3; 3]) -> [f64; 3] {
    [
        a[0].dot(b[0]),
        a[1].dot(b[0]) + a[0].dot(b[1]),
        a[2].dot(b[0]) + 2.0 * a[1].dot(b[1]) + a[0].dot(b[2]),
    ]
}

/// `[θ, θ̇, θ̈]` of `θ = atan2(s, c)` from the series of s and c:
/// `θ̇ = (c ṡ − s ċ)/ρ`, `θ̈ = (c s̈ − s c̈)/ρ − 2 (c ṡ − s ċ)(s ṡ + c ċ)/ρ²`, `ρ = s² + c²`
/// (rates zero where ρ vanishes).
pub fn atan2_series([sn, sd, sdd]: [f64; 3], [cs, cd, cdd]: [f64; 3]) -> [f64; 3] {
    let rho = sn * sn + cs * cs;
    if rho <= ATAN2_DEGENERATE {
        return [sn.atan2(cs), 0.0, 0.0];
    }
    let rate = (cs * sd - sn * cd) / rho;
    let acc =
        (cs * sdd - sn * cdd) / rho - 2.0 * (cs * sd - sn * cd) * (sn * sd + cs * cd) / (rho * rho);
    [sn.atan2(cs), rate, acc]
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
    /// The row's rate `J_row · v = Σ_k (∂/∂x_k · v_k + ∂/∂θ_k · ω_k)` for the velocities (or
    /// accelerations) `v`, one (CM, angular) pair per part in ground axes.
    pub fn rate(&self, v: &Velocities) -> f64 {
        self.blocks
            .iter()
            .map(|(k, b)| {
                DVec3::new(b[0], b[1], b[2]).dot(v[*k].0)
                    + DVec3::new(b[3], b[4], b[5]).dot(v[*k].1)
            })
            .sum()
    }

    /// Adds a 6-vector to part `k`'s block.
    pub fn add_block(&mut self, k: usize, v: [f64; 6]) {
        if let Some((_, b)) = self.blocks.iter_mut().find(|(kk, _)| *kk == k) {
            for (bi, vi) in b.iter_mut().zip(v) {
                *bi += vi;
            }
        } else {
            self.blocks.push((k, v));
        }
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
            Quantity::Euler(e) => {
                let EulerAngle { i, j, seq, k } = &**e;
                let (_, ri) = i.eval(s);
                let (_, rj) = j.eval(s);
                seq.angles(&(rj.transpose() * ri))[*k]
            }
            Quantity::CurveGap(q) => q.value(s),
            Quantity::CurveContact(q) => q.value(s),
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
                if den <= ATAN2_DEGENERATE {
                    return;
                }
                // dθ = (cs·ds − sn·dc)/den; ds = d(x·y_ref), dc = d(x·x_ref).
                let (fs, fc) = (c * cs / den, -c * sn / den);
                g.add(x.body, fs, DVec3::ZERO, vx.cross(vyr));
                g.add(y_ref.body, fs, DVec3::ZERO, vyr.cross(vx));
                g.add(x.body, fc, DVec3::ZERO, vx.cross(vxr));
                g.add(x_ref.body, fc, DVec3::ZERO, vxr.cross(vx));
            }
            Quantity::Euler(e) => {
                let EulerAngle { i, j, seq, k } = &**e;
                let (_, ri) = i.eval(s);
                let (_, rj) = j.eval(s);
                let b = seq.angles(&(rj.transpose() * ri));
                let Some(einv) = seq.rate_map(b) else {
                    return;
                };
                // ω (in J axes) = R_jᵀ(δθ_i − δθ_j); ḃ_k = row_k(E⁻¹)·ω.
                let row = DVec3::new(einv.col(0)[*k], einv.col(1)[*k], einv.col(2)[*k]);
                let w = rj * row;
                g.add(i.body, c, DVec3::ZERO, w);
                g.add(j.body, -c, DVec3::ZERO, w);
            }
            Quantity::CurveGap(q) => q.gradient(s, c, g),
            Quantity::CurveContact(q) => q.gradient(s, c, g),
        }
    }

    /// `dQ/dt` and `d²Q/dt²` along the part velocities `v` with zero part accelerations (the
    /// "γ" term of the acceleration equations: `Q̈ = ∇Q·a + bias`).
    pub fn rates(&self, s: &State, v: &Velocities) -> (f64, f64) {
        let [_, rate, acc] = self.series(s, v, None);
        (rate, acc)
    }

    /// `[Q, Q̇, Q̈]` with the parts moving with the twists `v` and the accelerations `acc`
    /// (CM acceleration and angular acceleration in ground; zero when `None`, which gives the
    /// bias of `Q̈ = ∇Q·a + bias`). Rates are zero at a pose where the quantity is not
    /// differentiable (an angle of two parallel axes, a singular Euler sequence).
    pub fn series(&self, s: &State, v: &Velocities, acc: Option<&Velocities>) -> [f64; 3] {
        match self {
            Quantity::Dot(a, b) => dot_series(&dir_series(a, s, v, acc), &dir_series(b, s, v, acc)),
            Quantity::Proj { i, j, e } => {
                let pi = point_series(i, s, v, acc);
                let pj = point_series(j, s, v, acc);
                let d = [pi[0] - pj[0], pi[1] - pj[1], pi[2] - pj[2]];
                dot_series(&d, &dir_series(e, s, v, acc))
            }
            Quantity::Angle { x, x_ref, y_ref } => {
                let x = dir_series(x, s, v, acc);
                let sn = dot_series(&x, &dir_series(y_ref, s, v, acc));
                let cs = dot_series(&x, &dir_series(x_ref, s, v, acc));
                atan2_series(sn, cs)
            }
            Quantity::Euler(e) => {
                let EulerAngle { i, j, seq, k } = &**e;
                let (_, ri) = i.eval(s);
                let (_, rj) = j.eval(s);
                let b = seq.angles(&(rj.transpose() * ri));
                let (e, d0, d1) = seq.rate_matrix(b);
                if e.determinant().abs() <= EULER_RATE_SINGULAR {
                    return [b[*k], 0.0, 0.0];
                }
                let einv = e.inverse();
                let (_, wi) = twist(v, i.body);
                let (_, wj) = twist(v, j.body);
                let alpha = |body: Body| acc.map_or(DVec3::ZERO, |a| twist(a, body).1);
                // ω_rel = R_jᵀ(ω_i − ω_j) in J axes; d/dt(R_jᵀ x) = R_jᵀ(ẋ − ω_j × x).
                let w_rel = rj.transpose() * (wi - wj);
                let w_rel_dot =
                    rj.transpose() * (alpha(i.body) - alpha(j.body) - wj.cross(wi - wj));
                let bd = einv * w_rel;
                let e_dot = d0 * bd[0] + d1 * bd[1];
                let bdd = einv * (w_rel_dot - e_dot * bd);
                [b[*k], bd[*k], bdd[*k]]
            }
            Quantity::CurveGap(q) => q.series(s, v, acc),
            Quantity::CurveContact(q) => q.series(s, v, acc),
        }
    }

    /// Whether the quantity is an angle (radians) rather than a dot product or a length.
    pub fn is_angle(&self) -> bool {
        matches!(self, Quantity::Angle { .. } | Quantity::Euler { .. })
    }
}
