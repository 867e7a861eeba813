//! The verdict a page opens with: whether the analysis succeeded, in words, with every error
//! of the report and its warnings. Read from the report JSON (the keys every
//! `linkage-report` structure uses: `errors`, `warnings`, `converged`, `stable`, `completed`,
//! …); nothing is recomputed.

use serde_json::Value;

/// How the analysis went.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Level {
    /// Done, nothing to worry about.
    Ok,
    /// Done, but with something the reader must know first (an unstable equilibrium, a model
    /// later analyses refuse).
    Attention,
    /// Failed: errors, no convergence, a run that did not complete.
    Failed,
}

/// The verdict of one report.
#[derive(Clone, Debug, PartialEq)]
pub struct Verdict {
    pub level: Level,
    /// One sentence.
    pub headline: String,
    /// Every error of the report, as it states them.
    pub errors: Vec<String>,
    pub warnings: Vec<String>,
}

fn strings(report: &Value, key: &str) -> Vec<String> {
    report
        .get(key)
        .and_then(Value::as_array)
        .map(|a| {
            a.iter()
                .map(|v| match v {
                    Value::String(s) => s.clone(),
                    other => other.to_string(),
                })
                .collect()
        })
        .unwrap_or_default()
}

fn flag(report: &Value, key: &str) -> Option<bool> {
    report.get(key).and_then(Value::as_bool)
}

fn count(report: &Value, key: &str) -> Option<u64> {
    report
        .get(key)
        .and_then(|v| v.as_u64().or_else(|| v.as_array().map(|a| a.len() as u64)))
}

fn plural(n: u64, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// What went right, in a few words, per analysis.
fn facts(analysis: &str, report: &Value) -> String {
    let dof = count(report, "dof");
    let mut parts = Vec::new();
    match analysis {
        "verify" => {
            if let Some(d) = dof {
                parts.push(plural(d, "degree of freedom", "degrees of freedom"));
            }
            if let Some(r) = count(report, "redundant") {
                parts.push(plural(
                    r,
                    "redundant constraint equation",
                    "redundant constraint equations",
                ));
            }
        }
        "ic" => {
            if let Some(i) = count(report, "iterations") {
                parts.push(format!(
                    "assembled in {}",
                    plural(i, "iteration", "iterations")
                ));
            }
            if let Some(d) = dof {
                parts.push(plural(d, "degree of freedom", "degrees of freedom"));
            }
        }
        "static" => {
            if let Some(steps) = report.get("steps").and_then(Value::as_array) {
                if !steps.is_empty() {
                    parts.push(plural(steps.len() as u64, "equilibrium", "equilibria"));
                }
            }
            match flag(report, "stable") {
                Some(true) => parts.push("stable".into()),
                Some(false) => parts.push("UNSTABLE".into()),
                None => {}
            }
        }
        "linear" => {
            let modes: Vec<&Value> = report
                .get("modes")
                .and_then(Value::as_array)
                .map(|m| {
                    m.iter()
                        .filter(|m| m.get("zero").and_then(Value::as_bool) != Some(true))
                        .collect()
                })
                .unwrap_or_default();
            parts.push(plural(modes.len() as u64, "mode", "modes"));
            let lowest = modes
                .iter()
                .filter_map(|m| m.get("frequency").and_then(Value::as_f64))
                .fold(f64::INFINITY, f64::min);
            if lowest.is_finite() {
                parts.push(format!("lowest {} Hz", crate::text::number(lowest)));
            }
        }
        "simulate" => {
            if let Some(t) = report.get("end_time").and_then(Value::as_f64) {
                parts.push(format!("ran to time {}", crate::text::number(t)));
            }
            if let Some(n) = count(report, "outputs") {
                parts.push(plural(n, "output", "outputs"));
            }
        }
        _ => {}
    }
    parts.join(", ")
}

/// The verdict of `report`, the JSON of `analysis` (`verify`, `ic`, `static`, `linear`,
/// `simulate`, `run`).
pub fn verdict(analysis: &str, report: &Value) -> Verdict {
    let errors = strings(report, "errors");
    let warnings = strings(report, "warnings");
    let mut failures = Vec::new();
    if flag(report, "converged") == Some(false) {
        failures.push("did not converge");
    }
    if flag(report, "velocity_converged") == Some(false) {
        failures.push("the velocities did not converge");
    }
    if flag(report, "completed") == Some(false) {
        failures.push("did not complete");
    }
    let unstable = flag(report, "stable") == Some(false);
    let refused = strings(report, "later_refused_by");
    let name = match analysis {
        "static" => "The static analysis",
        "verify" => "Verification",
        "ic" => "The initial conditions",
        "linear" => "The linearization",
        "simulate" => "The simulation",
        "run" => "The command file",
        _ => "The analysis",
    };
    let facts = facts(analysis, report);
    let with_facts = |s: String| {
        if facts.is_empty() {
            s
        } else {
            format!("{s}: {facts}.")
        }
    };
    let (level, headline) = if !errors.is_empty() || !failures.is_empty() {
        let mut why: Vec<String> = failures.iter().map(|f| f.to_string()).collect();
        if !errors.is_empty() {
            why.push(plural(errors.len() as u64, "error", "errors"));
        }
        let mut h = format!("{name} FAILED: {}.", why.join(", "));
        if unstable {
            h.push_str(" The equilibrium is unstable.");
        }
        (Level::Failed, h)
    } else if unstable {
        (
            Level::Attention,
            with_facts(format!(
                "{name} found an UNSTABLE equilibrium (it would not stay there)"
            )),
        )
    } else if !refused.is_empty() {
        (
            Level::Attention,
            with_facts(format!(
                "{name} succeeded, but these analyses will refuse the model: {}",
                refused.join(", ")
            )),
        )
    } else {
        (Level::Ok, with_facts(format!("{name} succeeded")))
    };
    Verdict {
        level,
        headline,
        errors,
        warnings,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn errors_make_a_failed_verdict_that_lists_them() {
        let v = verdict(
            "static",
            &json!({"converged": true, "stable": false, "errors": ["the equilibrium is unstable"]}),
        );
        assert_eq!(v.level, Level::Failed);
        assert_eq!(
            v.headline,
            "The static analysis FAILED: 1 error. The equilibrium is unstable."
        );
        assert_eq!(v.errors, ["the equilibrium is unstable"]);
    }

    #[test]
    fn an_unstable_equilibrium_allowed_is_not_a_success() {
        let v = verdict(
            "static",
            &json!({"converged": true, "stable": false, "errors": [], "steps": []}),
        );
        assert_eq!(v.level, Level::Attention);
        assert_eq!(
            v.headline,
            "The static analysis found an UNSTABLE equilibrium (it would not stay there): UNSTABLE."
        );
    }

    #[test]
    fn a_success_states_its_facts() {
        let v = verdict(
            "verify",
            &json!({"dof": 1, "redundant": [{}, {}], "errors": [], "warnings": ["w"]}),
        );
        assert_eq!(v.level, Level::Ok);
        assert_eq!(
            v.headline,
            "Verification succeeded: 1 degree of freedom, 2 redundant constraint equations."
        );
        assert_eq!(v.warnings, ["w"]);
        let v = verdict(
            "linear",
            &json!({"modes": [{"frequency": 1e-12, "zero": true}, {"frequency": 6.366, "zero": false}]}),
        );
        assert_eq!(
            v.headline,
            "The linearization succeeded: 1 mode, lowest 6.366 Hz."
        );
        let v = verdict("simulate", &json!({"completed": false, "errors": []}));
        assert_eq!(v.headline, "The simulation FAILED: did not complete.");
    }
}
