//! Force elements and data elements, resolved against the model's markers and checked.
//!
//! What is resolved here (ADM-REFERENCE §2.10–2.11): marker ids become indices into
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

use crate::model::{Body, Marker, Origin, Part};
use linkage_adm::{
    ArrayKind, BeamFormulation, Dataset, Diagnostic, ForceDof, Function, Header, IdRef, Located,
    Span,
};
use std::collections::HashMap;
use std::sync::Arc;

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

/// Force and data elements of a model.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ForceData {
    pub forces: Vec<ForceElement>,
    pub variables: Vec<Variable>,
    pub arrays: Vec<Array>,
    pub splines: Vec<Spline>,
}

/// What the resolver needs to know about markers.
pub(crate) struct MarkerTable<'a> {
    pub index: &'a HashMap<u64, usize>,
    pub markers: &'a [Marker],
    /// Per marker: the carrier kind linkage does not model (POINT_MASS, …), if any.
    pub unsupported: &'a [Option<&'static str>],
    pub parts: &'a [Part],
    pub ground_name: &'a str,
}

fn origin(statement: &'static str, h: &Header) -> Origin {
    Origin {
        statement,
        id: h.id,
        name: h.name.clone(),
        span: h.span,
        statement_index: h.statement,
    }
}

struct Resolver<'a, 'd> {
    file: Arc<str>,
    errors: &'d mut Vec<Diagnostic>,
    warnings: &'d mut Vec<Diagnostic>,
    table: &'d MarkerTable<'a>,
}

impl Resolver<'_, '_> {
    fn error(&mut self, span: Span, msg: impl Into<String>) {
        self.errors
            .push(Diagnostic::error(self.file.clone(), Some(span), msg));
    }

    fn warn(&mut self, span: Span, msg: impl Into<String>) {
        self.warnings
            .push(Diagnostic::warning(self.file.clone(), Some(span), msg));
    }

    /// A marker that exists on a part or ground. `fixed`: FLOATING is refused.
    fn marker(&mut self, r: IdRef, elem: &str, role: &str, fixed: bool) -> Option<usize> {
        let Some(&m) = self.table.index.get(&r.id) else {
            self.error(
                r.span,
                format!("{elem}: {role} marker {} does not exist", r.id),
            );
            return None;
        };
        if let Some(kind) = self.table.unsupported.get(m).copied().flatten() {
            self.error(
                r.span,
                format!(
                    "{elem}: {role} marker {} is on a {kind}, which linkage does not model",
                    r.id
                ),
            );
            return None;
        }
        if fixed && self.table.markers[m].floating {
            self.error(
                r.span,
                format!(
                    "{elem}: {role} marker {} is FLOATING; {role} must be a fixed marker",
                    r.id
                ),
            );
            return None;
        }
        Some(m)
    }

    fn body_name(&self, b: Body) -> &str {
        match b {
            Body::Ground => self.table.ground_name,
            Body::Part(k) => &self.table.parts[k].origin.name,
        }
    }

    /// I and J of a two-marker element; a warning when both are on one body (unless the
    /// element acts on I only, J giving just a direction).
    fn pair(
        &mut self,
        i: IdRef,
        j: IdRef,
        h: &Header,
        action_only: bool,
    ) -> Option<(usize, usize)> {
        let mi = self.marker(i, &h.name, "I", true);
        let mj = self.marker(j, &h.name, "J", true);
        let (mi, mj) = (mi?, mj?);
        let body = self.table.markers[mi].body;
        if body == self.table.markers[mj].body && !action_only {
            let msg = format!(
                "{}: I marker {} and J marker {} are both on {}; the element exerts no net load",
                h.name,
                i.id,
                j.id,
                self.body_name(body)
            );
            self.warn(h.span, msg);
        }
        Some((mi, mj))
    }

    /// A value that must not be negative (stiffness, damping).
    fn non_negative(&mut self, v: Option<&Located<f64>>, what: &str, elem: &str) -> f64 {
        match v {
            Some(l) if l.value < 0.0 => {
                self.error(
                    l.span,
                    format!("{elem}: {what} must not be negative ({})", l.value),
                );
                0.0
            }
            Some(l) => l.value,
            None => 0.0,
        }
    }

