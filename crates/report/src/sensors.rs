//! SENSOR events as the reports show them: which sensor fired, when, with what value and
//! which actions, and the state YYDUMP asked for.

use crate::poses::{part_states, PartStateJson};
use linkage_model::Model;
use linkage_solve::stages::dynamics::{SensorEvent, SensorStop};
use serde::Serialize;
use std::fmt::Write;

#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct SensorEventJson {
    pub name: String,
    pub element: String,
    pub time: f64,
    /// FUNCTION at the event.
    pub function: f64,
    /// The value `SENVAL` returns from then on (EVALUATE, else FUNCTION).
    pub stored: f64,
    pub actions: Vec<&'static str>,
    /// YYDUMP: every part's state at the event.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dump: Option<Vec<PartStateJson>>,
}

/// The events of a run, named for reports.
pub fn events_json(model: &Model, events: &[SensorEvent]) -> Vec<SensorEventJson> {
    events
        .iter()
        .map(|e| SensorEventJson {
            name: e.name.clone(),
            element: e.element.clone(),
            time: e.time,
            function: e.function,
            stored: e.stored,
            actions: e.actions.clone(),
            dump: e
                .dump
                .as_ref()
                .map(|o| part_states(model, &o.state, &o.velocities, Some(&o.accelerations))),
        })
        .collect()
}

/// `HALT` or `RETURN`.
pub fn stop_name(stop: SensorStop) -> &'static str {
    match stop {
        SensorStop::Halt => "HALT",
        SensorStop::Return => "RETURN",
    }
}

/// One line per event (`Sensor SENSOR_1 (SENSOR/1) fired at time 1.0096: FUNCTION = 1e-9;
/// HALT`), the YYDUMP states under it.
pub fn events_text(events: &[SensorEventJson]) -> String {
    let mut s = String::new();
    for e in events {
        let actions = if e.actions.is_empty() {
            "no action".to_string()
        } else {
            e.actions.join(", ")
        };
        let _ = writeln!(
            s,
            "Sensor {} ({}) fired at time {}: FUNCTION = {:.6e}, stored (SENVAL) {:.6e}; {actions}",
            e.name, e.element, e.time, e.function, e.stored
        );
        for p in e.dump.iter().flatten() {
            let _ = writeln!(
                s,
                "   YYDUMP {:<24} position ({:.6e}, {:.6e}, {:.6e})  velocity ({:.6e}, {:.6e}, {:.6e})",
                p.name,
                p.position[0],
                p.position[1],
                p.position[2],
                p.velocity[0],
                p.velocity[1],
                p.velocity[2]
            );
        }
    }
    s
}
