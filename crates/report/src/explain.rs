//! The `--explain` part of the verify report: replacement advice, determinate reactions,
//! singular configuration, conflicting drivers (text and JSON).

use linkage_model::Model;
use linkage_solve::constraints::system::RowUnit;
use linkage_solve::stages::explain::{
    ConflictKind, Direction, ElementReactions, Explanation, Proposal,
};
use serde::Serialize;
use std::fmt::Write;

/// One element changed by a proposal.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct ChangeJson {
    /// `coupler_rocker`.
    pub name: String,
    /// `JOINT/3`.
    pub element: String,
    /// `REVOLUTE`.
    pub from: String,
    /// `JPRIM INLINE`, `UNIVERSAL (new I marker: … turned 90° …)`.
    pub to: String,
}

/// Reaction components of one element.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct ReactionJson {
    pub name: String,
    #[serde(rename = "type")]
    pub kind: String,
    /// `force along Zj`, `torque about Xj`, or an equation label.
    pub directions: Vec<String>,
}

/// One proposal (numbered from 1 as in the text report and `--apply`).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct SuggestionJson {
    pub number: usize,
    pub changes: Vec<ChangeJson>,
    pub dof_after: i64,
    pub redundant_after: usize,
    /// `σ_min/σ_max` of the changed loops' equations (1 ideal; small: some load is carried by
    /// large opposing reactions). `null` for very large loops.
    pub reaction_conditioning: Option<f64>,
    /// Reaction components indeterminate before that become determinate.
    pub determinate_after: Vec<ReactionJson>,
    /// Reaction components still indeterminate after the change.
    pub indeterminate_after: Vec<ReactionJson>,
}

/// A motion or initial condition that fixes a DOF already fixed.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct ConflictJson {
    pub name: String,
    /// `Rotational Motion`, `IC rotation`, `EXACT X`.
    #[serde(rename = "type")]
    pub what: String,
    /// `duplicate` (same value), `conflict` (different value) or `unknown`.
    pub kind: &'static str,
    /// What fixes that DOF already.
    pub with: Vec<String>,
    /// Only constraint equations (no other driver) fix it already.
    pub fixed_by_constraints: bool,
    /// Disagreement in `mismatch_unit`.
    pub mismatch: Option<f64>,
    pub mismatch_unit: &'static str,
}

/// The dataset written with a proposal applied, and its verification.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct AppliedJson {
    pub number: usize,
    pub file: String,
    pub dof: i64,
    pub redundant: usize,
}

/// The keys `--explain` adds to the verify JSON.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct ExplainJson {
    pub suggestions: Vec<SuggestionJson>,
    /// `input configuration`, or `regular configuration near the input` when the input pose is
    /// singular.
    pub suggestions_checked_at: &'static str,
    /// Elements whose reaction is not unique, by component.
    pub indeterminate: Vec<ReactionJson>,
    /// Elements with uniquely determined components (trustworthy reactions).
    pub determinate: Vec<ReactionJson>,
    /// DOF and redundancy at nearby admissible configurations (`null` when none could be
    /// assembled).
    pub generic_dof: Option<i64>,
    pub generic_redundant: Option<usize>,
    /// DOF and redundancy at the input by the same analysis.
    pub input_dof: i64,
    pub input_redundant: usize,
    pub singular_configuration: bool,
    pub generic_trials: usize,
    pub generic_trials_assembled: usize,
    /// Loops too large for the nearby-pose check (their input rank is used).
    pub generic_unchecked_loops: usize,
    pub conflicting_drivers: Vec<ConflictJson>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub applied: Option<AppliedJson>,
}

fn directions(d: &[Direction]) -> Vec<String> {
    d.iter().map(|x| x.label()).collect()
}

fn reaction(model: &Model, r: &ElementReactions, d: &[Direction]) -> ReactionJson {
    let c = &model.constraints[r.element];
    ReactionJson {
        name: c.origin.name.clone(),
        kind: c.description().to_string(),
        directions: directions(d),
    }
}

fn suggestion(model: &Model, number: usize, p: &Proposal) -> SuggestionJson {
    let named = |list: &[linkage_solve::stages::explain::repair::NamedReactions]| {
        list.iter()
            .map(|r| ReactionJson {
                name: r.name.clone(),
                kind: r.kind.clone(),
                directions: directions(&r.directions),
            })
            .collect()
    };
    SuggestionJson {
        number,
        changes: p
            .changes
            .iter()
            .map(|c| {
                let (from, to) = c.describe(model);
                let o = &model.constraints[c.element].origin;
                ChangeJson {
                    name: o.name.clone(),
                    element: o.element(),
                    from,
                    to,
                }
            })
            .collect(),
        dof_after: p.dof_after,
        redundant_after: p.redundant_after,
        reaction_conditioning: p.conditioning,
        determinate_after: named(&p.now_determinate),
        indeterminate_after: named(&p.indeterminate_after),
    }
}

