//! Simulation output: CSV time histories and a JSON/text summary.

use linkage_adm::Diagnostic;
use linkage_model::frames::matrix_to_euler313;
use linkage_model::Model;
use linkage_solve::dynamics::{DynamicRun, Output};
use serde::Serialize;
use std::fmt::Write;

/// Extra columns (e.g. REQUEST components) appended to every CSV row: `(names, values per
/// output)`.
pub type ExtraColumns = (Vec<String>, Vec<Vec<f64>>);

/// Column names: `time`, then `<part>.x .y .z .psi .theta .phi .vx .vy .vz .wx .wy .wz` for every
/// moving part and `<element>.fx .fy .fz .tx .ty .tz` for every joint, primitive and motion.
pub fn csv_header(model: &Model, reaction_elements: &[usize], extra: &[String]) -> String {
    let mut s = String::from("time");
    for p in &model.parts {
        for c in [
            "x", "y", "z", "psi", "theta", "phi", "vx", "vy", "vz", "wx", "wy", "wz",
        ] {
            let _ = write!(s, ",{}.{c}", p.origin.name);
        }
    }
    for &e in reaction_elements {
        for c in ["fx", "fy", "fz", "tx", "ty", "tz"] {
            let _ = write!(s, ",{}.{c}", model.constraints[e].origin.name);
        }
    }
    for x in extra {
        let _ = write!(s, ",{x}");
    }
    s
}

/// One CSV row (angles in degrees, positions of centres of mass, ground axes).
pub fn csv_row(o: &Output, reaction_elements: &[usize], extra: &[f64]) -> String {
    let mut s = format!("{}", o.time);
    for (k, pose) in o.state.poses.iter().enumerate() {
        let e = matrix_to_euler313(&pose.r).map(f64::to_degrees);
        let (v, w) = o.velocities[k];
        for x in [
            pose.p.x, pose.p.y, pose.p.z, e[0], e[1], e[2], v.x, v.y, v.z, w.x, w.y, w.z,
        ] {
            let _ = write!(s, ",{x}");
        }
    }
    for &el in reaction_elements {
        let r = o.reactions.iter().find(|r| r.element == el);
        let vals = r.map_or([0.0; 6], |r| {
            [
                r.force.x, r.force.y, r.force.z, r.torque.x, r.torque.y, r.torque.z,
            ]
        });
        for x in vals {
            let _ = write!(s, ",{x}");
        }
    }
    for x in extra {
        let _ = write!(s, ",{x}");
    }
    s
}

/// The whole CSV document.
pub fn to_csv(model: &Model, run: &DynamicRun, extra: Option<&ExtraColumns>) -> String {
    let Some(sim) = &run.simulation else {
        return csv_header(model, &[], &[]) + "\n";
    };
    let elements: Vec<usize> = sim
        .outputs
        .first()
        .map(|o| o.reactions.iter().map(|r| r.element).collect())
        .unwrap_or_default();
    let names: &[String] = extra.map_or(&[], |e| &e.0);
    let mut s = csv_header(model, &elements, names);
    s.push('\n');
    for (k, o) in sim.outputs.iter().enumerate() {
        let vals: &[f64] = extra.and_then(|e| e.1.get(k)).map_or(&[], |v| v.as_slice());
        s.push_str(&csv_row(o, &elements, vals));
        s.push('\n');
    }
    s
}

/// Summary of `linkage simulate --format json`.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct SimulateJson {
    pub file: String,
    pub title: String,
    pub completed: bool,
    pub end_time: f64,
    pub outputs: usize,
    pub steps: usize,
    pub rejected_steps: usize,
    pub kinematic: bool,
    pub notes: Vec<String>,
    pub warnings: Vec<String>,
    pub errors: Vec<String>,
}

/// Builds the summary.
pub fn summary(
    model: &Model,
    run: &DynamicRun,
    notes: Vec<String>,
    warnings: &[Diagnostic],
) -> SimulateJson {
    let mut errors = Vec::new();
    let mut warnings: Vec<String> = warnings.iter().map(|w| w.to_string()).collect();
    if let Some(e) = &run.error {
        errors.push(e.clone());
    }
    let (completed, end_time, outputs, steps, rejected, kinematic) = match &run.simulation {
        Some(sim) => {
            if let Some(f) = &sim.failure {
                errors.push(format!(
                    "simulation stopped at time {}: {}",
                    f.time, f.message
                ));
            }
            if sim.kinematic {
                warnings.push("The data set is kinematically determinate (0 degrees of freedom): a kinematic analysis was run instead of integration (positions from the constraints at each output time, then velocities, accelerations and reactions).".into());
            }
            (
                sim.failure.is_none(),
                sim.outputs.last().map_or(0.0, |o| o.time),
                sim.outputs.len(),
                sim.steps,
                sim.rejected,
                sim.kinematic,
            )
        }
        None => (false, 0.0, 0, 0, 0, false),
    };
    SimulateJson {
        file: model.file.to_string(),
        title: model.title.clone(),
        completed,
        end_time,
        outputs,
        steps,
        rejected_steps: rejected,
        kinematic,
        notes,
        warnings,
        errors,
    }
}

/// Human summary.
pub fn to_text(j: &SimulateJson) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "DYNAMIC SIMULATION: {}", j.title);
    let _ = writeln!(s, "  file: {}", j.file);
    let _ = writeln!(
        s,
        "Simulation {} at time {}: {} outputs, {} steps ({} rejected)",
        if j.completed { "finished" } else { "STOPPED" },
        j.end_time,
        j.outputs,
        j.steps,
        j.rejected_steps
    );
    for n in &j.notes {
        let _ = writeln!(s, "note: {n}");
    }
    for w in &j.warnings {
        let _ = writeln!(s, "warning: {w}");
    }
    for e in &j.errors {
        let _ = writeln!(s, "error: {e}");
    }
    s
}
