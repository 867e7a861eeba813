//! The initial-conditions report: text and JSON.

use crate::num::sci;
use crate::poses::{a3, fixed, part_states, PartStateJson};
use crate::reactions::reaction_table;
use crate::reactions::{reactions_json, ReactionJson};
use crate::units::{text_line, units_json, Angle, UnitsJson};
use crate::verify::{equation_ref, to_json as verify_json, EquationRef, RedundantJson};
use linkage_adm::Diagnostic;
use linkage_model::Model;
use linkage_solve::constraints::system::RowUnit;
use linkage_solve::pipeline::assemble::Equation;
use linkage_solve::pipeline::ic::InitialConditions;
use serde::Serialize;
use std::fmt::Write;

#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct MovedJson {
    pub name: String,
    pub translation: [f64; 3],
    pub rotation_deg: f64,
}

#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct RepairJson {
    #[serde(flatten)]
    pub equation: EquationRef,
    pub before: f64,
    pub after: f64,
    pub residual_unit: &'static str,
}

#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct ResidualJson {
    pub name: String,
    pub equation: String,
    pub residual: f64,
}

/// The JSON document of `linkage ic --format json`.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct IcJson {
    pub file: String,
    pub title: String,
    /// Positions, 3-1-3 angles (degrees), velocities, accelerations and reactions.
    pub units: UnitsJson,
    /// Statements left out on request (`--deactivate`).
    pub left_out: Vec<crate::coverage::LeftOutJson>,
    /// Statements this analysis ran without (not modelled, not used by it).
    pub runs_without: Vec<crate::coverage::FindingJson>,
    pub converged: bool,
    pub iterations: usize,
    pub max_residual: f64,
    /// When not converged: the equations with the largest residuals.
    pub largest_residuals: Vec<ResidualJson>,
    pub moved_parts: Vec<MovedJson>,
    pub repaired: Vec<RepairJson>,
    pub dof: i64,
    pub redundant: Vec<RedundantJson>,
    pub inconsistent: bool,
    pub velocity_converged: Option<bool>,
    pub velocity_error: Option<f64>,
    pub acceleration_error: Option<f64>,
    pub parts: Vec<PartStateJson>,
    pub reactions: Vec<ReactionJson>,
    /// Joint friction at the reported state (only when the model has FRICTION elements).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub frictions: Vec<crate::friction::FrictionJson>,
    /// Curve constraints' contacts at the reported state (only when the model has PTCVs or
    /// CVCVs).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub curve_contacts: Vec<crate::curve_contacts::CurveContactJson>,
    pub warnings: Vec<String>,
    pub errors: Vec<String>,
    /// The model's force scale ([`crate::reactions::weight_scale`]): what the text's reaction
    /// table judges rounding noise against (not in the JSON).
    #[serde(skip)]
    pub force_scale: f64,
}

fn unit_name(u: RowUnit) -> &'static str {
    match u {
        RowUnit::Length | RowUnit::Mixed => "length",
        RowUnit::Direction | RowUnit::Angle => "degrees",
    }
}

/// Builds the JSON document.
pub fn to_json(model: &Model, ic: &InitialConditions, warnings: &[Diagnostic]) -> IcJson {
    let v = &ic.analysis;
    let mut errors = Vec::new();
    let mut warnings: Vec<String> = warnings.iter().map(|w| w.to_string()).collect();
    let largest_residuals = if ic.assembly.converged {
        Vec::new()
    } else {
        ic.assembly
            .residuals
            .iter()
            .take(5)
            .map(|(eq, r)| match eq {
                Equation::Row(row) => {
                    let e = equation_ref(model, v, *row);
                    ResidualJson {
                        name: e.name.to_string(),
                        equation: e.equation.to_string(),
                        residual: *r,
                    }
                }
                Equation::Hard(h) => {
                    let hr = &ic.hard[*h];
                    ResidualJson {
                        name: hr.name.clone(),
                        equation: hr.label.clone(),
                        residual: *r,
                    }
                }
            })
            .collect()
    };
    errors.extend(ic.motion_errors.iter().cloned());
    if let Some(v) = &ic.velocity {
        errors.extend(v.motion_errors.iter().cloned());
    }
    if !ic.assembly.converged {
        errors.push(format!(
            "displacement initial conditions did not converge in {} iterations (largest residual {})",
            ic.assembly.iterations,
            sci(ic.assembly.max_residual, 4)
        ));
    }
    let acc = match &ic.acceleration {
        Some(Ok(a)) => Some(a),
        Some(Err(e)) => {
            warnings.push(format!(
                "acceleration/force initial conditions not computed: {e}"
            ));
            None
        }
        None => None,
    };
    let parts = match &ic.velocity {
        Some(vel) => part_states(
            model,
            &ic.assembly.state,
            &vel.velocities,
            acc.map(|a| a.accelerations.as_slice()),
        ),
        None => Vec::new(),
    };
    let vj = verify_json(model, v, &[]);
    IcJson {
        file: model.file.to_string(),
        title: model.title.clone(),
        units: units_json(model, Angle::Degree, false),
        left_out: Vec::new(),
        runs_without: Vec::new(),
        converged: ic.assembly.converged,
        iterations: ic.assembly.iterations,
        max_residual: ic.assembly.max_residual,
        largest_residuals,
        moved_parts: ic
            .moved
            .iter()
            .map(|m| MovedJson {
                name: model.parts[m.part].origin.name.clone(),
                translation: a3(m.translation),
                rotation_deg: m.rotation_deg,
            })
            .collect(),
        repaired: ic
            .repaired
            .iter()
            .map(|r| RepairJson {
                equation: equation_ref(model, v, r.row),
                before: r.before,
                after: r.after,
                residual_unit: unit_name(v.system.rows[r.row].unit),
            })
            .collect(),
        dof: v.dof,
        redundant: vj.redundant,
        inconsistent: ic.inconsistent(),
        velocity_converged: ic.velocity.as_ref().map(|x| x.converged),
        velocity_error: ic.velocity.as_ref().map(|x| x.max_error),
        acceleration_error: acc.map(|a| a.max_error),
        parts,
        reactions: acc
            .map(|a| reactions_json(model, &a.reactions))
            .unwrap_or_default(),
        frictions: Vec::new(),
        curve_contacts: Vec::new(),
        warnings,
        errors,
        force_scale: crate::reactions::weight_scale(model),
    }
}

