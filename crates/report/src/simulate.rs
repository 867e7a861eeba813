//! Simulation output: CSV time histories and a JSON/text summary.

use crate::num::{denoise, general, scale_of, sci, sci_in, CSV_DIGITS, TIME_DIGITS};
use crate::poses::{part_states, pose_line, PartStateJson};
use crate::statics::{settling_line, settling_summary, SettlingJson};
use crate::units::{text_line, units_json, Angle, CsvUnits, UnitsJson};
use crate::verify::{equation_ref, EquationRef};
use linkage_adm::Diagnostic;
use linkage_model::frames::EulerHistory;
use linkage_model::settings::{Formulation, IntegratorMethod};
use linkage_model::Model;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::dynamics::{DynamicRun, Output, RunError, StartingEquilibrium};
use serde::Serialize;
use std::fmt::Write;

/// Extra columns (e.g. REQUEST components) appended to every CSV row: `(names, values per
/// output)`.
pub type ExtraColumns = (Vec<String>, Vec<Vec<f64>>);

/// Column names: `time`, then `<part>.x .y .z .psi .theta .phi .vx .vy .vz .wx .wy .wz` for every
/// moving part, the flex bodies' modal coordinates `<body>.q<mode> .qdot<mode>`
/// ([`crate::flex`]), `<element>.fx .fy .fz .tx .ty .tz` for every joint, primitive and
/// motion, then `extra`; each with its unit as a suffix, `PART_2.x [mm]` (see [`crate::units`]).
pub fn csv_header(model: &Model, reaction_elements: &[usize], extra: &[String]) -> String {
    let units = CsvUnits::of(model);
    let mut s = units.header("time");
    for p in &model.parts {
        for c in [
            "x", "y", "z", "psi", "theta", "phi", "vx", "vy", "vz", "wx", "wy", "wz",
        ] {
            let _ = write!(s, ",{}", units.header(&format!("{}.{c}", p.origin.name)));
        }
    }
    for c in crate::flex::modal_columns(model) {
        let _ = write!(s, ",{}", units.header(&c));
    }
    for &e in reaction_elements {
        for c in ["fx", "fy", "fz", "tx", "ty", "tz"] {
            let name = format!("{}.{c}", model.constraints[e].origin.name);
            let _ = write!(s, ",{}", units.header(&name));
        }
    }
    for x in extra {
        let _ = write!(s, ",{}", units.header(x));
    }
    s
}

/// One CSV row (angles in degrees, positions of centres of mass, ground axes), each field
/// with [`CSV_DIGITS`] significant digits. The parts' body 3-1-3 angles continue the split of
/// ψ and φ at θ ≈ 0 from the previous row's, kept in `angles` (a run's writer passes the same
/// history from its first row to its last; [`EulerHistory`]). Rounding noise is printed as 0, judged per kind of
/// quantity in the row (positions, angles against a full turn, velocities, angular velocities,
/// forces, torques; see [`crate::num::denoise`]).
pub fn csv_row(
    model: &Model,
    o: &Output,
    reaction_elements: &[usize],
    extra: &[f64],
    angles: &mut EulerHistory<usize>,
) -> String {
    let mut s = general(o.time, CSV_DIGITS);
    let poses = &o.state.poses;
    let position_scale = scale_of(poses.iter().flat_map(|p| p.p.to_array()));
    let v_scale = scale_of(o.velocities.iter().flat_map(|(v, _)| v.to_array()));
    let w_scale = scale_of(o.velocities.iter().flat_map(|(_, w)| w.to_array()));
    for (k, pose) in poses.iter().enumerate() {
        let e = angles.angles(k, &pose.r).map(f64::to_degrees);
        let (v, w) = o.velocities[k];
        let fields = [
            (pose.p.x, position_scale),
            (pose.p.y, position_scale),
            (pose.p.z, position_scale),
            (e[0], 360.0),
            (e[1], 360.0),
            (e[2], 360.0),
            (v.x, v_scale),
            (v.y, v_scale),
            (v.z, v_scale),
            (w.x, w_scale),
            (w.y, w_scale),
            (w.z, w_scale),
        ];
        for (x, scale) in fields {
            let _ = write!(s, ",{}", general(denoise(x, scale), CSV_DIGITS));
        }
    }
    for x in crate::flex::modal_values(model, &o.state, &o.velocities) {
        let _ = write!(s, ",{}", general(x, CSV_DIGITS));
    }
    let force_scale = scale_of(o.reactions.iter().flat_map(|r| r.force.to_array()));
    let torque_scale = scale_of(o.reactions.iter().flat_map(|r| r.torque.to_array()));
    for &el in reaction_elements {
        let r = o.reactions.iter().find(|r| r.element == el);
        let vals = r.map_or([0.0; 6], |r| {
            [
                denoise(r.force.x, force_scale),
                denoise(r.force.y, force_scale),
                denoise(r.force.z, force_scale),
                denoise(r.torque.x, torque_scale),
                denoise(r.torque.y, torque_scale),
                denoise(r.torque.z, torque_scale),
            ]
        });
        for x in vals {
            let _ = write!(s, ",{}", general(x, CSV_DIGITS));
        }
    }
    for &x in extra {
        let _ = write!(s, ",{}", general(x, CSV_DIGITS));
    }
    s
}

