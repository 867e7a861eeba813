//! Typed statements: the elements linkage computes with.
//!
//! Values are in the dataset's units, angles in radians (the `D` suffix is already applied).
//! References to other elements are [`IdRef`]s (id + where it was written); they are checked by
//! `linkage-model`, not here.

use crate::diagnostic::{Diagnostic, Span};
use crate::statement::{ExprText, Statement};
use std::sync::Arc;

/// A value and the position it was written at.
#[derive(Clone, Debug, PartialEq)]
pub struct Located<T> {
    pub value: T,
    pub span: Span,
}

/// A reference to another element by id (`CM = 0201`, `I = 0102`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct IdRef {
    pub id: u64,
    pub span: Span,
}

/// What every element has: id, display name, and where its statement starts.
#[derive(Clone, Debug, PartialEq)]
pub struct Header {
    pub id: u64,
    /// From the `adams_view_name='…'` comment, else `<STATEMENT>_<id>` (`PART_2`, `JOINT_1`),
    /// leading zeros of the id dropped, as Adams View does.
    pub name: String,
    /// Position of the statement keyword.
    pub span: Span,
    /// Index of the statement in [`Dataset::statements`].
    pub statement: usize,
}

/// The whole dataset: title, every statement in generic form, and the typed elements.
#[derive(Clone, Debug, PartialEq)]
pub struct Dataset {
    /// File name used in diagnostics.
    pub file: Arc<str>,
    /// The original text (kept so the writer can reproduce everything it does not change).
    pub text: String,
    /// Line 1, verbatim (trailing whitespace and line ending removed).
    pub title: String,
    /// Every statement before the first `END`, in order (the title line is not a statement).
    pub statements: Vec<Statement>,
    /// Line of the first `END` statement, if any.
    pub end_line: Option<u32>,
    pub units: Option<Units>,
    pub accgrav: Option<Accgrav>,
    pub parts: Vec<Part>,
    pub markers: Vec<Marker>,
    pub joints: Vec<Joint>,
    pub jprims: Vec<Jprim>,
    pub motions: Vec<Motion>,
    pub couplers: Vec<Coupler>,
    pub gears: Vec<Gear>,
    pub gcons: Vec<Gcon>,
    /// Non-fatal findings (unknown statements, unknown arguments, …).
    pub warnings: Vec<Diagnostic>,
}

/// `UNITS/ FORCE=, MASS=, LENGTH=, TIME=` or `SYSTEM=` or `UCF=`. Unit names are upper-case
/// full names as written (prefixes resolved against ADM-REFERENCE §2.1 lists).
#[derive(Clone, Debug, PartialEq)]
pub struct Units {
    pub header: Header,
    pub force: Option<Located<String>>,
    pub mass: Option<Located<String>>,
    pub length: Option<Located<String>>,
    pub time: Option<Located<String>>,
    pub system: Option<Located<String>>,
    pub ucf: Option<Located<f64>>,
}

/// `ACCGRAV/ IGRAV=, JGRAV=, KGRAV=` (missing components are 0).
#[derive(Clone, Debug, PartialEq)]
pub struct Accgrav {
    pub header: Header,
    pub gravity: [f64; 3],
}

/// One coordinate named in `EXACT=` (PART).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExactCoord {
    X,
    Y,
    Z,
    Psi,
    Theta,
    Phi,
}

/// `PART/id, …` (ADM-REFERENCE §2.3).
#[derive(Clone, Debug, PartialEq)]
pub struct Part {
    pub header: Header,
    pub ground: bool,
    pub mass: Option<Located<f64>>,
    pub cm: Option<IdRef>,
    pub im: Option<IdRef>,
    /// `IP = Ixx, Iyy, Izz [, Ixy, Ixz, Iyz]`; products default to 0. As written (Adams'
    /// positive-integral convention for products).
    pub ip: Option<Located<[f64; 6]>>,
    pub qg: Option<Located<[f64; 3]>>,
    pub reuler: Option<Located<[f64; 3]>>,
    pub xg: Option<Located<[f64; 3]>>,
    pub zg: Option<Located<[f64; 3]>>,
    /// `VX, VY, VZ, WX, WY, WZ` in that order (`None` = not given, an "inexact zero").
    pub velocity: [Option<f64>; 6],
    pub vm: Option<IdRef>,
    pub wm: Option<IdRef>,
    pub exact: Vec<ExactCoord>,
}

/// What a marker is attached to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MarkerCarrier {
    Part(IdRef),
    PointMass(IdRef),
    FlexBody(IdRef),
    FePart(IdRef),
}

/// `MARKER/id, …` (ADM-REFERENCE §2.4). `carrier` is the explicit `PART=` (etc.) or the most
/// recently read PART/POINT_MASS/FLEX_BODY statement; `None` when there is neither.
#[derive(Clone, Debug, PartialEq)]
pub struct Marker {
    pub header: Header,
    pub carrier: Option<MarkerCarrier>,
    pub qp: Option<Located<[f64; 3]>>,
    pub reuler: Option<Located<[f64; 3]>>,
    pub zp: Option<Located<[f64; 3]>>,
    pub xp: Option<Located<[f64; 3]>>,
    pub usexp: bool,
    pub floating: bool,
    pub rm: Option<IdRef>,
}