fn unit_name(u: RowUnit) -> &'static str {
    match u {
        RowUnit::Length | RowUnit::Mixed => "length",
        RowUnit::Direction | RowUnit::Angle => "degrees",
    }
}

/// Builds the JSON keys of an explanation.
pub fn to_json(model: &Model, e: &Explanation) -> ExplainJson {
    let m = &e.mobility;
    ExplainJson {
        suggestions: e
            .suggestions
            .iter()
            .enumerate()
            .map(|(k, p)| suggestion(model, k + 1, p))
            .collect(),
        suggestions_checked_at: if e.suggestions_at_regular_configuration {
            "regular configuration near the input"
        } else {
            "input configuration"
        },
        indeterminate: e
            .reactions
            .iter()
            .filter(|r| !r.indeterminate.is_empty())
            .map(|r| reaction(model, r, &r.indeterminate))
            .collect(),
        determinate: e
            .reactions
            .iter()
            .filter(|r| !r.determinate.is_empty())
            .map(|r| reaction(model, r, &r.determinate))
            .collect(),
        generic_dof: m.generic.map(|g| g.dof),
        generic_redundant: m.generic.map(|g| g.redundant),
        input_dof: m.at_input.dof,
        input_redundant: m.at_input.redundant,
        singular_configuration: m.singular,
        generic_trials: m.trials,
        generic_trials_assembled: m.assembled_trials,
        generic_unchecked_loops: m.unchecked_loops,
        conflicting_drivers: e
            .conflicts
            .iter()
            .map(|c| ConflictJson {
                name: c.name.clone(),
                what: c.what.clone(),
                kind: match c.kind {
                    ConflictKind::Duplicate => "duplicate",
                    ConflictKind::Conflict => "conflict",
                    ConflictKind::Unknown => "unknown",
                },
                with: c.with.clone(),
                fixed_by_constraints: c.with_constraints_only,
                mismatch: c.mismatch,
                mismatch_unit: unit_name(c.unit),
            })
            .collect(),
        applied: None,
    }
}

fn plural(n: usize, one: &str, many: &str) -> String {
    if n == 1 {
        format!("{n} {one}")
    } else {
        format!("{n} {many}")
    }
}

fn mismatch(x: f64, unit: &str) -> String {
    match unit {
        "degrees" => format!("{x:.4} deg"),
        _ => crate::num::sci(x, 5),
    }
}

/// At most this many elements are listed per reaction group in the text.
const LIST_LIMIT: usize = 20;

