//! Analysis settings from the dataset's IC/, EQUILIBRIUM/, … statements, with Adams' defaults
//! (ADM-REFERENCE §9).

use linkage_adm::{Dataset, Diagnostic, Statement, Value};
use std::sync::Arc;

/// `IC/` settings (ADM-REFERENCE §9.2).
#[derive(Clone, Debug, PartialEq)]
pub struct IcSettings {
    /// Maximum displacement error of the assembly.
    pub error: f64,
    pub maxit: usize,
    /// Jacobian re-evaluation pattern (repeats).
    pub pattern: Vec<bool>,
    /// Maximum translation per iteration (model length units).
    pub tlimit: f64,
    /// Maximum rotation per iteration (radians).
    pub alimit: f64,
    /// Velocity error tolerance.
    pub verror: f64,
    /// Acceleration/force error tolerance.
    pub aerror: f64,
}

impl Default for IcSettings {
    fn default() -> Self {
        IcSettings {
            error: 1e-10,
            maxit: 25,
            pattern: vec![true; 10],
            tlimit: 1e10,
            alimit: 30f64.to_radians(),
            verror: 1e-4,
            aerror: 1e-4,
        }
    }
}

/// Finds an argument of a generic statement by unambiguous prefix of one of `names`.
fn find<'a>(stmt: &'a Statement, name: &str, names: &[&str]) -> Option<&'a linkage_adm::Argument> {
    stmt.args.iter().find(|a| {
        let key = a.key.as_str();
        if key == name {
            return true;
        }
        if key.is_empty() || !name.starts_with(key) {
            return false;
        }
        // Unambiguous among the statement's keywords.
        names.iter().filter(|n| n.starts_with(key)).count() == 1
    })
}

fn number(stmt: &Statement, name: &str, names: &[&str]) -> Option<f64> {
    find(stmt, name, names).and_then(|a| match a.values.first() {
        Some(Value::Number { value, .. }) => Some(*value),
        _ => None,
    })
}

fn pattern(stmt: &Statement, name: &str, names: &[&str]) -> Option<Vec<bool>> {
    let a = find(stmt, name, names)?;
    let mut out = Vec::new();
    for v in &a.values {
        let text = match v {
            Value::Word { text, .. } | Value::Str { text, .. } => text.clone(),
            Value::Expr(e) => e.text.trim().to_uppercase(),
            Value::Number { .. } => return None,
        };
        for part in text.split(':') {
            match part.trim() {
                "T" | "TRUE" => out.push(true),
                "F" | "FALSE" => out.push(false),
                _ => return None,
            }
        }
    }
    (!out.is_empty()).then_some(out)
}

const IC_NAMES: [&str; 12] = [
    "ERROR", "MAXIT", "PATTERN", "TLIMIT", "ALIMIT", "VERROR", "AERROR", "AMAXIT", "APATTERN",
    "LIST", "DEFAULT", "TYPE",
];

/// Reads the last `IC/` statement (warnings for values that are not usable).
pub fn ic_settings(ds: &Dataset, file: &Arc<str>, warnings: &mut Vec<Diagnostic>) -> IcSettings {
    let mut s = IcSettings::default();
    for stmt in ds.statements.iter().filter(|st| st.keyword == "IC") {
        let n = |k: &str| number(stmt, k, &IC_NAMES);
        let positive = |v: Option<f64>, what: &str, w: &mut Vec<Diagnostic>| -> Option<f64> {
            match v {
                Some(x) if x > 0.0 && x.is_finite() => Some(x),
                Some(x) => {
                    w.push(Diagnostic::warning(
                        file.clone(),
                        Some(stmt.span),
                        format!("IC: {what} = {x} is not positive; default kept"),
                    ));
                    None
                }
                None => None,
            }
        };
        if let Some(v) = positive(n("ERROR"), "ERROR", warnings) {
            s.error = v;
        }
        if let Some(v) = positive(n("MAXIT"), "MAXIT", warnings) {
            s.maxit = v as usize;
        }
        if let Some(v) = positive(n("TLIMIT"), "TLIMIT", warnings) {
            s.tlimit = v;
        }
        if let Some(v) = positive(n("ALIMIT"), "ALIMIT", warnings) {
            s.alimit = v;
        }
        if let Some(v) = positive(n("VERROR"), "VERROR", warnings) {
            s.verror = v;
        }
        if let Some(v) = positive(n("AERROR"), "AERROR", warnings) {
            s.aerror = v;
        }
        if let Some(p) = pattern(stmt, "PATTERN", &IC_NAMES) {
            s.pattern = p;
        }
    }
    s
}