/// Joint types of ADM-REFERENCE §2.5.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum JointType {
    Convel,
    Cylindrical,
    Fixed,
    Hooke,
    Planar,
    Rackpin,
    Revolute,
    Screw,
    Spherical,
    Translational,
    Universal,
}

impl JointType {
    /// Upper-case keyword as in the dataset.
    pub fn keyword(self) -> &'static str {
        match self {
            JointType::Convel => "CONVEL",
            JointType::Cylindrical => "CYLINDRICAL",
            JointType::Fixed => "FIXED",
            JointType::Hooke => "HOOKE",
            JointType::Planar => "PLANAR",
            JointType::Rackpin => "RACKPIN",
            JointType::Revolute => "REVOLUTE",
            JointType::Screw => "SCREW",
            JointType::Spherical => "SPHERICAL",
            JointType::Translational => "TRANSLATIONAL",
            JointType::Universal => "UNIVERSAL",
        }
    }
}

/// `JOINT/id, type, I=, J= [, IC=] [, ICTRAN=] [, ICROT=] [, PD=] [, PITCH=]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    pub header: Header,
    pub kind: JointType,
    pub i: IdRef,
    pub j: IdRef,
    /// `IC = disp [, vel]` (revolute/translational coordinate).
    pub ic: Option<Located<Vec<f64>>>,
    /// `ICTRAN = disp [, vel]` (cylindrical translation).
    pub ictran: Option<Located<Vec<f64>>>,
    /// `ICROT = disp [, vel]` (cylindrical rotation), radians.
    pub icrot: Option<Located<Vec<f64>>>,
    pub pd: Option<Located<f64>>,
    pub pitch: Option<Located<f64>>,
}

/// Joint primitive types of ADM-REFERENCE §2.6.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum JprimType {
    Atpoint,
    Inline,
    Inplane,
    Orientation,
    ParallelAxes,
    Perpendicular,
}

impl JprimType {
    pub fn keyword(self) -> &'static str {
        match self {
            JprimType::Atpoint => "ATPOINT",
            JprimType::Inline => "INLINE",
            JprimType::Inplane => "INPLANE",
            JprimType::Orientation => "ORIENTATION",
            JprimType::ParallelAxes => "PARALLEL_AXES",
            JprimType::Perpendicular => "PERPENDICULAR",
        }
    }
}

/// `JPRIM/id, type, I=, J=`.
#[derive(Clone, Debug, PartialEq)]
pub struct Jprim {
    pub header: Header,
    pub kind: JprimType,
    pub i: IdRef,
    pub j: IdRef,
}

/// An expression-valued argument: the text, or a `USER(…)` call that linkage cannot run.
#[derive(Clone, Debug, PartialEq)]
pub struct Function {
    pub expr: ExprText,
    /// True when the expression is a `USER(...)` subroutine call.
    pub user: bool,
}

/// Which coordinate a joint motion drives (needed only for CYLINDRICAL joints).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MotionDof {
    Translation,
    Rotation,
}

/// Axis of a marker motion: translations along J's axes, or body 1-2-3 angles.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MotionAxis {
    X,
    Y,
    Z,
    B1,
    B2,
    B3,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MotionTarget {
    /// `JOINT=id [, TRANSLATION | ROTATION]`.
    Joint {
        joint: IdRef,
        dof: Option<MotionDof>,
    },
    /// `I=id, J=id, X|Y|Z|B1|B2|B3`.
    Markers {
        i: IdRef,
        j: IdRef,
        axis: MotionAxis,
    },
}

/// Whether the function gives displacement, velocity or acceleration.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum MotionLevel {
    #[default]
    Displacement,
    Velocity,
    Acceleration,
}

/// `MOTION/id, …, FUNCTION = e [, ICDISP=] [, ICVEL=]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Motion {
    pub header: Header,
    pub target: MotionTarget,
    pub level: MotionLevel,
    pub function: Option<Located<Function>>,
    pub icdisp: Option<f64>,
    pub icvel: Option<f64>,
}

/// `T` or `R` in a COUPLER's `TYPE=`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CouplerDof {
    Translation,
    Rotation,
}

/// `COUPLER/id, JOINTS=j1,j2[,j3], TYPE=T|R:…, SCALES=…` (or `FUNCTION=USER(…)`).
#[derive(Clone, Debug, PartialEq)]
pub struct Coupler {
    pub header: Header,
    pub joints: Vec<IdRef>,
    /// Empty when TYPE is omitted.
    pub types: Vec<CouplerDof>,
    /// As written (1, 2 or 3 numbers); see ADM-REFERENCE §2.9 for how they map to r1..r3.
    pub scales: Vec<f64>,
    pub function: Option<Located<Function>>,
}

/// `GEAR/id, JOINTS=j1,j2, CV=id`.
#[derive(Clone, Debug, PartialEq)]
pub struct Gear {
    pub header: Header,
    pub joints: Vec<IdRef>,
    pub cv: Option<IdRef>,
}

/// `GCON/id, I=id, FUNCTION=e`.
#[derive(Clone, Debug, PartialEq)]
pub struct Gcon {
    pub header: Header,
    pub i: Option<IdRef>,
    pub function: Option<Located<Function>>,
}
