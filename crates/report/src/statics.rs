//! The static-equilibrium report: text, JSON and CSV.

use crate::num::{general, sci, TIME_DIGITS};
use crate::poses::{part_poses, pose_line, PartPoseJson};
use crate::reactions::{reaction_table, reactions_json, ReactionJson};
use crate::units::{text_line, units_json, Angle, UnitsJson};
use linkage_adm::Diagnostic;
use linkage_model::settings::shown;
use linkage_model::Model;
use linkage_solve::constraints::system::System;
use linkage_solve::pipeline::{Assembled, NotAssembled};
use linkage_solve::stages::settle::{SettleOutcome, SettleStop};
use linkage_solve::stages::stable_equilibrium::Search;
use linkage_solve::stages::statics::{Equilibrium, StaticRun};
use serde::Serialize;
use std::fmt::Write;

#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct ImbalanceJson {
    pub name: String,
    pub equation: String,
    pub value: f64,
}

#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct StepJson {
    pub time: f64,
    pub converged: bool,
    pub iterations: usize,
    pub imbalance: f64,
    /// `null` when not evaluated (zero DOF, or a model too large for the dense check).
    pub stable: Option<bool>,
    pub lowest_stiffness: Option<f64>,
    pub parts: Vec<PartPoseJson>,
    pub reactions: Vec<ReactionJson>,
    pub largest_imbalance: Vec<ImbalanceJson>,
    /// The Newton correction was unbounded: the largest imbalances act along free motions
    /// nothing resists (no equilibrium near).
    pub unbounded: bool,
    pub error: Option<String>,
}

/// The JSON document of `linkage static --format json`: the first step's values at the top
/// level, and `steps` for a quasi-static series.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct StaticJson {
    pub file: String,
    pub title: String,
    /// Positions, 3-1-3 angles (degrees) and reactions.
    pub units: UnitsJson,
    /// Statements left out on request (`--deactivate`).
    pub left_out: Vec<crate::coverage::LeftOutJson>,
    /// Statements this analysis ran without (not modelled, not used by it).
    pub runs_without: Vec<crate::coverage::FindingJson>,
    pub converged: bool,
    pub iterations: usize,
    pub imbalance: f64,
    pub stable: Option<bool>,
    /// Lowest eigenvalue of the reduced stiffness (force × length per unit free motion, with
    /// translations over the characteristic length): negative means unstable.
    pub lowest_stiffness: Option<f64>,
    /// The model has no degrees of freedom: solved kinematically.
    pub kinematic: bool,
    pub parts: Vec<PartPoseJson>,
    /// The FLEX_BODYs' modal coordinates at the first step (only when there are some).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub modal_coordinates: Vec<crate::flex::ModalJson>,
    pub reactions: Vec<ReactionJson>,
    /// Joint friction at the reported state (only when the model has FRICTION elements).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub frictions: Vec<crate::friction::FrictionJson>,
    /// Curve constraints' contacts at the reported state (only when the model has PTCVs or
    /// CVCVs).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub curve_contacts: Vec<crate::curve_contacts::CurveContactJson>,
    pub steps: Vec<StepJson>,
    /// The SENSORs that fired during a quasi-static series, in time order.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub sensors: Vec<crate::sensors::SensorEventJson>,
    /// `SENSOR_1 (HALT)` when a sensor ended the series (complete) at its event.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ended_by_sensor: Option<String>,
    /// When found by damped dynamics: what stopped the settling.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub settling: Option<SettlingJson>,
    /// One equilibrium by the search for a stable one: which path found it and every path
    /// tried (`linkage_solve::stages::stable_equilibrium`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub search: Option<SearchJson>,
    pub warnings: Vec<String>,
    pub errors: Vec<String>,
    /// The model's force scale ([`crate::reactions::weight_scale`]): what the text's reaction
    /// table judges rounding noise against (not in the JSON).
    #[serde(skip)]
    pub force_scale: f64,
}

