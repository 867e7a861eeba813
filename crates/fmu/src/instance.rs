//! One FMU instance, FMI-version-free: the configuration and dataset read from the resources,
//! the values the master set, and the plant once the initialisation ends. The C functions of
//! [`crate::fmi3`] and [`crate::fmi2`] translate to and from it.
//!
//! Life: instantiated (the dataset read and loaded, its ports checked against the
//! configuration) → initialisation (inputs, parameters and `initial_static` set) → the plant
//! is made (the parameters applied with [`Source::set`] and the model loaded again when one
//! changed), its initial conditions (and statics) run, and it is stepped to the start time
//! when that is not 0 → steps → terminated. A failure leaves the instance failed: only reset
//! and free are then accepted.

use crate::config::{Config, Layout, Slot, CONFIG_FILE};
use linkage_api::cosim::{ports, Plant, PlantState, Ports};
use linkage_api::{ArgValue, Loaded, Source};
use linkage_solve::coverage::Analysis;
use std::path::Path;

/// An FMI status (the same numbers in FMI 2.0 and 3.0).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(i32)]
pub enum Status {
    Ok = 0,
    Warning = 1,
    Discard = 2,
    Error = 3,
    Fatal = 4,
}

/// The importer's logger: status, category, message.
pub type Logger = Box<dyn Fn(Status, &str, &str)>;

/// Where the instance is in its life.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Phase {
    Instantiated,
    Initialization,
    Stepping,
    Terminated,
    Failed,
}

