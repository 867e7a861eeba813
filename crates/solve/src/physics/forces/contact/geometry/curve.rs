//! 2-D curve contacts: a GRAPHICS CURVE's polyline (in its CRM marker's xy plane, extruded
//! along its z; `linkage_model::contacts` states the solid side) against a round solid
//! (sphere, POINT, CIRCLE disc), a PLANE or another curve. Everything is measured in the
//! curve's plane: other geometry is projected onto it.
//!
//! Signed distance `s` of a point `q` (curve frame, xy) from the curve: `d` the distance to
//! the nearest point `p` of the polyline, `s = +d` outside the solid and `−d` inside; the side
//! is that of `q − p` against the outward normal at `p` (a chord's normal, or at a vertex the
//! sum of its two chords' normals: the pseudo-normal, exact for a polyline). Past the end of
//! an open curve a point is outside. The outward normal of a chord of tangent `t` is
//! `σ (z × t)`: σ = +1 on an open curve (solid on the right of increasing α) and on a
//! clockwise closed curve (inside solid), −1 on a counter-clockwise one; a flipped curve
//! negates σ.
//!
//! Incidents (one per connected region of penetration):
//! - round solid of radius `r` and centre `c`: depth `r − s(c)` at the nearest point, normal
//!   the outward normal there (towards `c`);
//! - PLANE: each polyline vertex below the plane, depth its distance under it, normal the
//!   plane's +z; consecutive penetrating vertices are one incident;
//! - curve I against curve J: each vertex of I's polyline inside J's solid, depth `−s`, normal
//!   J's outward normal at its nearest point; consecutive vertices are one incident. Only I's
//!   vertices are tested (testing J's against I too would count one overlap twice), so both
//!   curves should be smooth at the sampling scale: a sharp corner of J pressing into I is
//!   seen through I's vertices around it, not at the corner.

use super::{Incident, IncidentPoint, Placed, Placement};
use glam::{DVec2, DVec3};
use linkage_model::contacts::Polyline;
use std::sync::Arc;

/// A curve geometry's polyline and solid side.
#[derive(Clone, Debug)]
pub struct CurveSide {
    pub polyline: Arc<Polyline>,
    /// σ of the module docs (+1 or −1), flip included.
    pub sigma: f64,
}

impl CurveSide {
    /// The side of `polyline`, reversed when `flip`.
    pub fn new(polyline: Arc<Polyline>, flip: bool) -> CurveSide {
        let pts = &polyline.points;
        let mut sigma = 1.0;
        if polyline.closed {
            // Shoelace: twice the signed area, > 0 counter-clockwise.
            let area: f64 = (0..pts.len())
                .map(|k| {
                    let (a, b) = (pts[k], pts[(k + 1) % pts.len()]);
                    a.x * b.y - b.x * a.y
                })
                .sum();
            if area > 0.0 {
                sigma = -1.0;
            }
        }
        if flip {
            sigma = -sigma;
        }
        CurveSide { polyline, sigma }
    }

    fn point(&self, k: usize) -> DVec2 {
        let p = self.polyline.points[k % self.polyline.points.len()];
        DVec2::new(p.x, p.y)
    }

    fn chords(&self) -> usize {
        let n = self.polyline.points.len();
        if self.polyline.closed {
            n
        } else {
            n.saturating_sub(1)
        }
    }

    /// Outward unit normal of chord `k`.
    fn chord_normal(&self, k: usize) -> DVec2 {
        let t = (self.point(k + 1) - self.point(k)).normalize_or_zero();
        DVec2::new(-t.y, t.x) * self.sigma
    }

