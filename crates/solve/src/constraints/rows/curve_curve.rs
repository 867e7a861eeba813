//! CVCV: the rows that keep a planar curve carried by one body in contact with, and tangent
//! to, a planar curve carried by another (ADM-ELEMENTS §16), with both contact parameters
//! solved inside the row.
//!
//! **Equations.** Curve I is `c_I(α)` in the x-y plane of frame A (the IRM marker), curve J is
//! `c_J(β)` in the x-y plane of frame B (the JRM marker). In ground, with `z` frame A's z axis
//! (the binormal of curve I, as ADM-ELEMENTS gives IFLOAT's z):
//!
//! ```text
//! P_I = p_A + R_A c_I(α),  T_I = R_A c_I'(α),   P_J = p_B + R_B c_J(β),  T_J = R_B c_J'(β)
//! d = P_I − P_J
//! ```
//!
//! The contact parameters `(α, β)` solve the two common-normal conditions
//!
//! ```text
//! g_1 = d·T_I = 0            (no offset along the common tangent)
//! g_2 = (T_I × T_J)·z = 0    (the tangents parallel in the plane)
//! ```
//!
//! by Newton warm-started from the last contact ([`LastContact`], shared with PTCV), steps
//! limited to a quarter piece of each curve, with a search over samples of both curves when
//! there is no usable warm start. The two rows are the remaining components of the gap:
//!
//! ```text
//! Φ_n = n·d,  n = unit(z × T_I)   (the in-plane gap along the common normal)
//! Φ_b = z·d                       (the offset out of the plane)
//! ```
//!
//! Adams' form (ADM-ELEMENTS §16) carries α and β as coordinates with the four equations
//! `d = 0`, `(T_I × T_J)·z = 0`: eliminating α and β by `g_1 = g_2 = 0` leaves these two rows
//! on the same manifold (as for PTCV, [`super::curve_gap`]). A CVCV thus removes 2 degrees of
//! freedom: the curves may roll and slide on each other but not separate nor leave the plane.
//! It does not hold the two planes parallel (the Adams equations do not either): a planar
//! mechanism holds them with its joints, and then the binormal row duplicates those joints.
//! The rows are admitted for the rank analysis after the joints' (`Tier::Coupling`), so verify
//! names that binormal row redundant — not a joint row whose dependence on the CVCV would
//! vanish at another pose (at a contact on the follower's own sliding axis, say).
//!
//! **Derivatives, exact.** Everything is a second-order jet (value, rate, acceleration) of the
//! two frames' motions and of `α(t)`, `β(t)`. Writing `x = (α, β)` and `G = ∂g/∂x`,
//! differentiating `g(x(t), t) = 0` gives `G ẋ = −ġ|_{ẋ=0}` and `G ẍ = −g̈|_{ẍ=0}`: the jets
//! of `g` evaluated with the rates of `x` held at zero, then with its accelerations held at
//! zero, give `ẋ` and `ẍ` by two 2 × 2 solves; the rows' jets follow with the full jets of
//! `x`. The gradient is the rate along each of the 12 unit twists of the two bodies; the
//! Hessian is by polarization of the series ([`crate::constraints::hessian`]).
//!
//! Cost: per series, five jet evaluations of a few cross and dot products and one curve
//! evaluation per parameter; per gradient, twelve series. No allocation.

use crate::constraints::rows::curve_gap::{
    jet_cross, jet_scale, jet_sub, jet_unit, Jet, LastContact, ScalarJet,
};
use crate::constraints::rows::{dot_series, twist, BodyFrame, RowGradient, Velocities};
use crate::state::State;
use glam::{DMat3, DVec3};
use linkage_model::curves::Curve;
use std::sync::{Arc, Mutex};

/// A CVCV's last contact: the relative pose of frame B in frame A (`R_Aᵀ(p_B − p_A)` and the
/// columns of `R_Aᵀ R_B`) and `[α, β]`.
pub type PairContact = LastContact<[f64; 12], [f64; 2]>;