    fn non_negative3(&mut self, v: Option<&Located<[f64; 3]>>, what: &str, elem: &str) -> [f64; 3] {
        match v {
            Some(l) if l.value.iter().any(|x| *x < 0.0) => {
                self.error(
                    l.span,
                    format!("{elem}: {what} must not be negative ({:?})", l.value),
                );
                [0.0; 3]
            }
            Some(l) => l.value,
            None => [0.0; 3],
        }
    }

    /// A required positive BEAM property.
    fn positive(&mut self, v: Option<&Located<f64>>, key: &str, h: &Header) -> Option<f64> {
        match v {
            None => {
                self.error(h.span, format!("{}: {key} is missing", h.name));
                None
            }
            Some(l) if l.value <= 0.0 => {
                self.error(
                    l.span,
                    format!("{}: {key} must be positive ({})", h.name, l.value),
                );
                None
            }
            Some(l) => Some(l.value),
        }
    }

    /// An error for the second statement of a type with an id already used.
    fn unique(&mut self, seen: &mut HashMap<u64, ()>, statement: &str, h: &Header) -> bool {
        if seen.insert(h.id, ()).is_some() {
            self.error(h.span, format!("duplicate {statement} id {}", h.id));
            return false;
        }
        true
    }
}

/// `m[r][c]` from 36 values written column by column.
pub fn matrix_by_columns(v: &[f64; 36]) -> [[f64; 6]; 6] {
    let mut m = [[0.0; 6]; 6];
    for (n, x) in v.iter().enumerate() {
        m[n % 6][n / 6] = *x;
    }
    m
}

/// The symmetric `m[r][c]` from the 21 values of its lower triangle written column by column
/// (column 1 rows 1..6, column 2 rows 2..6, …).
pub fn symmetric_by_columns(v: &[f64; 21]) -> [[f64; 6]; 6] {
    let mut m = [[0.0; 6]; 6];
    let lower = (0..6).flat_map(|c| (c..6).map(move |r| (r, c)));
    for ((r, c), x) in lower.zip(v) {
        m[r][c] = *x;
        m[c][r] = *x;
    }
    m
}

/// Resolves every force and data element of `ds`.
pub(crate) fn build_forces(
    ds: &Dataset,
    table: &MarkerTable,
    errors: &mut Vec<Diagnostic>,
    warnings: &mut Vec<Diagnostic>,
) -> ForceData {
    let mut rs = Resolver {
        file: ds.file.clone(),
        errors,
        warnings,
        table,
    };
    let mut out = ForceData::default();
    two_marker_elements(ds, &mut rs, &mut out.forces);
    vector_elements(ds, &mut rs, &mut out.forces);
    data_elements(ds, &mut rs, &mut out);
    out
}