/// Why a call was refused (the message goes to the logger with [`Status::Error`]).
#[derive(Debug, thiserror::Error)]
pub enum FmuError {
    #[error("cannot read {path}: {why}")]
    Resources { path: String, why: String },
    #[error("the instantiation token {given} is not this FMU's ({own})")]
    Token { given: String, own: String },
    #[error("the dataset: {0}")]
    Dataset(String),
    #[error("no variable has value reference {0}")]
    NoVariable(u32),
    #[error("value reference {vr} is not a {kind} variable")]
    WrongType { vr: u32, kind: &'static str },
    #[error("{what} cannot be set {when}")]
    NotSettable {
        what: &'static str,
        when: &'static str,
    },
    #[error("{call} is not allowed {when}")]
    Phase {
        call: &'static str,
        when: &'static str,
    },
    #[error(
        "the step starts at {given}, but the plant is at {time}; step from where the last \
         step ended"
    )]
    Discontinuous { given: f64, time: f64 },
    #[error("{0}")]
    Plant(#[from] linkage_api::cosim::CosimError),
    #[error("{0}")]
    Unsupported(&'static str),
}

/// One FMU instance (see the module documentation).
pub struct Instance {
    pub name: String,
    config: Config,
    source: Source,
    /// The model as loaded at instantiation (used when no parameter changed).
    loaded: Option<Loaded>,
    ports: Ports,
    layout: Layout,
    inputs: Vec<f64>,
    parameters: Vec<f64>,
    initial_static: bool,
    start_time: f64,
    plant: Option<Plant>,
    /// The outputs at the plant's time (after each step).
    outputs: Vec<f64>,
    phase: Phase,
    logger: Logger,
    /// Whether the importer wants the informational messages (warnings and errors are
    /// always logged).
    pub logging_on: bool,
}

/// A saved instance state (FMI's FMU state).
pub struct SavedState {
    plant: Option<PlantState>,
    inputs: Vec<f64>,
    outputs: Vec<f64>,
}

fn read_text(path: &Path) -> Result<String, FmuError> {
    std::fs::read_to_string(path).map_err(|e| FmuError::Resources {
        path: path.display().to_string(),
        why: e.to_string(),
    })
}

impl Instance {
    /// The instance of the FMU whose resources are in `resources`, checked against the
    /// instantiation token `token` (`None`: not checked).
    pub fn new(
        name: String,
        resources: &Path,
        token: Option<&str>,
        logger: Logger,
        logging_on: bool,
    ) -> Result<Instance, FmuError> {
        let config_path = resources.join(CONFIG_FILE);
        let config: Config =
            serde_json::from_str(&read_text(&config_path)?).map_err(|e| FmuError::Resources {
                path: config_path.display().to_string(),
                why: e.to_string(),
            })?;
        if let Some(given) = token.filter(|t| *t != config.token) {
            return Err(FmuError::Token {
                given: given.to_string(),
                own: config.token.clone(),
            });
        }
        let source = Source::read(&resources.join(&config.dataset))
            .map_err(|d| FmuError::Dataset(d.to_string()))?;
        let loaded = source
            .load(&[], Some(Analysis::Simulate))
            .map_err(|d| FmuError::Dataset(d.to_string()))?;
        let ports = ports(&loaded.model, config.pinput, config.poutput)?;
        let layout = Layout::new(&ports, &config);
        let instance = Instance {
            name,
            inputs: ports.inputs.iter().map(|p| p.start).collect(),
            parameters: config.parameters.iter().map(|p| p.start).collect(),
            initial_static: config.initial_static,
            outputs: vec![0.0; ports.outputs.len()],
            config,
            source,
            loaded: Some(loaded),
            ports,
            layout,
            start_time: 0.0,
            plant: None,
            phase: Phase::Instantiated,
            logger,
            logging_on,
        };
        for w in instance
            .loaded
            .as_ref()
            .map_or(&[][..], |l| &l.warnings[..])
        {
            let message = w.to_string();
            (instance.logger)(Status::Warning, "logStatusWarning", &message);
        }
        Ok(instance)
    }

    /// Hands `message` to the importer's logger.
    pub fn log(&self, status: Status, message: &str) {
        let category = match status {
            Status::Ok => "logEvents",
            Status::Warning => "logStatusWarning",
            Status::Discard => "logStatusDiscard",
            Status::Error => "logStatusError",
            Status::Fatal => "logStatusFatal",
        };
        if status != Status::Ok || self.logging_on {
            (self.logger)(status, category, message);
        }
    }

    /// `Ok` as it is, an error logged and turned into its status (a failed plant makes
    /// every later call but reset and free an error).
    pub fn status(&mut self, result: Result<(), FmuError>) -> Status {
        match result {
            Ok(()) => Status::Ok,
            Err(e) => {
                self.log(Status::Error, &e.to_string());
                if matches!(e, FmuError::Plant(_)) {
                    self.phase = Phase::Failed;
                }
                Status::Error
            }
        }
    }

    fn usable(&self, call: &'static str) -> Result<(), FmuError> {
        match self.phase {
            Phase::Failed => Err(FmuError::Phase {
                call,
                when: "after an error (reset or free the instance)",
            }),
            _ => Ok(()),
        }
    }

    /// Sets the Float64 (Real) variable `vr`.
    pub fn set_real(&mut self, vr: u32, value: f64) -> Result<(), FmuError> {
        self.usable("setting a variable")?;
        match self.layout.slot(vr).ok_or(FmuError::NoVariable(vr))? {
            Slot::Input(k) => {
                self.inputs[k] = value;
                if let Some(p) = self.plant.as_mut() {
                    p.set_input(k, value)?;
                }
                Ok(())
            }
            Slot::Parameter(k) => {
                if self.plant.is_some() {
                    return Err(FmuError::NotSettable {
                        what: "a fixed parameter",
                        when: "after the initialisation",
                    });
                }
                self.parameters[k] = value;
                Ok(())
            }
            Slot::Time | Slot::Output(_) => Err(FmuError::NotSettable {
                what: "time or an output",
                when: "by the master",
            }),
            Slot::InitialStatic => Err(FmuError::WrongType {
                vr,
                kind: "Float64",
            }),
        }
    }

    /// The Float64 (Real) variable `vr`; an output asked for during the initialisation
    /// makes the plant (its initial conditions) first.
    pub fn get_real(&mut self, vr: u32) -> Result<f64, FmuError> {
        self.usable("getting a variable")?;
        match self.layout.slot(vr).ok_or(FmuError::NoVariable(vr))? {
            Slot::Time => Ok(self.plant.as_ref().map_or(self.start_time, Plant::time)),
            Slot::Input(k) => Ok(self.inputs[k]),
            Slot::Output(k) => {
                if self.plant.is_none() && self.phase == Phase::Initialization {
                    self.make_plant()?;
                }
                Ok(self.outputs[k])
            }
            Slot::Parameter(k) => Ok(self.parameters[k]),
            Slot::InitialStatic => Err(FmuError::WrongType {
                vr,
                kind: "Float64",
            }),
        }
    }

    pub fn set_bool(&mut self, vr: u32, value: bool) -> Result<(), FmuError> {
        self.usable("setting a variable")?;
        match self.layout.slot(vr).ok_or(FmuError::NoVariable(vr))? {
            Slot::InitialStatic if self.plant.is_none() => {
                self.initial_static = value;
                Ok(())
            }
            Slot::InitialStatic => Err(FmuError::NotSettable {
                what: "initial_static",
                when: "after the initialisation",
            }),
            _ => Err(FmuError::WrongType {
                vr,
                kind: "Boolean",
            }),
        }
    }

    pub fn get_bool(&mut self, vr: u32) -> Result<bool, FmuError> {
        match self.layout.slot(vr).ok_or(FmuError::NoVariable(vr))? {
            Slot::InitialStatic => Ok(self.initial_static),
            _ => Err(FmuError::WrongType {
                vr,
                kind: "Boolean",
            }),
        }
    }

    /// The start time FMI 2.0's setup gives for the initialisation that follows.
    pub fn setup(&mut self, start_time: f64) {
        self.start_time = start_time;
    }

    /// The start time of the initialisation (0 unless set up otherwise).
    pub fn start_time(&self) -> f64 {
        self.start_time
    }

    /// Enters the initialisation at `start_time`.
    pub fn enter_initialization(&mut self, start_time: f64) -> Result<(), FmuError> {
        if self.phase != Phase::Instantiated {
            return Err(FmuError::Phase {
                call: "entering the initialisation",
                when: "now (only right after instantiation or a reset)",
            });
        }
        if !(start_time.is_finite() && start_time >= 0.0) {
            return Err(FmuError::Unsupported(
                "the plant starts at time 0 (its dataset's IC): the start time must be 0 or later",
            ));
        }
        self.start_time = start_time;
        self.phase = Phase::Initialization;
        Ok(())
    }

    /// Ends the initialisation: the plant is made (if an output did not make it already).
    pub fn exit_initialization(&mut self) -> Result<(), FmuError> {
        if self.phase != Phase::Initialization {
            return Err(FmuError::Phase {
                call: "exiting the initialisation",
                when: "outside it",
            });
        }
        if self.plant.is_none() {
            self.make_plant()?;
        }
        self.phase = Phase::Stepping;
        Ok(())
    }

    /// The model with the parameters set, as a plant with the inputs set, initialised.
    fn make_plant(&mut self) -> Result<(), FmuError> {
        let changed: Vec<usize> = (0..self.parameters.len())
            .filter(|&k| self.parameters[k] != self.config.parameters[k].start)
            .collect();
        let loaded = if changed.is_empty() {
            match self.loaded.take() {
                Some(l) => l,
                None => self.load(&self.source.clone())?,
            }
        } else {
            let mut source = self.source.clone();
            for k in changed {
                let p = &self.config.parameters[k];
                source
                    .set(
                        &p.statement,
                        &p.argument,
                        &ArgValue::Number(self.parameters[k]),
                    )
                    .map_err(|d| FmuError::Dataset(d.to_string()))?;
            }
            self.load(&source)?
        };
        let mut plant = Plant::new(loaded, self.ports.clone());
        for (k, &v) in self.inputs.iter().enumerate() {
            plant.set_input(k, v)?;
        }
        let result = plant.initialize(self.initial_static);
        let started = match result {
            Ok(s) => s,
            Err(e) => {
                self.phase = Phase::Failed;
                return Err(e.into());
            }
        };
        for m in &started.messages {
            self.log(Status::Ok, m);
        }
        if self.start_time > 0.0 {
            plant.step(self.start_time)?;
        }
        self.outputs = plant.outputs()?;
        self.plant = Some(plant);
        Ok(())
    }

    fn load(&self, source: &Source) -> Result<Loaded, FmuError> {
        source
            .load(&[], Some(Analysis::Simulate))
            .map_err(|d| FmuError::Dataset(d.to_string()))
    }

    /// One communication step from `time` (where the last ended) by `step`.
    pub fn do_step(&mut self, time: f64, step: f64) -> Result<(), FmuError> {
        if self.phase != Phase::Stepping {
            return Err(FmuError::Phase {
                call: "a step",
                when: "before the initialisation ends, after an error or termination",
            });
        }
        let plant = self.plant.as_mut().ok_or(FmuError::Phase {
            call: "a step",
            when: "without a plant",
        })?;
        let at = plant.time();
        if (time - at).abs() > 1e-9 * at.abs().max(1.0) {
            return Err(FmuError::Discontinuous {
                given: time,
                time: at,
            });
        }
        if !(step.is_finite() && step >= 0.0) {
            return Err(FmuError::Unsupported(
                "the step size must be finite and not negative",
            ));
        }
        let stepped = plant.step(time + step);
        let stepped = match stepped {
            Ok(s) => s,
            Err(e) => {
                self.phase = Phase::Failed;
                return Err(e.into());
            }
        };
        let outputs = plant.outputs();
        for m in &stepped.messages {
            self.log(Status::Ok, m);
        }
        self.outputs = outputs?;
        Ok(())
    }

    pub fn terminate(&mut self) -> Result<(), FmuError> {
        self.phase = Phase::Terminated;
        Ok(())
    }

    /// Back to just after instantiation, every value at its start.
    pub fn reset(&mut self) -> Result<(), FmuError> {
        self.plant = None;
        self.inputs = self.ports.inputs.iter().map(|p| p.start).collect();
        self.parameters = self.config.parameters.iter().map(|p| p.start).collect();
        self.initial_static = self.config.initial_static;
        self.outputs = vec![0.0; self.ports.outputs.len()];
        self.start_time = 0.0;
        self.phase = Phase::Instantiated;
        Ok(())
    }

    /// The state a master may come back to.
    pub fn save(&self) -> Result<SavedState, FmuError> {
        self.usable("getting the FMU state")?;
        Ok(SavedState {
            plant: self.plant.as_ref().and_then(Plant::save),
            inputs: self.inputs.clone(),
            outputs: self.outputs.clone(),
        })
    }

    /// Back to `saved`.
    pub fn restore(&mut self, saved: &SavedState) -> Result<(), FmuError> {
        self.usable("setting the FMU state")?;
        match (&saved.plant, self.plant.as_mut()) {
            (Some(s), Some(p)) => p.restore(s)?,
            (None, _) => {}
            (Some(_), None) => {
                return Err(FmuError::Unsupported(
                    "a state saved after the initialisation cannot be set before it",
                ))
            }
        }
        self.inputs = saved.inputs.clone();
        self.outputs = saved.outputs.clone();
        Ok(())
    }
}