/// One row of a CVCV (module docs).
#[derive(Clone, Debug)]
pub struct CurveContact {
    /// The IRM and JRM frames (each curve's coordinates are in its frame).
    pub frames: [BodyFrame; 2],
    /// Curve I and curve J.
    pub curves: [Arc<Curve>; 2],
    /// 0: the in-plane gap along the common normal `n·d`; 1: the out-of-plane offset `z·d`.
    pub axis: usize,
    /// The last contact (the Newton warm start), shared by the CVCV's two rows.
    pub contact: Arc<Mutex<PairContact>>,
}

impl PartialEq for CurveContact {
    fn eq(&self, other: &Self) -> bool {
        self.frames == other.frames
            && self.axis == other.axis
            && Arc::ptr_eq(&self.curves[0], &other.curves[0])
            && Arc::ptr_eq(&self.curves[1], &other.curves[1])
    }
}

/// A frame's origin and axes as jets.
#[derive(Clone, Copy)]
struct FrameJet {
    origin: Jet,
    axes: [Jet; 3],
}

impl FrameJet {
    /// The frame `f` moving with its body's twist `(v, ω)` and acceleration `(a, ω̇)`.
    fn new(f: &BodyFrame, s: &State, tw: (DVec3, DVec3), acc: (DVec3, DVec3)) -> FrameJet {
        let pose = s.pose(f.body);
        let (v, w) = tw;
        let (a, al) = acc;
        let u = pose.r * f.p_b;
        let r = pose.r * f.r_b;
        let moving = |e: DVec3| [e, w.cross(e), al.cross(e) + w.cross(w.cross(e))];
        FrameJet {
            origin: [
                pose.p + u,
                v + w.cross(u),
                a + al.cross(u) + w.cross(w.cross(u)),
            ],
            axes: [moving(r.x_axis), moving(r.y_axis), moving(r.z_axis)],
        }
    }

    /// The same frame at rest.
    fn at_rest(&self) -> FrameJet {
        let rest = |j: &Jet| [j[0], DVec3::ZERO, DVec3::ZERO];
        FrameJet {
            origin: rest(&self.origin),
            axes: [
                rest(&self.axes[0]),
                rest(&self.axes[1]),
                rest(&self.axes[2]),
            ],
        }
    }

    /// `R·w` for a vector jet `w` of frame coordinates.
    fn rotate(&self, w: &Jet) -> Jet {
        let mut out = [DVec3::ZERO; 3];
        for (k, axis) in self.axes.iter().enumerate() {
            let comp = [w[0][k], w[1][k], w[2][k]];
            let term = jet_scale(comp, axis);
            for o in 0..3 {
                out[o] += term[o];
            }
        }
        out
    }
}

/// A curve's point and tangent jets, in its frame's coordinates, along a parameter jet
/// `x = [x, ẋ, ẍ]` from the curve's value and derivatives `e` at `x`.
fn along(e: &[DVec3; 4], x: ScalarJet) -> (Jet, Jet) {
    let [c, c1, c2, c3] = *e;
    (
        [c, c1 * x[1], c2 * (x[1] * x[1]) + c1 * x[2]],
        [c1, c2 * x[1], c3 * (x[1] * x[1]) + c2 * x[2]],
    )
}

/// `[g_1, g_2, Φ_n, Φ_b]` as jets (module docs).
fn contact_jets(
    fa: &FrameJet,
    fb: &FrameJet,
    ea: &[DVec3; 4],
    eb: &[DVec3; 4],
    a: ScalarJet,
    b: ScalarJet,
) -> [ScalarJet; 4] {
    let (ci, ti) = along(ea, a);
    let (cj, tj) = along(eb, b);
    let pi = fa.rotate(&ci);
    let pj = fb.rotate(&cj);
    let d = jet_sub(
        &[
            fa.origin[0] + pi[0],
            fa.origin[1] + pi[1],
            fa.origin[2] + pi[2],
        ],
        &[
            fb.origin[0] + pj[0],
            fb.origin[1] + pj[1],
            fb.origin[2] + pj[2],
        ],
    );
    let ti = fa.rotate(&ti);
    let tj = fb.rotate(&tj);
    let z = fa.axes[2];
    let n = jet_unit(&jet_cross(&z, &ti));
    [
        dot_series(&d, &ti),
        dot_series(&jet_cross(&ti, &tj), &z),
        dot_series(&n, &d),
        dot_series(&z, &d),
    ]
}

