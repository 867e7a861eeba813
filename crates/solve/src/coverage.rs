//! What each analysis does with each statement of a dataset: the one judge of "what would
//! this analysis refuse, or run without, and why".
//!
//! Every statement kind the dataset language knows is in one of four classes
//! ([`statement_use`]):
//! - [`Use::Modelled`]: computed by every analysis that needs it (parts, markers,
//!   constraints, the force elements linkage writes laws for, data elements, the control
//!   states of DIFF, LSE and TFSISO with their MATRIX data, UNITS, ACCGRAV);
//! - [`Use::Settings`]: read by the analyses it is for (EQUILIBRIUM by statics, IC by the
//!   assembly, INTEGRATOR by dynamics, PINPUT/POUTPUT by LINEAR/STATEMAT in command files and
//!   by PINVAL/POUVAL), as in Adams;
//! - [`Use::Bookkeeping`]: no effect on any result (TITLE, END, GRAPHICS, RESULTS, OUTPUT,
//!   solver diagnostics options, STRING texts for user subroutines);
//! - [`Use::Named`]: linkage does not model it; every such statement is a [`Finding`].
//!
//! [`findings`] lists, for a dataset, every statement some analysis refuses or runs without:
//! statements linkage does not model, `USER(…)` subroutine calls (refused unless the user gave
//! subroutine libraries and linkage calls the statement's family: then [`findings_with`]
//! lists the subroutine each calls, refused by no analysis), external files that are missing or that linkage does not read,
//! statements that no analysis reads. Each finding names the element, its place and the
//! analyses that refuse a model holding it ([`Finding::refused_by`]); `verify` lists them all,
//! and every other analysis refuses with all of its own at once ([`refusals`]). Unknown
//! statements (not Adams keywords) are findings too.

mod contact;
mod curve_use;
mod flex_body;

use linkage_adm::{Dataset, Diagnostic, Span, Statement, Value};
use linkage_model::functions::UserRoutines;
use std::path::Path;
use std::sync::Arc;

/// An analysis that may refuse a model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Analysis {
    /// Initial conditions (assembly, velocities, accelerations and forces at the start).
    Ic,
    /// Static equilibrium at one time (Newton, or damped settling).
    Static,
    /// A quasi-static series over time (`static --end`, `SIMULATE/STATIC, END =`).
    QuasiStatic,
    /// Linearization about an operating point.
    Linear,
    /// Dynamic (or kinematic) simulation over time.
    Simulate,
}

impl Analysis {
    /// Every analysis, in the order the reports list them.
    pub const ALL: [Analysis; 5] = [
        Analysis::Ic,
        Analysis::Static,
        Analysis::QuasiStatic,
        Analysis::Linear,
        Analysis::Simulate,
    ];

    /// How the command line names it (`ic`, `static`, `static --end`, `linear`, `simulate`).
    pub fn name(self) -> &'static str {
        match self {
            Analysis::Ic => "ic",
            Analysis::Static => "static",
            Analysis::QuasiStatic => "static --end",
            Analysis::Linear => "linear",
            Analysis::Simulate => "simulate",
        }
    }
}

/// Analyses that compute forces: every one.
const FORCE_ANALYSES: &[Analysis] = &Analysis::ALL;

/// Why a statement is a finding.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Reason {
    /// linkage has no model of this element.
    NotModelled,
    /// A `USER(…)` subroutine call, which linkage cannot run (no library given, or a family
    /// it does not call).
    UserSubroutine,
    /// A `USER(…)` subroutine call that every analysis makes (from a `--user-lib` library).
    UserCalled,
    /// A file the statement names does not exist.
    ExternalFileMissing,
    /// No analysis reads it (data only elements that are not modelled use, unknown
    /// statements, settings linkage does not read).
    NotUsed,
}

impl Reason {
    /// `not modelled`, `USER subroutine`, `user subroutine called`, `external file missing`,
    /// `not used`.
    pub fn name(self) -> &'static str {
        match self {
            Reason::NotModelled => "not modelled",
            Reason::UserSubroutine => "USER subroutine",
            Reason::UserCalled => "user subroutine called",
            Reason::ExternalFileMissing => "external file missing",
            Reason::NotUsed => "not used",
        }
    }
}

/// How linkage uses a statement kind (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Use {
    Modelled,
    Settings,
    Bookkeeping,
    Named,
}

