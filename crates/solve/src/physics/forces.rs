//! Applied force elements of a model: [`ForceSet`], the [`AppliedForces`] of linkage.
//!
//! One law per element kind, each in its own module with its equation and sign convention:
//!
//! | element | module | law |
//! |---|---|---|
//! | SFORCE, SPRINGDAMPER | [`scalar`] | scalar along the line J→I (repelling > 0) or torque about z_j |
//! | BUSHING, FIELD | [`six_dof`] | `F = −K·(q − q₀) − C·q̇ + F₀` in J's axes, at I |
//! | BEAM | [`beam`] | LINEAR as [`six_dof`]; STRING adds the axial force's geometric stiffness; NONLINEAR is [`corotational`] |
//! | VFORCE, VTORQUE, GFORCE | [`vector`] | expression components along RM's axes, at I |
//! | FE_PART elements, FE_LOAD | [`fe_beam`] (+ [`corotational`]) | corotational beam between node bodies; Rayleigh damping; lumped loads |
//! | FLEX_BODY weight on its modes | [`flex_weight`] | `gᵀ·A·I3_j` on mode j, the torque of the deformation's weight on the reference body |
//! | FLEX_BODY inertia coupling | [`flex_velocity`] | the quadratic velocity terms of the rigid–modal coupling |
//! | CONTACT | [`contact`] | IMPACT or POISSON normal force and Coulomb friction per incident |
//! | FRICTION | [`crate::physics::forces::friction`] | stick-slip friction on a joint, with a state |
//!
//! Conventions shared by all elements:
//! - Every element produces at most two *loads*: a force (at a point) and a torque on a body.
//!   The generalised force of part k (as [`crate::physics::applied`] defines it) adds, for each load on
//!   k, `F` at the centre of mass and `(P − c_k) × F + T` about it. Loads on ground are
//!   dropped.
//! - Action–reaction elements put the reaction on the other body *at the same point* as the
//!   action (for BUSHING/FIELD/BEAM/VFORCE/…: at I's origin), so that the pair has zero net
//!   force and zero net moment about any point: the J-side moment about J's origin is
//!   `−T − (P_i − P_j) × F`, as Adams documents for BUSHING and FIELD.
//! - Values are in model units (force, force × length); the units consistency factor is the
//!   analyses' business.
//! - Everything is written once, generic over [`algebra::Real`]: evaluated with `f64` for
//!   [`AppliedForces::add_forces`] and with [`linkage_expr::Dual`] for
//!   [`AppliedForces::add_jacobians`], so the Jacobians are exact (expression gradients from
//!   the `Dual` arithmetic, geometric terms from the lifted kinematics of [`algebra`]).
//! - Expressions see a [`StateEnv`]: position and velocity measures, `TIME`, `MODE`,
//!   `VARVAL`, `ARYVAL`, `AKISPL`/`CUBSPL`. Acceleration and force measures are unavailable.
//!
//! [`ForceSet::new`] parses every expression once. Input errors are diagnostics located in
//! the dataset: a syntax error at the line and column inside the expression; a `USER(…)`
//! subroutine (which linkage cannot run) naming the element and its line; a reference from a
//! force expression to a VARIABLE, ARRAY or SPLINE that does not exist or cannot be
//! evaluated.

pub mod algebra;
pub mod beam;
pub mod contact;
pub mod corotational;
pub mod data;
pub mod fe_beam;
pub mod flex_velocity;
pub mod flex_weight;
pub mod friction;
pub mod scalar;
pub mod six_dof;
pub mod vector;

use crate::constraints::rows::{BodyFrame, Velocities};
use crate::physics::applied::{AppliedForces, ForceError, LawError, Regime};
use crate::physics::controls::ControlSet;
use crate::physics::forces::friction::{FrictionSet, FrictionValue};
use crate::physics::measures::{MarkerFrames, StateEnv};
use crate::physics::reactions::Reaction;
use crate::state::State;
pub use crate::tolerances::COINCIDENT_POINTS;
use algebra::{Kinematics, Real, V3};
use data::{ArrayData, DataElements, VariableProblem};
use linkage_adm::{Diagnostic, Diagnostics, Function, Located};
use linkage_expr::{Dual, Expr, Special, StateKind};
use linkage_model::forces::{ForceKind, VectorKind};
use linkage_model::{Body, Model, Origin};

