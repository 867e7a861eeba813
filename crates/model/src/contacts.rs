//! CONTACT elements as the model holds them: the two sides' geometries resolved to solids in
//! the frames of markers, external meshes read, the laws checked (`build/contacts.rs`).
//!
//! Geometry contract (dataset length unit, in the frame of [`ContactGeometry::marker`]):
//!
//! | GRAPHICS | solid |
//! |---|---|
//! | ELLIPSOID | centred at CM, semi-axes XSCALE/2, YSCALE/2, ZSCALE/2 (a sphere when equal) |
//! | BOX | corner at CORNER, edges X, Y, Z along its axes (signed) |
//! | CYLINDER | bottom face centred at CM, axis z from 0 to LENGTH, RADIUS (full turn) |
//! | FRUSTUM | like the cylinder, radius BOTTOM at z = 0 and TOP at z = LENGTH |
//! | CIRCLE | the flat disc of RADIUS in CM's xy plane |
//! | POINT | RM's origin |
//! | PLANE | the half-space z ≤ 0 of RM: infinite (its XMIN…YMAX only draw it), +z outside |
//! | EXTERNAL (`.stl` ascii or binary, `.obj`) | the file's triangles, coordinates in RM's frame and the dataset's length unit, the file relative to the dataset's folder |
//! | CURVE (CID, CRM) | 2-D: the CURVE (which must lie in CRM's xy plane) sampled into a polyline ([`CHORD_TOLERANCE`]) and extruded along CRM's z. A closed curve bounds a solid region (inside is solid); an open curve's solid side is on the right of increasing α (looking down CRM's z), so its outward normal is `z × t`. A GRAPHICS id listed in IFLIP_GEOMETRY / JFLIP_GEOMETRY has its solid side reversed (a flipped closed curve: the outside is solid, a ring). |
//!
//! What cannot be a contact geometry, named by [`geometry_problem`] (and so by coverage, which
//! makes every force analysis refuse the contact until it is deactivated): an EXTERNAL file
//! that is missing, or in a format linkage does not read (Parasolid `.xmt_txt`/`.x_t`, …);
//! a CURVE given by a USER subroutine (`FUNCTION = USER(…)`: it is not built) — named when
//! the contact is built; ARC, OUTLINE, LINK, SPDP, FORCE, TORUS (display-only shapes).

use glam::DVec3;
use linkage_adm::contact::{Friction, NormalLaw};
use linkage_adm::graphics::Shape;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A triangle mesh: vertices in the geometry's marker frame, triangles as vertex indices.
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    /// The file it was read from (as the dataset names it).
    pub file: String,
    pub vertices: Vec<DVec3>,
    pub triangles: Vec<[u32; 3]>,
}

/// The solid of one contact geometry (see the module table).
#[derive(Clone, Debug, PartialEq)]
pub enum Solid {
    Ellipsoid {
        radii: DVec3,
    },
    Box {
        extent: DVec3,
    },
    Cylinder {
        length: f64,
        radius: f64,
    },
    Frustum {
        length: f64,
        bottom: f64,
        top: f64,
    },
    Disc {
        radius: f64,
    },
    Point,
    HalfSpace,
    Mesh(Arc<Mesh>),
    /// A 2-D curve (see the table); `flip` reverses its solid side.
    Curve {
        polyline: Arc<Polyline>,
        flip: bool,
    },
}

/// A CURVE sampled into a polyline in its CRM marker's xy plane (z = 0).
#[derive(Clone, Debug, PartialEq)]
pub struct Polyline {
    /// The CURVE id.
    pub curve: u64,
    /// Points in increasing α; a closed polyline joins the last to the first.
    pub points: Vec<DVec3>,
    pub closed: bool,
}

/// Largest distance between the sampled polyline and the curve, as a fraction of the
/// curve's size (the diagonal of its bounding box), checked at every chord's mid-parameter.
pub const CHORD_TOLERANCE: f64 = 1e-5;

/// Why a GRAPHICS statement cannot be a contact solid.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum GeometryError {
    #[error(
        "CURVE/{id} is not in its frame's xy plane (every z = 0): a 2-D contact curve must be"
    )]
    CurveNotPlanar { id: u64 },
    #[error("CURVE/{id} cannot be sampled within the chord tolerance in {chords} chords")]
    CurveTooFine { id: u64, chords: usize },
    #[error("CID names CURVE/{cid}, which does not exist")]
    MissingCurve { cid: u64 },
    /// A graphic of a kind no contact uses (`kind`: its statement's kind).
    #[error("a {kind} is not a contact solid")]
    NotASolid { kind: String },
    /// An EXTERNAL mesh that cannot be read (`why`: the reader's reason).
    #[error("cannot read the mesh '{name}': {why}")]
    Mesh { name: String, why: String },
}

/// Most chords a curve is sampled into.
const MAX_CHORDS: usize = 1 << 18;