fn two_marker_elements(ds: &Dataset, rs: &mut Resolver, forces: &mut Vec<ForceElement>) {
    let mut seen = HashMap::new();
    for s in &ds.sforces {
        let h = &s.header;
        if !rs.unique(&mut seen, "SFORCE", h) {
            continue;
        }
        let Some((i, j)) = rs.pair(s.i, s.j, h, s.action_only) else {
            continue;
        };
        let Some(function) = s.function.clone() else {
            rs.error(h.span, format!("{}: FUNCTION is missing", h.name));
            continue;
        };
        forces.push(ForceElement {
            origin: origin("SFORCE", h),
            kind: ForceKind::Sforce(Sforce {
                i,
                j,
                dof: s.dof,
                action_only: s.action_only,
                function,
            }),
        });
    }
    let mut seen = HashMap::new();
    for s in &ds.springdampers {
        let h = &s.header;
        if !rs.unique(&mut seen, "SPRINGDAMPER", h) {
            continue;
        }
        let Some((i, j)) = rs.pair(s.i, s.j, h, false) else {
            continue;
        };
        let value = |v: &Option<Located<f64>>| v.as_ref().map_or(0.0, |l| l.value);
        let sd = match s.dof {
            ForceDof::Translational => SpringDamper {
                i,
                j,
                dof: s.dof,
                stiffness: rs.non_negative(s.k.as_ref(), "K", &h.name),
                damping: rs.non_negative(s.c.as_ref(), "C", &h.name),
                free: value(&s.length),
                preload: value(&s.force),
            },
            ForceDof::Rotational => SpringDamper {
                i,
                j,
                dof: s.dof,
                stiffness: rs.non_negative(s.kt.as_ref(), "KT", &h.name),
                damping: rs.non_negative(s.ct.as_ref(), "CT", &h.name),
                free: value(&s.angle),
                preload: value(&s.torque),
            },
        };
        forces.push(ForceElement {
            origin: origin("SPRINGDAMPER", h),
            kind: ForceKind::SpringDamper(sd),
        });
    }
    let mut seen = HashMap::new();
    for b in &ds.bushings {
        let h = &b.header;
        if !rs.unique(&mut seen, "BUSHING", h) {
            continue;
        }
        let Some((i, j)) = rs.pair(b.i, b.j, h, false) else {
            continue;
        };
        let value = |v: &Option<Located<[f64; 3]>>| v.as_ref().map_or([0.0; 3], |l| l.value);
        let bushing = Bushing {
            i,
            j,
            stiffness: rs.non_negative3(b.k.as_ref(), "K", &h.name),
            damping: rs.non_negative3(b.c.as_ref(), "C", &h.name),
            rotational_stiffness: rs.non_negative3(b.kt.as_ref(), "KT", &h.name),
            rotational_damping: rs.non_negative3(b.ct.as_ref(), "CT", &h.name),
            force: value(&b.force),
            torque: value(&b.torque),
        };
        forces.push(ForceElement {
            origin: origin("BUSHING", h),
            kind: ForceKind::Bushing(bushing),
        });
    }
    let mut seen = HashMap::new();
    for f in &ds.fields {
        let h = &f.header;
        if !rs.unique(&mut seen, "FIELD", h) {
            continue;
        }
        let Some((i, j)) = rs.pair(f.i, f.j, h, false) else {
            continue;
        };
        let stiffness = f
            .kmatrix
            .as_ref()
            .map_or([[0.0; 6]; 6], |k| matrix_by_columns(&k.value));
        let damping = match (&f.cmatrix, &f.cratio) {
            (Some(c), _) => matrix_by_columns(&c.value),
            (None, Some(r)) => stiffness.map(|row| row.map(|k| k * r.value)),
            (None, None) => [[0.0; 6]; 6],
        };
        let user = f.function.clone();
        if user.as_ref().is_some_and(|u| !u.value.user) {
            rs.error(
                h.span,
                format!(
                    "{}: a FIELD FUNCTION must be USER(…) (a FIESUB subroutine)",
                    h.name
                ),
            );
            continue;
        }
        forces.push(ForceElement {
            origin: origin("FIELD", h),
            kind: ForceKind::Field(Box::new(Field {
                i,
                j,
                stiffness,
                damping,
                length: f.length.as_ref().map_or([0.0; 6], |l| l.value),
                force: f.force.as_ref().map_or([0.0; 6], |l| l.value),
                user,
            })),
        });
    }
    let mut seen = HashMap::new();
    for b in &ds.beams {
        let h = &b.header;
        if !rs.unique(&mut seen, "BEAM", h) {
            continue;
        }
        let pair = rs.pair(b.i, b.j, h, false);
        let props = [
            rs.positive(b.length.as_ref(), "LENGTH", h),
            rs.positive(b.ixx.as_ref(), "IXX", h),
            rs.positive(b.iyy.as_ref(), "IYY", h),
            rs.positive(b.izz.as_ref(), "IZZ", h),
            rs.positive(b.area.as_ref(), "AREA", h),
            rs.positive(b.emodulus.as_ref(), "EMODULUS", h),
            rs.positive(b.gmodulus.as_ref(), "GMODULUS", h),
        ];
        let ratio = |rs: &mut Resolver, v: &Option<Located<f64>>, key: &str| {
            rs.non_negative(v.as_ref(), key, &h.name)
        };
        let (asy, asz) = (ratio(rs, &b.asy, "ASY"), ratio(rs, &b.asz, "ASZ"));
        let damping = match &b.cmatrix {
            Some(c) => BeamDamping::Matrix(Box::new(symmetric_by_columns(&c.value))),
            None => BeamDamping::Ratio(ratio(rs, &b.cratio, "CRATIO")),
        };
        let (
            Some((i, j)),
            [Some(length), Some(ixx), Some(iyy), Some(izz), Some(area), Some(emodulus), Some(gmodulus)],
        ) = (pair, props)
        else {
            continue;
        };
        forces.push(ForceElement {
            origin: origin("BEAM", h),
            kind: ForceKind::Beam(Box::new(Beam {
                i,
                j,
                length,
                ixx,
                iyy,
                izz,
                area,
                asy,
                asz,
                emodulus,
                gmodulus,
                damping,
                formulation: b
                    .formulation
                    .as_ref()
                    .map_or_else(Default::default, |f| f.value),
                formulation_span: b.formulation.as_ref().map(|f| f.span),
            })),
        });
    }
}