/// A force (at a point) and a torque acting on one body, in ground axes.
#[derive(Clone, Debug)]
pub struct Load<R> {
    pub body: Body,
    /// Point of application of `force` (ground coordinates).
    pub point: V3<R>,
    pub force: V3<R>,
    pub torque: V3<R>,
}

impl<R: Real> Load<R> {
    /// A pure torque.
    pub fn torque(body: Body, torque: V3<R>) -> Self {
        Load {
            body,
            point: V3::zero(),
            force: V3::zero(),
            torque,
        }
    }

    /// A pure force at a point.
    pub fn force(body: Body, point: V3<R>, force: V3<R>) -> Self {
        Load {
            body,
            point,
            force,
            torque: V3::zero(),
        }
    }
}

/// The loads of one element: the action on I's body and the reaction (if any).
pub type Loads<R> = [Option<Load<R>>; 2];

/// What a law sees while it is evaluated.
pub struct Context<'a> {
    pub kin: Kinematics<'a>,
    pub env: &'a StateEnv<'a>,
    /// Lengths at or below this are zero ([`COINCIDENT_POINTS`] × characteristic length).
    pub tiny_length: f64,
}

/// The law of one element.
#[derive(Clone, Debug)]
pub enum Law {
    Scalar(Box<scalar::ScalarLaw>),
    SixDof(Box<six_dof::SixDofLaw>),
    Beam(Box<beam::BeamLaw>),
    Vector(Box<vector::VectorLaw>),
    FeBeam(Box<fe_beam::BeamElementLaw>),
    FeDamping(Box<fe_beam::NodeDampingLaw>),
    FeLoad(Box<fe_beam::NodeLoadLaw>),
    ModalWeight(Box<flex_weight::ModalWeightLaw>),
    ModalVelocity(Box<flex_velocity::ModalVelocityLaw>),
    Contact(Box<contact::ContactLaw>),
}

impl Law {
    fn loads<R: Real>(&self, cx: &Context) -> Result<Loads<R>, LawError> {
        match self {
            Law::Scalar(l) => l.loads(cx),
            Law::SixDof(l) => l.loads(cx),
            Law::Beam(l) => l.loads(cx),
            Law::Vector(l) => l.loads(cx),
            Law::FeBeam(l) => l.loads(cx),
            Law::FeDamping(l) => l.loads(cx),
            Law::FeLoad(l) => l.loads(cx),
            Law::ModalWeight(l) => l.loads(cx),
            Law::ModalVelocity(l) => l.loads(cx),
            Law::Contact(l) => l.loads(cx),
        }
    }
}

/// A force element ready to evaluate.
#[derive(Clone, Debug)]
pub struct Element {
    /// `SFORCE_3 (SFORCE/3, line 12)`: how messages name the element.
    pub label: String,
    pub law: Law,
}

/// Every applied force element of a model (gravity excluded), parsed and resolved.
#[derive(Clone, Debug)]
pub struct ForceSet {
    nparts: usize,
    frames: MarkerFrames,
    data: DataElements,
    elements: Vec<Element>,
    /// FRICTION on joints, with their state (not among `elements`: their loads need it).
    frictions: FrictionSet,
    /// The state equations of the DIFF, LSE and TFSISO elements.
    controls: ControlSet,
    mode: i32,
    tiny_length: f64,
    warnings: Vec<Diagnostic>,
}

/// The frame of marker `m` of the model.
pub(crate) fn marker_frame(model: &Model, m: usize) -> BodyFrame {
    let mk = &model.markers[m];
    BodyFrame {
        body: mk.body,
        p_b: mk.p_bm,
        r_b: mk.r_bm,
    }
}

use linkage_model::functions::parse_component;
pub(crate) use linkage_model::functions::parse_function;

/// The elements whose USER subroutines linkage does not call yet (FIELD's FIESUB, FE_LOAD):
/// their USER calls are refused as unlinked.
const NO_LINKER: &linkage_model::functions::UserRoutines =
    &linkage_model::functions::UserRoutines(None);

/// The label used in messages: `SFORCE_3 (SFORCE/3, line 12)`.
fn label(o: &Origin) -> String {
    o.label()
}

