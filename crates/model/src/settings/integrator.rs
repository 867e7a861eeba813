//! `INTEGRATOR/` (ADM-REFERENCE §8.5, §9.4): the settings linkage integrates with, resolved
//! beside IC and EQUILIBRIUM. Every Adams integrator name is accepted: GSTIFF, WSTIFF and
//! CONSTANT_BDF (constant step) run the BDF in the I3 or SI2 formulation (SI1 as SI2), HHT and
//! NEWMARK the HHT-α method (I3); the others run the BDF, said in a note, as are the arguments
//! without effect; values that cannot be used are left out with a warning naming what is used
//! instead.

use super::{find, number, shown};
// INTEGRATOR_TYPES: the integrator names Adams accepts (each maps to HHT).
use linkage_adm::{Dataset, INTEGRATOR_METHODS as INTEGRATOR_TYPES};
use thiserror::Error;

/// The integration method a run uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IntegratorMethod {
    /// HHT-α (Adams' HHT; NEWMARK with α = 0), second order.
    Hht,
    /// Variable-order, variable-step BDF, orders 1 … KMAX (Adams' GSTIFF, WSTIFF).
    Bdf,
}

/// The form of the equations the BDF integrates (Adams' I3, SI2, SI1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Formulation {
    /// Index 3: the position constraints `Φ(q, t) = 0` with the equations of motion; velocities
    /// are the BDF derivative of the positions (Adams' default).
    I3,
    /// Stabilised index 2: the velocity constraints `J v + Φ_t = 0` with the equations of
    /// motion, the positions projected back onto `Φ = 0` after each step (the correction has
    /// its own multipliers, so it does not change the velocities); velocities in the error test.
    Si2,
}

/// Integrator settings (INTEGRATOR statement).
#[derive(Clone, Debug, PartialEq)]
pub struct IntegratorSettings {
    pub method: IntegratorMethod,
    /// Highest BDF order (KMAX, 1 … 6).
    pub kmax: usize,
    /// The BDF's formulation (HHT integrates I3 only).
    pub formulation: Formulation,
    /// CONSTANT_BDF: the BDF steps at a constant size (HMAX, or the output interval when HMAX
    /// is not given), its order still chosen step by step; the error estimate does not reject
    /// steps (a corrector that fails still retries smaller, then returns to the step).
    pub constant_step: bool,
    /// Error tolerance of the run: the error the steps may accumulate over the whole run, in
    /// positions (translations relative to the characteristic length, rotations in radians);
    /// each step of size h of a run of span T is allowed `ERROR·h/T` of local error.
    pub error: f64,
    pub hmax: Option<f64>,
    pub hinit: Option<f64>,
    pub hmin: f64,
    /// HHT α in [−1/3, 0].
    pub alpha: f64,
    /// Newton iterations per step before the step is retried smaller.
    pub maxit: usize,
}

impl Default for IntegratorSettings {
    fn default() -> Self {
        IntegratorSettings {
            method: IntegratorMethod::Bdf,
            kmax: 6,
            formulation: Formulation::I3,
            constant_step: false,
            error: 1e-3,
            hmax: None,
            hinit: None,
            hmin: 1e-10,
            alpha: -0.3,
            maxit: 10,
        }
    }
}

/// The fewest Newton iterations per step linkage allows: a smaller INTEGRATOR MAXIT is raised
/// to it (a step is judged only after the corrector has had a few iterations to converge).
pub const MIN_INTEGRATOR_MAXIT: usize = 4;

/// The smallest INTEGRATOR ERROR linkage honours: below it the local error estimate is
/// rounding (coordinates carry about 1e-16 of their size, and models far from the origin
/// more), so a smaller tolerance could only pin the step at HMIN.
pub const MIN_INTEGRATOR_ERROR: f64 = 1e-12;

