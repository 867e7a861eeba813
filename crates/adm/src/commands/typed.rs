//! The typed form of a command file: what each command asks for, as values.
//!
//! Contract:
//! - Every command keeps its position ([`CommandEntry::span`], the keyword's line:column) and
//!   its physical lines, so the runner can echo it and place its diagnostics.
//! - Settings commands (INTEGRATOR, EQUILIBRIUM, IC, KINEMATICS, ACCGRAV) are *edits*: a field is
//!   `Some` exactly when the command gives that argument. No Adams default is applied here; the
//!   runner merges an edit into the settings in force (ADM-REFERENCE §7.5, §9).
//! - Numbers are as the dataset language reads them: an angle written with `D` is already in
//!   radians (`ALIMIT = 5.0D` gives 5° in radians); no other argument accepts `D`.
//! - Commands that change nothing in a solver without the feature (DEBUG, OUTPUT, PREFERENCES,
//!   LSOLVER) are typed as [`Options`]: every argument is kept, none is dropped.

use crate::diagnostic::{Diagnostic, Span};
use crate::statement::Statement;
use std::sync::Arc;

/// A command file, typed: the dataset it loads and its commands in order.
#[derive(Clone, Debug, PartialEq)]
pub struct TypedCommandFile {
    /// File name used in diagnostics.
    pub file: Arc<str>,
    /// Line 1 when it names the dataset (classic header), else `None`.
    pub model: Option<String>,
    /// Line 2 of a classic header when not blank.
    pub output_prefix: Option<String>,
    /// The commands, in order; the last one is [`Command::Stop`] when the file has `STOP`.
    pub commands: Vec<CommandEntry>,
    /// Non-fatal findings (an argument given twice, …).
    pub warnings: Vec<Diagnostic>,
}

/// One command and where it was written.
#[derive(Clone, Debug, PartialEq)]
pub struct CommandEntry {
    /// Position of the command keyword (for `STOP`: its line, column 1).
    pub span: Span,
    /// First and last physical line (1-based, inclusive), continuation lines included.
    pub lines: (u32, u32),
    pub command: Command,
}

/// One command of a command file (ADM-REFERENCE §7.2).
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    /// `SIMULATE/…` (§7.3).
    Simulate(Simulate),
    /// `LINEAR/…` (§7.4).
    Linear(Linear),
    /// `INTEGRATOR/…` (§7.5, §9.4).
    Integrator(IntegratorEdit),
    /// `EQUILIBRIUM/…` (§7.5, §9.1).
    Equilibrium(EquilibriumEdit),
    /// `IC/…` (§7.5, §9.2).
    Ic(IcEdit),
    /// `KINEMATICS/…` (§7.5, §9.3).
    Kinematics(KinematicsEdit),
    /// `ACCGRAV/…`: the gravity components given.
    Accgrav(AccgravEdit),
    /// `ACTIVATE/type, ID=… | RANGE=…`.
    Activate(Activation),
    /// `DEACTIVATE/type, ID=… | RANGE=…`.
    Deactivate(Activation),
    /// An element statement given as a command (`VARIABLE/id, FUNCTION=…`, `MOTION/id, …`,
    /// `PART/id, MASS=…`, …): the runner applies it to the dataset.
    Redefine(Redefinition),
    /// `FILE/MODEL=… [,OUTPUT_PREFIX=…]` or `FILE/COMMAND=…`.
    File(FileCommand),
    /// `SAVE/{SYSTEM|STATES}, FILE=…`.
    Save(StateFile),
    /// `RELOAD/{SYSTEM|STATES}, FILE=… [,OUTPUT_PREFIX=…]`.
    Reload(StateFile),
    /// `ENVIRONMENT/NAME=… {, VALUE=… | , UNSET}` or `ENVIRONMENT/LIST`.
    Environment(Environment),
    /// `OUTPUT/…` (REQSAVE, GRSAVE, NOSEPARATOR, …).
    Output(Options),
    /// `DEBUG/…` (EPRINT, NOEPRINT, …).
    Debug(Options),
    /// `PREFERENCES/…`.
    Preferences(Options),
    /// `LSOLVER/…` (linear-solver choice).
    Lsolver(Options),
    /// `CONTROL/FUNCTION=USER(…)`: hands control to a user subroutine (kept generic).
    Control(Statement),
    /// HELP, INFO, MENU, SHOW, TIME: interactive information requests (kept generic).
    Information(Statement),
    /// `STOP`: ends the command file.
    Stop,
}

