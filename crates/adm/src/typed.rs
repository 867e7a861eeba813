//! Typed statements: the elements linkage computes with.
//!
//! Values are in the dataset's units, angles in radians (the `D` suffix is already applied).
//! References to other elements are [`IdRef`]s (id + where it was written); they are checked by
//! `linkage-model`, not here.

use crate::diagnostic::{Diagnostic, Span};
use crate::statement::{ExprText, Statement};
mod controls;
mod friction;
pub use controls::{
    ControlStatements, Diff, Gse, Lse, Matrix, MatrixData, MatrixOrder, PlantList, Tfsiso,
};
use std::sync::Arc;

/// The integrator names of INTEGRATOR (statement and command), of which one is in force.
pub const INTEGRATOR_METHODS: [&str; 8] = [
    "GSTIFF",
    "WSTIFF",
    "HHT",
    "NEWMARK",
    "HASTIFF",
    "CONSTANT_BDF",
    "ABAM",
    "RKF45",
];

/// The index formulations of INTEGRATOR, of which one is in force.
pub const INTEGRATOR_FORMULATIONS: [&str; 3] = ["I3", "SI2", "SI1"];

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

pub use friction::{Friction, FrictionEffect, FrictionInputs, OverlapDelta};

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
    /// POINT_MASS statements, typed as parts that have a mass and no inertia (ADM-ELEMENTS
    /// §13): `ip`, `im`, `vm`, `wm` and `WX, WY, WZ` are never set, `ground` is false.
    pub point_masses: Vec<Part>,
    pub markers: Vec<Marker>,
    /// SENSOR statements (ADM-ELEMENTS §5).
    pub sensors: Vec<Sensor>,
    /// FRICTION statements (ADM-ELEMENTS §4).
    pub frictions: Vec<Friction>,
    pub joints: Vec<Joint>,
    pub jprims: Vec<Jprim>,
    pub motions: Vec<Motion>,
    pub couplers: Vec<Coupler>,
    pub gears: Vec<Gear>,
    pub gcons: Vec<Gcon>,
    pub sforces: Vec<Sforce>,
    pub springdampers: Vec<SpringDamper>,
    pub bushings: Vec<Bushing>,
    pub fields: Vec<Field>,
    pub beams: Vec<Beam>,
    pub vforces: Vec<Vforce>,
    pub vtorques: Vec<Vtorque>,
    pub gforces: Vec<Gforce>,
    pub variables: Vec<Variable>,
    pub arrays: Vec<Array>,
    pub splines: Vec<Spline>,
    /// REQUEST statements (output definitions; ADM-REFERENCE §2.12).
    pub requests: Vec<Request>,
    /// DIFF, LSE, TFSISO, GSE, MATRIX, PINPUT and POUTPUT (ADM-ELEMENTS §6–§12).
    pub controls: ControlStatements,
    /// Non-fatal findings (unknown statements, unknown arguments, …).
    pub warnings: Vec<Diagnostic>,
}

