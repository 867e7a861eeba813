//! Complete argument tables of the commands (ADM-REFERENCE §7, §9), one per command.
//!
//! Each table lists every argument linkage accepts for the command; anything else is an error
//! naming it. Where the reference is thin (OUTPUT, DEBUG, PREFERENCES, LSOLVER) the tables
//! hold the Adams Solver arguments known to the authors; extend them when a real command file
//! needs more. RESULTS is a dataset statement, not a command (ADM-REFERENCE §7.2).

use super::args::Kind::{Angle, Count, Flag, Ids, Pattern, Real, Text, Word};
use super::args::{alias, spec, Spec};

pub(super) const SIMULATE: &[Spec] = &[
    spec("DYNAMICS", Flag),
    spec("KINEMATICS", Flag),
    spec("STATICS", Flag),
    spec("TRANSIENT", Flag),
    spec("INITIAL_CONDITIONS", Flag),
    spec("DISPLACEMENT", Flag),
    spec("VELOCITY", Flag),
    spec("ACCELERATION", Flag),
    spec("END", Real),
    spec("DURATION", Real),
    spec("STEPS", Count),
    spec("DTOUT", Real),
];

pub(super) const LINEAR: &[Spec] = &[
    spec("EIGENSOL", Flag),
    spec("STATEMAT", Flag),
    spec("MKB", Flag),
    spec("NODAMPIN", Flag),
    alias("NODAMPING", "NODAMPIN", Flag),
    spec("NOVECTOR", Flag),
    spec("COORDS", Ids),
    spec("ENERGY", Ids),
    spec("KINETIC", Ids),
    spec("STRAIN", Ids),
    spec("DISSIPAT", Ids),
    spec("RM", Ids),
    spec("PSTATE", Ids),
    spec("ORIGINAL", Flag),
    spec("PINPUT", Ids),
    spec("POUTPUT", Ids),
    spec("FORMAT", Word),
    spec("FILE", Text),
];

/// LINEAR arguments that only EIGENSOL takes.
pub(super) const EIGENSOL_ONLY: &[&str] = &[
    "NODAMPIN", "NOVECTOR", "COORDS", "ENERGY", "KINETIC", "STRAIN", "DISSIPAT",
];
/// LINEAR arguments that only STATEMAT and MKB take.
pub(super) const EXPORT_ONLY: &[&str] = &["PINPUT", "POUTPUT", "FORMAT", "FILE"];

pub(super) const INTEGRATOR_METHODS: &[&str] = &crate::typed::INTEGRATOR_METHODS;

pub(super) const INTEGRATOR: &[Spec] = &[
    spec("GSTIFF", Flag),
    spec("WSTIFF", Flag),
    spec("HHT", Flag),
    spec("NEWMARK", Flag),
    spec("HASTIFF", Flag),
    spec("CONSTANT_BDF", Flag),
    spec("ABAM", Flag),
    spec("RKF45", Flag),
    spec("I3", Flag),
    spec("SI2", Flag),
    spec("SI1", Flag),
    spec("ERROR", Real),
    spec("HMAX", Real),
    spec("HMIN", Real),
    spec("HINIT", Real),
    spec("ALPHA", Real),
    spec("BETA", Real),
    spec("GAMMA", Real),
    spec("ADAPTIVITY", Real),
    spec("KMAX", Count),
    spec("MAXIT", Count),
    spec("CORRECTOR", Word),
    spec("INTERPOLATE", Word),
    spec("PATTERN", Pattern),
    spec("LIST", Flag),
    spec("DEFAULT", Flag),
];

pub(super) const EQUILIBRIUM: &[Spec] = &[
    spec("ALIMIT", Angle),
    spec("ERROR", Real),
    spec("IMBALANCE", Real),
    spec("MAXIT", Count),
    spec("PATTERN", Pattern),
    spec("STABILITY", Real),
    spec("TLIMIT", Real),
    spec("STATIC", Flag),
    spec("DYNAMIC", Flag),
    spec("GLOBAL_DAMPING", Real),
    spec("SETTLING_TIME", Real),
    spec("ACCELERATION_ERROR", Real),
    spec("KINETIC_ENERGY_ERROR", Real),
    spec("METHOD", Word),
    spec("ATOL", Real),
    spec("RTOL", Real),
    spec("MAXITL", Count),
    spec("ETAMAX", Real),
    spec("ETA", Real),
    spec("LIST", Flag),
    spec("DEFAULT", Flag),
];

pub(super) const IC: &[Spec] = &[
    spec("ERROR", Real),
    spec("MAXIT", Count),
    spec("PATTERN", Pattern),
    spec("TLIMIT", Real),
    spec("ALIMIT", Angle),
    spec("VERROR", Real),
    spec("AERROR", Real),
    spec("AMAXIT", Count),
    spec("APATTERN", Pattern),
    spec("LIST", Flag),
    spec("DEFAULT", Flag),
];

pub(super) const KINEMATICS: &[Spec] = &[
    spec("ERROR", Real),
    spec("MAXIT", Count),
    spec("PATTERN", Pattern),
    spec("TLIMIT", Real),
    spec("ALIMIT", Angle),
    spec("AERROR", Real),
    spec("AMAXIT", Count),
    spec("APATTERN", Pattern),
    spec("LIST", Flag),
    spec("DEFAULT", Flag),
];