impl Command {
    /// The command's canonical name (`"SIMULATE"`, `"DEACTIVATE"`, `"VARIABLE"` for a
    /// redefinition, …).
    pub fn name(&self) -> &str {
        match self {
            Command::Simulate(_) => "SIMULATE",
            Command::Linear(_) => "LINEAR",
            Command::Integrator(_) => "INTEGRATOR",
            Command::Equilibrium(_) => "EQUILIBRIUM",
            Command::Ic(_) => "IC",
            Command::Kinematics(_) => "KINEMATICS",
            Command::Accgrav(_) => "ACCGRAV",
            Command::Activate(_) => "ACTIVATE",
            Command::Deactivate(_) => "DEACTIVATE",
            Command::Redefine(r) => r.element,
            Command::File(_) => "FILE",
            Command::Save(_) => "SAVE",
            Command::Reload(_) => "RELOAD",
            Command::Environment(_) => "ENVIRONMENT",
            Command::Output(o)
            | Command::Debug(o)
            | Command::Preferences(o)
            | Command::Lsolver(o) => o.command,
            Command::Control(_) => "CONTROL",
            Command::Information(st) => st.keyword.as_str(),
            Command::Stop => "STOP",
        }
    }
}

// ---- SIMULATE --------------------------------------------------------------------------------

/// `SIMULATE/kind [, END=r | DURATION=r] [, STEPS=i | DTOUT=r]`.
///
/// At most one of END/DURATION and one of STEPS/DTOUT (checked). DYNAMICS, KINEMATICS and
/// TRANSIENT need END or DURATION; STATICS without them is one equilibrium, with them a
/// quasi-static sequence. Which output spacing applies when neither STEPS nor DTOUT is given is
/// the runner's decision.
#[derive(Clone, Debug, PartialEq)]
pub struct Simulate {
    pub kind: SimulateKind,
    /// Absolute end time.
    pub end: Option<f64>,
    /// End time relative to the current time (> 0).
    pub duration: Option<f64>,
    /// Number of output steps (≥ 1).
    pub steps: Option<u32>,
    /// Output interval (> 0).
    pub dtout: Option<f64>,
}

/// What `SIMULATE` runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SimulateKind {
    /// `STATICS`.
    Static,
    /// `DYNAMICS`.
    Dynamic,
    /// `KINEMATICS` (zero-DOF models).
    Kinematic,
    /// `TRANSIENT`: dynamics, or kinematics at zero DOF.
    Transient,
    /// `INITIAL_CONDITIONS [, DISPLACEMENT | VELOCITY | ACCELERATION]`: the IC phases up to the
    /// one named (all three when `None`).
    InitialConditions(Option<IcPhase>),
}

/// A phase of the initial-conditions analysis (ADM-REFERENCE §8.1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IcPhase {
    Displacement,
    Velocity,
    Acceleration,
}

// ---- LINEAR ----------------------------------------------------------------------------------

/// `LINEAR/…` (ADM-REFERENCE §7.4).
#[derive(Clone, Debug, PartialEq)]
pub enum Linear {
    /// `LINEAR/EIGENSOL`.
    Eigensol(Eigensol),
    /// `LINEAR/STATEMAT`: state matrices to a file.
    Statemat(MatrixExport),
    /// `LINEAR/MKB`: mass, stiffness and damping (and input) matrices to a file.
    Mkb(MatrixExport),
}

/// `LINEAR/EIGENSOL` options; the mode ranges are the tables the .out file gets.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Eigensol {
    /// `NODAMPIN`: undamped modes.
    pub nodamping: bool,
    /// `NOVECTOR`: eigenvalues only.
    pub novector: bool,
    /// `COORDS = i1[, i2]`: modes whose normalised coordinates are tabulated.
    pub coordinates: Option<ModeRange>,
    /// `ENERGY = i1[, i2]`.
    pub energy: Option<ModeRange>,
    /// `KINETIC = i1[, i2]`.
    pub kinetic: Option<ModeRange>,
    /// `STRAIN = i1[, i2]`.
    pub strain: Option<ModeRange>,
    /// `DISSIPAT = i1[, i2]`.
    pub dissipative: Option<ModeRange>,
    /// `RM = id`: reference marker of the relative coordinates.
    pub rm: Option<u64>,
    /// `PSTATE = id`: user-chosen states.
    pub pstate: Option<u64>,
    /// `ORIGINAL`: the original (pre-PSTATE) linearization.
    pub original: bool,
}