/// What the `INTEGRATOR/` statements say, as written (later statements override earlier ones).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct IntegratorStatement {
    /// The integrator named (GSTIFF, WSTIFF, HHT, NEWMARK, HASTIFF, …), upper case.
    pub name: Option<String>,
    pub error: Option<f64>,
    pub hmax: Option<f64>,
    pub hinit: Option<f64>,
    pub hmin: Option<f64>,
    pub alpha: Option<f64>,
    pub maxit: Option<usize>,
    /// Highest BDF order, 1 … 6.
    pub kmax: Option<usize>,
    /// Arguments given that linkage does not use (KMAX, CORRECTOR, FORMULATION, …).
    pub ignored: Vec<String>,
    /// Values that cannot be used, each with what is used instead.
    pub invalid: Vec<IntegratorIssue>,
}

/// A value of INTEGRATOR that cannot be used as given (a warning of `simulate`).
#[derive(Clone, Debug, PartialEq, Error)]
pub enum IntegratorIssue {
    /// ERROR, HMAX, HINIT or HMIN that is not a positive number: left out.
    #[error("INTEGRATOR {key} = {} is not a positive number; it is ignored", shown(*.value))]
    NotPositive { key: &'static str, value: f64 },
    /// ERROR below [`MIN_INTEGRATOR_ERROR`]: `used` instead.
    #[error(
        "INTEGRATOR ERROR = {} is below what double precision can meet; {} is used",
        shown(*.given),
        shown(*.used)
    )]
    ErrorBelowPrecision { given: f64, used: f64 },
    /// ALPHA outside HHT's range [−1/3, 0]: left out.
    #[error("INTEGRATOR ALPHA = {alpha} is outside HHT's range −1/3 … 0; it is ignored")]
    AlphaOutOfRange { alpha: f64 },
    /// KMAX not an order 1 … 6: left out.
    #[error("INTEGRATOR KMAX = {kmax} is not a BDF order 1 … 6; it is ignored")]
    KmaxOutOfRange { kmax: f64 },
    /// MAXIT below 1 (or not finite): left out.
    #[error("INTEGRATOR MAXIT = {maxit} is not a positive count; it is ignored")]
    MaxitNotACount { maxit: f64 },
    /// HMIN above HMAX: HMIN left out.
    #[error(
        "INTEGRATOR HMIN = {} exceeds HMAX = {}; HMIN is ignored",
        shown(*.hmin),
        shown(*.hmax)
    )]
    HminAboveHmax { hmin: f64, hmax: f64 },
}

/// What `simulate` notes about the INTEGRATOR statement (not a problem: information).
#[derive(Clone, Debug, PartialEq, Error)]
pub enum IntegratorNote {
    /// NEWMARK was named: linkage runs HHT-I3 with `alpha`.
    #[error("INTEGRATOR {name} is mapped to linkage's HHT-I3 integrator (α = {alpha})")]
    MappedToHht { name: String, alpha: f64 },
    /// An Adams integrator linkage does not have (HASTIFF, ABAM, RKF45): linkage runs its
    /// variable-order, variable-step BDF.
    #[error(
        "INTEGRATOR {name} is run with linkage's variable-step BDF (GSTIFF), orders 1 … {kmax}"
    )]
    MappedToBdf { name: String, kmax: usize },
    /// SI1 was asked for: linkage integrates SI2 (both stabilise the index with the velocity
    /// constraints).
    #[error("INTEGRATOR SI1 is integrated with the SI2 formulation")]
    Si1AsSi2,
    /// SI2 or SI1 with HHT or NEWMARK, which integrate the index-3 form (as in Adams).
    #[error("INTEGRATOR {formulation}: {name} integrates the index-3 (I3) formulation")]
    FormulationI3 { name: String, formulation: String },
    /// Arguments given that linkage does not use.
    #[error("INTEGRATOR arguments without effect in linkage: {}", .arguments.join(", "))]
    WithoutEffect { arguments: Vec<String> },
    /// Arguments of the other integrator family: ALPHA with a BDF, KMAX with HHT or NEWMARK.
    #[error("INTEGRATOR {name} does not use {}", .arguments.join(", "))]
    NotForIntegrator {
        name: String,
        arguments: Vec<String>,
    },
    /// GSTIFF was named: Adams' GSTIFF keeps the BDF coefficients of a constant step and
    /// interpolates its history when the step changes; linkage's BDF computes its coefficients
    /// from the actual step sizes (variable coefficients, as Adams' WSTIFF), for GSTIFF and
    /// WSTIFF alike.
    #[error(
        "INTEGRATOR GSTIFF is run with variable BDF coefficients (as WSTIFF); Adams' GSTIFF \
         keeps fixed-step coefficients and interpolates its history when the step changes"
    )]
    GstiffAsVariableCoefficient,
}