/// Human report.
pub fn to_text(j: &IcJson) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "INITIAL CONDITIONS: {}", j.title);
    let _ = writeln!(s, "  file: {}", j.file);
    let _ = writeln!(s, "{}", text_line(&j.units));
    s.push_str(&crate::coverage::analysis_text(
        &j.left_out,
        &j.runs_without,
    ));
    let _ = writeln!(s);
    let _ = writeln!(
        s,
        "Displacement: {} in {} iterations, largest residual {}",
        if j.converged {
            "converged"
        } else {
            "DID NOT CONVERGE"
        },
        j.iterations,
        sci(j.max_residual, 4)
    );
    for r in &j.largest_residuals {
        let _ = writeln!(
            s,
            "   {} {}  residual {}",
            r.name,
            r.equation,
            sci(r.residual, 5)
        );
    }
    if !j.moved_parts.is_empty() {
        let _ = writeln!(s);
        let _ = writeln!(s, "Moved parts:");
        for m in &j.moved_parts {
            let t = m.translation.map(|x| fixed(x, 6));
            let _ = writeln!(
                s,
                "   {:<24} translation ({}, {}, {})  rotation {} deg",
                m.name,
                t[0],
                t[1],
                t[2],
                fixed(m.rotation_deg, 4)
            );
        }
    }
    if !j.repaired.is_empty() {
        let _ = writeln!(s);
        let _ = writeln!(s, "Repaired joints (residual before → after):");
        for r in &j.repaired {
            let u = if r.residual_unit == "degrees" {
                " deg"
            } else {
                ""
            };
            let _ = writeln!(
                s,
                "   {} ({})  {}  {}{u} → {}{u}",
                r.equation.name,
                r.equation.kind,
                r.equation.equation,
                sci(r.before, 5),
                sci(r.after, 5)
            );
        }
    }
    let _ = writeln!(s);
    let _ = writeln!(
        s,
        "{} Degrees of Freedom at the assembled configuration",
        j.dof
    );
    if j.redundant.is_empty() {
        let _ = writeln!(s, "There are no redundant constraint equations.");
    } else {
        let _ = writeln!(
            s,
            "Redundant constraint equations (removed; their reactions are zero):"
        );
        for r in &j.redundant {
            let status = match (r.consistent, r.residual) {
                (Some(true), _) => "consistent".to_string(),
                (Some(false), Some(x)) => {
                    format!("INCONSISTENT, residual {} {}", sci(x, 5), r.residual_unit)
                }
                _ => "consistency unknown".to_string(),
            };
            let _ = writeln!(
                s,
                "   {} ({})  {}  {status}",
                r.equation.name, r.equation.kind, r.equation.equation
            );
        }
    }
    if let Some(ok) = j.velocity_converged {
        let _ = writeln!(s);
        let _ = writeln!(
            s,
            "Velocity: {} (largest error {})",
            if ok { "converged" } else { "DID NOT CONVERGE" },
            sci(j.velocity_error.unwrap_or(f64::NAN), 4)
        );
    }
    if let Some(e) = j.acceleration_error {
        let _ = writeln!(s, "Acceleration and force: largest error {}", sci(e, 4));
    }
    if !j.reactions.is_empty() {
        let _ = writeln!(s);
        let _ = writeln!(s, "Reactions on the I markers (ground axes):");
        reaction_table(&mut s, &j.reactions, j.force_scale);
    }
    crate::friction::friction_table(&mut s, &j.frictions);
    crate::curve_contacts::curve_contact_table(&mut s, &j.curve_contacts);
    for w in &j.warnings {
        let _ = writeln!(s, "{w}");
    }
    for e in &j.errors {
        let _ = writeln!(s, "error: {e}");
    }
    s
}