/// Modes `first..=last` (1-based); `last == first` when one number is given.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ModeRange {
    pub first: u32,
    pub last: u32,
}

/// `LINEAR/STATEMAT` and `LINEAR/MKB`: matrices written to `file`.
#[derive(Clone, Debug, PartialEq)]
pub struct MatrixExport {
    /// `FILE = name` (required).
    pub file: String,
    pub format: Option<MatrixFormat>,
    /// `PINPUT = id`, `POUTPUT = id`.
    pub pinput: Option<u64>,
    pub poutput: Option<u64>,
    pub rm: Option<u64>,
    pub pstate: Option<u64>,
    pub original: bool,
}

/// `FORMAT = …` of exported matrices.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MatrixFormat {
    Matrixx,
    Matlab,
}

// ---- settings edits --------------------------------------------------------------------------

/// `INTEGRATOR/…`: the arguments given (ADM-REFERENCE §9.4).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct IntegratorEdit {
    pub method: Option<IntegratorMethod>,
    pub formulation: Option<Formulation>,
    pub error: Option<f64>,
    pub hmax: Option<f64>,
    pub hmin: Option<f64>,
    pub hinit: Option<f64>,
    pub alpha: Option<f64>,
    pub beta: Option<f64>,
    pub gamma: Option<f64>,
    pub adaptivity: Option<f64>,
    pub kmax: Option<u32>,
    pub maxit: Option<u32>,
    pub corrector: Option<Corrector>,
    /// `INTERPOLATE = ON | OFF`.
    pub interpolate: Option<bool>,
    /// `PATTERN = T:F:…` (true = re-evaluate the Jacobian).
    pub pattern: Option<Vec<bool>>,
    /// `LIST`: print the settings.
    pub list: bool,
    /// `DEFAULT`: reset to Adams' defaults before applying the rest.
    pub default: bool,
}

/// The integrator named by `INTEGRATOR/`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IntegratorMethod {
    Gstiff,
    Wstiff,
    Hht,
    Newmark,
    Hastiff,
    ConstantBdf,
    Abam,
    Rkf45,
}

/// Index formulation of the equations of motion.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Formulation {
    I3,
    Si2,
    Si1,
}

/// `CORRECTOR = ORIGINAL | MODIFIED`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Corrector {
    Original,
    Modified,
}

/// `EQUILIBRIUM/…`: the arguments given (ADM-REFERENCE §9.1).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EquilibriumEdit {
    /// Radians (`D` accepted).
    pub alimit: Option<f64>,
    pub error: Option<f64>,
    pub imbalance: Option<f64>,
    pub maxit: Option<u32>,
    pub pattern: Option<Vec<bool>>,
    pub stability: Option<f64>,
    pub tlimit: Option<f64>,
    /// `STATIC` or `DYNAMIC` (settling by damped dynamics).
    pub mode: Option<EquilibriumMode>,
    pub global_damping: Option<f64>,
    pub settling_time: Option<f64>,
    pub acceleration_error: Option<f64>,
    pub kinetic_energy_error: Option<f64>,
    pub method: Option<StaticMethod>,
    pub atol: Option<f64>,
    pub rtol: Option<f64>,
    pub maxitl: Option<u32>,
    pub etamax: Option<f64>,
    pub eta: Option<f64>,
    pub list: bool,
    pub default: bool,
}

/// `STATIC` / `DYNAMIC` of EQUILIBRIUM.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EquilibriumMode {
    Static,
    Dynamic,
}

/// `METHOD = …` of EQUILIBRIUM.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StaticMethod {
    Original,
    Advanced,
    Aggressive,
    All,
}

/// `IC/…`: the arguments given (ADM-REFERENCE §9.2).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct IcEdit {
    pub error: Option<f64>,
    pub maxit: Option<u32>,
    pub pattern: Option<Vec<bool>>,
    pub tlimit: Option<f64>,
    /// Radians (`D` accepted).
    pub alimit: Option<f64>,
    pub verror: Option<f64>,
    pub aerror: Option<f64>,
    pub amaxit: Option<u32>,
    pub apattern: Option<Vec<bool>>,
    pub list: bool,
    pub default: bool,
}