/// The time-history CSV written as the outputs come (`simulate --out`, a command file's
/// `.csv`): the header at the first output, whose reactions fix the element columns; each row
/// then written and flushed. Element columns are matched by name, so rows of a model rebuilt
/// since (a command file's DEACTIVATE) keep their columns, an element gone writing zeros.
pub struct CsvHistory<W: std::io::Write> {
    out: W,
    /// Names of the elements with reaction columns (fixed at the first output).
    elements: Option<Vec<String>>,
    /// Their indices in the model last written, searched by name only when the model's
    /// constraints no longer have those names there (a rebuilt model), not at every output.
    indices: Vec<usize>,
    /// The parts' angles at the last row written.
    angles: EulerHistory<usize>,
}

impl<W: std::io::Write> CsvHistory<W> {
    pub fn new(out: W) -> Self {
        CsvHistory {
            out,
            elements: None,
            indices: Vec::new(),
            angles: EulerHistory::new(),
        }
    }

    /// Writes the output `o` of a run of `model`, with the request columns `names` and their
    /// `values` (the header first, at the first output).
    pub fn write(
        &mut self,
        model: &Model,
        o: &Output,
        names: &[String],
        values: &[f64],
    ) -> std::io::Result<()> {
        if self.elements.is_none() {
            let elements: Vec<usize> = o.reactions.iter().map(|r| r.element).collect();
            writeln!(self.out, "{}", csv_header(model, &elements, names))?;
            self.elements = Some(
                elements
                    .iter()
                    .map(|&e| model.constraints[e].origin.name.clone())
                    .collect(),
            );
        }
        let names = self.elements.as_deref().unwrap_or(&[]);
        let still = |(name, &k): (&String, &usize)| {
            k == usize::MAX && !model.constraints.iter().any(|c| &c.origin.name == name)
                || model
                    .constraints
                    .get(k)
                    .is_some_and(|c| &c.origin.name == name)
        };
        if self.indices.len() != names.len() || !names.iter().zip(&self.indices).all(still) {
            self.indices = names
                .iter()
                .map(|name| {
                    model
                        .constraints
                        .iter()
                        .position(|c| &c.origin.name == name)
                        .unwrap_or(usize::MAX)
                })
                .collect();
        }
        let indices = &self.indices;
        let row = csv_row(model, o, indices, values, &mut self.angles);
        writeln!(self.out, "{row}")?;
        self.out.flush()
    }

    /// Writes the header alone when no output came (the file then names its columns).
    pub fn finish_empty(&mut self, model: &Model) -> std::io::Result<()> {
        if self.elements.is_none() {
            writeln!(self.out, "{}", csv_header(model, &[], &[]))?;
            self.elements = Some(Vec::new());
        }
        self.out.flush()
    }

    /// Flushes what is written.
    pub fn flush(&mut self) -> std::io::Result<()> {
        self.out.flush()
    }
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
    let mut angles = EulerHistory::new();
    for (k, o) in sim.outputs.iter().enumerate() {
        let vals: &[f64] = extra.and_then(|e| e.1.get(k)).map_or(&[], |v| v.as_slice());
        s.push_str(&csv_row(model, o, &elements, vals, &mut angles));
        s.push('\n');
    }
    s
}

