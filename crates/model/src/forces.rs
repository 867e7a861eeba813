//! Force elements and data elements as the model holds them: resolved against the model's
//! markers and checked by the builder (`build/forces.rs`, `build/data.rs`).
//!
//! What is resolved (ADM-REFERENCE §2.10–2.11): marker ids become indices into
//! [`crate::Model::markers`]; a `JFLOAT` floating marker becomes the body it floats on; FIELD
//! and BEAM matrices are unpacked from the dataset's column-by-column order into
//! `m[row][col]`; defaults are filled in (stiffness, damping, lengths and preloads 0,
//! `CRATIO` 0). The force *laws* are not evaluated here (that is `linkage-solve`'s job), and
//! expressions are kept as text: a `USER(…)` function is accepted by the model and refused by
//! the solver, so that `verify` still works on models whose forces linkage cannot compute.
//!
//! Checks (errors, with the position of the argument): unknown or unusable markers (on a
//! POINT_MASS, FLEX_BODY or FE_PART; a FLOATING marker as I, J or RM), duplicate ids within a
//! statement type, an SFORCE without FUNCTION, negative stiffness or damping of SPRINGDAMPER/BUSHING, missing or
//! non-positive BEAM properties, ARRAY `VARIABLES` naming a missing VARIABLE, inconsistent
//! SPLINE data. Warnings: I and J on the same body (the element exerts no net load; not
//! for ACTIONONLY, whose J only gives a direction), a
//! `JFLOAT` marker that is not FLOATING, VFORCE/VTORQUE/GFORCE components not given (zero).

use crate::bodies::{Body, Origin};
use linkage_adm::{ArrayKind, BeamFormulation, ForceDof, Function, Located, Span};

/// A force element and where it came from.
#[derive(Clone, Debug, PartialEq)]
pub struct ForceElement {
    pub origin: Origin,
    pub kind: ForceKind,
}

/// Every force element linkage models.
#[derive(Clone, Debug, PartialEq)]
pub enum ForceKind {
    Sforce(Sforce),
    SpringDamper(SpringDamper),
    Bushing(Bushing),
    Field(Box<Field>),
    Beam(Box<Beam>),
    /// VFORCE, VTORQUE and GFORCE.
    Vector(Box<VectorForce>),
    /// CONTACT between the geometries of two parts ([`crate::contacts`]).
    Contact(Box<crate::contacts::Contact>),
}

/// `SFORCE`: a scalar force along the line J→I (or a torque about z_j), given by an
/// expression.
#[derive(Clone, Debug, PartialEq)]
pub struct Sforce {
    /// Marker indices.
    pub i: usize,
    pub j: usize,
    pub dof: ForceDof,
    pub action_only: bool,
    pub function: Located<Function>,
}

/// `SPRINGDAMPER`, with defaults applied. For a translational element `free` is `LENGTH` and
/// `preload` is `FORCE`; for a rotational one they are `ANGLE` (radians) and `TORQUE`.
#[derive(Clone, Debug, PartialEq)]
pub struct SpringDamper {
    pub i: usize,
    pub j: usize,
    pub dof: ForceDof,
    pub stiffness: f64,
    pub damping: f64,
    pub free: f64,
    pub preload: f64,
}

/// `BUSHING`, with defaults applied (components along/about the J marker's axes).
#[derive(Clone, Debug, PartialEq)]
pub struct Bushing {
    pub i: usize,
    pub j: usize,
    pub stiffness: [f64; 3],
    pub damping: [f64; 3],
    pub rotational_stiffness: [f64; 3],
    pub rotational_damping: [f64; 3],
    pub force: [f64; 3],
    pub torque: [f64; 3],
}