/// A data element an expression names with a literal id.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum DataRef {
    Variable(u32),
    Array(u32),
    Spline(u32),
    Diff(u32),
    Pinput(u32),
    Poutput(u32),
    Sensor(u32),
}

fn literal_id(e: Option<&Expr>) -> Option<u32> {
    match e {
        Some(Expr::Number(v)) if v.fract() == 0.0 && (0.0..=f64::from(u32::MAX)).contains(v) => {
            // Exact: an integral value in u32 range.
            Some(*v as u32)
        }
        _ => None,
    }
}

/// VARVAL, ARYVAL and spline references with literal ids in `e`.
fn data_refs(e: &Expr) -> Vec<DataRef> {
    let mut out = Vec::new();
    e.walk(&mut |node| {
        if let Expr::Call { func, args } = node {
            let r = match func {
                linkage_expr::Function::State(StateKind::Varval) => {
                    literal_id(args.first()).map(DataRef::Variable)
                }
                linkage_expr::Function::State(StateKind::Dif | StateKind::Dif1) => {
                    literal_id(args.first()).map(DataRef::Diff)
                }
                linkage_expr::Function::State(StateKind::Pinval) => {
                    literal_id(args.first()).map(DataRef::Pinput)
                }
                linkage_expr::Function::State(StateKind::Pouval) => {
                    literal_id(args.first()).map(DataRef::Poutput)
                }
                linkage_expr::Function::State(StateKind::Aryval) => {
                    literal_id(args.first()).map(DataRef::Array)
                }
                linkage_expr::Function::State(StateKind::Senval) => {
                    literal_id(args.first()).map(DataRef::Sensor)
                }
                linkage_expr::Function::Special(Special::Akispl | Special::Cubspl) => {
                    literal_id(args.get(2)).map(DataRef::Spline)
                }
                _ => None,
            };
            out.extend(r);
        }
    });
    out
}

/// Why a data element an expression uses cannot be evaluated.
enum RefProblem {
    /// Reported at the expression that uses it.
    Message(String),
    /// A VARIABLE that does not parse: its own diagnostic, located in its expression.
    Located(Diagnostic),
}

/// The VARIABLE ids `e` uses (directly or through other VARIABLEs and ARRAYs), or why one of
/// the data elements it uses cannot be evaluated.
fn reachable(data: &DataElements, e: &Expr) -> Result<Vec<u32>, RefProblem> {
    let mut todo = data_refs(e);
    let mut seen = Vec::new();
    let mut variables = Vec::new();
    while let Some(r) = todo.pop() {
        if seen.contains(&r) {
            continue;
        }
        seen.push(r);
        match r {
            DataRef::Variable(id) => match data.variables.get(&id) {
                None => {
                    return Err(RefProblem::Message(format!(
                        "VARVAL({id}): VARIABLE/{id} does not exist"
                    )))
                }
                Some(v) => {
                    variables.push(id);
                    match &v.expr {
                        Err(VariableProblem::User) => {
                            return Err(RefProblem::Message(format!(
                            "VARIABLE/{id} ({}) calls a USER subroutine, which linkage cannot run",
                            v.name
                        )))
                        }
                        Err(VariableProblem::Syntax(d)) => {
                            return Err(RefProblem::Located(d.clone()))
                        }
                        Ok(x) => todo.extend(data_refs(x)),
                    }
                }
            },
            DataRef::Array(id) => match data.arrays.get(&id) {
                None => {
                    return Err(RefProblem::Message(format!(
                        "ARYVAL({id}, …): ARRAY/{id} does not exist"
                    )))
                }
                Some(ArrayData::Unowned) => {
                    return Err(RefProblem::Message(format!(
                        "ARRAY/{id} is an X or Y array that no LSE or TFSISO uses (a GSE's \
                         arrays are filled by USER subroutines, which linkage cannot run)"
                    )))
                }
                Some(ArrayData::Variables(v)) => {
                    todo.extend(v.iter().map(|&id| DataRef::Variable(id)))
                }
                Some(ArrayData::Outputs(map)) => {
                    todo.extend(map.inputs.iter().map(|&id| DataRef::Variable(id)))
                }
                Some(ArrayData::Numbers(_) | ArrayData::States { .. }) => {}
            },
            DataRef::Diff(id) => {
                if !data.diffs.contains_key(&id) {
                    return Err(RefProblem::Message(format!("DIFF/{id} does not exist")));
                }
            }
            DataRef::Pinput(id) | DataRef::Poutput(id) => {
                let (kind, list) = match r {
                    DataRef::Pinput(_) => ("PINPUT", data.pinputs.get(&id)),
                    _ => ("POUTPUT", data.poutputs.get(&id)),
                };
                match list {
                    None => return Err(RefProblem::Message(format!("{kind}/{id} does not exist"))),
                    Some(v) => todo.extend(v.iter().map(|&id| DataRef::Variable(id))),
                }
            }
            DataRef::Sensor(id) => {
                if !data.sensors.contains_key(&id) {
                    return Err(RefProblem::Message(format!("SENSOR/{id} does not exist")));
                }
            }
            DataRef::Spline(id) => {
                if let Some(why) = data.unsupported_splines.get(&id) {
                    return Err(RefProblem::Message(why.clone()));
                }
                if !data.splines.contains_key(&id) {
                    return Err(RefProblem::Message(format!("SPLINE/{id} does not exist")));
                }
            }
        }
    }
    Ok(variables)
}

