//! A plant stepped by a co-simulation master (an FMU's `doStep`): the Adams Controls view of a
//! dataset, its inputs the VARIABLEs of a PINPUT and its outputs those of a POUTPUT.
//!
//! ```text
//! Plant::new(loaded, ports) ─set_input*─▶ initialize(statics?) ─▶ [set_input* · step(to) · outputs]*
//! ```
//!
//! - An input is a VARIABLE held at the value the master sets ([`Loaded::hold_variable`]: its
//!   FUNCTION replaced by the number, in the forces every later step runs with): inputs are
//!   held over a step, as Adams Controls' discrete co-simulation holds them.
//! - [`Plant::initialize`] runs the initial conditions at time 0 (and, when asked, the static
//!   equilibrium the dataset's EQUILIBRIUM statement describes, as Adams Controls' initial
//!   static option does) through [`crate::simulate::run`] with the one output time 0.
//! - [`Plant::step`] is [`crate::simulate::run`] from where the last step left the model
//!   ([`Start::Left`], the assembly kept: nothing is compiled or assembled again) to the
//!   communication point, with the dataset's INTEGRATOR settings.
//! - An output is the value of a POUTPUT VARIABLE at the state the last step left.
//! - [`Plant::save`] / [`Plant::restore`]: the state (poses, velocities, control and element
//!   states, time, inputs) a master keeps to roll a step back (FMI's get/set FMU state). The
//!   assembly is the same for every saved state: only what the integration changes is saved.

use crate::error::Error;
use crate::simulate::{SimulateArgs, SimulateRun};
use crate::sink::NoSink;
use crate::source::Loaded;
use crate::start::{Left, Start, Velocities};
use linkage_model::Model;
use linkage_solve::coverage::Analysis;
use linkage_solve::state::State;

/// One plant input or output: a VARIABLE.
#[derive(Clone, Debug, PartialEq)]
pub struct Port {
    /// The VARIABLE's id.
    pub id: u32,
    /// Its name: the `adams_view_name`, else `VARIABLE_id`.
    pub name: String,
    /// The value it starts at: its IC, 0 without one (an input until the master sets it).
    pub start: f64,
}

/// The plant's inputs (PINPUT VARIABLEs in order, each once) and outputs (POUTPUT VARIABLEs,
/// each once, without those that are inputs), and the lists they came from (`None`: all).
#[derive(Clone, Debug, PartialEq)]
pub struct Ports {
    pub pinput: Option<u64>,
    pub poutput: Option<u64>,
    pub inputs: Vec<Port>,
    pub outputs: Vec<Port>,
}

/// Why a plant cannot be made or stepped.
#[derive(Debug, thiserror::Error)]
pub enum CosimError {
    /// The PINPUT or POUTPUT asked for is not in the dataset.
    #[error("{keyword}/{id} is not in the dataset (it has {have})")]
    NoPlantList {
        keyword: &'static str,
        id: u64,
        have: String,
    },
    /// A dataset without PINPUT and POUTPUT has nothing to exchange with a master.
    #[error(
        "the dataset has no PINPUT and no POUTPUT: a co-simulation plant needs its inputs \
         (PINPUT/id, VARIABLES = …) or outputs (POUTPUT/id, VARIABLES = …)"
    )]
    NoPorts,
    /// A VARIABLE id that expressions cannot name.
    #[error("VARIABLE/{0}: the id is too large to be a plant input or output")]
    LargeId(u64),
    /// An input index past the plant's inputs.
    #[error("the plant has {count} inputs; there is no input {index}")]
    NoInput { index: usize, count: usize },
    /// A step or output asked for before [`Plant::initialize`], or after a failed step.
    #[error("the plant is not initialised (or a failed step left it without a state)")]
    NotInitialized,
    /// A communication point before the plant's time.
    #[error("the communication point {to} is before the plant's time {time}")]
    Backwards { time: f64, to: f64 },
    /// An output VARIABLE that cannot be evaluated.
    #[error("output {name} (VARIABLE/{id}) cannot be evaluated: {cause}")]
    Output {
        name: String,
        id: u32,
        cause: String,
    },
    /// The analysis refused the model or stopped on an input error.
    #[error(transparent)]
    Analysis(#[from] Error),
    /// The initial conditions or the integration failed (the report's errors).
    #[error("{0}")]
    Failed(String),
}