/// How dynamic settling ended, with the limits it was judged against (EQUILIBRIUM/DYNAMIC).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct SettlingJson {
    /// `settled` (kinetic energy and acceleration below their limits), `settling_time` (ran out:
    /// not settled) or `failed`.
    pub criterion: &'static str,
    pub settling_time_used: f64,
    /// Kinetic energy when the settling stopped (model force × length).
    pub kinetic_energy: Option<f64>,
    /// Largest CM or angular acceleration of a part when the settling stopped.
    pub acceleration: Option<f64>,
    pub kinetic_energy_limit: f64,
    pub acceleration_limit: f64,
    /// The settling time the integration was allowed (the dataset's SETTLING_TIME, or adapted
    /// to the slowest mode when the damping was chosen from the model).
    pub settling_time_limit: f64,
    /// The dataset's GLOBAL_DAMPING.
    pub global_damping: f64,
    /// The damping `c` the settling used (per time unit).
    pub damping: f64,
    /// The damping and settling time were chosen from the model's lowest mode (GLOBAL_DAMPING
    /// was 0).
    pub damping_from_model: bool,
    /// The lowest angular frequency they were chosen from (rad per time unit).
    pub lowest_frequency: Option<f64>,
    /// Whether the Newton polish from the settled configuration converged (`null`: not run).
    pub polish_converged: Option<bool>,
    /// Every part where the damped integration stopped, before the polish.
    pub settled_parts: Vec<PartPoseJson>,
    pub message: Option<String>,
}

/// The settling summary of an outcome (`None`: the model could not be assembled, nothing
/// was integrated).
pub fn settling_summary(model: &Model, outcome: Option<&SettleOutcome>) -> SettlingJson {
    let eq = &model.equilibrium;
    let (criterion, ke, acc, message) = match outcome.map(|o| &o.stop) {
        Some(SettleStop::Settled {
            kinetic_energy,
            acceleration,
        }) => ("settled", Some(*kinetic_energy), Some(*acceleration), None),
        Some(SettleStop::SettlingTime {
            kinetic_energy,
            acceleration,
        }) => (
            "settling_time",
            Some(*kinetic_energy),
            Some(*acceleration),
            None,
        ),
        Some(SettleStop::Failed(m)) => ("failed", None, None, Some(m.to_string())),
        None => (
            "failed",
            None,
            None,
            Some("the model could not be assembled".to_string()),
        ),
    };
    let time_used = outcome.map_or(0.0, |o| o.time_used);
    let polish_converged = outcome
        .and_then(|o| o.equilibrium.as_ref())
        .map(|e| e.as_ref().is_ok_and(|e| e.converged));
    SettlingJson {
        criterion,
        settling_time_used: time_used,
        kinetic_energy: ke,
        acceleration: acc,
        kinetic_energy_limit: eq.kinetic_energy_error,
        acceleration_limit: eq.acceleration_error,
        settling_time_limit: outcome.map_or(eq.settling_time, |o| o.choice.settling_time),
        global_damping: eq.global_damping,
        damping: outcome.map_or(eq.global_damping, |o| o.choice.damping),
        damping_from_model: outcome.is_some_and(|o| o.choice.from_model),
        lowest_frequency: outcome.and_then(|o| o.choice.lowest_frequency),
        polish_converged,
        settled_parts: outcome.map_or_else(Vec::new, |o| part_poses(model, &o.state)),
        message,
    }
}

/// The note for settling without GLOBAL_DAMPING: with `−c m v` on every part a mode of
/// natural frequency ω gets the damping ratio `c / 2ω`, so the settling chose `c = 2ω₁` of
/// the lowest mode (critical damping, `linkage_solve::stages::settle::choose`).
pub const NO_GLOBAL_DAMPING: &str = "GLOBAL_DAMPING is 0 (the default): the settling damped \
    every part with twice the lowest natural frequency of the model (critical damping of its \
    lowest mode) and adapted the settling time to that mode; a positive GLOBAL_DAMPING sets \
    both from the dataset instead";

/// One line saying how the settling ended, against its limits.
pub fn settling_line(st: &SettlingJson) -> String {
    let values = |ke: Option<f64>, acc: Option<f64>| match (ke, acc) {
        (Some(ke), Some(acc)) => format!(
            "kinetic energy {} (KINETIC_ENERGY_ERROR {}), largest acceleration {} \
             (ACCELERATION_ERROR {})",
            sci(ke, 4),
            sci(st.kinetic_energy_limit, 4),
            sci(acc, 4),
            sci(st.acceleration_limit, 4)
        ),
        _ => String::new(),
    };
    let body = match st.criterion {
        "settled" => format!(
            "settled after {} time units: {}",
            shown(st.settling_time_used),
            values(st.kinetic_energy, st.acceleration)
        ),
        "settling_time" => format!(
            "did NOT settle: {} {} ran out with {}",
            if st.damping_from_model {
                "the settling time"
            } else {
                "SETTLING_TIME"
            },
            shown(st.settling_time_limit),
            values(st.kinetic_energy, st.acceleration)
        ),
        _ => format!(
            "FAILED after {} time units: {}",
            shown(st.settling_time_used),
            st.message.clone().unwrap_or_default()
        ),
    };
    let damping = if st.damping_from_model {
        let from = st.lowest_frequency.map_or_else(
            || "the model (no mode with stiffness was found)".to_string(),
            |w| format!("the lowest mode, ω₁ = {} rad per time unit", sci(w, 4)),
        );
        format!(
            "damping {} chosen from {from}, as GLOBAL_DAMPING is 0; settling time {}",
            sci(st.damping, 4),
            sci(st.settling_time_limit, 4)
        )
    } else {
        format!("GLOBAL_DAMPING {}", shown(st.global_damping))
    };
    format!("Dynamic settling ({damping}, time frozen at the start) {body}")
}