/// The polyline of curve `c` (id `id`): uniform in α, the chord count doubled from 32 per
/// spline piece until the mid-parameter point of every chord is within [`CHORD_TOLERANCE`]
/// × size of the chord. Errors: a curve not in its frame's xy plane, or one that needs more
/// than [`MAX_CHORDS`].
pub fn sample_curve(id: u64, c: &crate::curves::Curve) -> Result<Polyline, GeometryError> {
    if !c.planar {
        return Err(GeometryError::CurveNotPlanar { id });
    }
    let mut n = 32 * c.pieces().max(1);
    loop {
        let alpha = |k: usize| -1.0 + 2.0 * k as f64 / n as f64;
        let count = if c.closed { n } else { n + 1 };
        let points: Vec<DVec3> = (0..count).map(|k| c.eval(alpha(k))[0]).collect();
        let (lo, hi) = points.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        let size = (hi - lo).length();
        let worst = (0..n)
            .map(|k| {
                let (a, b) = (points[k], points[(k + 1) % points.len()]);
                let m = c.eval(0.5 * (alpha(k) + alpha(k + 1)))[0];
                segment_distance(m, a, b)
            })
            .fold(0.0, f64::max);
        if worst <= CHORD_TOLERANCE * size {
            return Ok(Polyline {
                curve: id,
                points,
                closed: c.closed,
            });
        }
        if n >= MAX_CHORDS {
            return Err(GeometryError::CurveTooFine {
                id,
                chords: MAX_CHORDS,
            });
        }
        n *= 2;
    }
}

/// Distance from `p` to the segment `a b`.
fn segment_distance(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let d = b - a;
    let t = if d.length_squared() > 0.0 {
        ((p - a).dot(d) / d.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + d * t)).length()
}

/// One geometry of a contact side.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactGeometry {
    /// GRAPHICS id and display name.
    pub graphic: u64,
    pub name: String,
    /// Marker (index into [`crate::Model::markers`]) whose frame the solid is measured in.
    pub marker: usize,
    pub solid: Solid,
}

/// A CONTACT between the geometries of two parts.
#[derive(Clone, Debug, PartialEq)]
pub struct Contact {
    /// The marker of the first I geometry (its body is the I part): the I marker of the
    /// element for requests and the CONTACT function.
    pub i: usize,
    /// The marker of the first J geometry.
    pub j: usize,
    pub i_geometries: Vec<ContactGeometry>,
    pub j_geometries: Vec<ContactGeometry>,
    pub normal: NormalLaw,
    pub friction: Friction,
}

/// Why a geometry cannot be used by a contact.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum GeometryProblem {
    /// The EXTERNAL file does not exist (the path as written).
    Missing(String),
    /// An EXTERNAL file in a format linkage does not read.
    Unreadable(String),
    /// Not a contact geometry linkage models (with the reason).
    NotModelled(String),
}

impl GeometryProblem {
    /// A sentence naming the graphic and the problem.
    pub fn describe(&self, graphic: u64) -> String {
        match self {
            GeometryProblem::Missing(f) => {
                format!("GRAPHICS/{graphic}'s file '{f}' does not exist")
            }
            GeometryProblem::Unreadable(f) => format!(
                "GRAPHICS/{graphic}'s file '{f}' is in a format linkage does not read (it reads \
                 STL and OBJ meshes; a Parasolid file can be exported to STL)"
            ),
            GeometryProblem::NotModelled(why) => format!("GRAPHICS/{graphic}: {why}"),
        }
    }
}

/// The path of `name` relative to the dataset `dataset_file`'s folder.
pub fn external_path(dataset_file: &str, name: &str) -> PathBuf {
    let dir = Path::new(dataset_file).parent().unwrap_or(Path::new(""));
    dir.join(name)
}

/// Mesh formats read: `stl` or `obj` (by extension, any case).
pub fn mesh_format(name: &str) -> Option<&'static str> {
    let ext = Path::new(name).extension()?.to_str()?.to_ascii_lowercase();
    match ext.as_str() {
        "stl" => Some("stl"),
        "obj" => Some("obj"),
        _ => None,
    }
}

/// Why the GRAPHICS shape `shape` cannot be a contact geometry of a dataset read from
/// `dataset_file` (`None`: it can).
pub fn geometry_problem<M: Copy>(dataset_file: &str, shape: &Shape<M>) -> Option<GeometryProblem> {
    match shape {
        Shape::Ellipsoid { .. }
        | Shape::Box { .. }
        | Shape::Cylinder { .. }
        | Shape::Frustum { .. }
        | Shape::Circle { .. }
        | Shape::Point { .. }
        | Shape::Plane { .. }
        | Shape::Curve { .. } => None,
        Shape::External { file: None, .. } => Some(GeometryProblem::NotModelled(
            "an EXTERNAL geometry without FILE has no shape".to_string(),
        )),
        Shape::External { file: Some(f), .. } => {
            if !external_path(dataset_file, f).exists() {
                Some(GeometryProblem::Missing(f.clone()))
            } else if mesh_format(f).is_none() {
                Some(GeometryProblem::Unreadable(f.clone()))
            } else {
                None
            }
        }
        other => Some(GeometryProblem::NotModelled(format!(
            "a {} is display geometry, not a contact solid",
            other.kind()
        ))),
    }
}