/// Collects parse results and diagnostics while the laws are built.
struct Builder<'m> {
    model: &'m Model,
    data: &'m DataElements,
    errors: Vec<Diagnostic>,
    /// VARIABLE ids some force expression uses.
    used: Vec<u32>,
}

impl Builder<'_> {
    /// Parses and checks one expression argument; `None` (with diagnostics) when unusable.
    fn expr(&mut self, f: &Located<Function>, origin: &Origin, what: &str) -> Option<Expr> {
        match parse_function(&self.model.file, f, origin, what, &self.model.user) {
            Err(d) => {
                self.errors.push(d);
                None
            }
            Ok(e) => match reachable(self.data, &e) {
                Ok(vars) => {
                    self.used.extend(vars);
                    Some(e)
                }
                Err(RefProblem::Message(why)) => {
                    self.errors.push(Diagnostic::error(
                        self.model.file.clone(),
                        Some(f.span),
                        format!("{}: {what}: {why}", label(origin)),
                    ));
                    None
                }
                Err(RefProblem::Located(d)) => {
                    let message = format!("{} (used by {})", d.message, label(origin));
                    self.errors.push(Diagnostic { message, ..d });
                    None
                }
            },
        }
    }

    /// Value `component` (0-based) of the USER subroutine of `FUNCTION = USER(…)` `u`; `None`
    /// (with the diagnostic, `ok` cleared) when it cannot be linked.
    fn user_component(
        &mut self,
        u: &Located<Function>,
        origin: &Origin,
        component: usize,
        ok: &mut bool,
    ) -> Option<Expr> {
        let model = self.model;
        match parse_component(&model.file, u, origin, "FUNCTION", &model.user, component) {
            Ok(e) => Some(e),
            Err(d) => {
                // One diagnostic per statement, not one per component.
                if *ok {
                    self.errors.push(d);
                }
                *ok = false;
                None
            }
        }
    }

    fn optional(
        &mut self,
        f: &Option<Located<Function>>,
        origin: &Origin,
        what: &str,
        ok: &mut bool,
    ) -> Option<Expr> {
        let f = f.as_ref()?;
        let e = self.expr(f, origin, what);
        *ok &= e.is_some();
        e
    }

    fn law(&mut self, kind: &ForceKind, origin: &Origin) -> Option<Law> {
        let model = self.model;
        let frame = |m: usize| marker_frame(model, m);
        Some(match kind {
            ForceKind::Contact(c) => match contact::ContactLaw::new(model, c) {
                Ok(l) => Law::Contact(Box::new(l)),
                Err(why) => {
                    self.errors.push(Diagnostic::error(
                        model.file.clone(),
                        Some(origin.span),
                        format!("{}: {why}", label(origin)),
                    ));
                    return None;
                }
            },
            ForceKind::Sforce(s) => {
                let f = self.expr(&s.function, origin, "FUNCTION")?;
                Law::Scalar(Box::new(scalar::ScalarLaw::sforce(
                    frame(s.i),
                    frame(s.j),
                    s,
                    f,
                )))
            }
            ForceKind::SpringDamper(s) => Law::Scalar(Box::new(scalar::ScalarLaw::springdamper(
                frame(s.i),
                frame(s.j),
                s,
            ))),
            ForceKind::Bushing(b) => Law::SixDof(Box::new(six_dof::SixDofLaw::bushing(
                frame(b.i),
                frame(b.j),
                b,
            ))),
            ForceKind::Field(f) => {
                if let Some(u) = &f.user {
                    self.errors.extend(
                        parse_function(&model.file, u, origin, "FUNCTION", NO_LINKER).err(),
                    );
                    return None;
                }
                Law::SixDof(Box::new(six_dof::SixDofLaw::field(
                    frame(f.i),
                    frame(f.j),
                    f,
                )))
            }
            ForceKind::Beam(b) => Law::Beam(Box::new(beam::law(frame(b.i), frame(b.j), b))),
            ForceKind::Vector(v) => {
                let mut ok = true;
                let names: [&str; 6] = ["FX", "FY", "FZ", "TX", "TY", "TZ"];
                let (force, torque) = match &v.user {
                    // GFOSUB (6 values), VFOSUB or VTOSUB (3): one linked call per component.
                    Some(u) => {
                        let (first, count) = match v.kind {
                            VectorKind::Vforce => (0, 3),
                            VectorKind::Vtorque => (3, 3),
                            VectorKind::Gforce => (0, 6),
                        };
                        let mut part = |k: usize| {
                            let c = k.checked_sub(first).filter(|&c| c < count)?;
                            self.user_component(u, origin, c, &mut ok)
                        };
                        ([0, 1, 2].map(&mut part), [3, 4, 5].map(&mut part))
                    }
                    None => (
                        [0, 1, 2].map(|c| self.optional(&v.force[c], origin, names[c], &mut ok)),
                        [0, 1, 2]
                            .map(|c| self.optional(&v.torque[c], origin, names[3 + c], &mut ok)),
                    ),
                };
                if !ok {
                    return None;
                }
                let has_force = !matches!(v.kind, VectorKind::Vtorque);
                let has_torque = !matches!(v.kind, VectorKind::Vforce);
                Law::Vector(Box::new(vector::VectorLaw {
                    i: frame(v.i),
                    reaction: v.reaction,
                    rm: frame(v.rm),
                    force: if has_force { force } else { [None, None, None] },
                    torque: if has_torque {
                        torque
                    } else {
                        [None, None, None]
                    },
                }))
            }
        })
    }
}