pub(super) const ACCGRAV: &[Spec] = &[
    spec("IGRAV", Real),
    spec("JGRAV", Real),
    spec("KGRAV", Real),
    spec("LIST", Flag),
];

/// ACTIVATE / DEACTIVATE: the element types of [`super::ElementType`] and the selection.
pub(super) const ACTIVATION: &[Spec] = &[
    spec("JOINT", Flag),
    spec("JPRIM", Flag),
    spec("MOTION", Flag),
    spec("COUPLER", Flag),
    spec("GEAR", Flag),
    spec("GCON", Flag),
    spec("CVCV", Flag),
    spec("PTCV", Flag),
    spec("UCON", Flag),
    spec("SFORCE", Flag),
    spec("SPRINGDAMPER", Flag),
    spec("BUSHING", Flag),
    spec("FIELD", Flag),
    spec("BEAM", Flag),
    spec("VFORCE", Flag),
    spec("VTORQUE", Flag),
    spec("GFORCE", Flag),
    spec("NFORCE", Flag),
    spec("MFORCE", Flag),
    spec("CONTACT", Flag),
    spec("FRICTION", Flag),
    spec("VARIABLE", Flag),
    spec("DIFF", Flag),
    spec("LSE", Flag),
    spec("GSE", Flag),
    spec("TFSISO", Flag),
    spec("SENSOR", Flag),
    spec("ID", Ids),
    spec("RANGE", Ids),
];

pub(super) const FILE: &[Spec] = &[
    spec("MODEL", Text),
    spec("COMMAND", Text),
    spec("OUTPUT_PREFIX", Text),
];

pub(super) const SAVE: &[Spec] = &[
    spec("SYSTEM", Flag),
    spec("STATES", Flag),
    spec("FILE", Text),
];

pub(super) const RELOAD: &[Spec] = &[
    spec("SYSTEM", Flag),
    spec("STATES", Flag),
    spec("FILE", Text),
    spec("OUTPUT_PREFIX", Text),
];

pub(super) const ENVIRONMENT: &[Spec] = &[
    spec("NAME", Text),
    spec("VALUE", Text),
    spec("UNSET", Flag),
    spec("LIST", Flag),
];

pub(super) const OUTPUT: &[Spec] = &[
    spec("CHART", Flag),
    spec("DACSAVE", Flag),
    spec("DSCALE", Real),
    spec("FIXED", Flag),
    spec("GRSAVE", Flag),
    spec("LOADS", Flag),
    spec("NOPRINT", Flag),
    spec("NOSEPARATOR", Flag),
    spec("OSFORMAT", Flag),
    spec("REQSAVE", Flag),
    spec("RPCSAVE", Flag),
    spec("SEPARATOR", Flag),
    spec("TELETYPE", Flag),
    spec("YPR", Flag),
];

pub(super) const DEBUG: &[Spec] = &[
    spec("EPRINT", Flag),
    spec("NOEPRINT", Flag),
    spec("JMDUMP", Flag),
    spec("NOJMDUMP", Flag),
    spec("RHSDUMP", Flag),
    spec("NORHSDUMP", Flag),
    spec("REQDUMP", Flag),
    spec("NOREQDUMP", Flag),
    spec("DUMP", Flag),
    spec("NODUMP", Flag),
    spec("VERBOSE", Flag),
    spec("NOVERBOSE", Flag),
    spec("TRACEOUT", Flag),
    spec("NOTRACEOUT", Flag),
    spec("DOF", Flag),
    spec("TOPOLOGY", Flag),
    spec("LIST", Flag),
];

pub(super) const PREFERENCES: &[Spec] = &[
    spec("CONTACT_GEOMETRY_LIBRARY", Word),
    spec("CONTACT_FACETING_TOLERANCE", Real),
    spec("FLEX_LIMIT_CHECK", Word),
    spec("FLEX_LIMIT_CHECK_ACTION", Word),
    spec("NTHREADS", Count),
    spec("SIMFAIL", Word),
    spec("SOLVERBIAS", Word),
    spec("STATUS_MESSAGE", Word),
    spec("LIST", Flag),
];

pub(super) const LSOLVER: &[Spec] = &[
    spec("CALAHAN", Flag),
    spec("UMF", Flag),
    spec("HARWELL", Flag),
    spec("LIST", Flag),
];

/// Element statements that may be given as commands (ADM-REFERENCE §7.2), as redefinitions.
pub(super) const REDEFINABLE: &[&str] = &[
    "ARRAY",
    "BEAM",
    "BUSHING",
    "FIELD",
    "FLEX_BODY",
    "FRICTION",
    "GCON",
    "GFORCE",
    "JOINT",
    "MARKER",
    "MOTION",
    "PART",
    "REQUEST",
    "SENSOR",
    "SFORCE",
    "SPLINE",
    "SPRINGDAMPER",
    "STRING",
    "VARIABLE",
    "VFORCE",
    "VTORQUE",
];

/// Commands that only ask for information (kept generic).
pub(super) const INFORMATION: &[&str] = &["HELP", "INFO", "MENU", "SHOW", "TIME"];