/// How the search for a stable equilibrium went.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct SearchJson {
    /// `newton`, `descent` or `settling`: the path whose equilibrium is reported (`newton`
    /// also when none was found: its solve is the one reported).
    pub path: &'static str,
    /// Whether an equilibrium was accepted.
    pub found: bool,
    pub attempts: Vec<AttemptJson>,
}

/// One path the search tried.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct AttemptJson {
    pub path: &'static str,
    /// Newton iterations, descent steps (one Newton step each), or the settling's polish
    /// iterations.
    pub iterations: usize,
    pub converged: bool,
    pub stable: Option<bool>,
    pub outcome: String,
}

/// The search's summary.
pub fn search_json(s: &Search, found: bool) -> SearchJson {
    SearchJson {
        path: s.path.name(),
        found,
        attempts: s
            .attempts
            .iter()
            .map(|a| AttemptJson {
                path: a.path.name(),
                iterations: a.iterations,
                converged: a.converged,
                stable: a.stable,
                outcome: a.outcome.clone(),
            })
            .collect(),
    }
}

/// One line per path tried: `Found by descent after newton: did not converge in 25 …`.
pub fn search_text(s: &SearchJson) -> String {
    let mut out = String::new();
    if s.found {
        let _ = writeln!(out, "Found by {}.", s.path);
    } else {
        let _ = writeln!(out, "No equilibrium was accepted.");
    }
    if s.attempts.len() > 1 || !s.found {
        for a in &s.attempts {
            let _ = writeln!(
                out,
                "  {:<9} {:>5} iterations: {}",
                a.path, a.iterations, a.outcome
            );
        }
    }
    out
}

/// One output time of a static run; a step whose equilibrium could not be computed carries the
/// error's text.
fn step_json<E: std::fmt::Display>(
    model: &Model,
    sys: &System,
    t: f64,
    e: &Result<Equilibrium, E>,
) -> StepJson {
    match e {
        Ok(eq) => StepJson {
            time: t,
            converged: eq.converged,
            iterations: eq.iterations,
            imbalance: eq.imbalance,
            stable: eq.stability.map(|s| s.0),
            lowest_stiffness: eq.stability.map(|s| s.1),
            parts: part_poses(model, &eq.state),
            reactions: reactions_json(model, &eq.reactions),
            largest_imbalance: if eq.converged {
                Vec::new()
            } else {
                eq.worst
                    .iter()
                    .map(|(w, v)| {
                        let (name, equation) = w.describe(model, sys);
                        ImbalanceJson {
                            name,
                            equation,
                            value: *v,
                        }
                    })
                    .collect()
            },
            unbounded: eq.unbounded,
            error: None,
        },
        Err(msg) => StepJson {
            time: t,
            converged: false,
            iterations: 0,
            imbalance: f64::NAN,
            stable: None,
            lowest_stiffness: None,
            parts: Vec::new(),
            reactions: Vec::new(),
            largest_imbalance: Vec::new(),
            unbounded: false,
            error: Some(msg.to_string()),
        },
    }
}

