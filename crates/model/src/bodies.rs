//! Bodies and the markers fixed on them, and where every element was defined: the building
//! blocks that constraints, force elements and the [`crate::Model`] refer to.

use glam::{DMat3, DVec3};
use linkage_adm::{ExactCoord, Span};

/// Where a marker lives: on ground or on moving part `k` (index into [`crate::Model::parts`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Body {
    Ground,
    Part(usize),
}

impl Body {
    pub fn part(self) -> Option<usize> {
        match self {
            Body::Ground => None,
            Body::Part(k) => Some(k),
        }
    }
}

/// Where an element was defined: for messages and for writing the dataset back.
#[derive(Clone, Debug, PartialEq)]
pub struct Origin {
    /// Statement keyword and id, e.g. `("JOINT", 7)`.
    pub statement: &'static str,
    pub id: u64,
    /// Display name (`JOINT_7` or the `adams_view_name`).
    pub name: String,
    pub span: Span,
    /// Index in the dataset's statement list.
    pub statement_index: usize,
}

impl Origin {
    /// `JOINT/7`.
    pub fn element(&self) -> String {
        linkage_adm::keyword_id(self.statement, '/', self.id)
    }

    /// The label used in messages: `SFORCE_3 (SFORCE/3, line 12)`.
    pub fn label(&self) -> String {
        format!(
            "{} ({}, line {})",
            self.name,
            self.element(),
            self.span.line
        )
    }
}

/// A moving part (or point mass). Its body frame B has its origin at the centre of mass and the axes of the
/// part's BCS.
#[derive(Clone, Debug, PartialEq)]
pub struct Part {
    pub origin: Origin,
    /// Mass in model units (0 for a massless part).
    pub mass: f64,
    /// Inertia about the centre of mass in body axes (model mass × length²).
    pub inertia: DMat3,
    /// Centre-of-mass position in ground at the input configuration.
    pub p_gb: DVec3,
    /// Orientation of the body (= BCS) axes in ground at the input configuration.
    pub r_gb: DMat3,
    /// BCS origin in the body frame (`QG = p_GB + R_GB·p_B_bcs`), to write QG back.
    pub p_b_bcs: DVec3,
    /// Initial velocities `VX, VY, VZ` (ground) and `WX, WY, WZ` as given (`None` = inexact 0).
    pub velocity: [Option<f64>; 6],
    /// Axes of the CM marker in the body frame (WX, WY, WZ are resolved in them).
    pub r_b_cm: DMat3,
    /// Coordinates named in `EXACT=`.
    pub exact: Vec<ExactCoord>,
    /// A POINT_MASS: three translational degrees of freedom, zero inertia, its orientation
    /// held at the input (`r_gb`) by the rotation hold the builder adds (an ORIENTATION
    /// primitive to ground whose origin is the POINT_MASS statement).
    pub point_mass: bool,
}

/// A marker fixed on a body (floating markers carry no fixed pose: `floating` is set and the
/// pose is the part frame's).
#[derive(Clone, Debug, PartialEq)]
pub struct Marker {
    pub id: u64,
    pub name: String,
    pub span: Span,
    pub body: Body,
    /// Origin in the body frame (in ground for ground markers).
    pub p_bm: DVec3,
    /// Axes in the body frame (in ground for ground markers).
    pub r_bm: DMat3,
    pub floating: bool,
}