/// `EQUILIBRIUM/` settings (ADM-REFERENCE §9.1).
#[derive(Clone, Debug, PartialEq)]
pub struct EquilibriumSettings {
    /// Maximum rotation per iteration (radians).
    pub alimit: f64,
    /// Convergence threshold on the relative correction.
    pub error: f64,
    /// Convergence threshold on the force imbalance (model force units).
    pub imbalance: f64,
    pub maxit: usize,
    pub pattern: Vec<bool>,
    /// Fraction of the mass matrix added to the Newton matrix (not to the equations).
    pub stability: f64,
    /// Maximum translation per iteration (model length units).
    pub tlimit: f64,
    /// Settle by damped dynamics instead of Newton statics (`DYNAMIC`).
    pub dynamic: bool,
    pub global_damping: f64,
    pub settling_time: f64,
    pub acceleration_error: f64,
    pub kinetic_energy_error: f64,
}

impl Default for EquilibriumSettings {
    fn default() -> Self {
        EquilibriumSettings {
            alimit: 10f64.to_radians(),
            error: 1e-4,
            imbalance: 1e-4,
            maxit: 25,
            pattern: vec![true; 10],
            stability: 1e-5,
            tlimit: 20.0,
            dynamic: false,
            global_damping: 0.0,
            settling_time: 100.0,
            acceleration_error: 1e-2,
            kinetic_energy_error: 1e-2,
        }
    }
}

const EQUIL_NAMES: [&str; 18] = [
    "ALIMIT",
    "ERROR",
    "IMBALANCE",
    "MAXIT",
    "PATTERN",
    "STABILITY",
    "TLIMIT",
    "STATIC",
    "DYNAMIC",
    "GLOBAL_DAMPING",
    "SETTLING_TIME",
    "ACCELERATION_ERROR",
    "KINETIC_ENERGY_ERROR",
    "METHOD",
    "ATOL",
    "RTOL",
    "MAXITL",
    "ETAMAX",
];