/// The parts common to VFORCE, VTORQUE and GFORCE.
struct VectorSource<'s> {
    statement: &'static str,
    kind: VectorKind,
    header: &'s Header,
    i: IdRef,
    jfloat: IdRef,
    rm: IdRef,
    force: [Option<Located<Function>>; 3],
    torque: [Option<Located<Function>>; 3],
    function: Option<Located<Function>>,
    /// Which of force/torque components this statement has.
    has: (bool, bool),
}

fn vector_elements(ds: &Dataset, rs: &mut Resolver, forces: &mut Vec<ForceElement>) {
    let none3 = || [None, None, None];
    let mut sources = Vec::new();
    for v in &ds.vforces {
        sources.push(VectorSource {
            statement: "VFORCE",
            kind: VectorKind::Vforce,
            header: &v.header,
            i: v.i,
            jfloat: v.jfloat,
            rm: v.rm,
            force: v.force.clone(),
            torque: none3(),
            function: v.function.clone(),
            has: (true, false),
        });
    }
    for v in &ds.vtorques {
        sources.push(VectorSource {
            statement: "VTORQUE",
            kind: VectorKind::Vtorque,
            header: &v.header,
            i: v.i,
            jfloat: v.jfloat,
            rm: v.rm,
            force: none3(),
            torque: v.torque.clone(),
            function: v.function.clone(),
            has: (false, true),
        });
    }
    for g in &ds.gforces {
        sources.push(VectorSource {
            statement: "GFORCE",
            kind: VectorKind::Gforce,
            header: &g.header,
            i: g.i,
            jfloat: g.jfloat,
            rm: g.rm,
            force: g.force.clone(),
            torque: g.torque.clone(),
            function: g.function.clone(),
            has: (true, true),
        });
    }
    let mut seen: HashMap<&str, HashMap<u64, ()>> = HashMap::new();
    for s in sources {
        let h = s.header;
        if !rs.unique(seen.entry(s.statement).or_default(), s.statement, h) {
            continue;
        }
        let i = rs.marker(s.i, &h.name, "I", true);
        let rm = rs.marker(s.rm, &h.name, "RM", true);
        let jfloat = rs.marker(s.jfloat, &h.name, "JFLOAT", false);
        let (Some(i), Some(rm), Some(jfloat)) = (i, rm, jfloat) else {
            continue;
        };
        if !rs.table.markers[jfloat].floating {
            let msg = format!(
                "{}: JFLOAT marker {} is not FLOATING; the reaction acts on its part at I's position",
                h.name, s.jfloat.id
            );
            rs.warn(s.jfloat.span, msg);
        }
        let reaction = rs.table.markers[jfloat].body;
        if reaction == rs.table.markers[i].body {
            let msg = format!(
                "{}: I marker {} and JFLOAT marker {} are on the same body; the element exerts no net load",
                h.name, s.i.id, s.jfloat.id
            );
            rs.warn(h.span, msg);
        }
        match &s.function {
            Some(f) if !f.value.user => {
                rs.error(
                    f.span,
                    format!(
                        "{}: FUNCTION must be USER(…); give the components as {}",
                        h.name,
                        match s.kind {
                            VectorKind::Vforce => "FX, FY, FZ",
                            VectorKind::Vtorque => "TX, TY, TZ",
                            VectorKind::Gforce => "FX, FY, FZ, TX, TY, TZ",
                        }
                    ),
                );
                continue;
            }
            Some(_) => {}
            None => {
                let names = [("FX", "TX"), ("FY", "TY"), ("FZ", "TZ")];
                let mut missing = Vec::new();
                for (k, (f, t)) in names.iter().enumerate() {
                    if s.has.0 && s.force[k].is_none() {
                        missing.push(*f);
                    }
                    if s.has.1 && s.torque[k].is_none() {
                        missing.push(*t);
                    }
                }
                missing.sort_unstable();
                if !missing.is_empty() {
                    let msg = format!(
                        "{}: {} not given; taken as zero",
                        h.name,
                        missing.join(", ")
                    );
                    rs.warn(h.span, msg);
                }
            }
        }
        forces.push(ForceElement {
            origin: origin(s.statement, h),
            kind: ForceKind::Vector(Box::new(VectorForce {
                kind: s.kind,
                i,
                jfloat,
                reaction,
                rm,
                force: s.force,
                torque: s.torque,
                user: s.function,
            })),
        });
    }
}

