//! Tessellation of display shapes into triangles and line segments.
//!
//! Every shape is built in its own frame (the frame of the marker it is defined on: axis z for
//! the solids of revolution, a corner at the origin for a box) and then moved into the body
//! frame with [`Mesh::transformed`]. Lengths are in the dataset's unit. Triangles are wound
//! counter-clockwise seen from outside, but the viewer shades both sides, so winding is not a
//! contract. Cost: O(sides) vertices for a solid of revolution, O(segments²) for an ellipsoid.

use glam::{DMat3, DVec3};

/// Triangles and line segments over one vertex list.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    pub positions: Vec<DVec3>,
    pub triangles: Vec<[u32; 3]>,
    pub lines: Vec<[u32; 2]>,
}

/// Fewest and most sides/segments a curved shape is drawn with (a page stays small whatever
/// SIDES says, and a 1-sided cylinder is still a solid).
pub const MIN_SEGMENTS: u32 = 3;
pub const MAX_SEGMENTS: u32 = 64;

impl Mesh {
    fn vertex(&mut self, p: DVec3) -> u32 {
        self.positions.push(p);
        (self.positions.len() - 1) as u32
    }

    /// Appends `other` (its indices shifted).
    pub fn append(&mut self, other: &Mesh) {
        let base = self.positions.len() as u32;
        self.positions.extend_from_slice(&other.positions);
        self.triangles
            .extend(other.triangles.iter().map(|t| t.map(|k| k + base)));
        self.lines
            .extend(other.lines.iter().map(|l| l.map(|k| k + base)));
    }

    /// The mesh moved by `p + R·x`.
    pub fn transformed(mut self, p: DVec3, r: DMat3) -> Mesh {
        for x in &mut self.positions {
            *x = p + r * *x;
        }
        self
    }

    pub fn is_empty(&self) -> bool {
        self.triangles.is_empty() && self.lines.is_empty()
    }
}

fn clamp_segments(n: u32) -> u32 {
    n.clamp(MIN_SEGMENTS, MAX_SEGMENTS)
}

/// A frustum about z: radius `bottom` at z = 0, `top` at z = `length`, swept from the x axis
/// through `angle` (a full turn gets no seam faces) with `sides` facets per turn, both ends
/// capped. A cylinder is a frustum with equal radii.
pub fn frustum(bottom: f64, top: f64, length: f64, angle: f64, sides: u32) -> Mesh {
    let full = angle.abs() >= std::f64::consts::TAU - 1e-12;
    let turn = if full { std::f64::consts::TAU } else { angle };
    // Facets in proportion to the swept angle, at least one.
    let n = ((clamp_segments(sides) as f64) * (turn.abs() / std::f64::consts::TAU)).ceil() as u32;
    let n = n.max(1);
    let mut m = Mesh::default();
    let ring = |m: &mut Mesh, r: f64, z: f64| -> Vec<u32> {
        let count = if full { n } else { n + 1 };
        (0..count)
            .map(|k| {
                let a = turn * k as f64 / n as f64;
                m.vertex(DVec3::new(r * a.cos(), r * a.sin(), z))
            })
            .collect()
    };
    let low = ring(&mut m, bottom, 0.0);
    let high = ring(&mut m, top, length);
    let c0 = m.vertex(DVec3::ZERO);
    let c1 = m.vertex(DVec3::new(0.0, 0.0, length));
    let next = |k: usize| if full { (k + 1) % low.len() } else { k + 1 };
    let facets = if full { low.len() } else { low.len() - 1 };
    for k in 0..facets {
        let (a, b, c, d) = (low[k], low[next(k)], high[next(k)], high[k]);
        m.triangles.push([a, b, c]);
        m.triangles.push([a, c, d]);
        m.triangles.push([c0, b, a]);
        m.triangles.push([c1, d, c]);
        m.lines.push([a, b]);
        m.lines.push([d, c]);
    }
    if !full {
        // The seam faces of a partial sweep.
        for (l, h) in [(low[0], high[0]), (low[facets], high[facets])] {
            m.triangles.push([c0, l, h]);
            m.triangles.push([c0, h, c1]);
        }
    }
    m
}

/// A cylinder of `radius` from z = 0 to z = `length` about z.
pub fn cylinder(radius: f64, length: f64, angle: f64, sides: u32) -> Mesh {
    frustum(radius, radius, length, angle, sides)
}

/// A box with one corner at the origin and edges `extent` along x, y, z (signed).
pub fn cuboid(extent: [f64; 3]) -> Mesh {
    let mut m = Mesh::default();
    let [ex, ey, ez] = extent;
    let v: Vec<u32> = (0..8)
        .map(|k| {
            let x = if k & 1 != 0 { ex } else { 0.0 };
            let y = if k & 2 != 0 { ey } else { 0.0 };
            let z = if k & 4 != 0 { ez } else { 0.0 };
            m.vertex(DVec3::new(x, y, z))
        })
        .collect();
    // Faces as quads of corner numbers (bit 0 = x, bit 1 = y, bit 2 = z).
    for [a, b, c, d] in [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ] {
        m.triangles.push([v[a], v[b], v[c]]);
        m.triangles.push([v[a], v[c], v[d]]);
    }
    for (a, b) in [
        (0, 1),
        (2, 3),
        (4, 5),
        (6, 7),
        (0, 2),
        (1, 3),
        (4, 6),
        (5, 7),
        (0, 4),
        (1, 5),
        (2, 6),
        (3, 7),
    ] {
        m.lines.push([v[a], v[b]]);
    }
    m
}