/// Reads the `EQUILIBRIUM/` statements (later ones override earlier ones).
pub fn equilibrium_settings(
    ds: &Dataset,
    file: &Arc<str>,
    warnings: &mut Vec<Diagnostic>,
) -> EquilibriumSettings {
    let mut s = EquilibriumSettings::default();
    for stmt in ds
        .statements
        .iter()
        .filter(|st| st.keyword == "EQUILIBRIUM")
    {
        let n = |k: &str| number(stmt, k, &EQUIL_NAMES);
        let mut set = |v: Option<f64>, what: &str, allow_zero: bool, slot: &mut f64| {
            if let Some(x) = v {
                if x.is_finite() && (x > 0.0 || (allow_zero && x == 0.0)) {
                    *slot = x;
                } else {
                    warnings.push(Diagnostic::warning(
                        file.clone(),
                        Some(stmt.span),
                        format!("EQUILIBRIUM: {what} = {x} is not valid; default kept"),
                    ));
                }
            }
        };
        set(n("ALIMIT"), "ALIMIT", false, &mut s.alimit);
        set(n("ERROR"), "ERROR", false, &mut s.error);
        set(n("IMBALANCE"), "IMBALANCE", false, &mut s.imbalance);
        set(n("STABILITY"), "STABILITY", true, &mut s.stability);
        set(n("TLIMIT"), "TLIMIT", false, &mut s.tlimit);
        set(
            n("GLOBAL_DAMPING"),
            "GLOBAL_DAMPING",
            true,
            &mut s.global_damping,
        );
        set(
            n("SETTLING_TIME"),
            "SETTLING_TIME",
            false,
            &mut s.settling_time,
        );
        set(
            n("ACCELERATION_ERROR"),
            "ACCELERATION_ERROR",
            false,
            &mut s.acceleration_error,
        );
        set(
            n("KINETIC_ENERGY_ERROR"),
            "KINETIC_ENERGY_ERROR",
            false,
            &mut s.kinetic_energy_error,
        );
        let mut maxit = s.maxit as f64;
        set(n("MAXIT"), "MAXIT", false, &mut maxit);
        s.maxit = maxit as usize;
        if let Some(p) = pattern(stmt, "PATTERN", &EQUIL_NAMES) {
            s.pattern = p;
        }
        if find(stmt, "DYNAMIC", &EQUIL_NAMES).is_some() {
            s.dynamic = true;
        }
        if find(stmt, "STATIC", &EQUIL_NAMES).is_some() {
            s.dynamic = false;
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ds(text: &str) -> Dataset {
        linkage_adm::parse_dataset(Arc::from("t.adm"), text).unwrap()
    }

    #[test]
    fn equilibrium_settings_from_a_real_style_statement() {
        // As in a real dataset (ADM-REFERENCE §2.13).
        let d = ds("t\nPART/1, GROUND\nEQUILIBRIUM/\n, ALIMIT = 1D, ERROR = 1, IMBALANCE = 1, MAXIT = 500, STABILITY = 5, TLIMIT = 0.5\nEND\n");
        let mut w = Vec::new();
        let s = equilibrium_settings(&d, &d.file, &mut w);
        assert!((s.alimit - 1f64.to_radians()).abs() < 1e-15);
        assert_eq!(
            (s.error, s.imbalance, s.maxit, s.stability, s.tlimit),
            (1.0, 1.0, 500, 5.0, 0.5)
        );
        assert!(w.is_empty());
        let d = ds("t\nPART/1, GROUND\nEND\n");
        assert_eq!(
            equilibrium_settings(&d, &d.file, &mut w),
            EquilibriumSettings::default()
        );
    }

    #[test]
    fn ic_defaults_and_overrides() {
        let d = ds("t\nPART/1, GROUND\nEND\n");
        let mut w = Vec::new();
        assert_eq!(ic_settings(&d, &d.file, &mut w), IcSettings::default());
        let d = ds("t\nPART/1, GROUND\nIC/, ERR = 1E-8, MAXIT = 50, ALIM = 5D, TLIM = 0.5, PATTERN = T:F:F\nEND\n");
        let s = ic_settings(&d, &d.file, &mut w);
        assert_eq!(s.error, 1e-8);
        assert_eq!(s.maxit, 50);
        assert!((s.alimit - 5f64.to_radians()).abs() < 1e-15);
        assert_eq!(s.tlimit, 0.5);
        assert_eq!(s.pattern, vec![true, false, false]);
    }

    #[test]
    fn numbers_in_messages_read_as_written() {
        let all: Vec<String> = [4.0, 2.25, 0.125, 1e12, 1.5e-9, -1.0, 0.0, 2.5e9, 1e-12]
            .iter()
            .map(|&x| shown(x))
            .collect();
        assert_eq!(
            all,
            ["4", "2.25", "0.125", "1e12", "1.5e-9", "-1", "0", "2.5e9", "1e-12"]
        );
    }

    #[test]
    fn integrator_values_that_cannot_be_used_are_named_and_left_out() {
        let d = ds("t\nPART/1, GROUND\nINTEGRATOR/HHT, ERROR = -1, HMAX = 0.01, HMIN = 0.5, ALPHA = 0.2, MAXIT = 0, KMAX = 6\nEND\n");
        let st = integrator_statement(&d);
        assert_eq!(st.name.as_deref(), Some("HHT"));
        assert_eq!(
            (st.error, st.hmax, st.hmin, st.alpha, st.maxit),
            (None, Some(0.01), None, None, None)
        );
        assert_eq!(st.ignored, vec!["KMAX".to_string()]);
        assert_eq!(
            st.invalid,
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
            st.invalid,
            vec!["INTEGRATOR ERROR = 1e-20 is below what double precision can meet; 1e-12 is used"]
        );
    }
}

/// Integrator settings (INTEGRATOR statement; Adams names are accepted by the caller and mapped
/// to HHT).
#[derive(Clone, Debug, PartialEq)]
pub struct IntegratorSettings {
    /// Local error tolerance (relative to the characteristic length for translations).
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
            error: 1e-3,
            hmax: None,
            hinit: None,
            hmin: 1e-10,
            alpha: -0.3,
            maxit: 10,
        }
    }
}

/// `INTEGRATOR/` settings (ADM-REFERENCE §8.5, §9.4). Adams' integrator names are accepted;
/// linkage always integrates with HHT (index 3) and says which settings had no effect.
#[derive(Clone, Debug, PartialEq)]
pub struct IntegratorStatement {
    /// The integrator named (GSTIFF, WSTIFF, HHT, NEWMARK, HASTIFF, …), upper case.
    pub name: Option<String>,
    pub error: Option<f64>,
    pub hmax: Option<f64>,
    pub hinit: Option<f64>,
    pub hmin: Option<f64>,
    pub alpha: Option<f64>,
    pub maxit: Option<usize>,
    /// Arguments given that linkage does not use (KMAX, CORRECTOR, FORMULATION, …).
    pub ignored: Vec<String>,
    /// Values that cannot be used, each with what is used instead (for warnings).
    pub invalid: Vec<String>,
}