fn data_elements(ds: &Dataset, rs: &mut Resolver, out: &mut ForceData) {
    let mut variable_index = HashMap::new();
    for v in &ds.variables {
        let h = &v.header;
        if variable_index.contains_key(&h.id) {
            rs.error(h.span, format!("duplicate VARIABLE id {}", h.id));
            continue;
        }
        if v.function.is_none() {
            rs.error(h.span, format!("{}: FUNCTION is missing", h.name));
            continue;
        }
        variable_index.insert(h.id, out.variables.len());
        out.variables.push(Variable {
            origin: origin("VARIABLE", h),
            function: v.function.clone(),
            ic: v.ic.as_ref().map(|l| l.value),
        });
    }
    let mut seen = HashMap::new();
    for a in &ds.arrays {
        let h = &a.header;
        if !rs.unique(&mut seen, "ARRAY", h) {
            continue;
        }
        let values = match (&a.numbers, &a.variables, a.kind) {
            (Some(n), _, _) => ArrayValues::Numbers(n.value.clone()),
            (None, Some(vars), _) => {
                let mut idx = Vec::with_capacity(vars.len());
                for r in vars {
                    match variable_index.get(&r.id) {
                        Some(&k) => idx.push(k),
                        None => rs.error(
                            r.span,
                            format!("{}: VARIABLE {} does not exist", h.name, r.id),
                        ),
                    }
                }
                if idx.len() != vars.len() {
                    continue;
                }
                ArrayValues::Variables(idx)
            }
            (None, None, Some(ArrayKind::X | ArrayKind::Y)) => ArrayValues::States,
            (None, None, _) => ArrayValues::Numbers(Vec::new()),
        };
        let len = match &values {
            ArrayValues::Numbers(n) => Some(n.len()),
            ArrayValues::Variables(v) => Some(v.len()),
            ArrayValues::States => None,
        };
        if let (Some(size), Some(len)) = (&a.size, len) {
            if size.value != len && len > 0 {
                let msg = format!(
                    "{}: SIZE = {} but {len} values are given",
                    h.name, size.value
                );
                rs.warn(size.span, msg);
            }
        }
        out.arrays.push(Array {
            origin: origin("ARRAY", h),
            kind: a.kind,
            values,
        });
    }
    let mut seen = HashMap::new();
    for s in &ds.splines {
        let h = &s.header;
        if !rs.unique(&mut seen, "SPLINE", h) {
            continue;
        }
        let Some(values) = spline_values(s, rs) else {
            continue;
        };
        out.splines.push(Spline {
            origin: origin("SPLINE", h),
            values,
            linear_extrapolate: s.linear_extrapolate,
        });
    }
}

