//! The contact geometry adapter: the model's contact solids as `parry3d-f64` shapes, and the
//! *incidents* (connected regions of penetration) between the two sides at a configuration.
//!
//! Shapes (in the frame of their marker, see `linkage_model::contacts`): a sphere is a
//! `Ball`; an ellipsoid with unequal semi-axes the convex hull of 24 × 12 points on it; a box
//! a `Cuboid` moved to its corner; a cylinder a `Cylinder` turned from parry's y axis to z;
//! a frustum the convex hull of its two end circles (48 points each); a disc a `Cylinder` of
//! zero height; a point a `Ball` of zero radius; a plane a `HalfSpace` with +z outside; a
//! mesh a `TriMesh` (a surface: penetration is measured from its triangles, so a body wholly
//! inside a mesh, touching no triangle, is not seen); a curve a `Polyline`, whose contacts are
//! computed in its plane by [`super::curve`] (not by parry).
//!
//! Incidents: parry reports *manifolds* (contact points sharing a normal, one per feature pair,
//! per triangle for meshes) for each pair of geometries. Two manifolds of a pair belong to
//! the same incident when neither side is a mesh (two convex solids meet in one convex, hence
//! connected, region), or when their triangles share a vertex on a mesh side (the penetrating
//! triangles of a connected patch). Each incident keeps its distinct points (points closer
//! than the merge distance are one: a mesh vertex is reported by every triangle around it),
//! each as a material point on each body, with its depth, and the normal of its deepest point.
//! Cost: one parry manifold query per geometry pair.

pub mod curve;

use glam::{DMat3, DVec3};
use linkage_model::contacts::{ContactGeometry, Solid};
use linkage_model::{Body, Model};
use parry3d_f64::math::{Matrix as PMat3, Pose as PPose, Rotation as PRot, Vector as PVec};
use parry3d_f64::query::{
    ContactManifold, DefaultQueryDispatcher, PersistentQueryDispatcher, Unsupported,
};
use parry3d_f64::shape::{ConvexPolyhedron, SharedShape};
use std::f64::consts::TAU;
use std::fmt;

fn pv(v: DVec3) -> PVec {
    PVec::new(v.x, v.y, v.z)
}

fn gv(v: PVec) -> DVec3 {
    DVec3::new(v.x, v.y, v.z)
}

/// A rigid placement `x ↦ p + R·x` (glam types of the workspace).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    pub p: DVec3,
    pub r: DMat3,
}

impl Placement {
    pub const IDENTITY: Placement = Placement {
        p: DVec3::ZERO,
        r: DMat3::IDENTITY,
    };

    /// `self ∘ inner`.
    pub fn then(&self, inner: &Placement) -> Placement {
        Placement {
            p: self.p + self.r * inner.p,
            r: self.r * inner.r,
        }
    }

    fn to_parry(self) -> PPose {
        let c = self.r.to_cols_array();
        let m = PMat3::from_cols_array(&c);
        PPose::from_parts(pv(self.p), PRot::from_mat3(&m).normalize())
    }
}

/// One geometry as a parry shape, placed in its body's frame (CM frame; ground: ground).
#[derive(Clone)]
pub struct Placed {
    pub graphic: u64,
    pub shape: SharedShape,
    /// Shape frame in the body frame.
    pub in_body: Placement,
    /// Mesh vertex ids of each triangle (for incident grouping); `None` for convex solids.
    pub triangles: Option<std::sync::Arc<Vec<[u32; 3]>>>,
    /// The radius of a sphere or point (0): its contact point is `centre ∓ radius·n`.
    pub radius: Option<f64>,
    /// A 2-D curve geometry's polyline and side (its shape is then only descriptive).
    pub curve: Option<curve::CurveSide>,
}

impl fmt::Debug for Placed {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Placed")
            .field("graphic", &self.graphic)
            .field("shape", &self.shape.shape_type())
            .field("in_body", &self.in_body)
            .finish()
    }
}