/// Statement kinds every analysis computes with.
pub const MODELLED: [&str; 38] = [
    "UNITS",
    "ACCGRAV",
    "PART",
    "POINT_MASS",
    "MARKER",
    "JOINT",
    "JPRIM",
    "MOTION",
    "COUPLER",
    "GEAR",
    "GCON",
    "PTCV",
    "CVCV",
    "CURVE",
    "SFORCE",
    "SPRINGDAMPER",
    "BUSHING",
    "FIELD",
    "BEAM",
    "VFORCE",
    "VTORQUE",
    "GFORCE",
    "CONTACT",
    "FRICTION",
    "VARIABLE",
    "ARRAY",
    "SPLINE",
    "FE_PART",
    "FE_NODE",
    "SECTION",
    "MATERIAL",
    "FE_LOAD",
    "SENSOR",
    "FLEX_BODY",
    "DIFF",
    "LSE",
    "TFSISO",
    "MATRIX",
];

/// Statement kinds that hold settings or outputs of some analyses, read by those.
pub const SETTINGS: [&str; 6] = [
    "EQUILIBRIUM",
    "IC",
    "INTEGRATOR",
    "PINPUT",
    "POUTPUT",
    "REQUEST",
];

/// Statement kinds with no effect on any result.
pub const BOOKKEEPING: [&str; 12] = [
    "TITLE",
    "END",
    "GRAPHICS",
    "RESULTS",
    "OUTPUT",
    "LIST",
    "NOLIST",
    "DEBUG",
    "LSOLVER",
    "PREFERENCES",
    "ENVIRONMENT",
    "STRING",
];

/// How linkage uses statements of kind `keyword` (canonical upper case); every other kind,
/// known or not, is [`Use::Named`].
pub fn statement_use(keyword: &str) -> Use {
    if MODELLED.contains(&keyword) {
        Use::Modelled
    } else if SETTINGS.contains(&keyword) {
        Use::Settings
    } else if BOOKKEEPING.contains(&keyword) {
        Use::Bookkeeping
    } else {
        Use::Named
    }
}

/// Why linkage does not model a statement kind, and which analyses refuse a model holding it
/// (`None`: linkage does not know the kind at all).
fn not_modelled(keyword: &str) -> Option<(Reason, &'static str, &'static [Analysis])> {
    let refused = |why| Some((Reason::NotModelled, why, FORCE_ANALYSES));
    let unused = |why| Some((Reason::NotUsed, why, &[][..]));
    match keyword {
        "NFORCE" => refused("multi-point force elements are not modelled"),
        "MFORCE" => refused("modal forces are not modelled"),
        "GSE" => refused(
            "a GSE's equations are USER subroutines (GSE_DERIV, GSE_OUTPUT, GSE_UPDATE), which \
             linkage cannot run; DIFF, LSE and TFSISO are the state equations it models",
        ),
        "UCON" => refused("user constraints are not modelled"),
        "SURFACE" => unused("surface data is not read (CONTACT geometries are GRAPHICS)"),
        "FEMDATA" => unused("finite-element output requests are not written"),
        "MREQUEST" => unused("multiple requests are not written (REQUEST is)"),
        "KINEMATICS" => unused(
            "KINEMATICS settings are not read: a kinematic run (no degrees of freedom) uses the IC \
             settings",
        ),
        _ => None,
    }
}

/// One statement that some analysis refuses or runs without.
#[derive(Clone, Debug, PartialEq)]
pub struct Finding {
    /// `SENSOR/3` (or `SENSOR` for a statement without an id).
    pub element: String,
    /// The `adams_view_name`, else `SENSOR_3`.
    pub name: String,
    pub keyword: String,
    pub id: Option<u64>,
    /// Index of the statement in [`Dataset::statements`].
    pub statement: usize,
    pub file: Arc<str>,
    /// Where it is: the statement's keyword, or the argument at fault (a USER call, a file).
    pub span: Span,
    pub reason: Reason,
    /// What linkage does not do, in a sentence.
    pub detail: String,
    /// The analyses that refuse a model holding it (empty: every analysis runs without it).
    pub refused_by: Vec<Analysis>,
}

impl Finding {
    /// Whether analysis `a` refuses a model holding this statement.
    pub fn refuses(&self, a: Analysis) -> bool {
        self.refused_by.contains(&a)
    }

    /// `SENSOR_3 (SENSOR/3)`: the name and the element.
    pub fn title(&self) -> String {
        format!("{} ({})", self.name, self.element)
    }

    /// The input error of an analysis that refuses it, at its place.
    pub fn error(&self) -> Diagnostic {
        Diagnostic::error(
            self.file.clone(),
            Some(self.span),
            format!("{}: {}: {}", self.title(), self.reason.name(), self.detail),
        )
    }
}