fn spline_values(s: &linkage_adm::Spline, rs: &mut Resolver) -> Option<SplineValues> {
    let h = &s.header;
    if let Some(f) = &s.file {
        return Some(SplineValues::File(f.value.clone()));
    }
    let (Some(x), Some(first_y)) = (&s.x, s.y.first()) else {
        rs.error(
            h.span,
            format!("{}: X and Y (or FILE) are required", h.name),
        );
        return None;
    };
    if x.value.len() < 2 {
        rs.error(
            x.span,
            format!("{}: at least two X values are needed", h.name),
        );
        return None;
    }
    if let Some(w) = x.value.windows(2).find(|w| w[1] <= w[0]) {
        rs.error(
            x.span,
            format!(
                "{}: X values must be strictly increasing, but {} is followed by {}",
                h.name, w[0], w[1]
            ),
        );
        return None;
    }
    if s.z.is_none() && s.y.len() == 1 {
        if first_y.value.len() != x.value.len() {
            rs.error(
                first_y.span,
                format!(
                    "{}: {} Y values for {} X values",
                    h.name,
                    first_y.value.len(),
                    x.value.len()
                ),
            );
            return None;
        }
        return Some(SplineValues::Curve {
            x: x.value.clone(),
            y: first_y.value.clone(),
        });
    }
    // A 2-D spline: every `Y = z_k, y_1, …, y_n`.
    let mut z = Vec::with_capacity(s.y.len());
    let mut curves = Vec::with_capacity(s.y.len());
    for y in &s.y {
        match y.value.split_first() {
            Some((zk, ys)) if ys.len() == x.value.len() => {
                z.push(*zk);
                curves.push(ys.to_vec());
            }
            _ => {
                rs.error(
                    y.span,
                    format!(
                        "{}: each Y of a 2-D spline needs its z value and {} y values, found {} values",
                        h.name,
                        x.value.len(),
                        y.value.len()
                    ),
                );
                return None;
            }
        }
    }
    Some(SplineValues::Surface {
        x: x.value.clone(),
        z,
        y: curves,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::build::{build_model, Built};

    const BASE: &str = "title\nPART/1, GROUND\nMARKER/1, PART = 1\nMARKER/2, PART = 1, QP = 1, 0, 0\nPART/2, MASS = 1, CM = 20, IP = 1, 1, 1\nMARKER/20, PART = 2, QP = 0, 2, 0\nMARKER/21, PART = 2, QP = 1, 2, 0\nMARKER/22, PART = 2, FLOATING\nPART/3, MASS = 1, CM = 30, IP = 1, 1, 1\nMARKER/30, PART = 3\nMARKER/31, PART = 3, FLOATING\n";

    fn build(extra: &str) -> Result<Built, linkage_adm::Diagnostics> {
        let text = format!("{BASE}{extra}\nEND\n");
        let ds =
            linkage_adm::parse_dataset(Arc::from("m.adm"), &text).unwrap_or_else(|e| panic!("{e}"));
        build_model(&ds)
    }

    fn ok(extra: &str) -> Built {
        build(extra).unwrap_or_else(|e| panic!("{e}"))
    }

    /// Errors as `(line, col, message)`, sorted; the extra text starts at line 12.
    fn errors(extra: &str) -> Vec<(u32, u32, String)> {
        match build(extra) {
            Ok(_) => panic!("expected errors"),
            Err(d) => {
                let mut e: Vec<_> =
                    d.0.into_iter()
                        .map(|d| {
                            let s = d.span.unwrap_or_default();
                            (s.line, s.col, d.message)
                        })
                        .collect();
                e.sort();
                e
            }
        }
    }

    #[test]
    fn two_marker_elements_resolve_markers_and_defaults() {
        let b = ok("SFORCE/1, I = 20, J = 1, FUNCTION = 10\nSPRINGDAMPER/1, I = 20, J = 2, K = 5, LENGTH = 1.5\nSPRINGDAMPER/2, I = 30, J = 21, ROTATIONAL, KT = 3, TORQUE = 2\nBUSHING/1, I = 30, J = 1, K = 1, 2, 3");
        let m = &b.model;
        assert_eq!(m.forces.len(), 4);
        let ForceKind::Sforce(s) = &m.forces[0].kind else {
            panic!("{:?}", m.forces[0])
        };
        assert_eq!((m.markers[s.i].id, m.markers[s.j].id), (20, 1));
        assert_eq!(s.function.value.expr.text, "10");
        assert_eq!(m.forces[0].origin.element(), "SFORCE/1");
        let ForceKind::SpringDamper(t) = &m.forces[1].kind else {
            panic!()
        };
        assert_eq!(
            (t.stiffness, t.damping, t.free, t.preload),
            (5.0, 0.0, 1.5, 0.0)
        );
        let ForceKind::SpringDamper(r) = &m.forces[2].kind else {
            panic!()
        };
        assert_eq!(
            (r.dof, r.stiffness, r.preload),
            (ForceDof::Rotational, 3.0, 2.0)
        );
        let ForceKind::Bushing(bu) = &m.forces[3].kind else {
            panic!()
        };
        assert_eq!(bu.stiffness, [1.0, 2.0, 3.0]);
        assert_eq!((bu.damping, bu.torque), ([0.0; 3], [0.0; 3]));
        assert!(b.warnings.is_empty(), "{:?}", b.warnings);
    }

    #[test]
    fn field_matrix_is_read_by_columns_and_cratio_scales_it() {
        let k: Vec<String> = (0..36).map(|n| n.to_string()).collect();
        let b = ok(&format!(
            "FIELD/1, I = 20, J = 30, KMATRIX = {}, CRATIO = 0.5, LENGTH = 1, 2, 3, 4, 5, 6",
            k.join(", ")
        ));
        let ForceKind::Field(f) = &b.model.forces[0].kind else {
            panic!()
        };
        // Value n sits in row n mod 6, column n div 6.
        assert_eq!(f.stiffness[1][0], 1.0);
        assert_eq!(f.stiffness[0][1], 6.0);
        assert_eq!(f.stiffness[5][5], 35.0);
        assert_eq!(f.damping[0][1], 3.0);
        assert_eq!(f.length, [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
        assert_eq!(f.force, [0.0; 6]);
    }

    #[test]
    fn beam_properties_and_symmetric_damping_matrix() {
        let c: Vec<String> = (1..=21).map(|n| n.to_string()).collect();
        let b = ok(&format!("BEAM/1, I = 20, J = 1, LENGTH = 2, IXX = 3, IYY = 4, IZZ = 5, AREA = 6, ASY = 1.2, EMODULUS = 7, GMODULUS = 8, CMATRIX = {}", c.join(", ")));
        let ForceKind::Beam(beam) = &b.model.forces[0].kind else {
            panic!()
        };
        assert_eq!(
            [
                beam.length,
                beam.ixx,
                beam.iyy,
                beam.izz,
                beam.area,
                beam.emodulus,
                beam.gmodulus
            ],
            [2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0]
        );
        assert_eq!((beam.asy, beam.asz), (1.2, 0.0));
        assert_eq!(beam.formulation, BeamFormulation::Linear);
        let BeamDamping::Matrix(m) = &beam.damping else {
            panic!()
        };
        // Column 1 = values 1..6, column 2 rows 2..6 = values 7..11, …, (6,6) = 21.
        assert_eq!((m[0][0], m[5][0], m[0][5]), (1.0, 6.0, 6.0));
        assert_eq!((m[1][1], m[2][1], m[1][2]), (7.0, 8.0, 8.0));
        assert_eq!(m[5][5], 21.0);
        let e = errors("BEAM/2, I = 20, J = 1, LENGTH = 0, IXX = 3, IYY = 4, IZZ = 5, EMODULUS = 7, GMODULUS = 8");
        assert_eq!(e[0], (12, 1, "BEAM_2: AREA is missing".to_string()));
        assert_eq!(
            e[1],
            (12, 24, "BEAM_2: LENGTH must be positive (0)".to_string())
        );
    }

    #[test]
    fn vector_forces_resolve_jfloat_to_its_part() {
        let b = ok("VFORCE/1, I = 20, JFLOAT = 31, RM = 1, FX = 1\\FY = 2\\FZ = 3\nVTORQUE/1, I = 20, JFLOAT = 31, RM = 30, TZ = 1\nGFORCE/1, I = 30, JFLOAT = 22, RM = 20, FUNCTION = USER(1)");
        let m = &b.model;
        let ForceKind::Vector(v) = &m.forces[0].kind else {
            panic!()
        };
        assert_eq!(v.kind, VectorKind::Vforce);
        assert_eq!(v.reaction, Body::Part(1));
        assert_eq!(m.markers[v.jfloat].id, 31);
        assert_eq!(m.markers[v.rm].id, 1);
        assert!(v.force.iter().all(Option::is_some) && v.torque.iter().all(Option::is_none));
        let ForceKind::Vector(g) = &m.forces[2].kind else {
            panic!()
        };
        assert_eq!((g.kind, g.reaction), (VectorKind::Gforce, Body::Part(0)));
        assert!(g.user.as_ref().is_some_and(|u| u.value.user));
        // VTORQUE without TX, TY: a warning at the statement.
        assert_eq!(b.warnings.len(), 1, "{:?}", b.warnings);
        assert_eq!(b.warnings[0].span, Some(Span::new(13, 1)));
        assert!(b.warnings[0].message.contains("TX, TY not given"));
    }

    #[test]
    fn reference_errors_point_at_the_argument() {
        let e = errors("SFORCE/1, I = 99, J = 1, FUNCTION = 1\nSPRINGDAMPER/1, I = 22, J = 1\nVFORCE/1, I = 20, JFLOAT = 31, RM = 77, FX = 1");
        assert_eq!(
            e,
            [
                (12, 15, "SFORCE_1: I marker 99 does not exist".to_string()),
                (
                    13,
                    21,
                    "SPRINGDAMPER_1: I marker 22 is FLOATING; I must be a fixed marker".to_string()
                ),
                (14, 37, "VFORCE_1: RM marker 77 does not exist".to_string()),
            ]
        );
        let e = errors("BUSHING/1, I = 20, J = 1, C = 1, -2, 3\nSPRINGDAMPER/2, I = 20, J = 1, K = -1\nSFORCE/2, I = 20, J = 1");
        assert_eq!((e[0].0, e[0].1), (12, 27));
        assert!(e[0].2.contains("C must not be negative"), "{}", e[0].2);
        assert_eq!((e[1].0, e[1].1), (13, 32));
        assert_eq!(e[2], (14, 1, "SFORCE_2: FUNCTION is missing".to_string()));
        let e =
            errors("SFORCE/1, I = 20, J = 1, FUNCTION = 1\nSFORCE/1, I = 20, J = 1, FUNCTION = 2");
        assert_eq!(e, [(13, 1, "duplicate SFORCE id 1".to_string())]);
    }

    #[test]
    fn same_body_is_a_warning_except_for_action_only() {
        let b = ok("SFORCE/1, I = 20, J = 21, FUNCTION = 1\nSFORCE/2, I = 20, J = 21, ACTIONONLY, FUNCTION = 1");
        assert_eq!(b.warnings.len(), 1);
        assert_eq!(b.warnings[0].span, Some(Span::new(12, 1)));
        assert!(b.warnings[0].message.contains("exerts no net load"));
    }

    #[test]
    fn data_elements_variables_arrays_splines() {
        let b = ok("VARIABLE/5, FUNCTION = DM(20, 1), IC = 1\nARRAY/1, IC, SIZE = 2, NUMBERS = 3, 4\nARRAY/2, U, VARIABLES = 5\nARRAY/3, X, SIZE = 4\nSPLINE/1, X = 0, 1, 2, Y = 0, 1, 4, LINEAR_EXTRAPOLATE\nSPLINE/2, X = 0, 1, Y = 0, 5, 6, Y = 1, 7, 8");
        let m = &b.model;
        assert_eq!(m.variables[0].origin.id, 5);
        assert_eq!(m.variables[0].ic, Some(1.0));
        assert_eq!(m.arrays[0].values, ArrayValues::Numbers(vec![3.0, 4.0]));
        assert_eq!(m.arrays[1].values, ArrayValues::Variables(vec![0]));
        assert_eq!(m.arrays[2].values, ArrayValues::States);
        assert_eq!(
            m.splines[0].values,
            SplineValues::Curve {
                x: vec![0.0, 1.0, 2.0],
                y: vec![0.0, 1.0, 4.0]
            }
        );
        assert!(m.splines[0].linear_extrapolate);
        assert_eq!(
            m.splines[1].values,
            SplineValues::Surface {
                x: vec![0.0, 1.0],
                z: vec![0.0, 1.0],
                y: vec![vec![5.0, 6.0], vec![7.0, 8.0]]
            }
        );
        let e = errors(
            "ARRAY/1, U, VARIABLES = 8\nSPLINE/1, X = 0, 0, Y = 1, 2\nSPLINE/2, X = 0, 1, Y = 1",
        );
        assert_eq!(
            e[0],
            (12, 25, "ARRAY_1: VARIABLE 8 does not exist".to_string())
        );
        assert_eq!((e[1].0, e[1].1), (13, 11));
        assert!(e[1].2.contains("strictly increasing"));
        assert_eq!(
            e[2],
            (14, 21, "SPLINE_2: 1 Y values for 2 X values".to_string())
        );
    }
}