/// `FIELD`: `stiffness[r][c]` and `damping[r][c]` (row r, column c; `CRATIO` already applied:
/// damping = CRATIO · stiffness), reference displacements `length` and preloads `force`, in
/// the order x, y, z, a, b, c.
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    pub i: usize,
    pub j: usize,
    pub stiffness: [[f64; 6]; 6],
    pub damping: [[f64; 6]; 6],
    pub length: [f64; 6],
    pub force: [f64; 6],
    /// `FUNCTION = USER(…)` (a nonlinear field linkage cannot compute).
    pub user: Option<Located<Function>>,
}

/// Damping of a BEAM.
#[derive(Clone, Debug, PartialEq)]
pub enum BeamDamping {
    /// Damping matrix = ratio · stiffness matrix.
    Ratio(f64),
    /// Symmetric damping matrix `m[r][c]`.
    Matrix(Box<[[f64; 6]; 6]>),
}

/// `BEAM` from J (start) to I (end) along J's x axis, section properties as given.
#[derive(Clone, Debug, PartialEq)]
pub struct Beam {
    pub i: usize,
    pub j: usize,
    pub length: f64,
    /// Torsional constant.
    pub ixx: f64,
    /// Area moments about the section's y and z axes.
    pub iyy: f64,
    pub izz: f64,
    pub area: f64,
    /// Shear area ratios (0 = no shear deflection).
    pub asy: f64,
    pub asz: f64,
    pub emodulus: f64,
    pub gmodulus: f64,
    pub damping: BeamDamping,
    pub formulation: BeamFormulation,
    /// Position of `FORMULATION =` when written (for messages).
    pub formulation_span: Option<Span>,
}

/// Which statement a [`VectorForce`] comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VectorKind {
    Vforce,
    Vtorque,
    Gforce,
}

/// `VFORCE`, `VTORQUE`, `GFORCE`: components along RM's axes, applied at I, reaction on the
/// body carrying the floating marker JFLOAT (at the point coincident with I).
#[derive(Clone, Debug, PartialEq)]
pub struct VectorForce {
    pub kind: VectorKind,
    pub i: usize,
    /// The JFLOAT marker (index into the markers) and the body it floats on.
    pub jfloat: usize,
    pub reaction: Body,
    pub rm: usize,
    /// `FX, FY, FZ`; `None` = zero.
    pub force: [Option<Located<Function>>; 3],
    /// `TX, TY, TZ`; `None` = zero.
    pub torque: [Option<Located<Function>>; 3],
    /// `FUNCTION = USER(…)`.
    pub user: Option<Located<Function>>,
}

/// `VARIABLE/id, FUNCTION = e [, IC = r]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Variable {
    pub origin: Origin,
    pub function: Option<Located<Function>>,
    pub ic: Option<f64>,
}

/// What an ARRAY holds.
#[derive(Clone, Debug, PartialEq)]
pub enum ArrayValues {
    /// `NUMBERS = …` (IC arrays and general constants).
    Numbers(Vec<f64>),
    /// `VARIABLES = …`: indices into [`crate::Model::variables`] (U arrays).
    Variables(Vec<usize>),
    /// X and Y arrays: states and outputs of LSE/GSE/TFSISO elements (not modelled).
    States,
}

/// `ARRAY/id`.
#[derive(Clone, Debug, PartialEq)]
pub struct Array {
    pub origin: Origin,
    pub kind: Option<ArrayKind>,
    pub values: ArrayValues,
}

/// What a SPLINE holds.
#[derive(Clone, Debug, PartialEq)]
pub enum SplineValues {
    /// A 1-D curve y(x), x strictly increasing, at least two points.
    Curve { x: Vec<f64>, y: Vec<f64> },
    /// A 2-D spline (several `Y = z_k, y_1, …` arguments): one curve y(x) per value of z.
    Surface {
        x: Vec<f64>,
        z: Vec<f64>,
        y: Vec<Vec<f64>>,
    },
    /// Data in an external file (`FILE =`).
    File(String),
}

/// `SPLINE/id`.
#[derive(Clone, Debug, PartialEq)]
pub struct Spline {
    pub origin: Origin,
    pub values: SplineValues,
    pub linear_extrapolate: bool,
}