/// How the run started.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct StartJson {
    /// `initial_conditions` (the assembled configuration and its velocities),
    /// `static_equilibrium` (Newton statics, then from rest), `settled_equilibrium` (damped
    /// dynamics and the Newton polish, then from rest) or `continued` (a command file's run
    /// from the state the last analysis left, on its assembly).
    pub from: &'static str,
    /// Whether the starting configuration was found (an equilibrium that did not converge or
    /// did not settle stops the run before it starts).
    pub found: bool,
    /// Newton iterations of the starting equilibrium (the polish after settling).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub iterations: Option<usize>,
    /// Force/torque imbalance left at the starting equilibrium.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub imbalance: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stable: Option<bool>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub settling: Option<SettlingJson>,
}

/// Summary of `linkage simulate --format json`.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct SimulateJson {
    pub file: String,
    pub title: String,
    /// Positions, 3-1-3 angles (degrees), velocities, accelerations.
    pub units: UnitsJson,
    /// Statements left out on request (`--deactivate`).
    pub left_out: Vec<crate::coverage::LeftOutJson>,
    /// Statements this analysis ran without (not modelled, not used by it).
    pub runs_without: Vec<crate::coverage::FindingJson>,
    pub completed: bool,
    pub end_time: f64,
    pub outputs: usize,
    pub steps: usize,
    pub rejected_steps: usize,
    /// The integrator and what its ERROR bounds, e.g. "BDF (GSTIFF, I3), orders 1 … 6, ERROR = 0.001
    /// over the run".
    pub integrator: String,
    pub kinematic: bool,
    pub start: StartJson,
    /// The redundant equations left out of the run, as in verify: their reactions are zero
    /// (the kept equations carry the load) and their residuals were checked every step.
    pub removed_equations: Vec<EquationRef>,
    /// Every part at the last output.
    pub final_state: Vec<PartStateJson>,
    /// The FLEX_BODYs' modal coordinates and rates at the last output (only when there are
    /// some).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub final_modal_coordinates: Vec<crate::flex::ModalJson>,
    /// Joint friction at the last output (only when the model has FRICTION elements).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub frictions: Vec<crate::friction::FrictionJson>,
    /// Curve constraints' contacts at the reported state (only when the model has PTCVs or
    /// CVCVs).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub curve_contacts: Vec<crate::curve_contacts::CurveContactJson>,
    /// The SENSORs that fired, in time order.
    pub sensors: Vec<crate::sensors::SensorEventJson>,
    /// `HALT` or `RETURN` when a sensor ended the run (at `end_time`, the run complete).
    pub ended_by_sensor: Option<String>,
    pub notes: Vec<String>,
    pub warnings: Vec<String>,
    pub errors: Vec<String>,
}

/// How the run started, from the run and the dataset's EQUILIBRIUM settings.
fn start_json(model: &Model, run: &DynamicRun) -> StartJson {
    let Some(found) = &run.equilibrium else {
        return StartJson {
            from: "initial_conditions",
            found: run.simulation.is_some(),
            iterations: None,
            imbalance: None,
            stable: None,
            settling: None,
        };
    };
    let (from, eq, settling) = match found {
        StartingEquilibrium::Newton(e) => ("static_equilibrium", e.as_ref().ok(), None),
        StartingEquilibrium::Settled(o) => (
            "settled_equilibrium",
            o.equilibrium.as_ref().and_then(|e| e.as_ref().ok()),
            Some(settling_summary(model, Some(o))),
        ),
    };
    StartJson {
        from,
        found: found.equilibrium().is_some(),
        iterations: eq.map(|e| e.iterations),
        imbalance: eq.map(|e| e.imbalance),
        stable: eq.and_then(|e| e.stability.map(|s| s.0)),
        settling,
    }
}