impl Dataset {
    /// A dataset with no statements, named `file`: what a caller keeps in place of a dataset
    /// it will not read again (its memory freed).
    pub fn empty(file: Arc<str>) -> Dataset {
        Dataset {
            file,
            text: String::new(),
            title: String::new(),
            statements: Vec::new(),
            end_line: None,
            units: None,
            accgrav: None,
            parts: Vec::new(),
            point_masses: Vec::new(),
            markers: Vec::new(),
            sensors: Vec::new(),
            frictions: Vec::new(),
            joints: Vec::new(),
            jprims: Vec::new(),
            motions: Vec::new(),
            couplers: Vec::new(),
            gears: Vec::new(),
            gcons: Vec::new(),
            sforces: Vec::new(),
            springdampers: Vec::new(),
            bushings: Vec::new(),
            fields: Vec::new(),
            beams: Vec::new(),
            vforces: Vec::new(),
            vtorques: Vec::new(),
            gforces: Vec::new(),
            variables: Vec::new(),
            arrays: Vec::new(),
            splines: Vec::new(),
            requests: Vec::new(),
            controls: ControlStatements::default(),
            warnings: Vec::new(),
        }
    }
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

/// Where a marker on an FE_PART is tied: a node label, or a place `S` along the beam.
#[derive(Clone, Debug, PartialEq)]
pub enum FeMarkerNode {
    Label(Located<u64>),
    S(Located<f64>),
}

/// `MARKER/id, …` (ADM-REFERENCE §2.4). `carrier` is the explicit `PART=` (etc.) or the most
/// recently read PART/POINT_MASS/FLEX_BODY statement; `None` when there is neither.
#[derive(Clone, Debug, PartialEq)]
pub struct Marker {
    pub header: Header,
    pub carrier: Option<MarkerCarrier>,
    /// On an FE_PART: the node it is tied to (NODE_LABEL, or S along the beam); `None`
    /// elsewhere, or when neither is given.
    pub fe_node: Option<FeMarkerNode>,
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
    /// The statement's `ROUTINE = lib::name` (as written) when the expression is a `USER(...)`
    /// call and the statement has one.
    pub routine: Option<String>,
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

/// How a SENSOR compares its FUNCTION with VALUE.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SensorCompare {
    /// `EQ` (default): `|f − VALUE| ≤ ERROR`.
    #[default]
    Eq,
    /// `GE`: `f ≥ VALUE − ERROR`.
    Ge,
    /// `LE`: `f ≤ VALUE + ERROR`.
    Le,
}

/// What a SENSOR does when it fires (ADM-ELEMENTS §5).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SensorActions {
    pub halt: bool,
    pub return_: bool,
    pub print: bool,
    pub restart: bool,
    pub codgen: bool,
    pub yydump: bool,
}

/// `SENSOR/id, FUNCTION=e, VALUE=r [, EQ|GE|LE] [, ERROR=r] [, actions] [, STEPSIZE=r]
/// [, BISECTION] [, EVALUATE=e]` (ADM-ELEMENTS §5). Defaults are not filled in (`None` = not
/// written).
#[derive(Clone, Debug, PartialEq)]
pub struct Sensor {
    pub header: Header,
    pub function: Option<Located<Function>>,
    pub value: Option<Located<f64>>,
    pub compare: SensorCompare,
    pub error: Option<Located<f64>>,
    pub actions: SensorActions,
    pub stepsize: Option<Located<f64>>,
    pub dt: Option<Located<f64>>,
    pub bisection: bool,
    pub angular: bool,
    pub evaluate: Option<Located<Function>>,
}

// ---- force elements (ADM-REFERENCE §2.10) ---------------------------------------------------

/// Whether a two-marker force element acts along a line or about an axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ForceDof {
    /// `TRANSLATIONAL` (the default when neither keyword is written).
    #[default]
    Translational,
    /// `ROTATIONAL`.
    Rotational,
}

/// `SFORCE/id, I=, J=, TRANSLATIONAL | ROTATIONAL [, ACTIONONLY], FUNCTION = e`.
#[derive(Clone, Debug, PartialEq)]
pub struct Sforce {
    pub header: Header,
    pub i: IdRef,
    pub j: IdRef,
    pub dof: ForceDof,
    pub action_only: bool,
    pub function: Option<Located<Function>>,
}

/// `SPRINGDAMPER/id, I=, J=, TRANSLATIONAL, K=, C=, LENGTH=, FORCE=` or
/// `ROTATIONAL, KT=, CT=, ANGLE=, TORQUE=`. Values as written (`None` = not given).
#[derive(Clone, Debug, PartialEq)]
pub struct SpringDamper {
    pub header: Header,
    pub i: IdRef,
    pub j: IdRef,
    pub dof: ForceDof,
    pub k: Option<Located<f64>>,
    pub c: Option<Located<f64>>,
    pub length: Option<Located<f64>>,
    pub force: Option<Located<f64>>,
    pub kt: Option<Located<f64>>,
    pub ct: Option<Located<f64>>,
    /// Radians.
    pub angle: Option<Located<f64>>,
    pub torque: Option<Located<f64>>,
}

