//! What the FMU's binary reads from its resources (`resources/linkage-fmu.json`), and the
//! value references of its variables: one layout that the model description and the binary
//! both derive from the same dataset and configuration.

use linkage_api::cosim::Ports;
use serde::{Deserialize, Serialize};

/// The configuration file's name in `resources/`.
pub const CONFIG_FILE: &str = "linkage-fmu.json";

/// A statement argument exposed as an FMU parameter (`SPRINGDAMPER/1.K`), set with
/// [`linkage_api::Source::set`] before the model is loaded.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Parameter {
    /// `KEYWORD/id`.
    pub statement: String,
    /// The argument keyword (`K`).
    pub argument: String,
    /// Its value in the dataset.
    pub start: f64,
}

impl Parameter {
    /// The FMU variable's name: `KEYWORD/id.ARGUMENT`.
    pub fn name(&self) -> String {
        format!("{}.{}", self.statement, self.argument)
    }
}

/// `resources/linkage-fmu.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Config {
    /// The dataset's file name in `resources/`.
    pub dataset: String,
    /// The PINPUT and POUTPUT the plant's ports come from (`None`: the last in the dataset).
    pub pinput: Option<u64>,
    pub poutput: Option<u64>,
    pub parameters: Vec<Parameter>,
    /// The start value of `initial_static`.
    pub initial_static: bool,
    /// The instantiation token (FMI 3.0) or GUID (FMI 2.0) of the model description.
    pub token: String,
}

/// What a value reference names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Slot {
    Time,
    Input(usize),
    Output(usize),
    Parameter(usize),
    InitialStatic,
}

/// The value references of an FMU's variables: time 0, inputs from 1, then outputs,
/// parameters and `initial_static`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    pub inputs: usize,
    pub outputs: usize,
    pub parameters: usize,
}

impl Layout {
    pub fn new(ports: &Ports, config: &Config) -> Layout {
        Layout {
            inputs: ports.inputs.len(),
            outputs: ports.outputs.len(),
            parameters: config.parameters.len(),
        }
    }

    /// The value reference of input `k`.
    pub fn input(&self, k: usize) -> u32 {
        (1 + k) as u32
    }

    pub fn output(&self, k: usize) -> u32 {
        (1 + self.inputs + k) as u32
    }

    pub fn parameter(&self, k: usize) -> u32 {
        (1 + self.inputs + self.outputs + k) as u32
    }

    pub fn initial_static(&self) -> u32 {
        (1 + self.inputs + self.outputs + self.parameters) as u32
    }

    /// What value reference `vr` names (`None`: no such variable).
    pub fn slot(&self, vr: u32) -> Option<Slot> {
        let vr = vr as usize;
        let (i, o, p) = (self.inputs, self.outputs, self.parameters);
        Some(match vr {
            0 => Slot::Time,
            v if v <= i => Slot::Input(v - 1),
            v if v <= i + o => Slot::Output(v - 1 - i),
            v if v <= i + o + p => Slot::Parameter(v - 1 - i - o),
            v if v == i + o + p + 1 => Slot::InitialStatic,
            _ => return None,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_value_reference_names_one_slot_and_back() {
        let l = Layout {
            inputs: 2,
            outputs: 3,
            parameters: 1,
        };
        assert_eq!(l.slot(0), Some(Slot::Time));
        for k in 0..2 {
            assert_eq!(l.slot(l.input(k)), Some(Slot::Input(k)));
        }
        for k in 0..3 {
            assert_eq!(l.slot(l.output(k)), Some(Slot::Output(k)));
        }
        assert_eq!(l.slot(l.parameter(0)), Some(Slot::Parameter(0)));
        assert_eq!(l.slot(l.initial_static()), Some(Slot::InitialStatic));
        assert_eq!(l.slot(l.initial_static() + 1), None);
    }
}