/// Why a contact solid has no shape the geometry library can collide.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ShapeError {
    #[error("its convex hull is degenerate (a zero dimension?)")]
    DegenerateHull,
    #[error("an ellipsoid needs positive XSCALE, YSCALE, ZSCALE")]
    Ellipsoid,
    #[error("a BOX needs non-zero X, Y and Z")]
    Box,
    #[error("a CYLINDER needs a non-zero LENGTH and RADIUS")]
    Cylinder,
    #[error("a FRUSTUM needs a non-zero LENGTH and a radius")]
    Frustum,
    #[error("a CIRCLE needs a positive RADIUS")]
    Circle,
    /// The mesh library's reason (`why`).
    #[error("the mesh '{file}' is not usable: {why}")]
    Mesh { file: String, why: String },
    #[error("CURVE/{0} has fewer than 2 points")]
    ShortCurve(u64),
}

fn hull(points: &[DVec3]) -> Result<SharedShape, ShapeError> {
    let p: Vec<PVec> = points.iter().map(|&q| pv(q)).collect();
    ConvexPolyhedron::from_convex_hull(&p)
        .map(SharedShape::new)
        .ok_or(ShapeError::DegenerateHull)
}

/// A parry shape, its placement in the solid's (marker) frame and, for a mesh, its triangles.
type Shaped = (SharedShape, Placement, Option<Vec<[u32; 3]>>);

/// The parry shape of a solid and its placement in the solid's (marker) frame.
fn shape(solid: &Solid) -> Result<Shaped, ShapeError> {
    let at = |p: DVec3| Placement {
        p,
        r: DMat3::IDENTITY,
    };
    // parry's cylinders run along y; ours along z from 0 to `length`.
    let y_to_z = |length: f64| Placement {
        p: DVec3::new(0.0, 0.0, 0.5 * length),
        r: DMat3::from_rotation_x(std::f64::consts::FRAC_PI_2),
    };
    Ok(match solid {
        Solid::Ellipsoid { radii } => {
            if radii.min_element() <= 0.0 {
                return Err(ShapeError::Ellipsoid);
            }
            if (radii.max_element() - radii.min_element()) <= 1e-12 * radii.max_element() {
                (SharedShape::ball(radii.x), Placement::IDENTITY, None)
            } else {
                let mut pts = Vec::with_capacity(24 * 11 + 2);
                pts.push(DVec3::new(0.0, 0.0, radii.z));
                pts.push(DVec3::new(0.0, 0.0, -radii.z));
                for a in 1..12 {
                    let th = std::f64::consts::PI * f64::from(a) / 12.0;
                    for b in 0..24 {
                        let ph = TAU * f64::from(b) / 24.0;
                        let u = DVec3::new(th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos());
                        pts.push(u * *radii);
                    }
                }
                (hull(&pts)?, Placement::IDENTITY, None)
            }
        }
        Solid::Box { extent } => {
            if extent.abs().min_element() <= 0.0 {
                return Err(ShapeError::Box);
            }
            let h = extent.abs() * 0.5;
            (SharedShape::cuboid(h.x, h.y, h.z), at(*extent * 0.5), None)
        }
        Solid::Cylinder { length, radius } => {
            if *radius <= 0.0 || *length == 0.0 {
                return Err(ShapeError::Cylinder);
            }
            (
                SharedShape::cylinder(0.5 * length.abs(), *radius),
                y_to_z(*length),
                None,
            )
        }
        Solid::Frustum {
            length,
            bottom,
            top,
        } => {
            let mut pts = Vec::with_capacity(96);
            for (z, r) in [(0.0, *bottom), (*length, *top)] {
                for b in 0..48 {
                    let ph = TAU * f64::from(b) / 48.0;
                    pts.push(DVec3::new(r * ph.cos(), r * ph.sin(), z));
                }
            }
            if *length == 0.0 || bottom.max(*top) <= 0.0 {
                return Err(ShapeError::Frustum);
            }
            (hull(&pts)?, Placement::IDENTITY, None)
        }
        Solid::Disc { radius } => {
            if *radius <= 0.0 {
                return Err(ShapeError::Circle);
            }
            (SharedShape::cylinder(0.0, *radius), y_to_z(0.0), None)
        }
        Solid::Point => (SharedShape::ball(0.0), Placement::IDENTITY, None),
        Solid::HalfSpace => (SharedShape::halfspace(PVec::Z), Placement::IDENTITY, None),
        Solid::Mesh(m) => {
            let v: Vec<PVec> = m.vertices.iter().map(|&q| pv(q)).collect();
            let shape =
                SharedShape::trimesh(v, m.triangles.clone()).map_err(|e| ShapeError::Mesh {
                    file: m.file.clone(),
                    why: e.to_string(),
                })?;
            (shape, Placement::IDENTITY, Some(m.triangles.clone()))
        }
        Solid::Curve { polyline, .. } => {
            if polyline.points.len() < 2 {
                return Err(ShapeError::ShortCurve(polyline.curve));
            }
            let v: Vec<PVec> = polyline.points.iter().map(|&q| pv(q)).collect();
            (SharedShape::polyline(v, None), Placement::IDENTITY, None)
        }
    })
}