impl Builder<'_> {
    /// The elements of every FE part: its beam elements (`FE_PART_2 element 3 (FE_PART/2,
    /// line 40)`), the mass-proportional damping of its nodes, its FE_LOADs on each node.
    fn fe_elements(&mut self, out: &mut Vec<Element>) {
        let model = self.model;
        for p in &model.fe_parts {
            for (k, e) in p.elements.iter().enumerate() {
                out.push(Element {
                    label: format!(
                        "{} element {} ({}, line {})",
                        p.origin.name,
                        k + 1,
                        p.origin.element(),
                        p.origin.span.line
                    ),
                    law: Law::FeBeam(Box::new(fe_beam::BeamElementLaw::new(p, e))),
                });
            }
            if p.cratiom > 0.0 {
                for n in &p.nodes {
                    let part = &model.parts[n.part];
                    out.push(Element {
                        label: format!("{} (CRATIOM)", part.origin.label()),
                        law: Law::FeDamping(Box::new(fe_beam::NodeDampingLaw {
                            body: Body::Part(n.part),
                            cratiom: p.cratiom,
                            mass: part.mass,
                            inertia: part.inertia,
                        })),
                    });
                }
            }
            for l in &p.loads {
                if let Some(u) = &l.user {
                    self.errors.extend(
                        parse_function(&model.file, u, &l.origin, "FUNCTION", NO_LINKER).err(),
                    );
                    continue;
                }
                let mut ok = true;
                let names = ["FX", "FY", "FZ", "TX", "TY", "TZ"];
                let force =
                    [0, 1, 2].map(|c| self.optional(&l.force[c], &l.origin, names[c], &mut ok));
                let torque = [0, 1, 2]
                    .map(|c| self.optional(&l.torque[c], &l.origin, names[3 + c], &mut ok));
                if !ok {
                    continue;
                }
                for (n, node) in p.nodes.iter().enumerate() {
                    out.push(Element {
                        label: label(&l.origin),
                        law: Law::FeLoad(Box::new(fe_beam::NodeLoadLaw {
                            body: Body::Part(node.part),
                            tributary: p.tributary[n],
                            rm: l.rm.map(|m| marker_frame(model, m)),
                            force: force.clone(),
                            torque: torque.clone(),
                        })),
                    });
                }
            }
        }
    }
}