/// The INTEGRATOR statement resolved: the settings the integrator runs with (Adams' defaults where
/// nothing usable is given), and what `simulate` reports about the statement.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ResolvedIntegrator {
    pub settings: IntegratorSettings,
    /// The Adams integrator mapped to HHT, arguments without effect.
    pub notes: Vec<IntegratorNote>,
    /// Values that could not be used.
    pub warnings: Vec<IntegratorIssue>,
}

/// Resolves the `INTEGRATOR/` statements: the values given (where usable) over
/// [`IntegratorSettings::default`], MAXIT at least [`MIN_INTEGRATOR_MAXIT`].
pub fn resolve_integrator(ds: &Dataset) -> ResolvedIntegrator {
    let stmt = integrator_statement(ds);
    let default = IntegratorSettings::default();
    let method = match stmt.name.as_deref() {
        Some("HHT" | "NEWMARK") => IntegratorMethod::Hht,
        Some(_) => IntegratorMethod::Bdf,
        None => default.method,
    };
    let (formulations, ignored): (Vec<String>, Vec<String>) = stmt
        .ignored
        .into_iter()
        .partition(|a| matches!(a.as_str(), "SI2" | "SI1" | "I3"));
    let stabilised = formulations.last().filter(|f| f.as_str() != "I3");
    let formulation = match (method, stabilised) {
        (IntegratorMethod::Bdf, Some(_)) => Formulation::Si2,
        _ => Formulation::I3,
    };
    let settings = IntegratorSettings {
        method,
        kmax: stmt.kmax.unwrap_or(default.kmax),
        formulation,
        constant_step: stmt.name.as_deref() == Some("CONSTANT_BDF"),
        error: stmt.error.unwrap_or(default.error),
        hmax: stmt.hmax,
        hinit: stmt.hinit,
        hmin: stmt.hmin.unwrap_or(default.hmin),
        alpha: stmt.alpha.unwrap_or(default.alpha),
        maxit: stmt
            .maxit
            .unwrap_or(default.maxit)
            .max(MIN_INTEGRATOR_MAXIT),
    };
    let mut notes = Vec::new();
    match stmt.name.clone() {
        Some(name) if name == "NEWMARK" => notes.push(IntegratorNote::MappedToHht {
            name,
            alpha: settings.alpha,
        }),
        Some(name) if !matches!(name.as_str(), "HHT" | "GSTIFF" | "WSTIFF" | "CONSTANT_BDF") => {
            notes.push(IntegratorNote::MappedToBdf {
                name,
                kmax: settings.kmax,
            })
        }
        _ => {}
    }
    if let Some(formulation) = stabilised {
        match method {
            IntegratorMethod::Hht => notes.push(IntegratorNote::FormulationI3 {
                name: stmt.name.clone().unwrap_or_default(),
                formulation: formulation.clone(),
            }),
            IntegratorMethod::Bdf if formulation == "SI1" => notes.push(IntegratorNote::Si1AsSi2),
            IntegratorMethod::Bdf => {}
        }
    }
    if stmt.name.as_deref() == Some("GSTIFF") {
        notes.push(IntegratorNote::GstiffAsVariableCoefficient);
    }
    if !ignored.is_empty() {
        notes.push(IntegratorNote::WithoutEffect { arguments: ignored });
    }
    let other_family: Vec<String> = match method {
        IntegratorMethod::Bdf => stmt
            .alpha
            .map(|_| "ALPHA".to_string())
            .into_iter()
            .collect(),
        IntegratorMethod::Hht => stmt.kmax.map(|_| "KMAX".to_string()).into_iter().collect(),
    };
    if !other_family.is_empty() {
        notes.push(IntegratorNote::NotForIntegrator {
            name: stmt.name.clone().unwrap_or_else(|| "GSTIFF".into()),
            arguments: other_family,
        });
    }
    ResolvedIntegrator {
        settings,
        notes,
        warnings: stmt.invalid,
    }
}