/// Builds the summary. The notes are what the model's INTEGRATOR resolution says (an Adams
/// integrator run by linkage's BDF or HHT, SI2/SI1 integrated as I3, arguments without
/// effect); the warnings end with the INTEGRATOR
/// values that could not be used.
pub fn summary(a: &Assembled, run: &DynamicRun, warnings: &[Diagnostic]) -> SimulateJson {
    let model = a.model;
    let mut errors = Vec::new();
    let mut warnings: Vec<String> = warnings.iter().map(|w| w.to_string()).collect();
    let start = start_json(model, run);
    if let Some(e) = &run.error {
        errors.push(match e {
            RunError::UnstableEquilibrium { .. } if start.from == "static_equilibrium" => format!(
                "{e}: `--settle` finds a stable one by damped dynamics; --allow-unstable starts \
                 from this one"
            ),
            RunError::UnstableEquilibrium { .. } => {
                format!("{e}: --allow-unstable starts from it")
            }
            _ => e.to_string(),
        });
    }
    if start.settling.is_some() && model.equilibrium.global_damping == 0.0 {
        warnings.push(crate::statics::NO_GLOBAL_DAMPING.to_string());
    }
    if start.found && start.stable == Some(false) && run.simulation.is_some() {
        warnings.push(if start.from == "static_equilibrium" {
            "the run starts at an UNSTABLE equilibrium (Newton converges to the nearest one): \
             it stays there only as long as rounding allows; `--settle` finds a stable one by \
             damped dynamics"
                .to_string()
        } else {
            "the run starts at an UNSTABLE equilibrium: it stays there only as long as \
             rounding allows"
                .to_string()
        });
    }
    let (completed, end_time, outputs, steps, rejected, kinematic) = match &run.simulation {
        Some(sim) => {
            if let Some(f) = &sim.failure {
                errors.push(format!(
                    "simulation stopped at time {}: {}",
                    general(f.time, TIME_DIGITS),
                    f.message
                ));
            }
            if sim.kinematic {
                warnings.push("The data set is kinematically determinate (0 degrees of freedom): a kinematic analysis was run instead of integration (positions from the constraints at each output time, then velocities, accelerations and reactions).".into());
            }
            (
                sim.failure.is_none(),
                sim.outputs.last().map_or(0.0, |o| o.time),
                sim.output_count,
                sim.steps,
                sim.rejected,
                sim.kinematic,
            )
        }
        None => (false, 0.0, 0, 0, 0, false),
    };
    let sensors = run
        .simulation
        .as_ref()
        .map(|sim| crate::sensors::events_json(model, &sim.sensor_events))
        .unwrap_or_default();
    let ended_by_sensor = run.simulation.as_ref().and_then(|sim| {
        let stop = sim.stopped_by_sensor?;
        let last = sim.sensor_events.last()?;
        Some(format!(
            "{} ({})",
            last.name,
            crate::sensors::stop_name(stop)
        ))
    });
    let removed_equations =
        a.ic.analysis
            .redundant
            .iter()
            .map(|r| equation_ref(model, &a.ic.analysis, r.row))
            .collect();
    let final_state = run
        .simulation
        .as_ref()
        .and_then(|s| s.outputs.last())
        .map(|o| part_states(model, &o.state, &o.velocities, Some(&o.accelerations)))
        .unwrap_or_default();
    let final_modal_coordinates = run
        .simulation
        .as_ref()
        .and_then(|s| s.outputs.last())
        .map(|o| crate::flex::modal_json(model, &o.state, Some(&o.velocities)))
        .unwrap_or_default();
    let integrator = &model.integrator;
    warnings.extend(integrator.warnings.iter().map(ToString::to_string));
    let i = &integrator.settings;
    let integrator_line = match i.method {
        IntegratorMethod::Bdf => format!(
            "BDF ({}, {}), orders 1 … {}, ERROR = {} over the run",
            if i.constant_step {
                "CONSTANT_BDF"
            } else {
                "GSTIFF"
            },
            match i.formulation {
                Formulation::I3 => "I3",
                Formulation::Si2 => "SI2",
            },
            i.kmax,
            i.error
        ),
        IntegratorMethod::Hht => format!("HHT-α (α = {}), ERROR = {} per step", i.alpha, i.error),
    };
    SimulateJson {
        file: model.file.to_string(),
        title: model.title.clone(),
        units: units_json(model, Angle::Degree, false),
        left_out: Vec::new(),
        runs_without: Vec::new(),
        completed,
        end_time,
        outputs,
        steps,
        rejected_steps: rejected,
        integrator: integrator_line,
        kinematic,
        start,
        removed_equations,
        final_state,
        final_modal_coordinates,
        frictions: Vec::new(),
        curve_contacts: Vec::new(),
        sensors,
        ended_by_sensor,
        notes: integrator.notes.iter().map(ToString::to_string).collect(),
        warnings,
        errors,
    }
}