/// `x` with `M x = r` for a 2 × 2 `M = [m00 m01; m10 m11]`; `None` when singular.
fn solve2(m: [[f64; 2]; 2], r: [f64; 2]) -> Option<[f64; 2]> {
    let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    let scale = m.iter().flatten().map(|x| x.abs()).fold(0.0, f64::max);
    // Also singular when not finite (a NaN compares false).
    if det.abs() <= 1e-14 * scale * scale || !det.is_finite() {
        return None;
    }
    Some([
        (r[0] * m[1][1] - m[0][1] * r[1]) / det,
        (m[0][0] * r[1] - m[1][0] * r[0]) / det,
    ])
}

impl CurveContact {
    fn frame_jets(
        &self,
        s: &State,
        v: Option<&Velocities>,
        acc: Option<&Velocities>,
    ) -> [FrameJet; 2] {
        let zero = (DVec3::ZERO, DVec3::ZERO);
        std::array::from_fn(|k| {
            let f = &self.frames[k];
            FrameJet::new(
                f,
                s,
                v.map_or(zero, |v| twist(v, f.body)),
                acc.map_or(zero, |a| twist(a, f.body)),
            )
        })
    }

    /// The relative pose of frame B in frame A (the warm start's key).
    fn key(fa: &FrameJet, fb: &FrameJet) -> [f64; 12] {
        let ra = DMat3::from_cols(fa.axes[0][0], fa.axes[1][0], fa.axes[2][0]);
        let rb = DMat3::from_cols(fb.axes[0][0], fb.axes[1][0], fb.axes[2][0]);
        let o = ra.transpose() * (fb.origin[0] - fa.origin[0]);
        let q = ra.transpose() * rb;
        let mut k = [0.0; 12];
        k[..3].copy_from_slice(&o.to_array());
        k[3..].copy_from_slice(&q.to_cols_array());
        k
    }

    /// `g` and `G = ∂g/∂(α, β)` at rest at `x`.
    fn conditions(&self, fa: &FrameJet, fb: &FrameJet, x: [f64; 2]) -> ([f64; 2], [[f64; 2]; 2]) {
        let (ea, eb) = (self.curves[0].eval(x[0]), self.curves[1].eval(x[1]));
        let da = contact_jets(fa, fb, &ea, &eb, [x[0], 1.0, 0.0], [x[1], 0.0, 0.0]);
        let db = contact_jets(fa, fb, &ea, &eb, [x[0], 0.0, 0.0], [x[1], 1.0, 0.0]);
        (
            [da[0][0], da[1][0]],
            [[da[0][1], db[0][1]], [da[1][1], db[1][1]]],
        )
    }

    /// Newton on `g(α, β) = 0` from `start`, steps limited to a quarter piece of each curve;
    /// `None` when it does not converge within 30 steps or meets a singular `G`.
    fn newton(&self, fa: &FrameJet, fb: &FrameJet, start: [f64; 2]) -> Option<[f64; 2]> {
        let limit = [0, 1].map(|k| 0.5 / self.curves[k].pieces() as f64);
        let mut x = start;
        for _ in 0..30 {
            let (g, m) = self.conditions(fa, fb, x);
            let step = solve2(m, [-g[0], -g[1]])?;
            let step = [0, 1].map(|k| step[k].clamp(-limit[k], limit[k]));
            x = [x[0] + step[0], x[1] + step[1]];
            if step[0].abs() <= 1e-13 && step[1].abs() <= 1e-13 {
                return Some([self.curves[0].wrap(x[0]), self.curves[1].wrap(x[1])]);
            }
        }
        None
    }

