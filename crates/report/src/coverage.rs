//! What a report says about the statements an analysis refuses, runs without, or was told to
//! leave out (`--deactivate`): JSON objects and text lines shared by every report.

use linkage_adm::amend::Selected;
use linkage_solve::coverage::{Analysis, Finding};
use serde::Serialize;
use std::fmt::Write;

/// One statement some analysis refuses or runs without.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct FindingJson {
    /// `SENSOR/3`.
    pub element: String,
    /// `SENSOR_3` or the `adams_view_name`.
    pub name: String,
    pub file: String,
    pub line: u32,
    /// `not modelled`, `USER subroutine`, `external file missing` or `not used`.
    pub reason: &'static str,
    pub detail: String,
    /// The analyses that refuse a model holding it (`ic`, `static`, `static --end`, `linear`,
    /// `simulate`); empty when every analysis runs without it.
    pub refused_by: Vec<&'static str>,
}

impl From<&Finding> for FindingJson {
    fn from(f: &Finding) -> Self {
        FindingJson {
            element: f.element.clone(),
            name: f.name.clone(),
            file: f.file.to_string(),
            line: f.span.line,
            reason: f.reason.name(),
            detail: f.detail.clone(),
            refused_by: f.refused_by.iter().map(|a| a.name()).collect(),
        }
    }
}

/// One statement left out on request (`--deactivate`, `DEACTIVATE`).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct LeftOutJson {
    pub element: String,
    pub name: String,
    pub line: u32,
}

impl From<&Selected> for LeftOutJson {
    fn from(s: &Selected) -> Self {
        LeftOutJson {
            element: s.element(),
            name: s.name.clone(),
            line: s.line,
        }
    }
}

/// The left-out statements as JSON.
pub fn left_out_json(left_out: &[Selected]) -> Vec<LeftOutJson> {
    left_out.iter().map(LeftOutJson::from).collect()
}

/// The findings analysis `a` runs without (those it would refuse stop it before any report).
pub fn runs_without_json(findings: &[Finding], a: Analysis) -> Vec<FindingJson> {
    findings
        .iter()
        .filter(|f| !f.refuses(a))
        .map(FindingJson::from)
        .collect()
}

/// The analyses that refuse a model with these findings, in the order of [`Analysis::ALL`].
pub fn refusing_analyses(findings: &[Finding]) -> Vec<&'static str> {
    Analysis::ALL
        .iter()
        .filter(|&&a| findings.iter().any(|f| f.refuses(a)))
        .map(|a| a.name())
        .collect()
}

