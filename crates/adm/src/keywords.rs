//! Keyword tables of the dataset (`.adm`) and command (`.acf`) languages, and prefix matching.
//!
//! Contract:
//! - Every statement (or command) the language knows has a [`StatementDef`]: its canonical name,
//!   whether an id follows the slash, and a table of arguments.
//! - A table is *complete* for the statements linkage types (PART, MARKER, JOINT, …): an
//!   argument not in it is reported, and an ambiguous prefix is an error. Other tables are
//!   *partial*: they only name what the parser needs (expression and text arguments, conditional
//!   keywords that end an expression, common abbreviations); anything else is kept as written.
//! - Matching is case-insensitive; an exact spelling wins over prefixes; a prefix is accepted when
//!   every spelling it starts resolves to the same canonical keyword ([`lookup`]).

/// Whether a statement carries an id after the slash (`PART/2`) or not (`UNITS/`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum IdRule {
    /// `NAME/id` is mandatory.
    Required,
    /// No id: the arguments may start right after the slash (`ACCGRAV/JGRAV = -9.8`).
    Absent,
    /// An id is read when digits follow the slash (statements linkage does not know).
    Optional,
}

/// How the value of an argument is read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ArgKind {
    /// Conditional keyword without a value (`GROUND`, `REVOLUTE`).
    Flag,
    /// Conditional keyword that may also be written `KEY = expression` (MOTION's `X`…`B3`).
    FlagOrExpr,
    /// Numbers separated by commas (`QP = 0, -.4, 0`, `I = 0102`); anything else is an error.
    Numbers,
    /// A word, or words/numbers separated by colons (`FORCE = NEWTON`, `EXACT = X:Y:PSI`).
    Words,
    /// A function expression: ends at an unnested `\`, at a same-line comma at depth 0, or at a
    /// continuation line that starts another argument (ADM-REFERENCE §1.2).
    Expr,
    /// Free text (`COMMENT = …`, `STRING = …`, `ROUTINE = lib::fn`, file names): read like an
    /// expression, but `\` is text and parentheses need not balance.
    Text,
    /// Comma-separated free-text items (`INTERFACE = lib::a, lib::b`), continuing over commas
    /// until the next argument.
    TextList,
    /// Not known: a plain list of numbers/words/strings when it is one, otherwise read as an
    /// expression-like text.
    Any,
}

/// One spelling of an argument keyword.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ArgDef {
    /// How it may be written (upper case).
    pub spelling: &'static str,
    /// The keyword it means (equal to `spelling` except for aliases such as `ROTATIONAL`).
    pub canonical: &'static str,
    pub kind: ArgKind,
}

const fn arg(name: &'static str, kind: ArgKind) -> ArgDef {
    ArgDef {
        spelling: name,
        canonical: name,
        kind,
    }
}

const fn alias(spelling: &'static str, canonical: &'static str, kind: ArgKind) -> ArgDef {
    ArgDef {
        spelling,
        canonical,
        kind,
    }
}

/// One statement or command of the language.
#[derive(Debug)]
pub(crate) struct StatementDef {
    pub name: &'static str,
    pub id: IdRule,
    pub args: &'static [ArgDef],
    /// Whether `args` lists every argument (unknown arguments are then reported).
    pub complete: bool,
}

const fn stmt(
    name: &'static str,
    id: IdRule,
    args: &'static [ArgDef],
    complete: bool,
) -> StatementDef {
    StatementDef {
        name,
        id,
        args,
        complete,
    }
}

/// Result of matching a written keyword against a table.
#[derive(Debug, PartialEq)]
pub(crate) enum Lookup<T> {
    Found(T),
    /// The prefix starts several keywords; their canonical names, sorted.
    Ambiguous(Vec<&'static str>),
    NotFound,
}

/// Matches `word` (any case) against `items`: an exact spelling wins; otherwise every spelling
/// that starts with `word` is a candidate, and the match is unique when all candidates share one
/// canonical name.
pub(crate) fn lookup<'t, T>(
    word: &str,
    items: &'t [T],
    spelling: impl Fn(&T) -> &'static str,
    canonical: impl Fn(&T) -> &'static str,
) -> Lookup<&'t T> {
    if word.is_empty() {
        return Lookup::NotFound;
    }
    // Spellings are upper-case ASCII: compare without allocating an upper-case copy.
    if let Some(item) = items
        .iter()
        .find(|it| spelling(it).eq_ignore_ascii_case(word))
    {
        return Lookup::Found(item);
    }
    let starts = |s: &str| {
        s.as_bytes()
            .get(..word.len())
            .is_some_and(|head| head.eq_ignore_ascii_case(word.as_bytes()))
    };
    let candidates: Vec<&T> = items.iter().filter(|it| starts(spelling(it))).collect();
    let mut names: Vec<&'static str> = candidates.iter().map(|it| canonical(it)).collect();
    names.sort_unstable();
    names.dedup();
    match (candidates.first(), names.len()) {
        (Some(first), 1) => Lookup::Found(first),
        (None, _) => Lookup::NotFound,
        _ => Lookup::Ambiguous(names),
    }
}