/// `KINEMATICS/…`: the arguments given (ADM-REFERENCE §9.3; IC's without VERROR).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct KinematicsEdit {
    pub error: Option<f64>,
    pub maxit: Option<u32>,
    pub pattern: Option<Vec<bool>>,
    pub tlimit: Option<f64>,
    /// Radians (`D` accepted).
    pub alimit: Option<f64>,
    pub aerror: Option<f64>,
    pub amaxit: Option<u32>,
    pub apattern: Option<Vec<bool>>,
    pub list: bool,
    pub default: bool,
}

/// `ACCGRAV/…`: the components given (model acceleration units, ground axes).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AccgravEdit {
    pub igrav: Option<f64>,
    pub jgrav: Option<f64>,
    pub kgrav: Option<f64>,
    pub list: bool,
}

// ---- ACTIVATE / DEACTIVATE -------------------------------------------------------------------

/// `ACTIVATE/type, …` or `DEACTIVATE/type, …`: the elements of one type selected by
/// `ID = id1, id2, …` and/or `RANGE = lo, hi` (every element of that type with lo ≤ id ≤ hi
/// that the model has; ranges are not expanded here).
#[derive(Clone, Debug, PartialEq)]
pub struct Activation {
    pub element: ElementType,
    pub ids: Vec<u64>,
    /// Inclusive `(lo, hi)` with lo ≤ hi.
    pub ranges: Vec<(u64, u64)>,
}

impl Activation {
    /// Whether the element with `id` is selected.
    pub fn selects(&self, id: u64) -> bool {
        self.ids.contains(&id) || self.ranges.iter().any(|&(lo, hi)| lo <= id && id <= hi)
    }
}

/// Element types that ACTIVATE/DEACTIVATE accept.
///
/// Decision: the elements that contribute equations or forces and can be switched off in
/// Adams Solver — constraints (JOINT, JPRIM, MOTION, COUPLER, GEAR, GCON, CVCV, PTCV, UCON),
/// forces (SFORCE, SPRINGDAMPER, BUSHING, FIELD, BEAM, VFORCE, VTORQUE, GFORCE, NFORCE, MFORCE,
/// CONTACT, FRICTION), system elements (VARIABLE, DIFF, LSE, GSE, TFSISO) and SENSOR. Parts,
/// markers and data elements (ARRAY, SPLINE, …) cannot be deactivated: naming one is an error.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ElementType {
    Joint,
    Jprim,
    Motion,
    Coupler,
    Gear,
    Gcon,
    Cvcv,
    Ptcv,
    Ucon,
    Sforce,
    SpringDamper,
    Bushing,
    Field,
    Beam,
    Vforce,
    Vtorque,
    Gforce,
    Nforce,
    Mforce,
    Contact,
    Friction,
    Variable,
    Diff,
    Lse,
    Gse,
    Tfsiso,
    Sensor,
}

impl ElementType {
    /// Every type, in the order of [`ElementType::keyword`]'s table.
    pub const ALL: [ElementType; 27] = [
        ElementType::Joint,
        ElementType::Jprim,
        ElementType::Motion,
        ElementType::Coupler,
        ElementType::Gear,
        ElementType::Gcon,
        ElementType::Cvcv,
        ElementType::Ptcv,
        ElementType::Ucon,
        ElementType::Sforce,
        ElementType::SpringDamper,
        ElementType::Bushing,
        ElementType::Field,
        ElementType::Beam,
        ElementType::Vforce,
        ElementType::Vtorque,
        ElementType::Gforce,
        ElementType::Nforce,
        ElementType::Mforce,
        ElementType::Contact,
        ElementType::Friction,
        ElementType::Variable,
        ElementType::Diff,
        ElementType::Lse,
        ElementType::Gse,
        ElementType::Tfsiso,
        ElementType::Sensor,
    ];