/// The ports of `model`: the inputs of PINPUT/`pinput` and the outputs of POUTPUT/`poutput`;
/// without an id, every PINPUT's (POUTPUT's) VARIABLEs in statement order, each once (Adams
/// Controls exports one of each, often repeated under several ids with the same VARIABLEs;
/// datasets written by hand have one per signal).
pub fn ports(
    model: &Model,
    pinput: Option<u64>,
    poutput: Option<u64>,
) -> Result<Ports, CosimError> {
    let controls = &model.controls;
    if controls.pinputs.is_empty() && controls.poutputs.is_empty() {
        return Err(CosimError::NoPorts);
    }
    let pin = pick(&controls.pinputs, "PINPUT", pinput)?;
    let pout = pick(&controls.poutputs, "POUTPUT", poutput)?;
    let inputs = variables(model, &pin, &[])?;
    let outputs = variables(model, &pout, &inputs)?;
    Ok(Ports {
        pinput,
        poutput,
        inputs,
        outputs,
    })
}

/// The VARIABLEs (indices into the model's) of the plant list `id` of `lists` (named
/// `keyword`), or of every list in order when `id` is `None`.
fn pick(
    lists: &[linkage_model::controls::PlantList],
    keyword: &'static str,
    id: Option<u64>,
) -> Result<Vec<usize>, CosimError> {
    let Some(id) = id else {
        return Ok(lists
            .iter()
            .flat_map(|l| l.variables.iter().copied())
            .collect());
    };
    lists
        .iter()
        .find(|l| l.origin.id == id)
        .map(|l| l.variables.clone())
        .ok_or_else(|| {
            let ids: Vec<String> = lists.iter().map(|l| l.origin.id.to_string()).collect();
            let have = if ids.is_empty() {
                format!("no {keyword}")
            } else {
                format!("{keyword} {}", ids.join(", "))
            };
            CosimError::NoPlantList { keyword, id, have }
        })
}

/// The VARIABLEs `indices` (into the model's variables) as ports, each once, without those in
/// `except`.
fn variables(model: &Model, indices: &[usize], except: &[Port]) -> Result<Vec<Port>, CosimError> {
    let mut out: Vec<Port> = Vec::new();
    for &k in indices {
        let v = &model.variables[k];
        let id = u32::try_from(v.origin.id).map_err(|_| CosimError::LargeId(v.origin.id))?;
        if out.iter().chain(except).any(|p| p.id == id) {
            continue;
        }
        out.push(Port {
            id,
            name: v.origin.name.clone(),
            start: v.ic.unwrap_or(0.0),
        });
    }
    Ok(out)
}

/// What a master keeps to go back to a step ([`Plant::save`]).
#[derive(Clone, Debug)]
pub struct PlantState {
    state: State,
    velocities: Velocities,
    inputs: Vec<f64>,
}

impl PlantState {
    /// The plant's time in this state.
    pub fn time(&self) -> f64 {
        self.state.time
    }
}

/// A dataset as a co-simulation plant (see the module documentation).
pub struct Plant {
    loaded: Loaded,
    ports: Ports,
    /// The value each input is held at.
    inputs: Vec<f64>,
    /// Where the last step left the model (`None` before [`Plant::initialize`] and after a
    /// step that failed without an output).
    left: Option<Left>,
}

/// What a step or the initialisation has to say besides its values: the report's notes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Stepped {
    /// Notes of the run (and the model's warnings, with the initialisation).
    pub messages: Vec<String>,
}

impl Plant {
    /// `loaded` (loaded for [`Analysis::Simulate`]) as a plant with `ports`, its inputs held at
    /// their start values.
    pub fn new(loaded: Loaded, ports: Ports) -> Plant {
        let inputs = ports.inputs.iter().map(|p| p.start).collect();
        let mut plant = Plant {
            loaded,
            ports,
            inputs,
            left: None,
        };
        plant.hold_inputs();
        plant
    }

    /// The plant's inputs and outputs.
    pub fn ports(&self) -> &Ports {
        &self.ports
    }

    /// The value each input is held at.
    pub fn inputs(&self) -> &[f64] {
        &self.inputs
    }

    /// The plant's time: that of the state the last step left (0 before the initialisation).
    pub fn time(&self) -> f64 {
        self.left.as_ref().map_or(0.0, |l| l.state.time)
    }

