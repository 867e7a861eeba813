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
//!
//! What cannot be a contact geometry, named by [`geometry_problem`] (and so by coverage, which
//! makes every force analysis refuse the contact until it is deactivated): an EXTERNAL file
//! that is missing, or in a format linkage does not read (Parasolid `.xmt_txt`/`.x_t`, …);
//! CURVE geometry (2-D curve contacts belong with the CURVE statement, which linkage does not
//! read yet); ARC, OUTLINE, LINK, SPDP, FORCE, TORUS (display-only shapes).

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
    Ellipsoid { radii: DVec3 },
    Box { extent: DVec3 },
    Cylinder { length: f64, radius: f64 },
    Frustum { length: f64, bottom: f64, top: f64 },
    Disc { radius: f64 },
    Point,
    HalfSpace,
    Mesh(Arc<Mesh>),
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
        | Shape::Plane { .. } => None,
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
        Shape::Other { kind } if kind == "CURVE" => Some(GeometryProblem::NotModelled(
            "a CURVE geometry (2-D curve contact) is not modelled: linkage does not read CURVE \
             statements"
                .to_string(),
        )),
        other => Some(GeometryProblem::NotModelled(format!(
            "a {} is display geometry, not a contact solid",
            other.kind()
        ))),
    }
}