    /// The closest pair of samples of the two curves (8 per piece and order, at most 512 per
    /// curve), the start of a search without a usable warm start.
    fn nearest_samples(&self, fa: &FrameJet, fb: &FrameJet) -> [f64; 2] {
        let points = |k: usize, f: &FrameJet| -> Vec<(f64, DVec3)> {
            let c = &self.curves[k];
            let n = (8 * c.pieces() * c.order + 1).min(512);
            (0..n)
                .map(|i| {
                    let a = -1.0 + 2.0 * i as f64 / (n - 1) as f64;
                    let p = c.eval(a)[0];
                    (a, f.origin[0] + f.rotate(&[p, DVec3::ZERO, DVec3::ZERO])[0])
                })
                .collect()
        };
        let (pa, pb) = (points(0, fa), points(1, fb));
        let mut best = (f64::INFINITY, [0.0, 0.0]);
        for (a, p) in &pa {
            for (b, q) in &pb {
                let d = (*p - *q).length_squared();
                if d < best.0 {
                    best = (d, [*a, *b]);
                }
            }
        }
        best.1
    }

    /// `[α, β]` for frames at rest `fa`, `fb`: from the last contact, or from a search.
    fn solve(&self, fa: &FrameJet, fb: &FrameJet) -> [f64; 2] {
        LastContact::solve_at(&self.contact, Self::key(fa, fb), |last| {
            let warm = last
                .iter()
                .all(|x| x.is_finite())
                .then(|| self.newton(fa, fb, last))
                .flatten();
            warm.unwrap_or_else(|| {
                let start = self.nearest_samples(fa, fb);
                self.newton(fa, fb, start).unwrap_or(start)
            })
        })
    }

    /// `[α, β]` at state `s` (curve I's and curve J's contact parameters).
    pub fn parameters_at(&self, s: &State) -> [f64; 2] {
        let [fa, fb] = self.frame_jets(s, None, None);
        self.solve(&fa, &fb)
    }

    /// The contact point on curve I and the frame `[tangent, normal, binormal]` there, in
    /// ground, at state `s` (the IFLOAT/JFLOAT placement: x along curve I's tangent, z along
    /// frame A's z, y = z × x).
    pub fn contact_frame(&self, s: &State) -> (DVec3, DMat3) {
        let [fa, _] = self.frame_jets(s, None, None);
        let x = self.parameters_at(s);
        let e = self.curves[0].eval(x[0]);
        let p = fa.origin[0] + fa.rotate(&[e[0], DVec3::ZERO, DVec3::ZERO])[0];
        let t = fa.rotate(&[e[1], DVec3::ZERO, DVec3::ZERO])[0].normalize_or_zero();
        let z = fa.axes[2][0];
        (p, DMat3::from_cols(t, z.cross(t), z))
    }

    /// The contact point's speeds along curve I and curve J relative to their bodies,
    /// `[α̇·|c_I'|, β̇·|c_J'|]`, along the twists `v` (CVCV's IVEL and JVEL).
    pub fn sliding_speeds(&self, s: &State, v: &Velocities) -> [f64; 2] {
        let (x, xd, _) = self.parameter_jets(s, Some(v), None);
        [0, 1].map(|k| xd[k] * self.curves[k].eval(x[k])[1].length())
    }

    /// `x`, `ẋ`, `ẍ` of `(α, β)` along `v`, `acc` (module docs).
    fn parameter_jets(
        &self,
        s: &State,
        v: Option<&Velocities>,
        acc: Option<&Velocities>,
    ) -> ([f64; 2], [f64; 2], [f64; 2]) {
        let [fa, fb] = self.frame_jets(s, v, acc);
        let x = self.solve(&fa.at_rest(), &fb.at_rest());
        self.rates_at(&fa, &fb, x)
    }

