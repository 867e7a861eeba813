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

#[cfg(test)]
mod tests {
    use super::*;

    fn ds(text: &str) -> Dataset {
        linkage_adm::parse_dataset(Arc::from("t.adm"), text).unwrap()
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
}