/// Whether `text` calls a `USER(…)` subroutine (anywhere in it).
fn calls_user(text: &str) -> bool {
    let upper = text.to_ascii_uppercase();
    let bytes = upper.as_bytes();
    let mut from = 0;
    while let Some(k) = upper[from..].find("USER") {
        let at = from + k;
        let before = at.checked_sub(1).map(|b| bytes[b]);
        let word_start = before.is_none_or(|c| !(c.is_ascii_alphanumeric() || c == b'_'));
        let after = upper[at + 4..].trim_start();
        if word_start && after.starts_with('(') {
            return true;
        }
        from = at + 4;
    }
    false
}

/// The statement's `ROUTINE = …` text, trimmed.
fn routine_text(st: &Statement) -> Option<String> {
    match st.arg("ROUTINE")?.values.first()? {
        Value::Expr(e) => Some(e.text.trim().to_string()),
        Value::Str { text, .. } | Value::Word { text, .. } => Some(text.trim().to_string()),
        Value::Number { .. } => None,
    }
}

/// The first `USER(…)` call among the statement's arguments: the argument's key and place.
fn user_call(st: &Statement) -> Option<(String, Span)> {
    st.args.iter().find_map(|a| {
        a.values.iter().find_map(|v| match v {
            Value::Expr(e) if calls_user(&e.text) => Some((a.key.clone(), e.span_at(0))),
            _ => None,
        })
    })
}

/// Every file a statement names (`FILE =`, `…_FILE =`): its text and place.
fn named_files(st: &Statement) -> Vec<(String, Span)> {
    st.args
        .iter()
        .filter(|a| a.key == "FILE" || a.key.ends_with("_FILE"))
        .filter_map(|a| {
            a.values.first().and_then(|v| match v {
                Value::Expr(e) => Some((e.text.trim().to_string(), e.span_at(0))),
                Value::Str { text, span } | Value::Word { text, span } => {
                    Some((text.clone(), *span))
                }
                Value::Number { .. } => None,
            })
        })
        .collect()
}

/// Whether `name` (relative to the dataset's folder) exists.
fn file_exists(dataset_file: &str, name: &str) -> bool {
    let dir = Path::new(dataset_file).parent().unwrap_or(Path::new(""));
    dir.join(name).exists()
}

/// Every statement of `ds` that some analysis refuses or runs without, in dataset order (see
/// the module documentation). Cost: one pass over the statements and their arguments.
pub fn findings(ds: &Dataset) -> Vec<Finding> {
    findings_with(ds, &UserRoutines::default())
}