    /// `(x, ẋ, ẍ)` for the moving frames `fa`, `fb` at contact `x`; zero rates where `G` is
    /// singular (the curves' curvatures conform there and the contact is not unique).
    fn rates_at(
        &self,
        fa: &FrameJet,
        fb: &FrameJet,
        x: [f64; 2],
    ) -> ([f64; 2], [f64; 2], [f64; 2]) {
        let (ea, eb) = (self.curves[0].eval(x[0]), self.curves[1].eval(x[1]));
        let (_, m) = self.conditions(&fa.at_rest(), &fb.at_rest(), x);
        let g = contact_jets(fa, fb, &ea, &eb, [x[0], 0.0, 0.0], [x[1], 0.0, 0.0]);
        let Some(xd) = solve2(m, [-g[0][1], -g[1][1]]) else {
            return (x, [0.0; 2], [0.0; 2]);
        };
        let g = contact_jets(fa, fb, &ea, &eb, [x[0], xd[0], 0.0], [x[1], xd[1], 0.0]);
        let xdd = solve2(m, [-g[0][2], -g[1][2]]).unwrap_or([0.0; 2]);
        (x, xd, xdd)
    }

    /// The row's `[Φ, Φ̇, Φ̈]` for the moving frames `fa`, `fb`.
    fn row_series(&self, fa: &FrameJet, fb: &FrameJet) -> ScalarJet {
        let x = self.solve(&fa.at_rest(), &fb.at_rest());
        let (x, xd, xdd) = self.rates_at(fa, fb, x);
        let (ea, eb) = (self.curves[0].eval(x[0]), self.curves[1].eval(x[1]));
        let j = contact_jets(
            fa,
            fb,
            &ea,
            &eb,
            [x[0], xd[0], xdd[0]],
            [x[1], xd[1], xdd[1]],
        );
        j[2 + self.axis]
    }

    /// `Φ` at state `s`.
    pub fn value(&self, s: &State) -> f64 {
        let [fa, fb] = self.frame_jets(s, None, None);
        let x = self.solve(&fa, &fb);
        let (ea, eb) = (self.curves[0].eval(x[0]), self.curves[1].eval(x[1]));
        contact_jets(&fa, &fb, &ea, &eb, [x[0], 0.0, 0.0], [x[1], 0.0, 0.0])[2 + self.axis][0]
    }

    /// `[Φ, Φ̇, Φ̈]` along the twists `v` and accelerations `acc`.
    pub fn series(&self, s: &State, v: &Velocities, acc: Option<&Velocities>) -> ScalarJet {
        let [fa, fb] = self.frame_jets(s, Some(v), acc);
        self.row_series(&fa, &fb)
    }