/// Matches a word against a plain list of names (unit names, joint types, …).
pub(crate) fn lookup_name(word: &str, names: &[&'static str]) -> Lookup<&'static str> {
    match lookup(word, names, |n| *n, |n| *n) {
        Lookup::Found(n) => Lookup::Found(*n),
        Lookup::Ambiguous(v) => Lookup::Ambiguous(v),
        Lookup::NotFound => Lookup::NotFound,
    }
}

/// Finds the statement (or command) a keyword names.
pub(crate) fn lookup_statement(
    word: &str,
    table: &'static [StatementDef],
) -> Lookup<&'static StatementDef> {
    lookup(word, table, |d| d.name, |d| d.name)
}

/// Finds an argument of a statement.
pub(crate) fn lookup_arg(word: &str, def: &'static StatementDef) -> Lookup<&'static ArgDef> {
    lookup(word, def.args, |a| a.spelling, |a| a.canonical)
}

/// The argument of `def` a misspelt `word` most likely means: the canonical name at the
/// smallest Damerau–Levenshtein distance (an edit is a letter added, dropped, changed or two
/// letters swapped), when that distance is at most a third of the word's length (at least 1)
/// and no other argument is as close; `None` otherwise.
pub(crate) fn closest_arg(word: &str, def: &StatementDef) -> Option<&'static str> {
    let word = word.to_ascii_uppercase();
    let limit = (word.chars().count() / 3).max(1);
    let mut best: Option<(usize, &'static str)> = None;
    let mut tie = false;
    for a in def.args {
        let d = strsim::damerau_levenshtein(&word, a.canonical);
        match best {
            Some((b, name)) if d == b && name != a.canonical => tie = true,
            Some((b, _)) if d >= b => {}
            _ => {
                best = Some((d, a.canonical));
                tie = false;
            }
        }
    }
    best.filter(|(d, _)| *d <= limit && !tie).map(|(_, n)| n)
}

/// The entry of `def` whose canonical name is `key` (used after canonicalisation).
pub(crate) fn arg_def(def: &StatementDef, key: &str) -> Option<&'static ArgDef> {
    def.args.iter().find(|a| a.canonical == key)
}

/// Kind of an argument no table knows: expression for `FUNCTION` (and prefixes of at least three
/// letters), `F1`..`F8`, `FX`, `FY`, `FZ`, `TX`, `TY`, `TZ`; otherwise [`ArgKind::Any`].
pub(crate) fn default_kind(key: &str) -> ArgKind {
    let k = key.to_ascii_uppercase();
    let function = k.len() >= 3 && "FUNCTION".starts_with(k.as_str());
    let fi = k.len() == 2 && k.starts_with('F') && matches!(k.as_bytes().get(1), Some(b'1'..=b'8'));
    let component = matches!(k.as_str(), "FX" | "FY" | "FZ" | "TX" | "TY" | "TZ");
    if function || fi || component {
        ArgKind::Expr
    } else {
        ArgKind::Any
    }
}

use ArgKind::{Any, Expr, Flag, FlagOrExpr, Numbers, Text, Words};
use IdRule::{Absent, Required};

// ---------------------------------------------------------------------------------------------
// Values of typed arguments (ADM-REFERENCE §2.1, §2.5, §2.6).

pub(crate) const FORCE_UNITS: &[&str] = &[
    "CENTINEWTON",
    "DYNE",
    "KILOGRAM_FORCE",
    "KNEWTON",
    "KPOUND_FORCE",
    "MEGANEWTON",
    "MICRONEWTON",
    "MILLINEWTON",
    "NANONEWTON",
    "NEWTON",
    "OUNCE_FORCE",
    "POUND_FORCE",
    "POUNDAL",
];
pub(crate) const MASS_UNITS: &[&str] = &[
    "GRAM",
    "KILOGRAM",
    "KPOUND_MASS",
    "MILLIGRAM",
    "MICROGRAM",
    "NANOGRAM",
    "OUNCE_MASS",
    "POUND_MASS",
    "SLINCH",
    "SLUG",
    "TONNE",
    "US_TON",
];
pub(crate) const LENGTH_UNITS: &[&str] = &[
    "ANGSTROM",
    "CENTIMETER",
    "FOOT",
    "KILOMETER",
    "INCH",
    "METER",
    "MICROINCH",
    "MICROMETER",
    "MILE",
    "MILLIMETER",
    "MILS",
    "NANOMETER",
    "YARD",
];
pub(crate) const TIME_UNITS: &[&str] = &[
    "DAY",
    "HOUR",
    "MICROSECOND",
    "MILLISECONDS",
    "MINUTE",
    "NANOSECOND",
    "SECOND",
];
pub(crate) const UNIT_SYSTEMS: &[&str] = &["CGS", "FPS", "IPS", "MKS", "NONE"];

pub(crate) const JOINT_TYPES: &[&str] = &[
    "CONVEL",
    "CYLINDRICAL",
    "FIXED",
    "HOOKE",
    "PLANAR",
    "RACKPIN",
    "REVOLUTE",
    "SCREW",
    "SPHERICAL",
    "TRANSLATIONAL",
    "UNIVERSAL",
];
pub(crate) const JPRIM_TYPES: &[&str] = &[
    "ATPOINT",
    "INLINE",
    "INPLANE",
    "ORIENTATION",
    "PARALLEL_AXES",
    "PERPENDICULAR",
];

// ---------------------------------------------------------------------------------------------
// Complete tables (typed statements). Force and data elements: ADM-REFERENCE §2.10–2.11.

const UNITS_ARGS: &[ArgDef] = &[
    arg("FORCE", Words),
    arg("MASS", Words),
    arg("LENGTH", Words),
    arg("TIME", Words),
    arg("SYSTEM", Words),
    arg("UCF", Numbers),
];

const ACCGRAV_ARGS: &[ArgDef] = &[
    arg("IGRAV", Numbers),
    arg("JGRAV", Numbers),
    arg("KGRAV", Numbers),
];

const PART_ARGS: &[ArgDef] = &[
    arg("GROUND", Flag),
    arg("MASS", Numbers),
    arg("CM", Numbers),
    arg("IM", Numbers),
    arg("IP", Numbers),
    arg("QG", Numbers),
    arg("REULER", Numbers),
    arg("XG", Numbers),
    arg("ZG", Numbers),
    arg("VX", Numbers),
    arg("VY", Numbers),
    arg("VZ", Numbers),
    arg("WX", Numbers),
    arg("WY", Numbers),
    arg("WZ", Numbers),
    arg("VM", Numbers),
    arg("WM", Numbers),
    arg("EXACT", Words),
    arg("MATERIAL", Any),
];

/// POINT_MASS (ADM-ELEMENTS §13): three translational degrees of freedom, no inertia.
const POINT_MASS_ARGS: &[ArgDef] = &[
    arg("MASS", Numbers),
    arg("CM", Numbers),
    arg("QG", Numbers),
    arg("REULER", Numbers),
    arg("XG", Numbers),
    arg("ZG", Numbers),
    arg("VX", Numbers),
    arg("VY", Numbers),
    arg("VZ", Numbers),
    arg("EXACT", Words),
    arg("MATERIAL", Any),
];

const MARKER_ARGS: &[ArgDef] = &[
    arg("PART", Numbers),
    arg("POINT_MASS", Numbers),
    arg("FLEX_BODY", Numbers),
    arg("FE_PART", Numbers),
    arg("NODE_ID", Numbers),
    arg("NODE_LABEL", Numbers),
    arg("S", Numbers),
    arg("QP", Numbers),
    arg("REULER", Numbers),
    arg("ZP", Numbers),
    arg("XP", Numbers),
    arg("USEXP", Flag),
    arg("FLOATING", Flag),
    arg("RM", Numbers),
];

const JOINT_ARGS: &[ArgDef] = &[
    arg("CONVEL", Flag),
    arg("CYLINDRICAL", Flag),
    arg("FIXED", Flag),
    arg("HOOKE", Flag),
    arg("PLANAR", Flag),
    arg("RACKPIN", Flag),
    arg("REVOLUTE", Flag),
    arg("SCREW", Flag),
    arg("SPHERICAL", Flag),
    arg("TRANSLATIONAL", Flag),
    arg("UNIVERSAL", Flag),
    arg("I", Numbers),
    arg("J", Numbers),
    arg("IC", Numbers),
    arg("ICTRAN", Numbers),
    arg("ICROT", Numbers),
    arg("PD", Numbers),
    arg("PITCH", Numbers),
    // Joint friction of the FORTRAN solver (accepted, not used by linkage).
    arg("FRICTION", Words),
    arg("MU_DYN_ROT", Numbers),
    arg("MU_STAT_ROT", Numbers),
    arg("MAX_FRIC_ROT", Numbers),
    arg("MU_DYN_TRANS", Numbers),
    arg("MU_STAT_TRANS", Numbers),
    arg("MAX_FRIC_TRANS", Numbers),
    arg("DELTA_V", Numbers),
    arg("MAXIMUM_DEFORMATION", Numbers),
    arg("PRELOAD_RADIAL", Numbers),
    arg("PRELOAD_AXIAL", Numbers),
    arg("INNER_RADIUS", Numbers),
    arg("OUTER_RADIUS", Numbers),
    arg("WIDTH", Numbers),
    arg("HEIGHT", Numbers),
];

const JPRIM_ARGS: &[ArgDef] = &[
    arg("ATPOINT", Flag),
    arg("INLINE", Flag),
    arg("INPLANE", Flag),
    arg("ORIENTATION", Flag),
    arg("PARALLEL_AXES", Flag),
    arg("PERPENDICULAR", Flag),
    arg("I", Numbers),
    arg("J", Numbers),
];

const MOTION_ARGS: &[ArgDef] = &[
    arg("JOINT", Numbers),
    arg("I", Numbers),
    arg("J", Numbers),
    arg("TRANSLATION", Flag),
    alias("TRANSLATIONAL", "TRANSLATION", Flag),
    arg("ROTATION", Flag),
    alias("ROTATIONAL", "ROTATION", Flag),
    arg("X", FlagOrExpr),
    arg("Y", FlagOrExpr),
    arg("Z", FlagOrExpr),
    arg("B1", FlagOrExpr),
    arg("B2", FlagOrExpr),
    arg("B3", FlagOrExpr),
    arg("DISPLACEMENT", Flag),
    arg("VELOCITY", Flag),
    arg("ACCELERATION", Flag),
    arg("FUNCTION", Expr),
    arg("ROUTINE", Text),
    arg("ICDISP", Numbers),
    arg("ICVEL", Numbers),
];

const GCON_ARGS: &[ArgDef] = &[
    arg("I", Numbers),
    arg("FUNCTION", Expr),
    arg("ROUTINE", Text),
];

const COUPLER_ARGS: &[ArgDef] = &[
    arg("JOINTS", Numbers),
    arg("TYPE", Words),
    arg("SCALES", Numbers),
    arg("FUNCTION", Expr),
    arg("ROUTINE", Text),
];

const GEAR_ARGS: &[ArgDef] = &[arg("JOINTS", Numbers), arg("CV", Numbers)];

const SFORCE_ARGS: &[ArgDef] = &[
    arg("I", Numbers),
    arg("J", Numbers),
    arg("TRANSLATIONAL", Flag),
    arg("ROTATIONAL", Flag),
    arg("ACTIONONLY", Flag),
    arg("FUNCTION", Expr),
    arg("ROUTINE", Text),
];

const SPRINGDAMPER_ARGS: &[ArgDef] = &[
    arg("I", Numbers),
    arg("J", Numbers),
    arg("TRANSLATIONAL", Flag),
    arg("ROTATIONAL", Flag),
    arg("K", Numbers),
    arg("C", Numbers),
    arg("KT", Numbers),
    arg("CT", Numbers),
    arg("LENGTH", Numbers),
    arg("FORCE", Numbers),
    arg("ANGLE", Numbers),
    arg("TORQUE", Numbers),
];

const BUSHING_ARGS: &[ArgDef] = &[
    arg("I", Numbers),
    arg("J", Numbers),
    arg("K", Numbers),
    arg("C", Numbers),
    arg("KT", Numbers),
    arg("CT", Numbers),
    arg("FORCE", Numbers),
    arg("TORQUE", Numbers),
];

const FIELD_ARGS: &[ArgDef] = &[
    arg("I", Numbers),
    arg("J", Numbers),
    arg("KMATRIX", Numbers),
    arg("CMATRIX", Numbers),
    arg("CRATIO", Numbers),
    arg("LENGTH", Numbers),
    arg("FORCE", Numbers),
    arg("FUNCTION", Expr),
    arg("ROUTINE", Text),
];

const BEAM_ARGS: &[ArgDef] = &[
    arg("I", Numbers),
    arg("J", Numbers),
    arg("LENGTH", Numbers),
    arg("IXX", Numbers),
    arg("IYY", Numbers),
    arg("IZZ", Numbers),
    arg("AREA", Numbers),
    arg("ASY", Numbers),
    arg("ASZ", Numbers),
    arg("EMODULUS", Numbers),
    arg("GMODULUS", Numbers),
    arg("CRATIO", Numbers),
    arg("CMATRIX", Numbers),
    arg("FORMULATION", Words),
];

const VFORCE_ARGS: &[ArgDef] = &[
    arg("I", Numbers),
    arg("JFLOAT", Numbers),
    arg("RM", Numbers),
    arg("FX", Expr),
    arg("FY", Expr),
    arg("FZ", Expr),
    arg("FUNCTION", Expr),
    arg("ROUTINE", Text),
];

const VTORQUE_ARGS: &[ArgDef] = &[
    arg("I", Numbers),
    arg("JFLOAT", Numbers),
    arg("RM", Numbers),
    arg("TX", Expr),
    arg("TY", Expr),
    arg("TZ", Expr),
    arg("FUNCTION", Expr),
    arg("ROUTINE", Text),
];

const GFORCE_ARGS: &[ArgDef] = &[
    arg("I", Numbers),
    arg("JFLOAT", Numbers),
    arg("RM", Numbers),
    arg("FX", Expr),
    arg("FY", Expr),
    arg("FZ", Expr),
    arg("TX", Expr),
    arg("TY", Expr),
    arg("TZ", Expr),
    arg("FUNCTION", Expr),
    arg("ROUTINE", Text),
];

const VARIABLE_ARGS: &[ArgDef] = &[
    arg("FUNCTION", Expr),
    arg("IC", Numbers),
    arg("ROUTINE", Text),
];

const ARRAY_ARGS: &[ArgDef] = &[
    arg("U", Flag),
    arg("X", Flag),
    arg("Y", Flag),
    arg("IC", Flag),
    arg("SIZE", Numbers),
    arg("VARIABLES", Numbers),
    arg("NUMBERS", Numbers),
];

const SPLINE_ARGS: &[ArgDef] = &[
    arg("X", Numbers),
    arg("Y", Numbers),
    arg("Z", Numbers),
    arg("LINEAR_EXTRAPOLATE", Flag),
    arg("FILE", Text),
    arg("BLOCK", Text),
];

// ---------------------------------------------------------------------------------------------
// Partial tables (statements kept in generic form).

const DIFF_ARGS: &[ArgDef] = &[
    arg("FUNCTION", Expr),
    arg("IC", Numbers),
    arg("IMPLICIT", Flag),
    arg("STATIC_HOLD", Flag),
    arg("ROUTINE", Text),
];

/// LSE (ADM-ELEMENTS §7).
const LSE_ARGS: &[ArgDef] = &[
    arg("X", Numbers),
    arg("A", Numbers),
    arg("U", Numbers),
    arg("B", Numbers),
    arg("Y", Numbers),
    arg("C", Numbers),
    arg("D", Numbers),
    arg("IC", Numbers),
    arg("STATIC_HOLD", Flag),
];

/// TFSISO (ADM-ELEMENTS §9).
const TFSISO_ARGS: &[ArgDef] = &[
    arg("NUMERATOR", Numbers),
    arg("DENOMINATOR", Numbers),
    arg("U", Numbers),
    arg("X", Numbers),
    arg("Y", Numbers),
    arg("STATIC_HOLD", Flag),
];

/// MATRIX (ADM-ELEMENTS §11).
const MATRIX_ARGS: &[ArgDef] = &[
    arg("FULL", Words),
    arg("SPARSE", Flag),
    arg("ROWS", Numbers),
    arg("COLUMNS", Numbers),
    arg("I", Numbers),
    arg("J", Numbers),
    arg("VALUES", Numbers),
    arg("FILE", Text),
    arg("NAME", Words),
];

/// PINPUT and POUTPUT (ADM-ELEMENTS §12).
const PLANT_ARGS: &[ArgDef] = &[arg("VARIABLES", Numbers)];

/// Statements whose only special argument is an expression-valued FUNCTION (+ ROUTINE).
const FUNCTION_ARGS: &[ArgDef] = &[arg("FUNCTION", Expr), arg("ROUTINE", Text)];

/// CURVE (ADM-ELEMENTS §14).
const CURVE_ARGS: &[ArgDef] = &[
    arg("MATRIX", Numbers),
    arg("CURVE_POINTS", Flag),
    arg("ORDER", Numbers),
    arg("OPEN", Flag),
    arg("CLOSED", Flag),
    arg("MINPAR", Numbers),
    arg("MAXPAR", Numbers),
    arg("FUNCTION", Expr),
    arg("ROUTINE", Text),
];

/// PTCV (ADM-ELEMENTS §15).
const PTCV_ARGS: &[ArgDef] = &[
    arg("I", Numbers),
    arg("JFLOAT", Numbers),
    arg("CURVE", Numbers),
    arg("RM", Numbers),
    arg("DISP", Numbers),
    arg("ICM", Numbers),
    arg("VEL", Numbers),
];

/// CVCV (ADM-ELEMENTS §16).
const CVCV_ARGS: &[ArgDef] = &[
    arg("ICURVE", Numbers),
    arg("IRM", Numbers),
    arg("IFLOAT", Numbers),
    arg("JCURVE", Numbers),
    arg("JRM", Numbers),
    arg("JFLOAT", Numbers),
    arg("IDISP", Numbers),
    arg("IICM", Numbers),
    arg("JDISP", Numbers),
    arg("JICM", Numbers),
    arg("IVEL", Numbers),
    arg("JVEL", Numbers),
];

const GSE_ARGS: &[ArgDef] = &[
    arg("FUNCTION", Expr),
    arg("ROUTINE", Text),
    arg("INTERFACE", ArgKind::TextList),
];

/// SENSOR (ADM-ELEMENTS §5).
const SENSOR_ARGS: &[ArgDef] = &[
    arg("FUNCTION", Expr),
    arg("EVALUATE", Expr),
    arg("ROUTINE", Text),
    arg("EVALUATE_ROUTINE", Text),
    arg("VALUE", Numbers),
    arg("EQ", Flag),
    arg("GE", Flag),
    arg("LE", Flag),
    arg("ERROR", Numbers),
    arg("HALT", Flag),
    arg("RETURN", Flag),
    arg("PRINT", Flag),
    arg("RESTART", Flag),
    arg("CODGEN", Flag),
    arg("YYDUMP", Flag),
    arg("DT", Numbers),
    arg("STEPSIZE", Numbers),
    arg("BISECTION", Flag),
    arg("ANGULAR", Flag),
];

/// FRICTION on a joint (ADM-ELEMENTS §4); `INACTIVE` is the documented spelling of
/// `INACTIVE_DURING`, which SolidWorks exports write.
const FRICTION_ARGS: &[ArgDef] = &[
    arg("JOINT", Numbers),
    arg("MU_STATIC", Numbers),
    arg("MU_DYNAMIC", Numbers),
    arg("STICTION_TRANSITION_VELOCITY", Numbers),
    arg("TRANSITION_VELOCITY_COEFFICIENT", Numbers),
    arg("MAX_STICTION_DEFORMATION", Numbers),
    arg("FRICTION_FORCE_PRELOAD", Numbers),
    arg("FRICTION_TORQUE_PRELOAD", Numbers),
    arg("PIN_RADIUS", Numbers),
    arg("BALL_RADIUS", Numbers),
    arg("FRICTION_ARM", Numbers),
    arg("BENDING_REACTION_ARM", Numbers),
    arg("REACTION_ARM", Numbers),
    arg("INITIAL_OVERLAP", Numbers),
    arg("OVERLAP_DELTA", Words),
    arg("EFFECT", Words),
    arg("INACTIVE_DURING", Words),
    alias("INACTIVE", "INACTIVE_DURING", Words),
    arg("INPUTS", Words),
];

/// REQUEST (ADM-REFERENCE §2.12): complete in datasets (typed), partial as a command.
const REQUEST_ARGS: &[ArgDef] = &[
    arg("DISPLACEMENT", Flag),
    alias("D", "DISPLACEMENT", Flag),
    arg("VELOCITY", Flag),
    alias("V", "VELOCITY", Flag),
    arg("ACCELERATION", Flag),
    alias("A", "ACCELERATION", Flag),
    arg("FORCE", Flag),
    alias("F", "FORCE", Flag),
    arg("I", Numbers),
    arg("J", Numbers),
    arg("RM", Numbers),
    arg("F1", Expr),
    arg("F2", Expr),
    arg("F3", Expr),
    arg("F4", Expr),
    arg("F5", Expr),
    arg("F6", Expr),
    arg("F7", Expr),
    arg("F8", Expr),
    arg("FUNCTION", Expr),
    arg("ROUTINE", Text),
    arg("COMMENT", Text),
    alias("C", "COMMENT", Text),
    arg("TITLE", Text),
    arg("CNAMES", Any),
    arg("CLABELS", Any),
    arg("CUNITS", Any),
    arg("RESULTS_NAME", Any),
];

const STRING_ARGS: &[ArgDef] = &[arg("STRING", Text)];
const FILE_DATA_ARGS: &[ArgDef] = &[arg("FILE", Text)];

const RESULTS_ARGS: &[ArgDef] = &[
    arg("XRF", Flag),
    arg("FORMATTED", Flag),
    arg("COMMENT", Text),
];

const OUTPUT_ARGS: &[ArgDef] = &[
    arg("REQSAVE", Flag),
    arg("GRSAVE", Flag),
    arg("NOSEPARATOR", Flag),
    arg("SEPARATOR", Flag),
    arg("YPR", Flag),
];

const EQUILIBRIUM_ARGS: &[ArgDef] = &[
    arg("ALIMIT", Any),
    arg("ERROR", Any),
    arg("IMBALANCE", Any),
    arg("MAXIT", Any),
    arg("PATTERN", Any),
    arg("STABILITY", Any),
    arg("TLIMIT", Any),
    arg("STATIC", Flag),
    arg("DYNAMIC", Flag),
    arg("GLOBAL_DAMPING", Any),
    arg("SETTLING_TIME", Any),
    arg("ACCELERATION_ERROR", Any),
    arg("KINETIC_ENERGY_ERROR", Any),
    arg("METHOD", Any),
    arg("ATOL", Any),
    arg("RTOL", Any),
    arg("MAXITL", Any),
    arg("ETAMAX", Any),
    arg("ETA", Any),
    arg("LIST", Flag),
    arg("DEFAULT", Flag),
];

const IC_ARGS: &[ArgDef] = &[
    arg("ERROR", Any),
    arg("MAXIT", Any),
    arg("PATTERN", Any),
    arg("TLIMIT", Any),
    arg("ALIMIT", Any),
    arg("VERROR", Any),
    arg("AERROR", Any),
    arg("AMAXIT", Any),
    arg("APATTERN", Any),
    arg("LIST", Flag),
    arg("DEFAULT", Flag),
];

const INTEGRATOR_ARGS: &[ArgDef] = &[
    arg("GSTIFF", Flag),
    arg("WSTIFF", Flag),
    arg("HHT", Flag),
    arg("NEWMARK", Flag),
    arg("HASTIFF", Flag),
    arg("I3", Flag),
    arg("SI2", Flag),
    arg("SI1", Flag),
    arg("ERROR", Any),
    arg("HMAX", Any),
    arg("HMIN", Any),
    arg("HINIT", Any),
    arg("KMAX", Any),
    arg("MAXIT", Any),
    arg("ALPHA", Any),
    arg("BETA", Any),
    arg("GAMMA", Any),
    arg("CORRECTOR", Any),
    arg("INTERPOLATE", Any),
    arg("PATTERN", Any),
    arg("LIST", Flag),
    arg("DEFAULT", Flag),
];

const NO_ARGS: &[ArgDef] = &[];

/// FE_PART (ADM-ELEMENTS §18): a nonlinear finite-element beam.
const FE_PART_ARGS: &[ArgDef] = &[
    arg("TYPE", Text),
    arg("NODE_LABELS", Numbers),
    arg("COORDINATES", Numbers),
    arg("SECTION", Numbers),
    arg("MATERIAL", Numbers),
    arg("CRATIOK", Numbers),
    arg("CRATIOM", Numbers),
    arg("QG", Numbers),
    arg("REULER", Numbers),
];

/// FE_NODE (ADM-ELEMENTS §18): Adams View's record of one node of an FE_PART.
const FE_NODE_ARGS: &[ArgDef] = &[
    arg("FE_PART", Numbers),
    arg("LABEL", Numbers),
    arg("S", Numbers),
    arg("ANGLE", Numbers),
    arg("SECTION_NODE", Numbers),
    arg("QG", Numbers),
    arg("REULER", Numbers),
];

/// SECTION (ADM-ELEMENTS §18): cross-section constants.
const SECTION_ARGS: &[ArgDef] = &[
    arg("TYPE", Text),
    arg("RECT_BASE", Numbers),
    arg("RECT_HEIGHT", Numbers),
    arg("RADIUS", Numbers),
    arg("INNER_RADIUS", Numbers),
    arg("OUTER_RADIUS", Numbers),
    arg("THICKNESS", Numbers),
    arg("AREA", Numbers),
    arg("IYY", Numbers),
    arg("IZZ", Numbers),
    arg("IYZ", Numbers),
    arg("JXX", Numbers),
];

/// MATERIAL (ADM-ELEMENTS §18).
const MATERIAL_ARGS: &[ArgDef] = &[
    arg("NAME", Text),
    arg("DENSITY", Numbers),
    arg("YOUNGS_MODULUS", Numbers),
    arg("POISSONS_RATIO", Numbers),
];

/// FE_LOAD (ADM-ELEMENTS §18): a distributed load on an FE_PART.
const FE_LOAD_ARGS: &[ArgDef] = &[
    arg("FE_PART", Numbers),
    arg("RM", Numbers),
    arg("FX", Expr),
    arg("FY", Expr),
    arg("FZ", Expr),
    arg("TX", Expr),
    arg("TY", Expr),
    arg("TZ", Expr),
    arg("FUNCTION", Expr),
    arg("ROUTINE", Text),
];

/// FLEX_BODY (ADM-ELEMENTS §19): a linear flexible body with modal coordinates.
const FLEX_BODY_ARGS: &[ArgDef] = &[
    arg("MATRICES", Numbers),
    arg("MNF_FILE", Text),
    arg("DB_FILE", Text),
    arg("MD_DB_FILE", Text),
    arg("BDF_FILE", Text),
    arg("INVARIANTS", Words),
    arg("QG", Numbers),
    arg("REULER", Numbers),
    arg("VX", Numbers),
    arg("VY", Numbers),
    arg("VZ", Numbers),
    arg("WX", Numbers),
    arg("WY", Numbers),
    arg("WZ", Numbers),
    arg("DMODE", Numbers),
    arg("VMODE", Numbers),
    arg("EXACT", Words),
    arg("CHAR_LEN", Numbers),
    arg("CRATIO", Expr),
];

/// Statements of a dataset (ADM-REFERENCE §1.5, plus FE_NODE and SECTION seen in real files).
pub(crate) static DATASET_STATEMENTS: &[StatementDef] = &[
    stmt("ACCGRAV", Absent, ACCGRAV_ARGS, true),
    stmt("ARRAY", Required, ARRAY_ARGS, true),
    stmt("BEAM", Required, BEAM_ARGS, true),
    stmt("BUSHING", Required, BUSHING_ARGS, true),
    stmt("CONTACT", Required, NO_ARGS, false),
    stmt("COUPLER", Required, COUPLER_ARGS, true),
    stmt("CURVE", Required, CURVE_ARGS, false),
    stmt("CVCV", Required, CVCV_ARGS, false),
    stmt("DEBUG", Absent, NO_ARGS, false),
    stmt("DIFF", Required, DIFF_ARGS, true),
    stmt("END", Absent, NO_ARGS, false),
    stmt("ENVIRONMENT", Absent, NO_ARGS, false),
    stmt("EQUILIBRIUM", Absent, EQUILIBRIUM_ARGS, false),
    stmt("FE_LOAD", Required, FE_LOAD_ARGS, true),
    stmt("FE_NODE", Required, FE_NODE_ARGS, true),
    stmt("FE_PART", Required, FE_PART_ARGS, true),
    stmt("FEMDATA", Required, NO_ARGS, false),
    stmt("FIELD", Required, FIELD_ARGS, true),
    stmt("FLEX_BODY", Required, FLEX_BODY_ARGS, true),
    stmt("FRICTION", Required, FRICTION_ARGS, true),
    stmt("GCON", Required, GCON_ARGS, true),
    stmt("GEAR", Required, GEAR_ARGS, true),
    stmt("GFORCE", Required, GFORCE_ARGS, true),
    stmt("GRAPHICS", Required, NO_ARGS, false),
    stmt("GSE", Required, GSE_ARGS, false),
    stmt("IC", Absent, IC_ARGS, false),
    stmt("INTEGRATOR", Absent, INTEGRATOR_ARGS, false),
    stmt("JOINT", Required, JOINT_ARGS, true),
    stmt("JPRIM", Required, JPRIM_ARGS, true),
    stmt("KINEMATICS", Absent, IC_ARGS, false),
    stmt("LIST", Absent, NO_ARGS, false),
    stmt("LSE", Required, LSE_ARGS, true),
    stmt("LSOLVER", Absent, NO_ARGS, false),
    stmt("MARKER", Required, MARKER_ARGS, true),
    stmt("MATERIAL", Required, MATERIAL_ARGS, true),
    stmt("MATRIX", Required, MATRIX_ARGS, true),
    stmt("MFORCE", Required, FUNCTION_ARGS, false),
    stmt("MOTION", Required, MOTION_ARGS, true),
    stmt("MREQUEST", Required, FUNCTION_ARGS, false),
    stmt("NFORCE", Required, NO_ARGS, false),
    stmt("NOLIST", Absent, NO_ARGS, false),
    stmt("OUTPUT", Absent, OUTPUT_ARGS, false),
    stmt("PART", Required, PART_ARGS, true),
    stmt("PINPUT", Required, PLANT_ARGS, true),
    stmt("POINT_MASS", Required, POINT_MASS_ARGS, true),
    stmt("POUTPUT", Required, PLANT_ARGS, true),
    stmt("PREFERENCES", Absent, NO_ARGS, false),
    stmt("PTCV", Required, PTCV_ARGS, false),
    stmt("REQUEST", Required, REQUEST_ARGS, true),
    stmt("RESULTS", Absent, RESULTS_ARGS, false),
    stmt("SECTION", Required, SECTION_ARGS, true),
    stmt("SENSOR", Required, SENSOR_ARGS, true),
    stmt("SFORCE", Required, SFORCE_ARGS, true),
    stmt("SPLINE", Required, SPLINE_ARGS, true),
    stmt("SPRINGDAMPER", Required, SPRINGDAMPER_ARGS, true),
    stmt("STRING", Required, STRING_ARGS, false),
    stmt("SURFACE", Required, FILE_DATA_ARGS, false),
    stmt("TFSISO", Required, TFSISO_ARGS, true),
    stmt("TITLE", Absent, NO_ARGS, false),
    stmt("UCON", Required, FUNCTION_ARGS, false),
    stmt("UNITS", Absent, UNITS_ARGS, true),
    stmt("VARIABLE", Required, VARIABLE_ARGS, true),
    stmt("VFORCE", Required, VFORCE_ARGS, true),
    stmt("VTORQUE", Required, VTORQUE_ARGS, true),
];

// ---------------------------------------------------------------------------------------------
// Command files (ADM-REFERENCE §7).

const SIMULATE_ARGS: &[ArgDef] = &[
    arg("DYNAMICS", Flag),
    arg("KINEMATICS", Flag),
    arg("STATICS", Flag),
    arg("TRANSIENT", Flag),
    arg("INITIAL_CONDITIONS", Flag),
    arg("DISPLACEMENT", Flag),
    arg("VELOCITY", Flag),
    arg("ACCELERATION", Flag),
    arg("END", Any),
    arg("DURATION", Any),
    arg("STEPS", Any),
    arg("DTOUT", Any),
];

const FILE_ARGS: &[ArgDef] = &[
    arg("MODEL", Text),
    arg("COMMAND", Text),
    arg("OUTPUT_PREFIX", Text),
];

/// SAVE and RELOAD: file names keep their case.
const STATE_FILE_ARGS: &[ArgDef] = &[
    arg("SYSTEM", Flag),
    arg("STATES", Flag),
    arg("FILE", Text),
    arg("OUTPUT_PREFIX", Text),
];

/// ENVIRONMENT: names and values keep their case.
const ENVIRONMENT_ARGS: &[ArgDef] = &[
    arg("NAME", Text),
    arg("VALUE", Text),
    arg("UNSET", Flag),
    arg("LIST", Flag),
];

const ACTIVATION_ARGS: &[ArgDef] = &[arg("ID", Any), arg("RANGE", Any)];

const LINEAR_ARGS: &[ArgDef] = &[
    arg("EIGENSOL", Flag),
    arg("STATEMAT", Flag),
    arg("MKB", Flag),
    arg("NODAMPIN", Flag),
    arg("NOVECTOR", Flag),
    arg("FILE", Text),
];

/// Commands of a command file. Element commands share the statement tables, as partial tables
/// (commands add arguments such as `LIST` or `ACTIVATE`).
pub(crate) static COMMANDS: &[StatementDef] = &[
    stmt("ACCGRAV", Absent, ACCGRAV_ARGS, false),
    stmt("ACTIVATE", Absent, ACTIVATION_ARGS, false),
    stmt("ARRAY", Required, FILE_DATA_ARGS, false),
    stmt("BEAM", Required, NO_ARGS, false),
    stmt("BUSHING", Required, NO_ARGS, false),
    stmt("CONTROL", Absent, FUNCTION_ARGS, false),
    stmt("DEACTIVATE", Absent, ACTIVATION_ARGS, false),
    stmt("DEBUG", Absent, NO_ARGS, false),
    stmt("ENVIRONMENT", Absent, ENVIRONMENT_ARGS, false),
    stmt("EQUILIBRIUM", Absent, EQUILIBRIUM_ARGS, false),
    stmt("FIELD", Required, NO_ARGS, false),
    stmt("FILE", Absent, FILE_ARGS, false),
    stmt("FLEX_BODY", Required, NO_ARGS, false),
    stmt("FRICTION", Required, NO_ARGS, false),
    stmt("GCON", Required, GCON_ARGS, false),
    stmt("GFORCE", Required, GFORCE_ARGS, false),
    stmt("HELP", Absent, NO_ARGS, false),
    stmt("IC", Absent, IC_ARGS, false),
    stmt("INFO", Absent, NO_ARGS, false),
    stmt("INTEGRATOR", Absent, INTEGRATOR_ARGS, false),
    stmt("JOINT", Required, JOINT_ARGS, false),
    stmt("KINEMATICS", Absent, IC_ARGS, false),
    stmt("LINEAR", Absent, LINEAR_ARGS, false),
    stmt("LSOLVER", Absent, NO_ARGS, false),
    stmt("MARKER", Required, MARKER_ARGS, false),
    stmt("MENU", Absent, NO_ARGS, false),
    stmt("MOTION", Required, MOTION_ARGS, false),
    stmt("OUTPUT", Absent, OUTPUT_ARGS, false),
    stmt("PART", Required, PART_ARGS, false),
    stmt("PREFERENCES", Absent, NO_ARGS, false),
    stmt("RELOAD", Absent, STATE_FILE_ARGS, false),
    stmt("REQUEST", Required, REQUEST_ARGS, false),
    stmt("SAVE", Absent, STATE_FILE_ARGS, false),
    stmt("SENSOR", Required, SENSOR_ARGS, true),
    stmt("SFORCE", Required, SFORCE_ARGS, false),
    stmt("SHOW", Absent, NO_ARGS, false),
    stmt("SIMULATE", Absent, SIMULATE_ARGS, false),
    stmt("SPLINE", Required, FILE_DATA_ARGS, false),
    stmt("SPRINGDAMPER", Required, SPRINGDAMPER_ARGS, false),
    stmt("STOP", Absent, NO_ARGS, false),
    stmt("STRING", Required, STRING_ARGS, false),
    stmt("TIME", Absent, NO_ARGS, false),
    stmt("VARIABLE", Required, VARIABLE_ARGS, false),
    stmt("VFORCE", Required, VFORCE_ARGS, false),
    stmt("VTORQUE", Required, VTORQUE_ARGS, false),
];

#[cfg(test)]
mod tests {
    use super::*;

    fn found_name(word: &str, table: &'static [StatementDef]) -> Option<&'static str> {
        match lookup_statement(word, table) {
            Lookup::Found(d) => Some(d.name),
            _ => None,
        }
    }

    #[test]
    fn statement_prefixes_resolve_when_unambiguous() {
        assert_eq!(found_name("part", DATASET_STATEMENTS), Some("PART"));
        assert_eq!(
            found_name("SPRING", DATASET_STATEMENTS),
            Some("SPRINGDAMPER")
        );
        assert_eq!(found_name("jp", DATASET_STATEMENTS), Some("JPRIM"));
        assert_eq!(found_name("sim", COMMANDS), Some("SIMULATE"));
        assert_eq!(found_name("equil", COMMANDS), Some("EQUILIBRIUM"));
        assert_eq!(found_name("accg", COMMANDS), Some("ACCGRAV"));
        assert_eq!(found_name("int", COMMANDS), Some("INTEGRATOR"));
        assert_eq!(found_name("LEONARDO", DATASET_STATEMENTS), None);
    }

    #[test]
    fn exact_match_wins_over_longer_keywords() {
        // IC is also the start of nothing else, but I alone starts IC and INTEGRATOR.
        assert_eq!(found_name("IC", DATASET_STATEMENTS), Some("IC"));
        assert_eq!(found_name("END", DATASET_STATEMENTS), Some("END"));
        let joint = found_def("JOINT");
        assert!(matches!(lookup_arg("I", joint), Lookup::Found(a) if a.canonical == "I"));
        assert!(matches!(lookup_arg("ic", joint), Lookup::Found(a) if a.canonical == "IC"));
    }

    fn found_def(name: &str) -> &'static StatementDef {
        match lookup_statement(name, DATASET_STATEMENTS) {
            Lookup::Found(d) => d,
            other => panic!("{name}: {other:?}"),
        }
    }

    #[test]
    fn ambiguous_prefix_names_candidates() {
        match lookup_statement("S", DATASET_STATEMENTS) {
            Lookup::Ambiguous(names) => {
                assert!(names.contains(&"SFORCE") && names.contains(&"SPLINE"));
            }
            other => panic!("{other:?}"),
        }
        match lookup_arg("V", found_def("PART")) {
            Lookup::Ambiguous(names) => assert_eq!(names, vec!["VM", "VX", "VY", "VZ"]),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn aliases_share_their_canonical_keyword() {
        let motion = found_def("MOTION");
        for w in ["TRANS", "TRANSLATION", "translational", "T"] {
            assert!(
                matches!(lookup_arg(w, motion), Lookup::Found(a) if a.canonical == "TRANSLATION"),
                "{w}"
            );
        }
        assert!(
            matches!(lookup_arg("ROTATIONAL", motion), Lookup::Found(a) if a.canonical == "ROTATION")
        );
        assert!(matches!(lookup_arg("FUN", motion), Lookup::Found(a) if a.canonical == "FUNCTION"));
        // R starts ROTATION and ROUTINE.
        assert!(matches!(lookup_arg("R", motion), Lookup::Ambiguous(_)));
    }

    #[test]
    fn unit_names_match_by_prefix() {
        assert_eq!(lookup_name("newton", FORCE_UNITS), Lookup::Found("NEWTON"));
        assert_eq!(
            lookup_name("POUND_F", FORCE_UNITS),
            Lookup::Found("POUND_FORCE")
        );
        assert!(matches!(
            lookup_name("POUND", FORCE_UNITS),
            Lookup::Ambiguous(_)
        ));
        assert_eq!(
            lookup_name("MILLISECOND", TIME_UNITS),
            Lookup::Found("MILLISECONDS")
        );
        assert_eq!(lookup_name("parsec", LENGTH_UNITS), Lookup::NotFound);
    }

    #[test]
    fn expression_keys_without_table() {
        assert_eq!(default_kind("FUN"), ArgKind::Expr);
        assert_eq!(default_kind("function"), ArgKind::Expr);
        assert_eq!(default_kind("F8"), ArgKind::Expr);
        assert_eq!(default_kind("F9"), ArgKind::Any);
        assert_eq!(default_kind("TZ"), ArgKind::Expr);
        assert_eq!(default_kind("FU"), ArgKind::Any);
        assert_eq!(default_kind("IC"), ArgKind::Any);
    }
}