/// `a`, `a and b`, `a, b and c`.
fn and_list(items: &[&str]) -> String {
    match items {
        [] => String::new(),
        [one] => one.to_string(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    }
}

/// `every analysis` when all of them refuse, else their list.
fn refused_by(analyses: &[&str]) -> String {
    if analyses.len() == Analysis::ALL.len() {
        "every analysis but verify".to_string()
    } else {
        and_list(analyses)
    }
}

/// `left out (--deactivate): SENSOR_3 (SENSOR/3, line 9), …` (nothing when none).
pub fn left_out_text(left_out: &[LeftOutJson]) -> String {
    if left_out.is_empty() {
        return String::new();
    }
    let names: Vec<String> = left_out
        .iter()
        .map(|l| format!("{} ({}, line {})", l.name, l.element, l.line))
        .collect();
    format!(
        "  left out on request ({}): {}\n",
        left_out.len(),
        names.join(", ")
    )
}

/// Names of a group of findings, at most `shown` of them then how many more.
fn names(group: &[&FindingJson], shown: usize) -> String {
    let mut s: Vec<String> = group
        .iter()
        .take(shown)
        .map(|f| format!("{} (line {})", f.name, f.line))
        .collect();
    if group.len() > shown {
        s.push(format!("… ({} more)", group.len() - shown));
    }
    s.join(", ")
}

/// Findings grouped by statement kind, reason and detail, in order of first appearance.
fn groups(findings: &[FindingJson]) -> Vec<Vec<&FindingJson>> {
    let mut out: Vec<Vec<&FindingJson>> = Vec::new();
    for f in findings {
        let kind = |g: &FindingJson| g.element.split('/').next().unwrap_or("").to_string();
        match out
            .iter_mut()
            .find(|g| kind(g[0]) == kind(f) && g[0].reason == f.reason && g[0].detail == f.detail)
        {
            Some(g) => g.push(f),
            None => out.push(vec![f]),
        }
    }
    out
}

/// The header lines of an analysis report: what was left out on request, and the statements
/// the analysis ran without (grouped by kind).
pub fn analysis_text(left_out: &[LeftOutJson], runs_without: &[FindingJson]) -> String {
    let mut s = left_out_text(left_out);
    for g in groups(runs_without) {
        let kind = g[0].element.split('/').next().unwrap_or("");
        if g[0].reason == USER_CALLED {
            for f in &g {
                let _ = writeln!(s, "  calls for {} (line {}): {}", f.name, f.line, f.detail);
            }
            continue;
        }
        let _ = writeln!(
            s,
            "  runs without {} {kind} ({}): {}: {}",
            g.len(),
            g[0].reason,
            names(&g, 4),
            g[0].detail
        );
    }
    s
}

/// The section of `verify`: every statement a later analysis refuses (one line each, with
/// file:line), then those every analysis runs without (grouped by kind).
pub fn verify_text(findings: &[FindingJson]) -> String {
    if findings.is_empty() {
        return String::new();
    }
    let mut s = String::new();
    let refused: Vec<&FindingJson> = findings
        .iter()
        .filter(|f| !f.refused_by.is_empty())
        .collect();
    if !refused.is_empty() {
        let _ = writeln!(
            s,
            "Elements later analyses refuse ({}; leave them out with --deactivate NAME):",
            refused.len()
        );
        for f in &refused {
            let _ = writeln!(
                s,
                "   {}:{}  {} ({}): {}: {}; refused by {}",
                f.file,
                f.line,
                f.name,
                f.element,
                f.reason,
                f.detail,
                refused_by(&f.refused_by)
            );
        }
    }
    let called: Vec<&FindingJson> = findings
        .iter()
        .filter(|f| f.reason == USER_CALLED)
        .collect();
    if !called.is_empty() {
        if !refused.is_empty() {
            let _ = writeln!(s);
        }
        let _ = writeln!(s, "User subroutines the analyses call:");
        for f in &called {
            let _ = writeln!(
                s,
                "   {} ({}, line {}): {}",
                f.name, f.element, f.line, f.detail
            );
        }
    }
    let unused: Vec<FindingJson> = findings
        .iter()
        .filter(|f| f.refused_by.is_empty() && f.reason != USER_CALLED)
        .cloned()
        .collect();
    if !unused.is_empty() {
        if !refused.is_empty() || !called.is_empty() {
            let _ = writeln!(s);
        }
        let _ = writeln!(s, "Elements every analysis runs without:");
        for g in groups(&unused) {
            let kind = g[0].element.split('/').next().unwrap_or("");
            let _ = writeln!(
                s,
                "   {} {kind} ({}): {}: {}",
                g.len(),
                g[0].reason,
                names(&g, 4),
                g[0].detail
            );
        }
    }
    s
}

/// The reason of a finding whose USER subroutine the analyses call (`--user-lib`).
const USER_CALLED: &str = "user subroutine called";

/// The verdict's words about later analyses: `; ic, static and simulate will refuse it` (empty
/// when none will).
pub fn refusal_verdict(refusing: &[&str]) -> String {
    if refusing.is_empty() {
        String::new()
    } else {
        format!(
            "; {} will refuse it (elements not modelled or not run, listed above)",
            if refusing.len() == Analysis::ALL.len() {
                "every other analysis".to_string()
            } else {
                and_list(refusing)
            }
        )
    }
}