/// `BUSHING/id, I=, J=, K=, C=, KT=, CT=, FORCE=, TORQUE=` (three values each, along/about
/// the J marker's x, y, z axes).
#[derive(Clone, Debug, PartialEq)]
pub struct Bushing {
    pub header: Header,
    pub i: IdRef,
    pub j: IdRef,
    pub k: Option<Located<[f64; 3]>>,
    pub c: Option<Located<[f64; 3]>>,
    pub kt: Option<Located<[f64; 3]>>,
    pub ct: Option<Located<[f64; 3]>>,
    pub force: Option<Located<[f64; 3]>>,
    pub torque: Option<Located<[f64; 3]>>,
}

/// `FIELD/id, I=, J=, KMATRIX=36 values, CMATRIX=36 values | CRATIO=r, LENGTH=6, FORCE=6`
/// (or `FUNCTION=USER(…)`). The matrices are as written: column by column (Adams enters "the
/// elements by columns from top to bottom, then from left to right").
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    pub header: Header,
    pub i: IdRef,
    pub j: IdRef,
    pub kmatrix: Option<Located<[f64; 36]>>,
    pub cmatrix: Option<Located<[f64; 36]>>,
    pub cratio: Option<Located<f64>>,
    pub length: Option<Located<[f64; 6]>>,
    pub force: Option<Located<[f64; 6]>>,
    pub function: Option<Located<Function>>,
}

/// `FORMULATION` of a BEAM.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum BeamFormulation {
    /// Linear Timoshenko beam (the default).
    #[default]
    Linear,
    String,
    Nonlinear,
}

/// `BEAM/id, I=, J=, LENGTH=, IXX=, IYY=, IZZ=, AREA=, ASY=, ASZ=, EMODULUS=, GMODULUS=,
/// CRATIO= | CMATRIX=21 values [, FORMULATION=]`. `CMATRIX` is the lower triangle of the
/// symmetric damping matrix, column by column, as written.
#[derive(Clone, Debug, PartialEq)]
pub struct Beam {
    pub header: Header,
    pub i: IdRef,
    pub j: IdRef,
    pub length: Option<Located<f64>>,
    pub ixx: Option<Located<f64>>,
    pub iyy: Option<Located<f64>>,
    pub izz: Option<Located<f64>>,
    pub area: Option<Located<f64>>,
    pub asy: Option<Located<f64>>,
    pub asz: Option<Located<f64>>,
    pub emodulus: Option<Located<f64>>,
    pub gmodulus: Option<Located<f64>>,
    pub cratio: Option<Located<f64>>,
    pub cmatrix: Option<Located<[f64; 21]>>,
    pub formulation: Option<Located<BeamFormulation>>,
}

/// `VFORCE/id, I=, JFLOAT=, RM=, FX=e\ FY=e\ FZ=e` (or `FUNCTION=USER(…)`).
#[derive(Clone, Debug, PartialEq)]
pub struct Vforce {
    pub header: Header,
    pub i: IdRef,
    pub jfloat: IdRef,
    pub rm: IdRef,
    /// `FX`, `FY`, `FZ` (components along RM's axes).
    pub force: [Option<Located<Function>>; 3],
    pub function: Option<Located<Function>>,
}

/// `VTORQUE/id, I=, JFLOAT=, RM=, TX=e\ TY=e\ TZ=e` (or `FUNCTION=USER(…)`).
#[derive(Clone, Debug, PartialEq)]
pub struct Vtorque {
    pub header: Header,
    pub i: IdRef,
    pub jfloat: IdRef,
    pub rm: IdRef,
    /// `TX`, `TY`, `TZ` (components about RM's axes).
    pub torque: [Option<Located<Function>>; 3],
    pub function: Option<Located<Function>>,
}

/// `GFORCE/id, I=, JFLOAT=, RM=, FX=e\ … \TZ=e` or `FUNCTION=USER(…)`.
#[derive(Clone, Debug, PartialEq)]
pub struct Gforce {
    pub header: Header,
    pub i: IdRef,
    pub jfloat: IdRef,
    pub rm: IdRef,
    pub force: [Option<Located<Function>>; 3],
    pub torque: [Option<Located<Function>>; 3],
    pub function: Option<Located<Function>>,
}

// ---- data elements (ADM-REFERENCE §2.11) ----------------------------------------------------

/// `VARIABLE/id, FUNCTION = e [, IC = r]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Variable {
    pub header: Header,
    pub function: Option<Located<Function>>,
    pub ic: Option<Located<f64>>,
}