/// Builds the JSON document.
pub fn to_json(a: &Assembled, run: &StaticRun, warnings: &[Diagnostic]) -> StaticJson {
    let model = a.model;
    let steps: Vec<StepJson> = run
        .steps
        .iter()
        .map(|(t, e)| step_json(model, &a.system, *t, e))
        .collect();
    let mut errors = Vec::new();
    let mut warnings: Vec<String> = warnings.iter().map(|w| w.to_string()).collect();
    if let Some(why) = a.failure() {
        errors.push(why.to_string());
    }
    for (t, e) in &run.steps {
        let why = match e {
            Err(e) => Some(e.to_string()),
            Ok(eq) => eq.failure(model, &a.system),
        };
        if let Some(why) = why {
            errors.push(format!("time {}: {why}", general(*t, TIME_DIGITS)));
        }
    }
    let kinematic = run
        .steps
        .first()
        .is_some_and(|(_, e)| e.as_ref().is_ok_and(|e| e.kinematic));
    if kinematic {
        warnings.push("the model has no degrees of freedom (kinematically determinate): there is no static problem; positions come from the constraints and the reactions balance the loads".into());
    }
    if run
        .steps
        .iter()
        .any(|(_, e)| e.as_ref().is_ok_and(|e| e.approximate_rows > 0))
    {
        warnings.push("the second derivatives of some general constraints (GCON) could not be evaluated at the solution: their geometric stiffness is omitted from the Newton matrix and the stability verdict".into());
    }
    let first = steps.first();
    StaticJson {
        file: model.file.to_string(),
        title: model.title.clone(),
        units: units_json(model, Angle::Degree, false),
        left_out: Vec::new(),
        runs_without: Vec::new(),
        converged: run.converged(),
        iterations: first.map_or(0, |s| s.iterations),
        imbalance: first.map_or(f64::NAN, |s| s.imbalance),
        stable: first.and_then(|s| s.stable),
        lowest_stiffness: first.and_then(|s| s.lowest_stiffness),
        kinematic,
        parts: first.map(|s| s.parts.clone()).unwrap_or_default(),
        modal_coordinates: match run.steps.first() {
            Some((_, Ok(eq))) => crate::flex::modal_json(model, &eq.state, None),
            _ => Vec::new(),
        },
        reactions: first.map(|s| s.reactions.clone()).unwrap_or_default(),
        frictions: Vec::new(),
        curve_contacts: Vec::new(),
        steps: if steps.len() > 1 { steps } else { Vec::new() },
        sensors: crate::sensors::events_json(model, &run.sensor_events),
        ended_by_sensor: run.stopped_by_sensor.and_then(|stop| {
            let last = run.sensor_events.last()?;
            Some(format!(
                "{} ({})",
                last.name,
                crate::sensors::stop_name(stop)
            ))
        }),
        settling: None,
        search: None,
        warnings,
        errors,
        force_scale: crate::reactions::weight_scale(model),
    }
}

/// Human report.
pub fn to_text(j: &StaticJson) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "STATIC EQUILIBRIUM: {}", j.title);
    let _ = writeln!(s, "  file: {}", j.file);
    let _ = writeln!(s, "{}", text_line(&j.units));
    s.push_str(&crate::coverage::analysis_text(
        &j.left_out,
        &j.runs_without,
    ));
    let _ = writeln!(s);
    let series: Vec<&StepJson> = j.steps.iter().collect();
    s.push_str(&crate::sensors::events_text(&j.sensors));
    if let (Some(by), Some(last)) = (&j.ended_by_sensor, j.steps.last()) {
        let _ = writeln!(
            s,
            "The series was ended at time {} by {by}.",
            general(last.time, TIME_DIGITS)
        );
    }
    if let Some(st) = &j.settling {
        let _ = writeln!(s, "{}", settling_line(st));
    }
    if let Some(search) = &j.search {
        s.push_str(&search_text(search));
    }
    if series.is_empty() {
        // After settling, the Newton iteration is the polish: its own convergence is stated;
        // the settling verdict is on the line above.
        let converged = match &j.settling {
            Some(st) => st.polish_converged,
            None => Some(j.converged),
        };
        let unsettled = j
            .settling
            .as_ref()
            .is_some_and(|st| st.criterion != "settled");
        match converged {
            Some(c) if unsettled => {
                let _ = writeln!(
                    s,
                    "Newton polish from where the settling stopped {} in {} iterations; not \
                     accepted as the equilibrium: the model did not settle.",
                    if c { "converged" } else { "did not converge" },
                    j.iterations
                );
            }
            Some(c) => {
                let _ = writeln!(
                    s,
                    "{} {} in {} iterations; residual imbalance {}",
                    if j.settling.is_some() {
                        "Newton polish"
                    } else {
                        "Static solution"
                    },
                    if c { "converged" } else { "DID NOT CONVERGE" },
                    j.iterations,
                    sci(j.imbalance, 5)
                );
            }
            None => {
                let _ = writeln!(s, "No Newton polish was run.");
            }
        }
        match j.stable.filter(|_| !unsettled) {
            Some(true) => {
                let _ = writeln!(s, "The equilibrium is stable.");
            }
            Some(false) => {
                let _ = writeln!(
                    s,
                    "The equilibrium is UNSTABLE (negative stiffness {} along a free motion).",
                    sci(j.lowest_stiffness.unwrap_or(f64::NAN), 4)
                );
            }
            None => {}
        }
        let _ = writeln!(s);
        let _ = writeln!(
            s,
            "Parts (centre of mass in ground, body 3-1-3 angles in degrees):"
        );
        for p in &j.parts {
            let _ = writeln!(s, "{}", pose_line(&p.name, p.position, p.reuler));
        }
        if !j.reactions.is_empty() {
            let _ = writeln!(s);
            let _ = writeln!(s, "Reactions on the I markers (ground axes):");
            reaction_table(&mut s, &j.reactions, j.force_scale);
        }
        crate::friction::friction_table(&mut s, &j.frictions);
        crate::curve_contacts::curve_contact_table(&mut s, &j.curve_contacts);
    } else {
        let _ = writeln!(
            s,
            "Quasi-static series: {} output times, {}",
            series.len(),
            if j.converged {
                "all converged"
            } else {
                "STOPPED"
            }
        );
        let _ = writeln!(
            s,
            "   {:>12} {:>10} {:>14} {:>8}",
            "time", "iterations", "imbalance", "stable"
        );
        for st in series {
            let stable = match st.stable {
                Some(true) => "yes",
                Some(false) => "NO",
                None => "-",
            };
            let _ = writeln!(
                s,
                "   {:>12.6} {:>10} {:>14} {:>8}",
                st.time,
                st.iterations,
                sci(st.imbalance, 5),
                stable
            );
        }
    }
    for w in &j.warnings {
        let _ = writeln!(s, "warning: {w}");
    }
    for e in &j.errors {
        let _ = writeln!(s, "error: {e}");
    }
    s
}