/// An ellipsoid centred at the origin with `diameters` along x, y, z: `segments` meridians and
/// `segments / 2` parallels.
pub fn ellipsoid(diameters: [f64; 3], segments: u32) -> Mesh {
    let n = clamp_segments(segments).max(6);
    let rings = n / 2;
    let half = DVec3::from(diameters) * 0.5;
    let mut m = Mesh::default();
    let south = m.vertex(DVec3::new(0.0, 0.0, -half.z));
    let mut rows: Vec<Vec<u32>> = Vec::new();
    for i in 1..rings {
        let polar = std::f64::consts::PI * i as f64 / rings as f64;
        let (s, c) = polar.sin_cos();
        rows.push(
            (0..n)
                .map(|k| {
                    let a = std::f64::consts::TAU * k as f64 / n as f64;
                    m.vertex(half * DVec3::new(s * a.cos(), s * a.sin(), -c))
                })
                .collect(),
        );
    }
    let north = m.vertex(DVec3::new(0.0, 0.0, half.z));
    let n = n as usize;
    if let (Some(first), Some(last)) = (rows.first(), rows.last()) {
        for k in 0..n {
            m.triangles.push([south, first[(k + 1) % n], first[k]]);
            m.triangles.push([north, last[k], last[(k + 1) % n]]);
        }
    }
    for pair in rows.windows(2) {
        let (a, b) = (&pair[0], &pair[1]);
        for k in 0..n {
            let k1 = (k + 1) % n;
            m.triangles.push([a[k], a[k1], b[k1]]);
            m.triangles.push([a[k], b[k1], b[k]]);
        }
    }
    m
}

/// An arc of `radius` in the xy plane from the x axis through `angle`, as line segments (a
/// full turn closes).
pub fn arc(radius: f64, angle: f64, segments: u32) -> Mesh {
    let n = clamp_segments(segments);
    let mut m = Mesh::default();
    let v: Vec<u32> = (0..=n)
        .map(|k| {
            let a = angle * k as f64 / n as f64;
            m.vertex(DVec3::new(radius * a.cos(), radius * a.sin(), 0.0))
        })
        .collect();
    for w in v.windows(2) {
        m.lines.push([w[0], w[1]]);
    }
    m
}

/// A polyline through `points`.
pub fn polyline(points: &[DVec3]) -> Mesh {
    let mut m = Mesh::default();
    let v: Vec<u32> = points.iter().map(|p| m.vertex(*p)).collect();
    for w in v.windows(2) {
        m.lines.push([w[0], w[1]]);
    }
    m
}

/// A link from `a` to `b` (Adams' LINK): a slab of `width` across the segment, in the plane
/// normal to `normal`, and `depth` along `normal` (centred on it), with semicircular ends of
/// radius `width / 2` about `a` and `b`.
pub fn link(a: DVec3, b: DVec3, normal: DVec3, width: f64, depth: f64) -> Mesh {
    let along = b - a;
    let length = along.length();
    let n = normal.normalize_or(DVec3::Z);
    let u = (along - n * along.dot(n)).normalize_or(n.any_orthonormal_vector());
    let w = n.cross(u);
    let r = width * 0.5;
    // The stadium outline (convex): a half circle about b, then one about a.
    let half = 8;
    let mut outline = Vec::with_capacity(2 * (half + 1));
    for (centre, start) in [
        (length, -std::f64::consts::FRAC_PI_2),
        (0.0, std::f64::consts::FRAC_PI_2),
    ] {
        for k in 0..=half {
            let t = start + std::f64::consts::PI * k as f64 / half as f64;
            outline.push((centre + r * t.cos(), r * t.sin()));
        }
    }
    let mut m = Mesh::default();
    let place = |x: f64, y: f64, z: f64| a + u * x + w * y + n * z;
    let low: Vec<u32> = outline
        .iter()
        .map(|(x, y)| m.vertex(place(*x, *y, -depth * 0.5)))
        .collect();
    let high: Vec<u32> = outline
        .iter()
        .map(|(x, y)| m.vertex(place(*x, *y, depth * 0.5)))
        .collect();
    let k = low.len();
    for i in 0..k {
        let j = (i + 1) % k;
        m.triangles.push([low[i], low[j], high[j]]);
        m.triangles.push([low[i], high[j], high[i]]);
        m.lines.push([high[i], high[j]]);
        m.lines.push([low[i], low[j]]);
        if i > 0 && j > 0 {
            m.triangles.push([low[0], low[j], low[i]]);
            m.triangles.push([high[0], high[i], high[j]]);
        }
    }
    m
}