    /// The nearest point `p` of the polyline to `q`, the outward unit normal `n` there
    /// (pointing from the solid towards `q` when `q` is outside) and the signed distance `s`
    /// (module docs). `None` for a polyline without a chord.
    pub fn nearest(&self, q: DVec2) -> Option<(DVec2, DVec2, f64)> {
        let m = self.chords();
        let mut best: Option<(f64, usize, f64)> = None;
        for k in 0..m {
            let (a, b) = (self.point(k), self.point(k + 1));
            let d = b - a;
            let t = if d.length_squared() > 0.0 {
                ((q - a).dot(d) / d.length_squared()).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let dist = (q - (a + d * t)).length();
            if best.is_none_or(|(bd, _, _)| dist < bd) {
                best = Some((dist, k, t));
            }
        }
        let (dist, k, t) = best?;
        let (a, b) = (self.point(k), self.point(k + 1));
        let p = a + (b - a) * t;
        let closed = self.polyline.closed;
        // Normal used for the side: the chord's, or the vertex pseudo-normal.
        let pseudo = if t <= 0.0 && (closed || k > 0) {
            self.chord_normal(k) + self.chord_normal(k + m - 1)
        } else if t >= 1.0 && (closed || k + 1 < m) {
            self.chord_normal(k) + self.chord_normal(k + 1)
        } else {
            self.chord_normal(k)
        };
        let off = q - p;
        let tangent = (b - a).normalize_or_zero();
        let past_end = !closed
            && ((t <= 0.0 && k == 0 && off.dot(tangent) < 0.0)
                || (t >= 1.0 && k + 1 == m && off.dot(tangent) > 0.0));
        let inside = !past_end && off.dot(pseudo) < 0.0;
        let s = if inside { -dist } else { dist };
        let n = if dist > 1e-12 * (1.0 + p.length()) {
            off / dist * s.signum()
        } else {
            pseudo.normalize_or_zero()
        };
        Some((p, n, s))
    }
}

/// The radius of a round solid (sphere, POINT, CIRCLE disc), `None` otherwise.
pub fn round_radius(p: &Placed) -> Option<f64> {
    p.radius.or_else(|| {
        p.shape
            .as_cylinder()
            .filter(|c| c.half_height == 0.0)
            .map(|c| c.radius)
    })
}

/// Whether a curve contact between `a` and `b` (at least one a curve) is computed.
pub fn supported(a: &Placed, b: &Placed) -> bool {
    let other_ok = |p: &Placed| {
        p.curve.is_some() || round_radius(p).is_some() || p.shape.as_halfspace().is_some()
    };
    other_ok(a) && other_ok(b)
}

/// A penetrating point found in world coordinates: on I, on J, depth, normal (J → I, world).
struct Hit {
    on_i: DVec3,
    on_j: DVec3,
    r_i: f64,
    r_j: f64,
    depth: f64,
    normal: DVec3,
}

fn to_plane(v: DVec3) -> DVec2 {
    DVec2::new(v.x, v.y)
}

fn from_plane(w: &Placement, p: DVec2) -> DVec3 {
    w.p + w.r * DVec3::new(p.x, p.y, 0.0)
}

/// The incidents between `a` (I body at `body_i`) and `b` (J body at `body_j`), at least one
/// of them a curve (module docs).
pub fn incidents(
    a: &Placed,
    body_i: &Placement,
    b: &Placed,
    body_j: &Placement,
    out: &mut Vec<Incident>,
) {
    let wa = body_i.then(&a.in_body);
    let wb = body_j.then(&b.in_body);
    // Runs of hits: each run one incident. `swap`: the curve is J's.
    let mut runs: Vec<Vec<Hit>> = Vec::new();
    match (&a.curve, &b.curve) {
        (Some(ca), Some(cb)) => {
            runs.extend(vertex_runs(ca, &wa, |v| inside_curve(cb, &wb, v), false));
        }
        (Some(c), None) => round_or_plane(c, &wa, b, &wb, true, &mut runs),
        (None, Some(c)) => round_or_plane(c, &wb, a, &wa, false, &mut runs),
        (None, None) => {}
    }
    let (inv_i, inv_j) = (body_i.r.transpose(), body_j.r.transpose());
    for run in runs {
        let Some(deepest) = (0..run.len()).max_by(|x, y| run[*x].depth.total_cmp(&run[*y].depth))
        else {
            continue;
        };
        let points = run
            .iter()
            .map(|h| IncidentPoint {
                on_i: inv_i * (h.on_i - body_i.p),
                on_j: inv_j * (h.on_j - body_j.p),
                depth: h.depth,
                r_i: h.r_i,
                r_j: h.r_j,
            })
            .collect();
        let normal_j = inv_j * run[deepest].normal;
        if normal_j != DVec3::ZERO {
            out.push(Incident {
                points,
                deepest,
                normal_j,
            });
        }
    }
}

/// A vertex `v` (world) inside curve `c` placed at `w`: its nearest point (world), the
/// outward normal (world) and the depth.
fn inside_curve(c: &CurveSide, w: &Placement, v: DVec3) -> Option<(DVec3, DVec3, f64)> {
    let q = to_plane(w.r.transpose() * (v - w.p));
    let (p, n, s) = c.nearest(q)?;
    (s < 0.0).then(|| (from_plane(w, p), w.r * DVec3::new(n.x, n.y, 0.0), -s))
}

/// Runs of consecutive vertices of curve `c` (placed at `w`) that `test` finds penetrating
/// (the other geometry's point, outward normal and depth). `c_is_j`: the curve is J's.
fn vertex_runs(
    c: &CurveSide,
    w: &Placement,
    test: impl Fn(DVec3) -> Option<(DVec3, DVec3, f64)>,
    c_is_j: bool,
) -> Vec<Vec<Hit>> {
    let n = c.polyline.points.len();
    let mut runs: Vec<Vec<Hit>> = Vec::new();
    let mut current: Vec<Hit> = Vec::new();
    let mut first_run_starts_at_0 = false;
    for k in 0..n {
        let v = from_plane(w, c.point(k));
        match test(v) {
            Some((p, out_n, depth)) => {
                if k == 0 {
                    first_run_starts_at_0 = true;
                }
                // The other's outward normal points towards the vertex: towards the curve.
                let (on_i, on_j, normal) = if c_is_j {
                    (p, v, -out_n)
                } else {
                    (v, p, out_n)
                };
                current.push(Hit {
                    on_i,
                    on_j,
                    r_i: 0.0,
                    r_j: 0.0,
                    depth,
                    normal,
                });
            }
            None => {
                if !current.is_empty() {
                    runs.push(std::mem::take(&mut current));
                }
            }
        }
    }
    if !current.is_empty() {
        // A closed curve's last run continues into its first.
        if c.polyline.closed && first_run_starts_at_0 && !runs.is_empty() {
            let first = runs.remove(0);
            current.extend(first);
        }
        runs.push(current);
    }
    runs
}

/// Curve `c` (placed at `wc`) against a round solid or a plane `o` (placed at `wo`).
/// `c_is_i`: the curve is I's.
fn round_or_plane(
    c: &CurveSide,
    wc: &Placement,
    o: &Placed,
    wo: &Placement,
    c_is_i: bool,
    runs: &mut Vec<Vec<Hit>>,
) {
    if let Some(r) = round_radius(o) {
        let q = to_plane(wc.r.transpose() * (wo.p - wc.p));
        let Some((p, n, s)) = c.nearest(q) else {
            return;
        };
        let depth = r - s;
        if depth <= 0.0 {
            return;
        }
        let (p, n) = (from_plane(wc, p), wc.r * DVec3::new(n.x, n.y, 0.0));
        runs.push(vec![if c_is_i {
            Hit {
                on_i: p,
                on_j: wo.p,
                r_i: 0.0,
                r_j: r,
                depth,
                normal: -n,
            }
        } else {
            Hit {
                on_i: wo.p,
                on_j: p,
                r_i: r,
                r_j: 0.0,
                depth,
                normal: n,
            }
        }]);
    } else if o.shape.as_halfspace().is_some() {
        let up = wo.r * DVec3::Z;
        let below = |v: DVec3| {
            let z = (v - wo.p).dot(up);
            (z < 0.0).then(|| (v - up * z, up, -z))
        };
        runs.extend(vertex_runs(c, wc, below, !c_is_i));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn side(points: &[(f64, f64)], closed: bool, flip: bool) -> CurveSide {
        let polyline = Polyline {
            curve: 1,
            points: points.iter().map(|&(x, y)| DVec3::new(x, y, 0.0)).collect(),
            closed,
        };
        CurveSide::new(Arc::new(polyline), flip)
    }

    #[test]
    fn open_curves_are_solid_on_the_right_and_closed_ones_inside() {
        // Along +x: the solid is below (y < 0), the outward normal +y.
        let line = side(&[(-1.0, 0.0), (0.0, 0.0), (1.0, 0.0)], false, false);
        let (p, n, s) = line.nearest(DVec2::new(0.3, 0.25)).unwrap();
        assert!((p - DVec2::new(0.3, 0.0)).length() < 1e-15);
        assert!((n - DVec2::Y).length() < 1e-15 && (s - 0.25).abs() < 1e-15);
        let (_, n, s) = line.nearest(DVec2::new(0.0, -0.5)).unwrap();
        assert!((n - DVec2::Y).length() < 1e-15 && (s + 0.5).abs() < 1e-15);
        let flipped = side(&[(-1.0, 0.0), (1.0, 0.0)], false, true);
        assert!((flipped.nearest(DVec2::new(0.0, -0.5)).unwrap().2 - 0.5).abs() < 1e-15);
        // Past the end of an open curve: outside.
        assert!(line.nearest(DVec2::new(2.0, -0.1)).unwrap().2 > 0.0);
        // A counter-clockwise unit square: inside is solid, whichever way it runs.
        let sq = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
        for pts in [sq.to_vec(), sq.iter().rev().copied().collect()] {
            let c = side(&pts, true, false);
            assert!((c.nearest(DVec2::new(0.5, 0.4)).unwrap().2 + 0.4).abs() < 1e-15);
            assert!((c.nearest(DVec2::new(2.0, 2.0)).unwrap().2 - 2f64.sqrt()).abs() < 1e-15);
            let ring = side(&pts, true, true);
            assert!((ring.nearest(DVec2::new(0.5, 0.4)).unwrap().2 - 0.4).abs() < 1e-15);
        }
    }
}