/// A geometry of the model as a placed parry shape.
pub fn place(model: &Model, g: &ContactGeometry) -> Result<Placed, ShapeError> {
    let (shape, local, triangles) = shape(&g.solid)?;
    let radius = shape.as_ball().map(|b| b.radius);
    let mk = &model.markers[g.marker];
    let marker = Placement {
        p: mk.p_bm,
        r: mk.r_bm,
    };
    Ok(Placed {
        graphic: g.graphic,
        shape,
        in_body: marker.then(&local),
        triangles: triangles.map(std::sync::Arc::new),
        radius,
        curve: match &g.solid {
            Solid::Curve { polyline, flip } => Some(curve::CurveSide::new(polyline.clone(), *flip)),
            _ => None,
        },
    })
}

/// A penetrating point of an incident: a material point of each body (body frame) and the
/// depth (> 0) there, at the configuration it was found. On a sphere (or point) the material
/// point is its centre and the contact point is `centre − r_i·n` (I) or `centre + r_j·n`
/// (J): the contact point of a sphere does not turn with it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IncidentPoint {
    /// On the I body, deepest inside J (body frame of I), or the centre of I's sphere.
    pub on_i: DVec3,
    /// On the J body's surface (body frame of J), or the centre of J's sphere.
    pub on_j: DVec3,
    pub depth: f64,
    /// Sphere radii of the I and J geometries (0 for other solids).
    pub r_i: f64,
    pub r_j: f64,
}

/// A connected region of penetration.
#[derive(Clone, Debug, PartialEq)]
pub struct Incident {
    pub points: Vec<IncidentPoint>,
    /// Index in `points` of the deepest point.
    pub deepest: usize,
    /// The contact normal at the deepest point, from J towards I, in J's body frame.
    pub normal_j: DVec3,
}

/// Whether parry can compute contacts between the two shapes (e.g. not two half-spaces).
pub fn supported(a: &Placed, b: &Placed) -> bool {
    if a.curve.is_some() || b.curve.is_some() {
        return curve::supported(a, b);
    }
    let mut manifolds: Vec<ContactManifold<(), ()>> = Vec::new();
    let pose = PPose::IDENTITY;
    !matches!(
        DefaultQueryDispatcher.contact_manifolds(
            &pose,
            a.shape.as_ref(),
            b.shape.as_ref(),
            0.0,
            &mut manifolds,
            &mut None,
        ),
        Err(Unsupported)
    )
}

/// Union–find root with path halving.
fn root(parent: &mut [usize], mut k: usize) -> usize {
    while parent[k] != k {
        parent[k] = parent[parent[k]];
        k = parent[k];
    }
    k
}

