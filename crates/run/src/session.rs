//! The model a command file works on: the dataset as the commands have amended it
//! ([`linkage_api::Source`]: redefinitions, deactivated elements), the model loaded from it
//! ([`linkage_api::Loaded`]), and where the last analysis left it ([`linkage_api::Left`]).
//!
//! Contract:
//! - [`Session::open`] reads and loads the dataset; every input error comes back at once.
//! - [`Session::redefine`] and [`Session::set_active`] change the statements and load the
//!   model again right away, so that an error names the command that caused it; the state
//!   the last analysis left is kept, its assembly is not (the next analysis assembles again).
//! - [`Session::settings`] changes settings assembly does not read (INTEGRATOR, EQUILIBRIUM,
//!   KINEMATICS, ACCGRAV): the loaded model takes the new settings and keeps its assembly, so
//!   the next analysis continues on it without assembling again. IC settings are read by the
//!   assembly: they drop it.
//! - [`Progress::start`] is where the next analysis starts: the input before the first
//!   analysis, afterwards the state the last one left (on its assembly while it holds).

use crate::error::RunError;
use linkage_adm::amend::Redefined;
use linkage_adm::{Diagnostic, Diagnostics, Statement};
use linkage_api::{Left, Loaded, Refusal, Source, Start};
use linkage_solve::coverage::Analysis;
use std::path::Path;

/// The dataset, its amendments, the model loaded from them and where it was left.
pub struct Session {
    source: Source,
    pub loaded: Loaded,
    pub progress: Progress,
}

/// Where the analyses have left the model.
#[derive(Default)]
pub struct Progress {
    /// `None` before the first analysis.
    left: Option<Left>,
    /// A SENSOR's HALT ended the last simulation: the command file ends there (`SENSOR_1 at
    /// time 1.0`).
    pub halted: Option<String>,
}

impl Progress {
    /// The time the last analysis left the model at (0 before the first).
    pub fn time(&self) -> f64 {
        self.left.as_ref().map_or(0.0, |l| l.state.time)
    }

    /// Where the next analysis starts (the session holds no state until [`Progress::leave`]
    /// gives it the one the analysis ends at).
    pub fn start(&mut self) -> Start {
        match self.left.take() {
            Some(left) => Start::Left(Box::new(left)),
            None => Start::Input,
        }
    }

    /// The analysis that started from [`Progress::start`] left the model at `left` (`None`:
    /// where it started, which was the input: a linearization of the input).
    pub fn leave(&mut self, left: Option<Left>) {
        self.left = left;
    }

    /// The state left loses its assembly: the next analysis assembles again.
    fn drop_assembly(&mut self) {
        if let Some(left) = self.left.as_mut() {
            left.assembly = None;
        }
    }
}

/// Loads `source` for a command file's analyses.
fn load(source: &Source) -> Result<Loaded, Diagnostics> {
    let mut loaded = source.load(&[], Some(Analysis::Ic))?;
    loaded.refusal = Refusal::CommandFile;
    Ok(loaded)
}

impl Session {
    /// Reads the dataset at `path` (as `options.read` says), links its USER calls to
    /// `options.user_libraries` and loads it without the statements `options.deactivate`
    /// names (see [`linkage_adm::amend::select`]).
    pub fn open(path: &Path, options: &crate::RunOptions) -> Result<Session, RunError> {
        let mut source = Source::read_with(path, options.read)
            .and_then(|s| s.with_user_libraries(&options.user_libraries))
            .map_err(RunError::Input)?;
        source
            .leave_out(&options.deactivate)
            .map_err(RunError::Input)?;
        let loaded = load(&source).map_err(RunError::Input)?;
        Ok(Session {
            source,
            loaded,
            progress: Progress::default(),
        })
    }

    /// The dataset's file name.
    pub fn file(&self) -> &str {
        self.source.file()
    }

    /// The time the last analysis left the model at (0 before the first).
    pub fn time(&self) -> f64 {
        self.progress.time()
    }

    /// Loads the model again from the amended statements, keeping the old one when that fails
    /// or when it would add or remove parts. The assembly the last analysis left is dropped.
    fn reload(&mut self, source: Source) -> Result<(), Diagnostics> {
        let loaded = load(&source)?;
        if loaded.model.parts.len() != self.loaded.model.parts.len() {
            return Err(Diagnostics(vec![Diagnostic::error(
                self.source.dataset().file.clone(),
                None,
                "a command may not add or remove parts".to_string(),
            )]));
        }
        self.source = source;
        self.loaded = loaded;
        self.progress.drop_assembly();
        // The model loaded again starts the sensors' stored values (SENVAL) at 0.
        if let Some(left) = self.progress.left.as_mut() {
            left.state.elements.sensors.clear();
        }
        Ok(())
    }

    /// Applies a statement given as a command (`VARIABLE/9105, FUNCTION = …`) and loads the
    /// model again.
    pub fn redefine(&mut self, change: &Statement) -> Result<Redefined, Diagnostics> {
        let mut source = self.source.clone();
        let done = source.redefine(change)?;
        self.reload(source)?;
        Ok(done)
    }

    /// Applies a settings command (`INTEGRATOR/ERROR = 1e-5`, `EQUILIBRIUM/…`, `IC/…`,
    /// `KINEMATICS/…`, `ACCGRAV/…`). Settings assembly does not read are taken into the
    /// loaded model as they are, so that the next analysis continues on the last assembly;
    /// IC settings drop it.
    pub fn settings(&mut self, change: &Statement) -> Result<(), Diagnostics> {
        let mut source = self.source.clone();
        source.redefine(change)?;
        let loaded = load(&source)?;
        self.source = source;
        let model = &mut self.loaded.model;
        model.integrator = loaded.model.integrator;
        model.equilibrium = loaded.model.equilibrium;
        model.gravity = loaded.model.gravity;
        if model.ic != loaded.model.ic {
            model.ic = loaded.model.ic;
            self.progress.drop_assembly();
        }
        self.loaded.dataset = loaded.dataset;
        Ok(())
    }

    /// Deactivates (or with `active`, activates again) the `keyword` statements whose ids
    /// `selects` accepts, and loads the model again. Selecting none is an error.
    pub fn set_active(
        &mut self,
        keyword: &str,
        selects: impl Fn(u64) -> bool,
        active: bool,
    ) -> Result<(), Diagnostics> {
        let mut source = self.source.clone();
        source.set_active(keyword, selects, active)?;
        self.reload(source)
    }

    /// The amended statement `keyword/id` (active or not).
    pub fn statement(&self, keyword: &str, id: u64) -> Option<&Statement> {
        self.source.statement(keyword, id)
    }

    /// How many statements are inactive.
    pub fn inactive(&self) -> usize {
        self.source.inactive_count()
    }
}