/// The report of a dynamic settling (`linkage static --settle`).
pub fn settling_json(
    a: &Assembled,
    settled: Result<SettleOutcome, NotAssembled>,
    warnings: &[Diagnostic],
) -> StaticJson {
    let model = a.model;
    let outcome = settled.ok();
    let settling = settling_summary(model, outcome.as_ref());
    let run = StaticRun {
        steps: outcome
            .and_then(|o| o.equilibrium)
            .map(|e| vec![(0.0, e)])
            .unwrap_or_default(),
        sensor_events: Vec::new(),
        stopped_by_sensor: None,
    };
    let mut j = to_json(a, &run, warnings);
    if settling.criterion != "settled" {
        j.converged = false;
        j.errors.push(match settling.criterion {
            "settling_time" if settling.damping_from_model => format!(
                "the model did not settle within settling time {} with damping {} chosen from \
                 its lowest mode: its motion does not die out under near-critical damping, so \
                 it has no stable equilibrium it can come to rest in from here (a free motion \
                 under a load nothing resists, or a force that keeps feeding energy)",
                sci(settling.settling_time_limit, 4),
                sci(settling.damping, 4)
            ),
            "settling_time" => format!(
                "the model did not settle within SETTLING_TIME = {} (GLOBAL_DAMPING {}): raise \
                 GLOBAL_DAMPING or SETTLING_TIME on the EQUILIBRIUM statement, or set \
                 GLOBAL_DAMPING 0 to have the damping chosen from the model",
                shown(settling.settling_time_limit),
                shown(settling.global_damping)
            ),
            _ => format!(
                "dynamic settling failed: {}",
                settling.message.clone().unwrap_or_default()
            ),
        });
    }
    j.settling = Some(settling);
    j
}

/// The verdict on an unstable equilibrium, for a run that does not accept one: the first
/// output time whose converged equilibrium is unstable, in one line with what to try (`None`
/// when every equilibrium is stable or its stability is unknown). A report that already
/// failed gets no second verdict.
pub fn unstable_verdict(j: &StaticJson) -> Option<String> {
    if !j.errors.is_empty() {
        return None;
    }
    let (time, stiffness) = if j.steps.is_empty() {
        (
            None,
            j.lowest_stiffness.filter(|_| j.stable == Some(false))?,
        )
    } else {
        let st = j.steps.iter().find(|st| st.stable == Some(false))?;
        (Some(st.time), st.lowest_stiffness?)
    };
    let at = time.map_or(String::new(), |t| {
        format!(" at time {}", general(t, TIME_DIGITS))
    });
    let try_next = if j.settling.is_some() {
        "pass --allow-unstable to accept it"
    } else if j.search.is_some() {
        "neither the descent nor damped settling found a stable one; pass --allow-unstable to \
         accept it"
    } else {
        // A quasi-static series (`--settle` takes no series): each equilibrium continues
        // from the last, with Newton alone.
        "the series follows the equilibrium it started from (a static analysis without a \
         series searches for a stable one); pass --allow-unstable to accept it"
    };
    Some(format!(
        "the equilibrium{at} is UNSTABLE (negative stiffness {} along a free motion): \
         {try_next}",
        sci(stiffness, 4)
    ))
}
