//! Analysis settings from the dataset's IC/, EQUILIBRIUM/ and INTEGRATOR/ ([`integrator`])
//! statements, with Adams' defaults (ADM-REFERENCE §9).

pub mod integrator;

pub use integrator::{
    integrator_statement, resolve_integrator, Formulation, IntegratorIssue, IntegratorMethod,
    IntegratorNote, IntegratorSettings, IntegratorStatement, ResolvedIntegrator,
    MIN_INTEGRATOR_ERROR,
};
use linkage_adm::{Dataset, Diagnostic, Statement, Value};
use std::sync::Arc;

/// Whether a Newton iteration re-evaluates its Jacobian at `iteration` (from 0) under the
/// PATTERN argument of IC or EQUILIBRIUM: the pattern repeats; an empty one means always.
pub fn refresh_at(pattern: &[bool], iteration: usize) -> bool {
    pattern
        .get(iteration % pattern.len().max(1))
        .copied()
        .unwrap_or(true)
}

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

/// A setting or time as a reader wants it in a message: `4`, `2.25`, `1E+12`, `1.5E-09`
/// (six significant digits at most; exponent form, as Adams prints it, when very small or
/// large: see [`linkage_adm::num::general`]).
pub fn shown(x: f64) -> String {
    linkage_adm::num::general(x, 6)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pattern_repeats_and_an_empty_one_always_refreshes() {
        let pattern = [true, false, false];
        let got: Vec<bool> = (0..7).map(|k| refresh_at(&pattern, k)).collect();
        assert_eq!(got, [true, false, false, true, false, false, true]);
        assert!((0..4).all(|k| refresh_at(&[], k)));
    }

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
            ["4", "2.25", "0.125", "1E+12", "1.5E-09", "-1", "0", "2.5E+09", "1E-12"]
        );
    }
}