/// Largest number of removed equations and parts the text summary lists one by one.
const TEXT_LIST_LIMIT: usize = 20;

/// Human summary.
pub fn to_text(j: &SimulateJson) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "DYNAMIC SIMULATION: {}", j.title);
    let _ = writeln!(s, "  file: {}", j.file);
    let _ = writeln!(s, "{}", text_line(&j.units));
    s.push_str(&crate::coverage::analysis_text(
        &j.left_out,
        &j.runs_without,
    ));
    let _ = writeln!(s);
    match j.start.from {
        "initial_conditions" if j.start.found => {
            let _ = writeln!(
                s,
                "Started from the initial conditions (assembled configuration)."
            );
        }
        "initial_conditions" => {
            let _ = writeln!(
                s,
                "The initial conditions give no configuration to start from (see the error below)."
            );
        }
        "continued" => {
            let _ = writeln!(
                s,
                "Continued from the state the last analysis left, on its assembly (nothing \
                 compiled or assembled again)."
            );
        }
        from => {
            if let Some(st) = &j.start.settling {
                let _ = writeln!(s, "{}", settling_line(st));
            }
            let (how, method) = if from == "settled_equilibrium" {
                (
                    "the settled equilibrium (Newton polish",
                    "by damped settling",
                )
            } else {
                ("static equilibrium (Newton statics", "by Newton statics")
            };
            // An equilibrium refused as unstable was found, but no run started from it.
            let verb = if j.outputs > 0 {
                "Started at rest from"
            } else {
                "Found"
            };
            match (j.start.found, j.start.iterations, j.start.imbalance) {
                (true, Some(it), Some(imb)) => {
                    let _ = writeln!(
                        s,
                        "{verb} {how}: {it} iterations, residual imbalance {}){}.",
                        sci(imb, 5),
                        match j.start.stable {
                            Some(true) => "; the equilibrium is stable",
                            Some(false) => "; the equilibrium is UNSTABLE",
                            None => "",
                        }
                    );
                }
                _ => {
                    let _ = writeln!(
                        s,
                        "No equilibrium to start from was found {method} (see the error below)."
                    );
                }
            }
        }
    }
    if !j.removed_equations.is_empty() {
        let _ = writeln!(
            s,
            "{} redundant constraint equation(s) left out, as in verify (their reactions are zero; checked every step):",
            j.removed_equations.len()
        );
        for e in j.removed_equations.iter().take(TEXT_LIST_LIMIT) {
            let _ = writeln!(s, "   {:<24} {} ({})", e.name, e.equation, e.short);
        }
        if j.removed_equations.len() > TEXT_LIST_LIMIT {
            let _ = writeln!(
                s,
                "   … and {} more (--format json lists them all)",
                j.removed_equations.len() - TEXT_LIST_LIMIT
            );
        }
    }
    if j.start.found && j.outputs > 0 {
        let _ = writeln!(
            s,
            "Simulation {} at time {}: {} outputs, {} steps ({} rejected)",
            if j.completed { "finished" } else { "STOPPED" },
            general(j.end_time, TIME_DIGITS),
            j.outputs,
            j.steps,
            j.rejected_steps
        );
        if !j.kinematic {
            let _ = writeln!(s, "Integrator: {}", j.integrator);
        }
        s.push_str(&crate::sensors::events_text(&j.sensors));
        if let Some(by) = &j.ended_by_sensor {
            let _ = writeln!(
                s,
                "The run was ended at time {} by {by}.",
                general(j.end_time, TIME_DIGITS)
            );
        }
    } else {
        let _ = writeln!(s, "No simulation was run.");
    }
    if !j.final_state.is_empty() {
        let _ = writeln!(
            s,
            "\nParts at time {} (CM in ground, 3-1-3 degrees, velocity, angular velocity):",
            j.end_time
        );
        let v_scale = scale_of(j.final_state.iter().flat_map(|p| p.velocity));
        let w_scale = scale_of(j.final_state.iter().flat_map(|p| p.angular_velocity));
        for p in j.final_state.iter().take(TEXT_LIST_LIMIT) {
            let (v, w) = (p.velocity, p.angular_velocity);
            let _ = writeln!(
                s,
                "{}  v ({}, {}, {})  w ({}, {}, {})",
                pose_line(&p.name, p.position, p.reuler),
                sci_in(v[0], 6, v_scale),
                sci_in(v[1], 6, v_scale),
                sci_in(v[2], 6, v_scale),
                sci_in(w[0], 6, w_scale),
                sci_in(w[1], 6, w_scale),
                sci_in(w[2], 6, w_scale)
            );
        }
        if j.final_state.len() > TEXT_LIST_LIMIT {
            let _ = writeln!(
                s,
                "   … and {} more parts (--out writes every part's history)",
                j.final_state.len() - TEXT_LIST_LIMIT
            );
        }
    }
    crate::friction::friction_table(&mut s, &j.frictions);
    crate::curve_contacts::curve_contact_table(&mut s, &j.curve_contacts);
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

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;
    use linkage_solve::physics::reactions::Reaction;
    use linkage_solve::state::State;

    fn model(text: &str) -> Model {
        let ds = linkage_adm::parse_dataset(std::sync::Arc::from("m.adm"), text).expect("parses");
        linkage_model::build_model(&ds).expect("builds").model
    }

    const TWO_JOINTS: &str = "m\nPART/1, GROUND\nMARKER/1, PART = 1\n\
        PART/2, MASS = 1, CM = 2, IP = 1, 1, 1\nMARKER/2, PART = 2\n\
        JOINT/7, SPHERICAL, I = 2, J = 1\nJPRIM/8, PERPENDICULAR, I = 2, J = 1\nEND\n";

    /// An output of `m` with reaction force `f` on each of its constraints.
    fn output(m: &Model, f: &[f64]) -> Output {
        Output {
            time: 0.0,
            state: State::input(m),
            velocities: vec![(DVec3::ZERO, DVec3::ZERO)],
            accelerations: vec![(DVec3::ZERO, DVec3::ZERO)],
            reactions: f
                .iter()
                .enumerate()
                .map(|(element, &x)| Reaction {
                    element,
                    force: DVec3::new(x, 0.0, 0.0),
                    torque: DVec3::ZERO,
                })
                .collect(),
        }
    }

    /// Columns are fixed by the first output and matched by element name afterwards: a model
    /// rebuilt without JOINT_7 (a command file's DEACTIVATE) writes zeros in its columns and
    /// JPRIM_8's value in JPRIM_8's.
    #[test]
    fn element_columns_follow_names_across_rebuilt_models() {
        let both = model(TWO_JOINTS);
        let only8 = model(&TWO_JOINTS.replace("JOINT/7, SPHERICAL, I = 2, J = 1\n", ""));
        let mut csv = CsvHistory::new(Vec::new());
        csv.write(&both, &output(&both, &[1.0, 2.0]), &[], &[])
            .unwrap();
        csv.write(&only8, &output(&only8, &[3.0]), &[], &[])
            .unwrap();
        let text = String::from_utf8(csv.out).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        let header: Vec<&str> = lines[0].split(',').collect();
        let col = |name: &str| header.iter().position(|h| h.starts_with(name)).unwrap();
        let (fx7, fx8) = (col("JOINT_7.fx"), col("JPRIM_8.fx"));
        let row =
            |k: usize| -> Vec<f64> { lines[k].split(',').map(|x| x.parse().unwrap()).collect() };
        assert_eq!((row(1)[fx7], row(1)[fx8]), (1.0, 2.0));
        assert_eq!((row(2)[fx7], row(2)[fx8]), (0.0, 3.0));
    }
}