/// A setting or time as a reader wants it in a message: `4`, `2.25`, `1e12`, `1.5e-9`
/// (exponent form when very small or large, six significant digits at most).
pub fn shown(x: f64) -> String {
    let trim = |t: &str| t.trim_end_matches('0').trim_end_matches('.').to_string();
    if x != 0.0 && (x.abs() < 1e-3 || x.abs() >= 1e6) {
        let t = format!("{x:.5e}");
        match t.split_once('e') {
            Some((mantissa, exponent)) => format!("{}e{exponent}", trim(mantissa)),
            None => t,
        }
    } else {
        trim(&format!("{x:.6}"))
    }
}

/// The smallest INTEGRATOR ERROR linkage honours: below it the local error estimate is
/// rounding (coordinates carry about 1e-16 of their size, and models far from the origin
/// more), so a smaller tolerance could only pin the step at HMIN.
pub const MIN_INTEGRATOR_ERROR: f64 = 1e-12;

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
    let mut out = IntegratorStatement {
        name: None,
        error: None,
        hmax: None,
        hinit: None,
        hmin: None,
        alpha: None,
        maxit: None,
        ignored: Vec::new(),
        invalid: Vec::new(),
    };
    for stmt in ds.statements.iter().filter(|st| st.keyword == "INTEGRATOR") {
        let n = |k: &str| number(stmt, k, &INTEGRATOR_NAMES);
        for name in [
            "GSTIFF",
            "WSTIFF",
            "HHT",
            "NEWMARK",
            "HASTIFF",
            "CONSTANT_BDF",
            "ABAM",
            "RKF45",
        ] {
            if find(stmt, name, &INTEGRATOR_NAMES).is_some_and(|a| a.values.is_empty()) {
                out.name = Some(name.to_string());
            }
        }
        // A positive time or tolerance, or a warning and the value left out.
        let positive = |key: &str, slot: &mut Option<f64>, invalid: &mut Vec<String>| match n(key) {
            Some(x) if x > 0.0 && x.is_finite() => *slot = Some(x),
            Some(x) => invalid.push(format!(
                "INTEGRATOR {key} = {} is not a positive number; it is ignored",
                shown(x)
            )),
            None => {}
        };
        positive("ERROR", &mut out.error, &mut out.invalid);
        positive("HMAX", &mut out.hmax, &mut out.invalid);
        positive("HINIT", &mut out.hinit, &mut out.invalid);
        positive("HMIN", &mut out.hmin, &mut out.invalid);
        if let Some(e) = out.error.filter(|e| *e < MIN_INTEGRATOR_ERROR) {
            out.invalid.push(format!(
                "INTEGRATOR ERROR = {} is below what double precision can meet; {} is used",
                shown(e),
                shown(MIN_INTEGRATOR_ERROR)
            ));
            out.error = Some(MIN_INTEGRATOR_ERROR);
        }
        if let Some(a) = n("ALPHA") {
            if (-1.0 / 3.0..=0.0).contains(&a) {
                out.alpha = Some(a);
            } else {
                out.invalid.push(format!(
                    "INTEGRATOR ALPHA = {a} is outside HHT's range −1/3 … 0; it is ignored"
                ));
            }
        }
        if let Some(m) = n("MAXIT") {
            if m >= 1.0 && m.is_finite() {
                out.maxit = Some(m as usize);
            } else {
                out.invalid.push(format!(
                    "INTEGRATOR MAXIT = {m} is not a positive count; it is ignored"
                ));
            }
        }
        for a in &stmt.args {
            let used = [
                "ERROR",
                "HMAX",
                "HINIT",
                "HMIN",
                "ALPHA",
                "MAXIT",
                "GSTIFF",
                "WSTIFF",
                "HHT",
                "NEWMARK",
                "HASTIFF",
                "CONSTANT_BDF",
                "ABAM",
                "RKF45",
            ]
            .iter()
            .any(|k| k.starts_with(a.key.as_str()) && !a.key.is_empty());
            if !used && !out.ignored.contains(&a.key) {
                out.ignored.push(a.key.clone());
            }
        }
    }
    if let (Some(lo), Some(hi)) = (out.hmin, out.hmax) {
        if lo > hi {
            out.invalid.push(format!(
                "INTEGRATOR HMIN = {} exceeds HMAX = {}; HMIN is ignored",
                shown(lo),
                shown(hi)
            ));
            out.hmin = None;
        }
    }
    out
}