/// [`findings`] when the user gave subroutine libraries (`user`): a statement whose USER
/// subroutine linkage calls is listed with the subroutine it calls, refused by no analysis
/// (a library or symbol that cannot be found is an input error when the model is built).
pub fn findings_with(ds: &Dataset, linker: &UserRoutines) -> Vec<Finding> {
    let mut out = Vec::new();
    let contacts = contact::ContactGeometries::new(ds);
    let curves = curve_use::CurveUse::new(ds);
    let flex_bodies = if ds.statements.iter().any(|s| s.keyword == "FLEX_BODY") {
        linkage_adm::flex_body::type_flex_bodies(ds).0.bodies
    } else {
        Vec::new()
    };
    for (index, st) in ds.statements.iter().enumerate() {
        let use_ = statement_use(&st.keyword);
        if use_ == Use::Bookkeeping {
            continue;
        }
        // The names are formatted only for a statement that is a finding (most are not).
        let element = || match st.id {
            Some(id) => format!("{}/{id}", st.keyword),
            None => st.keyword.clone(),
        };
        let name = || {
            st.view_name.clone().unwrap_or_else(|| match st.id {
                Some(id) => format!("{}_{id}", st.keyword),
                None => st.keyword.clone(),
            })
        };
        let finding =
            |span: Span, reason: Reason, detail: String, refused_by: &[Analysis]| Finding {
                element: element(),
                name: name(),
                keyword: st.keyword.clone(),
                id: st.id,
                statement: index,
                file: ds.file.clone(),
                span,
                reason,
                detail,
                refused_by: refused_by.to_vec(),
            };
        let user = user_call(st);
        let missing: Vec<(String, Span)> = named_files(st)
            .into_iter()
            .filter(|(f, _)| !file_exists(&ds.file, f))
            .collect();
        if use_ == Use::Named {
            let (mut reason, why, refused) = match not_modelled(&st.keyword) {
                Some(n) => n,
                None if !st.known => (
                    Reason::NotUsed,
                    "not a statement of the Adams dataset language; ignored",
                    &[][..],
                ),
                None => (
                    Reason::NotModelled,
                    "linkage does not model this statement",
                    FORCE_ANALYSES,
                ),
            };
            let mut detail = why.to_string();
            if let Some((key, _)) = &user {
                detail.push_str(&format!("; its {key} calls a USER subroutine"));
                if st.keyword == "GSE" {
                    reason = Reason::UserSubroutine;
                }
            }
            for (f, _) in &missing {
                detail.push_str(&format!("; its file '{f}' does not exist"));
            }
            out.push(finding(st.span, reason, detail, refused));
            continue;
        }
        // Modelled or settings statements: what linkage cannot run or read in them.
        if let Some((reason, detail, refused)) = curves.problem(st) {
            out.push(finding(st.span, reason, detail, refused));
            continue;
        }
        if let Some(c) = contacts.as_ref().filter(|_| st.keyword == "CONTACT") {
            for (span, reason, detail) in c.problems(ds, index) {
                out.push(finding(span, reason, detail, FORCE_ANALYSES));
            }
        }
        if st.keyword == "FLEX_BODY" {
            if let Some(fb) = flex_bodies.iter().find(|b| b.header.statement == index) {
                for (span, reason, detail) in flex_body::problems(ds, fb) {
                    out.push(finding(span, reason, detail, FORCE_ANALYSES));
                }
            }
            continue;
        }
        let called = user.as_ref().and_then(|_| {
            linker
                .0
                .as_ref()?
                .calls(&st.keyword, routine_text(st).as_deref())
        });
        if let (Some((key, span)), Some(called)) = (&user, called) {
            let detail = format!("its {key} calls the user subroutine {called}");
            out.push(finding(*span, Reason::UserCalled, detail, &[]));
        } else if let Some((key, span)) = user {
            let (detail, refused): (String, &[Analysis]) = match st.keyword.as_str() {
                "REQUEST" => (
                    format!(
                        "its {key} calls a USER subroutine, which linkage cannot run; its \
                         columns cannot be written (simulate --out and command files refuse it)"
                    ),
                    &[],
                ),
                _ => (
                    format!("its {key} calls a USER subroutine (linkage runs no Fortran or C subroutines)"),
                    FORCE_ANALYSES,
                ),
            };
            out.push(finding(span, Reason::UserSubroutine, detail, refused));
        }
        for (f, span) in named_files(st) {
            let exists = !missing.iter().any(|(m, _)| *m == f);
            if st.keyword == "MATRIX" {
                // linkage reads MATRIX files (ADAMSMAT); a missing one is named, and an LSE
                // that uses the matrix is refused when the model is built.
                if !exists {
                    let detail = format!(
                        "the file '{f}' it names does not exist (an LSE that uses the matrix is \
                         refused)"
                    );
                    out.push(finding(span, Reason::ExternalFileMissing, detail, &[]));
                }
                continue;
            }
            let (reason, detail) = if exists {
                (
                    Reason::NotModelled,
                    format!(
                        "its data are in the file '{f}', which linkage does not read (a force \
                         that uses it is refused)"
                    ),
                )
            } else {
                (
                    Reason::ExternalFileMissing,
                    format!(
                        "the file '{f}' it names does not exist (a force that uses it is refused)"
                    ),
                )
            };
            out.push(finding(span, reason, detail, &[]));
        }
    }
    out
}