impl Builder<'_> {
    /// The weight's modal load of every flex body mode with a first moment (INVAR3).
    fn flex_weights(&mut self, out: &mut Vec<Element>) {
        let model = self.model;
        for b in &model.flex_bodies {
            for mode in &b.modes {
                let Some(law) =
                    flex_weight::ModalWeightLaw::new(b, mode, model.gravity, model.ucf())
                else {
                    continue;
                };
                out.push(Element {
                    label: format!("{} (weight)", model.parts[mode.part].origin.label()),
                    law: Law::ModalWeight(Box::new(law)),
                });
            }
        }
    }
}

impl Builder<'_> {
    /// The quadratic velocity terms of every coupled flex body: one element on its reference
    /// body, one per mode.
    fn flex_velocities(&mut self, out: &mut Vec<Element>) {
        let model = self.model;
        for b in &model.flex_bodies {
            let Some(terms) = crate::physics::flex_inertia::FlexTerms::of(b) else {
                continue;
            };
            let terms = std::sync::Arc::new(terms);
            let targets = std::iter::once(flex_velocity::Target::Reference)
                .chain((0..b.modes.len()).map(flex_velocity::Target::Mode));
            for target in targets {
                let part = match target {
                    flex_velocity::Target::Reference => b.reference,
                    flex_velocity::Target::Mode(j) => b.modes[j].part,
                };
                out.push(Element {
                    label: format!("{} (inertia coupling)", model.parts[part].origin.label()),
                    law: Law::ModalVelocity(Box::new(flex_velocity::ModalVelocityLaw {
                        terms: terms.clone(),
                        target,
                        per_ucf: 1.0 / model.ucf(),
                    })),
                });
            }
        }
    }
}

impl ForceSet {
    /// Builds the force set of `model`: every expression parsed once, every reference to a
    /// data element checked. Errors are located in the dataset (see the module docs).
    pub fn new(model: &Model) -> Result<ForceSet, Diagnostics> {
        let (data, mut errors) = DataElements::new(model);
        let mut b = Builder {
            model,
            data: &data,
            errors: Vec::new(),
            used: Vec::new(),
        };
        let mut elements = Vec::with_capacity(model.forces.len());
        for f in &model.forces {
            if let Some(law) = b.law(&f.kind, &f.origin) {
                elements.push(Element {
                    label: label(&f.origin),
                    law,
                });
            }
        }
        b.fe_elements(&mut elements);
        b.flex_weights(&mut elements);
        b.flex_velocities(&mut elements);
        let controls = ControlSet::new(model, &mut |f, origin, what| b.expr(f, origin, what));
        // The inputs of linear state elements are used too.
        for e in &model.controls.states {
            if let linkage_model::controls::StateLaw::Linear(l) = &e.law {
                for &k in &l.inputs {
                    let Ok(id) = u32::try_from(model.variables[k].origin.id) else {
                        continue;
                    };
                    match reachable(
                        &data,
                        &Expr::Call {
                            func: linkage_expr::Function::State(StateKind::Varval),
                            args: vec![Expr::Number(f64::from(id))],
                        },
                    ) {
                        Ok(vars) => b.used.extend(vars),
                        Err(RefProblem::Message(why)) => b.errors.push(Diagnostic::error(
                            model.file.clone(),
                            Some(e.origin.span),
                            format!("{}: input: {why}", label(&e.origin)),
                        )),
                        Err(RefProblem::Located(d)) => {
                            let message = format!("{} (used by {})", d.message, label(&e.origin));
                            b.errors.push(Diagnostic { message, ..d });
                        }
                    }
                }
            }
        }
        errors.append(&mut b.errors);
        if !errors.is_empty() {
            errors.sort_by_key(|d| d.span);
            return Err(Diagnostics(errors));
        }
        // VARIABLEs no force uses may hold what linkage cannot parse (INCANG, SENVAL, …).
        let mut warnings: Vec<Diagnostic> = Vec::new();
        for (id, v) in &data.variables {
            if let (Err(VariableProblem::Syntax(d)), false) = (&v.expr, b.used.contains(id)) {
                let message = format!("{}; no force element uses it, so it is ignored", d.message);
                warnings.push(Diagnostic {
                    severity: linkage_adm::Severity::Warning,
                    message,
                    ..d.clone()
                });
            }
        }
        warnings.sort_by_key(|d| d.span);
        Ok(ForceSet {
            nparts: model.parts.len(),
            frames: MarkerFrames::new(model),
            data,
            elements,
            frictions: FrictionSet::new(model),
            controls,
            mode: 0,
            tiny_length: COINCIDENT_POINTS * model.characteristic_length,
            warnings,
        })
    }