/// Human text of the explanation (printed after the verify report).
pub fn to_text(j: &ExplainJson) -> String {
    let mut s = String::new();
    let _ = writeln!(s);
    let _ = writeln!(s, "EXPLAIN REDUNDANCY");
    let _ = writeln!(s);
    let _ = writeln!(s, "Configuration:");
    match (j.generic_dof, j.generic_redundant) {
        (Some(d), Some(r)) if j.singular_configuration => {
            let _ = writeln!(
                s,
                "   SINGULAR CONFIGURATION: at the input pose {} and {}, at nearby admissible poses {} and {}.",
                plural(j.input_dof.max(0) as usize, "DOF", "DOF"),
                plural(j.input_redundant, "redundant equation", "redundant equations"),
                plural(d.max(0) as usize, "DOF", "DOF"),
                plural(r, "redundant equation", "redundant equations"),
            );
            let _ = writeln!(
                s,
                "   The mechanism's mobility is the generic one; the extra DOF and redundancy exist only at this pose."
            );
        }
        (Some(d), Some(r)) => {
            let _ = writeln!(
                s,
                "   Generic (nearby admissible poses): {}, {}; the same as at the input: the pose is not singular{}.",
                plural(d.max(0) as usize, "DOF", "DOF"),
                plural(r, "redundant equation", "redundant equations"),
                if r > 0 { " and the redundancy is structural" } else { "" }
            );
        }
        _ if j.generic_trials == 0 && j.generic_unchecked_loops > 0 => {
            let _ = writeln!(
                s,
                "   Generic DOF not checked: every closed loop has more than {} parts.",
                linkage_solve::stages::explain::generic::MAX_LOOP_PARTS
            );
        }
        _ => {
            let _ = writeln!(
                s,
                "   Generic DOF unknown: none of {} nearby poses could be assembled with every equation satisfied (a near-singular pose or a slightly inconsistent model).",
                j.generic_trials
            );
        }
    }
    if j.generic_unchecked_loops > 0 && j.generic_trials > 0 {
        let _ = writeln!(
            s,
            "   ({} closed {} with more than {} parts kept {} input rank.)",
            j.generic_unchecked_loops,
            if j.generic_unchecked_loops == 1 {
                "loop"
            } else {
                "loops"
            },
            linkage_solve::stages::explain::generic::MAX_LOOP_PARTS,
            if j.generic_unchecked_loops == 1 {
                "its"
            } else {
                "their"
            }
        );
    }
    let _ = writeln!(s);
    let _ = writeln!(
        s,
        "Reactions (force and torque on each I marker, components in the J marker's axes):"
    );
    let width = j
        .determinate
        .iter()
        .chain(&j.indeterminate)
        .map(|r| r.name.len() + r.kind.len() + 3)
        .max()
        .unwrap_or(0)
        + 3;
    let list = |s: &mut String, title: &str, rows: &[ReactionJson]| {
        let _ = writeln!(s, "   {title}");
        for r in rows.iter().take(LIST_LIMIT) {
            let label = format!("{} ({})", r.name, r.kind);
            let _ = writeln!(s, "      {label:<width$}{}", r.directions.join(", "));
        }
        if rows.len() > LIST_LIMIT {
            let _ = writeln!(s, "      … ({} more)", rows.len() - LIST_LIMIT);
        }
    };
    if j.indeterminate.is_empty() && j.determinate.is_empty() {
        let _ = writeln!(s, "   No constraint element carries a reaction.");
    } else if j.indeterminate.is_empty() {
        let _ = writeln!(
            s,
            "   Every reaction is uniquely determined (no redundant equations): they can be trusted."
        );
    } else {
        list(
            &mut s,
            "Uniquely determined (can be trusted):",
            &j.determinate,
        );
        if j.determinate.is_empty() {
            let _ = writeln!(s, "      none");
        }
        list(
            &mut s,
            "Not unique: they depend on which redundant equations the solver removes (do not trust them):",
            &j.indeterminate,
        );
    }

    if j.suggestions.is_empty() {
        if j.input_redundant > 0 || j.generic_redundant.is_some_and(|r| r > 0) {
            let _ = writeln!(s);
            let _ = writeln!(
                s,
                "No change of a joint or primitive was found that removes redundancy while keeping the DOF."
            );
        }
    } else {
        let _ = writeln!(s);
        let _ = writeln!(
            s,
            "Proposed changes (each checked by a rank analysis of the changed model at the {}; best first):",
            j.suggestions_checked_at
        );
        for p in &j.suggestions {
            let changes: Vec<String> = p
                .changes
                .iter()
                .map(|c| format!("{}: {} -> {}", c.name, c.from, c.to))
                .collect();
            if changes.len() <= 2 {
                let _ = writeln!(s, "   {:>2}. {}", p.number, changes.join("; "));
            } else {
                let _ = writeln!(s, "   {:>2}. {} changes:", p.number, changes.len());
                for c in &changes {
                    let _ = writeln!(s, "          {c}");
                }
            }
            let cond = p
                .reaction_conditioning
                .map(|c| {
                    if c >= 1e-3 {
                        format!(", reaction conditioning {c:.3}")
                    } else {
                        format!(", reaction conditioning {}", crate::num::sci(c, 3))
                    }
                })
                .unwrap_or_default();
            let red = if p.redundant_after == 0 {
                "no redundant equations".to_string()
            } else {
                plural(
                    p.redundant_after,
                    "redundant equation",
                    "redundant equations",
                )
            };
            let _ = writeln!(
                s,
                "       after: {}, {red}{cond}",
                plural(p.dof_after.max(0) as usize, "DOF", "DOF")
            );
            if p.redundant_after == 0 {
                let _ = writeln!(s, "       every reaction becomes determinate");
            } else if !p.determinate_after.is_empty() {
                let made: Vec<String> = p
                    .determinate_after
                    .iter()
                    .map(|r| format!("{} ({})", r.name, r.directions.join(", ")))
                    .collect();
                let _ = writeln!(s, "       makes determinate: {}", made.join("; "));
            }
        }
        let _ = writeln!(
            s,
            "   Apply one with: linkage verify MODEL.adm --apply K --save OUT.adm"
        );
    }
    if let Some(a) = &j.applied {
        let _ = writeln!(
            s,
            "   Wrote {} with proposal {} applied; re-verified: {}, {}.",
            a.file,
            a.number,
            plural(a.dof.max(0) as usize, "DOF", "DOF"),
            plural(a.redundant, "redundant equation", "redundant equations")
        );
    }

    let _ = writeln!(s);
    let _ = writeln!(s, "Motions and initial conditions:");
    if j.conflicting_drivers.is_empty() {
        let _ = writeln!(
            s,
            "   No motion, joint initial condition or EXACT coordinate fixes a DOF twice."
        );
    }
    for c in &j.conflicting_drivers {
        let with = if c.with.len() > 6 {
            format!("{}, … ({} more)", c.with[..6].join(", "), c.with.len() - 6)
        } else {
            c.with.join(", ")
        };
        let by = if c.fixed_by_constraints {
            format!("a DOF the constraints already fix ({with})")
        } else {
            format!("the same DOF as {with}")
        };
        let verdict = match (c.kind, c.mismatch) {
            ("conflict", Some(x)) => format!(
                "CONFLICT: the values differ by {}",
                mismatch(x.abs(), c.mismatch_unit)
            ),
            ("duplicate", _) => "duplicate (same value)".to_string(),
            _ => "value unknown".to_string(),
        };
        let _ = writeln!(s, "   {} {} fixes {by}: {verdict}", c.name, c.what);
    }
    s
}