/// The input errors of analysis `a` on `ds`: every finding it refuses, all at once, each at
/// its place.
pub fn refusals(ds: &Dataset, a: Analysis) -> Vec<Diagnostic> {
    findings(ds)
        .iter()
        .filter(|f| f.refuses(a))
        .map(Finding::error)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dataset(body: &str) -> Dataset {
        linkage_adm::parse_dataset(Arc::from("t.adm"), &format!("t\n{body}\nEND\n"))
            .expect("parses")
    }

    #[test]
    fn user_calls_are_found_anywhere_in_an_expression() {
        assert!(calls_user("USER(1, 2)"));
        assert!(calls_user(" 2*user (1)"));
        assert!(!calls_user("USERS(1)"));
        assert!(!calls_user("MYUSER(1)"));
        assert!(!calls_user("DX(1,2)"));
    }

    #[test]
    fn every_unmodelled_statement_is_named_with_the_analyses_that_refuse_it() {
        let ds = dataset(
            "PART/1, GROUND\nMARKER/2, PART = 1\nFLEX_BODY/3, MNF_FILE = 'beam.mnf'\n\
             SENSOR/4, VALUE = 1, HALT, FUNCTION = TIME\nCURVE/5, MATRIX = 6\n\
             SFORCE/7, I = 2, J = 2, TRANSLATION, FUNCTION = USER(1)\nGRAPHICS/8, CYLINDER\n\
             PINPUT/9, VARIABLES = 1",
        );
        let f = findings(&ds);
        let got: Vec<(&str, Reason, usize)> = f
            .iter()
            .map(|f| (f.element.as_str(), f.reason, f.span.line as usize))
            .collect();
        assert_eq!(
            got,
            [
                ("FLEX_BODY/3", Reason::ExternalFileMissing, 4),
                ("CURVE/5", Reason::NotUsed, 6),
                ("SFORCE/7", Reason::UserSubroutine, 7),
            ]
        );
        assert!(f[0].refuses(Analysis::Ic) && f[0].refuses(Analysis::Simulate));
        // A sensor is modelled by every run over time (simulate, kinematic, quasi-static).
        assert!(f[1].refused_by.is_empty());
        assert_eq!(refusals(&ds, Analysis::Static).len(), 2);
        assert_eq!(refusals(&ds, Analysis::Simulate).len(), 2);
        assert_eq!(refusals(&ds, Analysis::QuasiStatic).len(), 2);
    }

    #[test]
    fn cvcv_is_modelled_and_reads_its_curves_unless_one_is_a_user_curve() {
        assert_eq!(statement_use("CVCV"), Use::Modelled);
        assert_eq!(MODELLED.len(), 38);
        let ds = dataset(
            "PART/1, GROUND\nCURVE/5, MATRIX = 6\nCURVE/7, MATRIX = 8\n\
             CVCV/9, ICURVE = 5, IRM = 1, IFLOAT = 2, JCURVE = 7, JRM = 3, JFLOAT = 4",
        );
        assert!(findings(&ds).is_empty(), "{:?}", findings(&ds));
        let ds = dataset(
            "PART/1, GROUND\nCURVE/5, MATRIX = 6\n\
             CURVE/7, FUNCTION = USER(1)\\, MINPAR = 0, MAXPAR = 1\n\
             CVCV/9, ICURVE = 5, IRM = 1, IFLOAT = 2, JCURVE = 7, JRM = 3, JFLOAT = 4",
        );
        let f = findings(&ds);
        let cvcv = f
            .iter()
            .find(|f| f.element == "CVCV/9")
            .expect("CVCV named");
        assert_eq!(cvcv.reason, Reason::NotModelled);
        assert!(
            cvcv.detail.contains("CURVE/7 is a USER subroutine"),
            "{}",
            cvcv.detail
        );
        assert!(cvcv.refuses(Analysis::Simulate));
    }

    #[test]
    fn every_statement_kind_of_the_language_is_classified() {
        for k in linkage_adm::dataset_keywords() {
            let ok = statement_use(k) != Use::Named || not_modelled(k).is_some();
            assert!(
                ok,
                "{k} is neither modelled, settings, bookkeeping nor named"
            );
        }
    }

    #[test]
    fn control_elements_are_modelled_and_a_user_gse_is_named_as_such() {
        let ds = dataset(
            "PART/1, GROUND\nDIFF/1, FUNCTION = -DIF(1)\n\
             MATRIX/2, FULL = RORDER, ROWS = 1, COLUMNS = 1, VALUES = -1\n\
             ARRAY/3, X\nLSE/4, X = 3, A = 2\n\
             GSE/5, NO = 1, FUNCTION = USER(1)",
        );
        let f = findings(&ds);
        assert_eq!(f.len(), 1, "{f:?}");
        assert_eq!(
            (f[0].element.as_str(), f[0].reason),
            ("GSE/5", Reason::UserSubroutine)
        );
        assert!(f[0].refuses(Analysis::Simulate) && f[0].refuses(Analysis::Linear));
    }

    #[test]
    fn a_missing_file_is_named() {
        let ds = dataset("MATRIX/1, FILE = surely_not_here.mtx\nSPLINE/2, FILE = nor_here.csv");
        let f = findings(&ds);
        assert_eq!(f.len(), 2);
        assert!(
            f[0].detail
                .contains("'surely_not_here.mtx' it names does not exist"),
            "{:?}",
            f[0]
        );
        assert_eq!(f[0].reason, Reason::ExternalFileMissing);
        assert_eq!(f[1].reason, Reason::ExternalFileMissing);
    }
}