    /// Findings that do not prevent evaluation (VARIABLEs no force uses that do not parse).
    pub fn warnings(&self) -> &[Diagnostic] {
        &self.warnings
    }

    /// This set with VARIABLE/`id` held at `value` (its FUNCTION replaced by the number): a
    /// plant input of a linearization. `None` when the model has no such VARIABLE.
    pub fn with_variable(&self, id: u32, value: f64) -> Option<ForceSet> {
        let mut set = self.clone();
        set.hold_variable(id, value).then_some(set)
    }

    /// Holds VARIABLE/`id` at `value` in this set (its FUNCTION replaced by the number): a
    /// plant input set by a co-simulation master between steps. `false` when the model has
    /// no such VARIABLE.
    pub fn hold_variable(&mut self, id: u32, value: f64) -> bool {
        match self.data.variables.get_mut(&id) {
            Some(v) => {
                v.expr = Ok(linkage_expr::Expr::Number(value));
                true
            }
            None => false,
        }
    }

    /// The value of VARIABLE/`id` at `(s, v)`.
    pub fn variable(
        &self,
        id: u32,
        s: &State,
        v: &Velocities,
    ) -> Result<f64, linkage_expr::EvalError> {
        let expr = self.data.variable_expr(id)?;
        linkage_expr::evaluate(expr, &self.env(s, v))
    }

    /// The value `MODE` returns in expressions (default 0; Adams uses e.g. 5 for statics).
    pub fn set_mode(&mut self, mode: i32) {
        self.mode = mode;
    }

    /// The elements, in model order.
    pub fn elements(&self) -> &[Element] {
        &self.elements
    }

    /// The frictions and their state.
    pub fn frictions(&self) -> &FrictionSet {
        &self.frictions
    }

    /// The data elements expressions read.
    pub fn data(&self) -> &DataElements {
        &self.data
    }

    /// The marker frames expressions read.
    pub fn frames(&self) -> &MarkerFrames {
        &self.frames
    }

    /// An expression environment on `(s, v)` with this set's data and mode.
    pub fn env<'a>(&'a self, s: &'a State, v: &'a Velocities) -> StateEnv<'a> {
        StateEnv::new(&self.frames, s, v, &self.data).with_mode(self.mode)
    }

    /// The loads of element `e` at `(s, v)`.
    pub fn loads<R: Real>(
        &self,
        e: usize,
        s: &State,
        v: &Velocities,
    ) -> Result<Loads<R>, ForceError> {
        let env = self.env(s, v);
        self.element_loads(e, &self.context(s, v, &env))
    }

    fn context<'a>(&self, s: &'a State, v: &'a Velocities, env: &'a StateEnv<'a>) -> Context<'a> {
        Context {
            kin: Kinematics {
                state: s,
                velocities: v,
            },
            env,
            tiny_length: self.tiny_length,
        }
    }

    fn element_loads<R: Real>(&self, e: usize, cx: &Context) -> Result<Loads<R>, ForceError> {
        let el = &self.elements[e];
        el.law.loads::<R>(cx).map_err(|cause| ForceError {
            element: el.label.clone(),
            time: cx.kin.state.time,
            cause,
        })
    }

    /// Calls `sink(k, Q_k)` with each element's generalised force on each moving part k
    /// (force at the CM, torque about the CM). One expression environment serves every
    /// element, so a VARIABLE is evaluated once per call.
    fn generalised<R: Real>(
        &self,
        regime: Regime,
        s: &State,
        v: &Velocities,
        mut sink: impl FnMut(usize, [R; 6]),
    ) -> Result<(), ForceError> {
        let env = self.env(s, v);
        let cx = self.context(s, v, &env);
        let kin = cx.kin;
        let mut apply = |load: Load<R>| {
            let Body::Part(k) = load.body else {
                return;
            };
            let arm = load.point.sub(&kin.cm::<R>(load.body));
            let moment = arm.cross(&load.force).add(&load.torque);
            let V3 { x, y, z } = load.force;
            sink(k, [x, y, z, moment.x, moment.y, moment.z]);
        };
        for e in 0..self.elements.len() {
            for load in self.element_loads::<R>(e, &cx)?.into_iter().flatten() {
                apply(load);
            }
        }
        self.frictions.each_load::<R>(regime, &cx, |loads| {
            loads.into_iter().flatten().for_each(&mut apply)
        });
        Ok(())
    }
}