/// The incidents between geometry `a` (on the I body, placed in world by `body_i`) and `b`
/// (J body, `body_j`). Points closer than `merge` are one point.
pub fn incidents(
    a: &Placed,
    body_i: &Placement,
    b: &Placed,
    body_j: &Placement,
    merge: f64,
    out: &mut Vec<Incident>,
) {
    if a.curve.is_some() || b.curve.is_some() {
        curve::incidents(a, body_i, b, body_j, out);
        return;
    }
    let wa = body_i.then(&a.in_body);
    let wb = body_j.then(&b.in_body);
    let pos12 = wa.to_parry().inverse() * wb.to_parry();
    let mut manifolds: Vec<ContactManifold<(), ()>> = Vec::new();
    if DefaultQueryDispatcher
        .contact_manifolds(
            &pos12,
            a.shape.as_ref(),
            b.shape.as_ref(),
            0.0,
            &mut manifolds,
            &mut None,
        )
        .is_err()
    {
        // Unsupported pairs are refused when the force set is built (`supported`).
        return;
    }
    manifolds.retain(|m| m.points.iter().any(|p| p.dist < 0.0));
    if manifolds.is_empty() {
        return;
    }
    // Group the manifolds.
    let n = manifolds.len();
    let mut parent: Vec<usize> = (0..n).collect();
    let tri = |p: &Placed, s: u32| -> Option<[u32; 3]> {
        p.triangles
            .as_ref()
            .and_then(|t| t.get(s as usize).copied())
    };
    let any_mesh = a.triangles.is_some() || b.triangles.is_some();
    for x in 0..n {
        for y in (x + 1)..n {
            let shares = |ta: Option<[u32; 3]>, tb: Option<[u32; 3]>| match (ta, tb) {
                (Some(u), Some(v)) => u.iter().any(|k| v.contains(k)),
                _ => false,
            };
            let joined = !any_mesh
                || shares(
                    tri(a, manifolds[x].subshape1),
                    tri(a, manifolds[y].subshape1),
                )
                || shares(
                    tri(b, manifolds[x].subshape2),
                    tri(b, manifolds[y].subshape2),
                );
            if joined {
                let (rx, ry) = (root(&mut parent, x), root(&mut parent, y));
                parent[rx] = ry;
            }
        }
    }
    let inv_i = body_i.r.transpose();
    let inv_j = body_j.r.transpose();
    let mut groups: Vec<(usize, Incident)> = Vec::new();
    for (k, m) in manifolds.iter().enumerate() {
        let r = root(&mut parent, k);
        let sub1 = m
            .subshape_poses
            .as_ref()
            .and_then(|s| s.pos1)
            .unwrap_or(PPose::IDENTITY);
        let sub2 = m
            .subshape_poses
            .as_ref()
            .and_then(|s| s.pos2)
            .unwrap_or(PPose::IDENTITY);
        let world_a = wa.to_parry() * sub1;
        let world_b = wb.to_parry() * sub2;
        // local_n2 points from shape 2 (J) towards shape 1 (I).
        let n_world = gv(world_b.rotation * m.local_n2);
        let idx = match groups.iter().position(|(g, _)| *g == r) {
            Some(i) => i,
            None => {
                groups.push((
                    r,
                    Incident {
                        points: Vec::new(),
                        deepest: 0,
                        normal_j: DVec3::ZERO,
                    },
                ));
                groups.len() - 1
            }
        };
        let inc = &mut groups[idx].1;
        for c in m.points.iter().filter(|c| c.dist < 0.0) {
            let p1 = gv(world_a * c.local_p1);
            let p2 = gv(world_b * c.local_p2);
            let depth = -c.dist;
            let (on_i, r_i) = match a.radius {
                Some(r) => (inv_i * (wa.p - body_i.p), r),
                None => (inv_i * (p1 - body_i.p), 0.0),
            };
            let (on_j, r_j) = match b.radius {
                Some(r) => (inv_j * (wb.p - body_j.p), r),
                None => (inv_j * (p2 - body_j.p), 0.0),
            };
            let same = inc.points.iter().position(|q| {
                (body_i.p + body_i.r * q.on_i - (body_i.p + body_i.r * on_i)).length() <= merge
                    && (body_j.r * q.on_j - body_j.r * on_j).length() <= merge
            });
            if same.is_some() {
                continue;
            }
            if inc.points.is_empty() || depth > inc.points[inc.deepest].depth {
                inc.deepest = inc.points.len();
                inc.normal_j = inv_j * n_world.normalize_or_zero();
            }
            inc.points.push(IncidentPoint {
                on_i,
                on_j,
                depth,
                r_i,
                r_j,
            });
        }
    }
    out.extend(
        groups
            .into_iter()
            .map(|(_, i)| i)
            .filter(|i| !i.points.is_empty() && i.normal_j != DVec3::ZERO),
    );
}

/// The placement of a body at a state: its CM and axes (identity for ground).
pub fn body_placement(state: &crate::state::State, b: Body) -> Placement {
    match b {
        Body::Ground => Placement::IDENTITY,
        Body::Part(k) => Placement {
            p: state.poses[k].p,
            r: state.poses[k].r,
        },
    }
}