    /// Adds `c·∂Φ/∂q` to `g`: the rate along each unit twist of the two bodies.
    pub fn gradient(&self, s: &State, c: f64, g: &mut RowGradient) {
        let zero = (DVec3::ZERO, DVec3::ZERO);
        for side in 0..2 {
            let Some(k) = self.frames[side].body.part() else {
                continue;
            };
            let mut block = [0.0; 6];
            for (comp, out) in block.iter_mut().enumerate() {
                let mut unit = DVec3::ZERO;
                unit[comp % 3] = 1.0;
                let tw = if comp < 3 {
                    (unit, DVec3::ZERO)
                } else {
                    (DVec3::ZERO, unit)
                };
                let jets: [FrameJet; 2] = std::array::from_fn(|f| {
                    let same = self.frames[f].body == self.frames[side].body;
                    FrameJet::new(&self.frames[f], s, if same { tw } else { zero }, zero)
                });
                *out = c * self.row_series(&jets[0], &jets[1])[1];
            }
            g.add_block(k, block);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::constraints::rows::curve_gap::tests::{
        assert_gradient_matches_differences, assert_series_matches_differences, TWIST,
    };
    use crate::state::{ControlValues, Pose};
    use linkage_model::curves::CurveSpec;
    use linkage_model::{Body, Origin};

    fn curve(points: Vec<DVec3>, closed: bool) -> Arc<Curve> {
        let origin = Origin {
            statement: "CURVE",
            id: 1,
            name: "CURVE_1".into(),
            span: Default::default(),
            statement_index: 0,
        };
        let spec = CurveSpec {
            points,
            order: 4,
            closed,
            through_points: true,
        };
        Arc::new(Curve::new(origin, &spec).unwrap())
    }

    /// An ellipse (closed, semi-axes 1 and 0.6) on part 0 and a wavy open planar curve on
    /// part 1, each through a tilted frame; the poses put the curves near each other but off
    /// contact (the rows are checked off the manifold, where the parameters' own rates
    /// matter), the planes not parallel.
    fn setup(axis: usize) -> (CurveContact, State) {
        let ellipse: Vec<DVec3> = (0..=40)
            .map(|i| {
                let t = std::f64::consts::TAU * i as f64 / 40.0;
                DVec3::new(t.cos(), 0.6 * t.sin(), 0.0)
            })
            .collect();
        let wave: Vec<DVec3> = (0..9)
            .map(|i| {
                let x = -2.0 + 0.5 * i as f64;
                DVec3::new(x, 0.15 * (1.3 * x).sin(), 0.0)
            })
            .collect();
        let row = CurveContact {
            frames: [
                BodyFrame {
                    body: Body::Part(0),
                    p_b: DVec3::new(0.1, -0.2, 0.05),
                    r_b: DMat3::from_rotation_z(0.3),
                },
                BodyFrame {
                    body: Body::Part(1),
                    p_b: DVec3::new(-0.3, 0.1, 0.0),
                    r_b: DMat3::from_rotation_x(0.1) * DMat3::from_rotation_z(-0.2),
                },
            ],
            curves: [curve(ellipse, true), curve(wave, false)],
            axis,
            contact: Arc::new(Mutex::new(PairContact {
                key: [f64::NAN; 12],
                params: [f64::NAN; 2],
            })),
        };
        // The ellipse's centre ~0.68 above the wave's line: its bottom (y = −0.6) ~0.08 off.
        let s = State {
            poses: vec![
                Pose {
                    p: DVec3::new(0.2, 0.8, 0.1),
                    r: DMat3::from_rotation_y(0.05) * DMat3::from_rotation_z(0.1),
                },
                Pose {
                    p: DVec3::new(0.3, -0.2, 0.05),
                    r: DMat3::from_rotation_z(0.05),
                },
            ],
            time: 0.0,
            controls: ControlValues::default(),
            elements: Default::default(),
        };
        (row, s)
    }

    #[test]
    fn the_contact_has_parallel_tangents_and_no_tangential_offset() {
        let (row, s) = setup(0);
        let [fa, fb] = row.frame_jets(&s, None, None);
        let x = row.parameters_at(&s);
        let (g, _) = row.conditions(&fa, &fb, x);
        assert!(g[0].abs() < 1e-12 && g[1].abs() < 1e-12, "{g:?}");
        // The ellipse's lower half faces the wave: its points run from angle 0 at α = −1, so
        // the contact's angle π(α + 1) has a negative sine.
        assert!((std::f64::consts::PI * (x[0] + 1.0)).sin() < -0.5, "{x:?}");
    }

    #[test]
    fn gradient_and_rates_match_finite_differences_off_contact() {
        for axis in [0, 1] {
            let (row, s) = setup(axis);
            let mut g = RowGradient::default();
            row.gradient(&s, 1.0, &mut g);
            let what = format!("axis {axis}");
            assert_gradient_matches_differences(|st| row.value(st), &g, &s, &what);
            let v = TWIST;
            let acc = [
                (DVec3::new(0.2, 0.1, -0.3), DVec3::new(-0.1, 0.3, 0.2)),
                (DVec3::new(0.0, -0.4, 0.1), DVec3::new(0.3, 0.0, -0.2)),
            ];
            let series = row.series(&s, &v, None);
            let qdd = series[2];
            assert_series_matches_differences(|st| row.value(st), series, &g, &s, &v, &what);
            // The accelerations enter linearly, through the gradient: Φ̈(acc) − Φ̈(0) = ∇Φ·acc.
            let with_acc = row.series(&s, &v, Some(&acc))[2];
            assert!(
                (with_acc - qdd - g.rate(&acc)).abs() < 1e-10,
                "axis {axis}: acceleration term"
            );
        }
    }
}