    /// Holds input `index` at `value` from now on (over the next steps).
    pub fn set_input(&mut self, index: usize, value: f64) -> Result<(), CosimError> {
        let count = self.inputs.len();
        let slot = self
            .inputs
            .get_mut(index)
            .ok_or(CosimError::NoInput { index, count })?;
        *slot = value;
        let id = self.ports.inputs[index].id;
        self.loaded.hold_variable(id, value);
        Ok(())
    }

    fn hold_inputs(&mut self) {
        for (p, &v) in self.ports.inputs.iter().zip(&self.inputs) {
            self.loaded.hold_variable(p.id, v);
        }
    }

    /// The initial conditions at time 0 with the inputs as set, then the static equilibrium
    /// when `equilibrium` (the run then starts from it at rest). The model's warnings are the
    /// messages.
    pub fn initialize(&mut self, equilibrium: bool) -> Result<Stepped, CosimError> {
        use linkage_solve::stages::dynamics::Start as DynamicStart;
        let start = if equilibrium {
            DynamicStart::Equilibrium
        } else {
            DynamicStart::InitialConditions
        };
        let (mut messages, notes) = self.run(Start::Input, &[0.0], start)?;
        messages.extend(notes);
        Ok(Stepped { messages })
    }

    /// Integrates from the plant's time to `to` with the inputs held, stopping there.
    pub fn step(&mut self, to: f64) -> Result<Stepped, CosimError> {
        let left = self.left.take().ok_or(CosimError::NotInitialized)?;
        let time = left.state.time;
        if to < time {
            self.left = Some(left);
            return Err(CosimError::Backwards { time, to });
        }
        if to == time {
            self.left = Some(left);
            return Ok(Stepped::default());
        }
        let (_, messages) = self.run(
            Start::Left(Box::new(left)),
            &[time, to],
            linkage_solve::stages::dynamics::Start::InitialConditions,
        )?;
        Ok(Stepped { messages })
    }

    /// One run of [`crate::simulate::run`] from `start` over `times`: the plant keeps where it
    /// left the model; the report's errors fail it, its warnings and notes are returned.
    fn run(
        &mut self,
        start: Start,
        times: &[f64],
        begin: linkage_solve::stages::dynamics::Start,
    ) -> Result<(Vec<String>, Vec<String>), CosimError> {
        let end = times.last().copied().unwrap_or(0.0);
        let args = SimulateArgs {
            times,
            start: begin,
            allow_unstable: true,
            time_limit: None,
            csv: None,
            progress: &mut |_| {},
            interrupted: &|| false,
            observe: None,
        };
        let SimulateRun { report, left, .. } =
            crate::simulate::run(&self.loaded, start, args, &mut NoSink)?;
        let reached = left.as_ref().is_some_and(|l| l.state.time == end);
        self.left = left;
        if !report.errors.is_empty() {
            return Err(CosimError::Failed(report.errors.join("; ")));
        }
        if !reached {
            return Err(CosimError::Failed(format!(
                "the simulation stopped before time {end}"
            )));
        }
        Ok((report.warnings, report.notes))
    }

    /// The outputs at the plant's time, in the order of [`Ports::outputs`].
    pub fn outputs(&self) -> Result<Vec<f64>, CosimError> {
        let left = self.left.as_ref().ok_or(CosimError::NotInitialized)?;
        let forces = self.loaded.forces(Analysis::Simulate)?;
        self.ports
            .outputs
            .iter()
            .map(|p| {
                forces
                    .variable(p.id, &left.state, &left.velocities)
                    .map_err(|cause| CosimError::Output {
                        name: p.name.clone(),
                        id: p.id,
                        cause: cause.to_string(),
                    })
            })
            .collect()
    }

    /// The plant's state, for [`Plant::restore`] (`None` before the initialisation).
    pub fn save(&self) -> Option<PlantState> {
        self.left.as_ref().map(|l| PlantState {
            state: l.state.clone(),
            velocities: l.velocities.clone(),
            inputs: self.inputs.clone(),
        })
    }

    /// Back to `saved` (taken from this plant): the next step continues from it on the same
    /// assembly. Refused before the initialisation (no assembly to continue on).
    pub fn restore(&mut self, saved: &PlantState) -> Result<(), CosimError> {
        let left = self.left.as_mut().ok_or(CosimError::NotInitialized)?;
        left.state = saved.state.clone();
        left.velocities = saved.velocities.clone();
        self.inputs = saved.inputs.clone();
        self.hold_inputs();
        Ok(())
    }
}