/// The type keyword of an ARRAY.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ArrayKind {
    /// Inputs of an LSE/GSE/TFSISO (`VARIABLES=`).
    U,
    /// States of an LSE/GSE/TFSISO.
    X,
    /// Outputs of an LSE/GSE/TFSISO.
    Y,
    /// Initial conditions / general constants (`NUMBERS=`).
    Ic,
}

/// `ARRAY/id, [U | X | Y | IC,] [SIZE = n,] VARIABLES = ids | NUMBERS = r1, …`.
#[derive(Clone, Debug, PartialEq)]
pub struct Array {
    pub header: Header,
    /// `None` when no type keyword is written.
    pub kind: Option<ArrayKind>,
    pub size: Option<Located<usize>>,
    pub numbers: Option<Located<Vec<f64>>>,
    pub variables: Option<Vec<IdRef>>,
}

/// `SPLINE/id, X = x1, …, Y = y1, … [, Z = …] [, LINEAR_EXTRAPOLATE]` or `FILE = name`.
/// A 2-D spline has `Z` and one `Y` per z value (each starting with its z value).
#[derive(Clone, Debug, PartialEq)]
pub struct Spline {
    pub header: Header,
    pub x: Option<Located<Vec<f64>>>,
    /// Every `Y =` argument, in order (one for a 1-D spline).
    pub y: Vec<Located<Vec<f64>>>,
    pub z: Option<Located<Vec<f64>>>,
    pub linear_extrapolate: bool,
    pub file: Option<Located<String>>,
}

// ---- output statements (ADM-REFERENCE §2.12) ------------------------------------------------

/// The standard quantity of a `REQUEST/id, DISPLACEMENT | VELOCITY | ACCELERATION | FORCE`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RequestKind {
    /// x, y, z of I relative to J (in RM's axes) and the body 3-1-3 angles of I relative to J.
    Displacement,
    /// Velocity and angular velocity of I relative to J, in RM's axes.
    Velocity,
    /// Acceleration and angular acceleration of I relative to J, in RM's axes.
    Acceleration,
    /// Force and torque acting at I from the elements between I and J, in RM's axes.
    Force,
}

impl RequestKind {
    /// Upper-case keyword as in the dataset.
    pub fn keyword(self) -> &'static str {
        match self {
            RequestKind::Displacement => "DISPLACEMENT",
            RequestKind::Velocity => "VELOCITY",
            RequestKind::Acceleration => "ACCELERATION",
            RequestKind::Force => "FORCE",
        }
    }
}

/// `REQUEST/id, {DISPLACEMENT|VELOCITY|ACCELERATION|FORCE}, I=, J= [, RM=]` (a standard
/// request), or `REQUEST/id, F1=e\F2=e\…\F8=e` (a function request), or
/// `REQUEST/id, FUNCTION=USER(…)`; plus texts that only label the output.
///
/// Typing checks the form only: a standard request needs `I`; a request is one form (a kind
/// with F1…F8 or FUNCTION is an error). `J` and `RM` default to ground when omitted (`None`).
/// Expressions are kept as text: a `USER(…)` call is accepted here and refused by whoever
/// evaluates the requests (linkage cannot run user subroutines).
#[derive(Clone, Debug, PartialEq)]
pub struct Request {
    pub header: Header,
    /// The standard quantity, `None` for function requests.
    pub kind: Option<RequestKind>,
    pub i: Option<IdRef>,
    pub j: Option<IdRef>,
    pub rm: Option<IdRef>,
    /// `F1` … `F8` (index 0 is F1); `None` = not written.
    pub functions: [Option<Located<Function>>; 8],
    /// `FUNCTION = USER(…)` (with `ROUTINE =`).
    pub function: Option<Located<Function>>,
    /// `COMMENT =` (alias `C`), as written.
    pub comment: Option<Located<String>>,
    /// `TITLE =`, as written (colon-separated labels).
    pub title: Option<Located<String>>,
    /// `CNAMES =` items, as written (quotes removed).
    pub cnames: Vec<String>,
    /// `RESULTS_NAME =`, as written.
    pub results_name: Option<Located<String>>,
}