/// The arguments linkage reads: the integrator names and these values.
const INTEGRATOR_VALUES: [&str; 7] = ["ERROR", "HMAX", "HINIT", "HMIN", "ALPHA", "MAXIT", "KMAX"];

/// Every keyword of the statement, for unambiguous prefixes.
const INTEGRATOR_NAMES: [&str; 18] = [
    "GSTIFF",
    "WSTIFF",
    "HHT",
    "NEWMARK",
    "HASTIFF",
    "CONSTANT_BDF",
    "ABAM",
    "RKF45",
    "SI2",
    "SI1",
    "I3",
    "ERROR",
    "HMAX",
    "HINIT",
    "HMIN",
    "ALPHA",
    "MAXIT",
    "KMAX",
];

/// Reads the `INTEGRATOR/` statements (later ones override earlier ones).
pub fn integrator_statement(ds: &Dataset) -> IntegratorStatement {
    let mut out = IntegratorStatement::default();
    for stmt in ds.statements.iter().filter(|st| st.keyword == "INTEGRATOR") {
        let n = |k: &str| number(stmt, k, &INTEGRATOR_NAMES);
        for name in INTEGRATOR_TYPES {
            if find(stmt, name, &INTEGRATOR_NAMES).is_some_and(|a| a.values.is_empty()) {
                out.name = Some(name.to_string());
            }
        }
        // A positive time or tolerance, or a warning and the value left out.
        let positive =
            |key: &'static str, slot: &mut Option<f64>, invalid: &mut Vec<_>| match n(key) {
                Some(x) if x > 0.0 && x.is_finite() => *slot = Some(x),
                Some(value) => invalid.push(IntegratorIssue::NotPositive { key, value }),
                None => {}
            };
        positive("ERROR", &mut out.error, &mut out.invalid);
        positive("HMAX", &mut out.hmax, &mut out.invalid);
        positive("HINIT", &mut out.hinit, &mut out.invalid);
        positive("HMIN", &mut out.hmin, &mut out.invalid);
        if let Some(given) = out.error.filter(|e| *e < MIN_INTEGRATOR_ERROR) {
            out.invalid.push(IntegratorIssue::ErrorBelowPrecision {
                given,
                used: MIN_INTEGRATOR_ERROR,
            });
            out.error = Some(MIN_INTEGRATOR_ERROR);
        }
        if let Some(alpha) = n("ALPHA") {
            if (-1.0 / 3.0..=0.0).contains(&alpha) {
                out.alpha = Some(alpha);
            } else {
                out.invalid.push(IntegratorIssue::AlphaOutOfRange { alpha });
            }
        }
        if let Some(kmax) = n("KMAX") {
            if (1.0..=6.0).contains(&kmax) && kmax.fract() == 0.0 {
                out.kmax = Some(kmax as usize);
            } else {
                out.invalid.push(IntegratorIssue::KmaxOutOfRange { kmax });
            }
        }
        if let Some(maxit) = n("MAXIT") {
            if maxit >= 1.0 && maxit.is_finite() {
                out.maxit = Some(maxit as usize);
            } else {
                out.invalid.push(IntegratorIssue::MaxitNotACount { maxit });
            }
        }
        for a in &stmt.args {
            let used = INTEGRATOR_VALUES
                .iter()
                .chain(&INTEGRATOR_TYPES)
                .any(|k| k.starts_with(a.key.as_str()) && !a.key.is_empty());
            if !used && !out.ignored.contains(&a.key) {
                out.ignored.push(a.key.clone());
            }
        }
    }
    if let (Some(hmin), Some(hmax)) = (out.hmin, out.hmax) {
        if hmin > hmax {
            out.invalid
                .push(IntegratorIssue::HminAboveHmax { hmin, hmax });
            out.hmin = None;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    fn ds(text: &str) -> Dataset {
        linkage_adm::parse_dataset(Arc::from("t.adm"), text).unwrap_or_else(|e| panic!("{e}"))
    }

    fn texts(issues: &[IntegratorIssue]) -> Vec<String> {
        issues.iter().map(ToString::to_string).collect()
    }

    #[test]
    fn integrator_values_that_cannot_be_used_are_named_and_left_out() {
        let d = ds("t\nPART/1, GROUND\nINTEGRATOR/HHT, ERROR = -1, HMAX = 0.01, HMIN = 0.5, ALPHA = 0.2, MAXIT = 0, KMAX = 6, PATTERN = F\nEND\n");
        let st = integrator_statement(&d);
        assert_eq!(st.name.as_deref(), Some("HHT"));
        assert_eq!(
            (st.error, st.hmax, st.hmin, st.alpha, st.maxit),
            (None, Some(0.01), None, None, None)
        );
        assert_eq!(st.ignored, vec!["PATTERN".to_string()]);
        assert_eq!(st.kmax, Some(6));
        assert_eq!(
            st.invalid,
            vec![
                IntegratorIssue::NotPositive {
                    key: "ERROR",
                    value: -1.0
                },
                IntegratorIssue::AlphaOutOfRange { alpha: 0.2 },
                IntegratorIssue::MaxitNotACount { maxit: 0.0 },
                IntegratorIssue::HminAboveHmax {
                    hmin: 0.5,
                    hmax: 0.01
                },
            ]
        );
        assert_eq!(
            texts(&st.invalid),
            vec![
                "INTEGRATOR ERROR = -1 is not a positive number; it is ignored",
                "INTEGRATOR ALPHA = 0.2 is outside HHT's range −1/3 … 0; it is ignored",
                "INTEGRATOR MAXIT = 0 is not a positive count; it is ignored",
                "INTEGRATOR HMIN = 0.5 exceeds HMAX = 0.01; HMIN is ignored",
            ]
        );
        let d = ds("t\nPART/1, GROUND\nINTEGRATOR/GSTIFF, ERROR = 1E-20, HMIN = 1E-6\nEND\n");
        let st = integrator_statement(&d);
        assert_eq!(
            (st.error, st.hmin),
            (Some(MIN_INTEGRATOR_ERROR), Some(1e-6))
        );
        assert_eq!(
            texts(&st.invalid),
            vec!["INTEGRATOR ERROR = 1E-20 is below what double precision can meet; 1E-12 is used"]
        );
    }

    #[test]
    fn no_integrator_statement_resolves_to_the_defaults_without_notes() {
        let r = resolve_integrator(&ds("t\nPART/1, GROUND\nEND\n"));
        assert_eq!(r, ResolvedIntegrator::default());
        assert_eq!(
            (
                r.settings.error,
                r.settings.hmin,
                r.settings.alpha,
                r.settings.maxit
            ),
            (1e-3, 1e-10, -0.3, 10)
        );
        assert_eq!((r.settings.hmax, r.settings.hinit), (None, None));
    }

    #[test]
    fn constant_bdf_runs_the_bdf_at_a_constant_step() {
        let r = resolve_integrator(&ds(
            "t\nPART/1, GROUND\nINTEGRATOR/CONSTANT_BDF, HMAX = 1E-3\nEND\n",
        ));
        assert!(r.settings.constant_step);
        assert_eq!(
            (r.settings.method, r.settings.hmax),
            (IntegratorMethod::Bdf, Some(1e-3))
        );
        assert!(r.notes.is_empty(), "{:?}", r.notes);
        let r = resolve_integrator(&ds("t\nPART/1, GROUND\nINTEGRATOR/GSTIFF\nEND\n"));
        assert!(!r.settings.constant_step);
    }

    #[test]
    fn gstiff_runs_the_bdf_with_the_values_given() {
        let r = resolve_integrator(&ds(
            "t\nPART/1, GROUND\nINTEGRATOR/GSTIFF, SI2, ERROR = 1E-4, HMAX = 0.01, HINIT = 1E-5, KMAX = 4, CORRECTOR = MODIFIED\nEND\n",
        ));
        assert_eq!(
            r.settings,
            IntegratorSettings {
                method: IntegratorMethod::Bdf,
                kmax: 4,
                formulation: Formulation::Si2,
                constant_step: false,
                error: 1e-4,
                hmax: Some(0.01),
                hinit: Some(1e-5),
                hmin: 1e-10,
                alpha: -0.3,
                maxit: 10,
            }
        );
        let notes: Vec<String> = r.notes.iter().map(ToString::to_string).collect();
        assert_eq!(
            notes,
            [
                "INTEGRATOR GSTIFF is run with variable BDF coefficients (as WSTIFF); Adams' \
                 GSTIFF keeps fixed-step coefficients and interpolates its history when the \
                 step changes",
                "INTEGRATOR arguments without effect in linkage: CORRECTOR"
            ]
        );
        assert!(r.warnings.is_empty());
        let r = resolve_integrator(&ds(
            "t\nPART/1, GROUND\nINTEGRATOR/HASTIFF, KMAX = 7\nEND\n",
        ));
        assert_eq!(
            (r.settings.method, r.settings.kmax),
            (IntegratorMethod::Bdf, 6)
        );
        let notes: Vec<String> = r.notes.iter().map(ToString::to_string).collect();
        assert_eq!(
            notes,
            ["INTEGRATOR HASTIFF is run with linkage's variable-step BDF (GSTIFF), orders 1 … 6"]
        );
        assert_eq!(r.warnings, [IntegratorIssue::KmaxOutOfRange { kmax: 7.0 }]);
    }

    #[test]
    fn hht_is_not_noted_and_a_small_maxit_is_raised() {
        let r = resolve_integrator(&ds(
            "t\nPART/1, GROUND\nINTEGRATOR/HHT, ALPHA = -0.1, MAXIT = 2, HMIN = 1E-8\nEND\n",
        ));
        assert!(r.notes.is_empty(), "{:?}", r.notes);
        assert_eq!(
            (
                r.settings.method,
                r.settings.alpha,
                r.settings.maxit,
                r.settings.hmin
            ),
            (IntegratorMethod::Hht, -0.1, MIN_INTEGRATOR_MAXIT, 1e-8)
        );
        // A later statement overrides an earlier one; an unusable value keeps the default.
        let r = resolve_integrator(&ds(
            "t\nPART/1, GROUND\nINTEGRATOR/NEWMARK, MAXIT = 20\nINTEGRATOR/, MAXIT = 30, ALPHA = -1\nEND\n",
        ));
        assert_eq!((r.settings.maxit, r.settings.alpha), (30, -0.3));
        assert_eq!(
            r.notes,
            [IntegratorNote::MappedToHht {
                name: "NEWMARK".into(),
                alpha: -0.3
            }]
        );
        assert_eq!(
            r.warnings,
            [IntegratorIssue::AlphaOutOfRange { alpha: -1.0 }]
        );
    }
}