/// Three axes of `length` from the origin: x, y, z as separate line meshes (the viewer colours
/// them red, green, blue).
pub fn triad(length: f64) -> [Mesh; 3] {
    [DVec3::X, DVec3::Y, DVec3::Z].map(|axis| polyline(&[DVec3::ZERO, axis * length]))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Distance of `p` from the line through the origin along `axis` (unit).
    fn from_axis(p: DVec3, axis: DVec3) -> f64 {
        (p - axis * p.dot(axis)).length()
    }

    #[test]
    fn a_cylinder_of_radius_r_and_length_l_has_its_rim_at_r_from_its_axis() {
        let (r, l) = (0.0375, 0.157);
        let m = cylinder(r, l, std::f64::consts::TAU, 20);
        // 20 rim vertices at each end and the two cap centres.
        assert_eq!(m.positions.len(), 42);
        let rim: Vec<&DVec3> = m
            .positions
            .iter()
            .filter(|p| from_axis(**p, DVec3::Z) > 1e-12)
            .collect();
        assert_eq!(rim.len(), 40);
        for p in &rim {
            assert!((from_axis(**p, DVec3::Z) - r).abs() < 1e-15, "{p}");
            assert!(p.z.abs() < 1e-15 || (p.z - l).abs() < 1e-15, "{p}");
        }
        // 20 side quads (2 triangles each) and 20 triangles per cap.
        assert_eq!(m.triangles.len(), 80);
    }

    #[test]
    fn a_cylinder_on_a_tilted_marker_keeps_its_radius_about_the_marker_z_axis() {
        let r_bm = DMat3::from_rotation_x(0.7) * DMat3::from_rotation_z(0.3);
        let at = DVec3::new(1.0, -2.0, 0.5);
        let m = cylinder(0.25, 2.0, std::f64::consts::TAU, 12).transformed(at, r_bm);
        let axis = r_bm * DVec3::Z;
        for p in &m.positions {
            let d = from_axis(*p - at, axis);
            assert!(d < 1e-12 || (d - 0.25).abs() < 1e-12, "{d}");
            let h = (*p - at).dot(axis);
            assert!((-1e-12..=2.0 + 1e-12).contains(&h));
        }
    }

    #[test]
    fn a_frustum_narrows_from_bottom_to_top_radius() {
        let m = frustum(0.34, 0.17, 0.15, std::f64::consts::TAU, 18);
        for p in m
            .positions
            .iter()
            .filter(|p| from_axis(**p, DVec3::Z) > 0.0)
        {
            let want = if p.z == 0.0 { 0.34 } else { 0.17 };
            assert!((from_axis(*p, DVec3::Z) - want).abs() < 1e-15);
        }
    }

    #[test]
    fn a_box_spans_its_signed_extents_from_the_corner() {
        let m = cuboid([2.0, -1.0, 0.5]);
        assert_eq!(
            (m.positions.len(), m.triangles.len(), m.lines.len()),
            (8, 12, 12)
        );
        let min = m.positions.iter().fold(DVec3::INFINITY, |a, p| a.min(*p));
        let max = m
            .positions
            .iter()
            .fold(DVec3::NEG_INFINITY, |a, p| a.max(*p));
        assert_eq!(
            (min, max),
            (DVec3::new(0.0, -1.0, 0.0), DVec3::new(2.0, 0.0, 0.5))
        );
    }

    #[test]
    fn ellipsoid_vertices_lie_on_the_surface_of_its_half_diameters() {
        let d = [40.0, 30.0, 20.0];
        let m = ellipsoid(d, 16);
        for p in &m.positions {
            let s = (p.x / 20.0).powi(2) + (p.y / 15.0).powi(2) + (p.z / 10.0).powi(2);
            assert!((s - 1.0).abs() < 1e-12, "{p} {s}");
        }
        assert_eq!(m.positions.len(), 2 + 7 * 16);
    }

    #[test]
    fn a_quarter_arc_ends_on_the_y_axis() {
        let m = arc(2.0, std::f64::consts::FRAC_PI_2, 8);
        assert_eq!(m.lines.len(), 8);
        let end = m.positions[8];
        assert!(end.x.abs() < 1e-15 && (end.y - 2.0).abs() < 1e-15);
        assert!(m.positions.iter().all(|p| (p.length() - 2.0).abs() < 1e-15));
    }

    #[test]
    fn a_link_reaches_half_its_width_beyond_both_markers() {
        let (a, b) = (DVec3::ZERO, DVec3::new(3.0, 0.0, 0.0));
        let m = link(a, b, DVec3::Z, 0.4, 0.1);
        let min_x = m
            .positions
            .iter()
            .map(|p| p.x)
            .fold(f64::INFINITY, f64::min);
        let max_x = m
            .positions
            .iter()
            .map(|p| p.x)
            .fold(f64::NEG_INFINITY, f64::max);
        assert!((min_x + 0.2).abs() < 1e-12 && (max_x - 3.2).abs() < 1e-12);
        assert!(m.positions.iter().all(|p| (p.z.abs() - 0.05).abs() < 1e-15));
    }
}