    /// The statement keyword of the type (`"JOINT"`, `"SPRINGDAMPER"`).
    pub fn keyword(self) -> &'static str {
        match self {
            ElementType::Joint => "JOINT",
            ElementType::Jprim => "JPRIM",
            ElementType::Motion => "MOTION",
            ElementType::Coupler => "COUPLER",
            ElementType::Gear => "GEAR",
            ElementType::Gcon => "GCON",
            ElementType::Cvcv => "CVCV",
            ElementType::Ptcv => "PTCV",
            ElementType::Ucon => "UCON",
            ElementType::Sforce => "SFORCE",
            ElementType::SpringDamper => "SPRINGDAMPER",
            ElementType::Bushing => "BUSHING",
            ElementType::Field => "FIELD",
            ElementType::Beam => "BEAM",
            ElementType::Vforce => "VFORCE",
            ElementType::Vtorque => "VTORQUE",
            ElementType::Gforce => "GFORCE",
            ElementType::Nforce => "NFORCE",
            ElementType::Mforce => "MFORCE",
            ElementType::Contact => "CONTACT",
            ElementType::Friction => "FRICTION",
            ElementType::Variable => "VARIABLE",
            ElementType::Diff => "DIFF",
            ElementType::Lse => "LSE",
            ElementType::Gse => "GSE",
            ElementType::Tfsiso => "TFSISO",
            ElementType::Sensor => "SENSOR",
        }
    }
}

// ---- redefinitions, files, options -----------------------------------------------------------

/// An element statement given as a command.
///
/// `statement` is the command in generic form with its argument keys resolved to canonical
/// names where the dataset language types the element (PART, MARKER, JOINT, MOTION, GCON, the
/// force elements, VARIABLE, ARRAY, SPLINE, REQUEST: an unknown or ambiguous key is an error);
/// for the other elements (FLEX_BODY, FRICTION, SENSOR, STRING) keys stay as written. A bare
/// `LIST` asks for the element to be printed.
#[derive(Clone, Debug, PartialEq)]
pub struct Redefinition {
    /// The statement keyword (`"VARIABLE"`, `"MOTION"`, …).
    pub element: &'static str,
    pub id: u64,
    pub statement: Statement,
}

/// `FILE/…`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FileCommand {
    /// `MODEL = name`: the dataset to load (`.adm` assumed when no extension).
    pub model: Option<String>,
    /// `OUTPUT_PREFIX = name` (only with MODEL).
    pub output_prefix: Option<String>,
    /// `COMMAND = name`: a command file to read (`.acf` assumed).
    pub command: Option<String>,
}

/// `SAVE/…` and `RELOAD/…`.
#[derive(Clone, Debug, PartialEq)]
pub struct StateFile {
    pub what: SavedState,
    pub file: String,
    /// `OUTPUT_PREFIX = …` (RELOAD only).
    pub output_prefix: Option<String>,
}

/// What SAVE writes and RELOAD reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SavedState {
    /// The whole model and its state.
    System,
    /// The state vector only.
    States,
}

/// `ENVIRONMENT/…`: sets, unsets or lists a solver environment variable.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Environment {
    /// `NAME = …` (case kept).
    pub name: Option<String>,
    /// `VALUE = …` (case kept).
    pub value: Option<String>,
    pub unset: bool,
    pub list: bool,
}

/// The arguments of a command that only sets options (DEBUG, OUTPUT, PREFERENCES, LSOLVER), each under its canonical name, in the order written.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// The command's canonical name.
    pub command: &'static str,
    pub items: Vec<OptionItem>,
}

impl Options {
    /// Whether the bare keyword `key` (canonical) was given.
    pub fn has(&self, key: &str) -> bool {
        self.items.iter().any(|i| i.key == key)
    }

    /// The value of `key` (canonical), if given.
    pub fn get(&self, key: &str) -> Option<&OptionValue> {
        self.items.iter().find(|i| i.key == key).map(|i| &i.value)
    }
}

/// One argument of an [`Options`] command.
#[derive(Clone, Debug, PartialEq)]
pub struct OptionItem {
    pub key: &'static str,
    pub value: OptionValue,
    pub span: Span,
}

/// The value of an option.
#[derive(Clone, Debug, PartialEq)]
pub enum OptionValue {
    /// A bare keyword (`EPRINT`, `REQSAVE`).
    Flag,
    Number(f64),
    Count(u32),
    /// A keyword value, upper case (`ON`, `UMF`).
    Word(String),
    /// Free text as written (`COMMENT = …`).
    Text(String),
}