impl AppliedForces for ForceSet {
    fn has_state(&self) -> bool {
        !self.frictions.is_empty()
    }

    fn start_state(&self, s: &mut State) {
        self.frictions.start(s);
    }

    fn accept_state(&self, s: &mut State, v: &Velocities, reactions: &[Reaction]) -> f64 {
        self.frictions.accept(s, v, reactions)
    }

    fn joint_frictions(&self) -> Option<&FrictionSet> {
        (!self.frictions.is_empty()).then_some(&self.frictions)
    }

    fn friction_values(&self, regime: Regime, s: &State, v: &Velocities) -> Vec<FrictionValue> {
        self.frictions.values(regime, s, v)
    }

    fn add_forces(
        &self,
        regime: Regime,
        s: &State,
        v: &Velocities,
        out: &mut [f64],
    ) -> Result<(), ForceError> {
        self.generalised::<f64>(regime, s, v, |k, q| {
            for (c, x) in q.iter().enumerate() {
                if let Some(o) = out.get_mut(6 * k + c) {
                    *o += x;
                }
            }
        })
    }

    fn add_jacobians(
        &self,
        regime: Regime,
        s: &State,
        v: &Velocities,
        dq: &mut Vec<(usize, usize, f64)>,
        mut dv: Option<&mut Vec<(usize, usize, f64)>>,
    ) -> Result<(), ForceError> {
        let n6 = 6 * self.nparts;
        self.generalised::<Dual>(regime, s, v, |k, q| {
            for (c, x) in q.iter().enumerate() {
                let row = 6 * k + c;
                for &(var, d) in x.gradient() {
                    let col = var as usize;
                    if col < n6 {
                        dq.push((row, col, d));
                    } else if col < 2 * n6 {
                        if let Some(dv) = dv.as_deref_mut() {
                            dv.push((row, col - n6, d));
                        }
                    }
                }
            }
        })
    }

    fn control_count(&self) -> usize {
        self.controls.count()
    }

    fn control_residuals(
        &self,
        s: &State,
        v: &Velocities,
        out: &mut [f64],
    ) -> Result<(), ForceError> {
        self.controls.residuals(&self.env(s, v), out)
    }

    fn control_jacobian(
        &self,
        s: &State,
        v: &Velocities,
        out: &mut Vec<(usize, usize, f64)>,
    ) -> Result<(), ForceError> {
        self.controls.jacobian(&self.env(s, v), out)
    }

    fn add_control_force_jacobian(
        &self,
        regime: Regime,
        s: &State,
        v: &Velocities,
        out: &mut Vec<(usize, usize, f64)>,
    ) -> Result<(), ForceError> {
        if self.controls.count() == 0 {
            return Ok(());
        }
        let n12 = 12 * self.nparts;
        self.generalised::<Dual>(regime, s, v, |k, q| {
            for (c, x) in q.iter().enumerate() {
                for &(var, d) in x.gradient() {
                    if let Some(col) = (var as usize).checked_sub(n12) {
                        out.push((6 * k + c, col, d));
                    }
                }
            }
        })
    }
}
