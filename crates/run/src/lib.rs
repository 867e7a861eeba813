//! # linkage-run — Adams command files
//!
//! Runs a command file (`.acf`) as Adams Solver does (`adams ru-s model.acf`): line 1 names the
//! dataset (relative to the command file; `.adm` added when it has no extension), line 2 the
//! output name, then the commands in order (ADM-REFERENCE §7). Every analysis continues from
//! where the previous one left the model; settings commands, redefinitions and
//! DEACTIVATE/ACTIVATE amend the dataset and rebuild the model ([`session`]).
//!
//! ```text
//! .acf ──type_commands──▶ commands ──▶ Session (dataset + amendments → model, state left)
//!                                        └─▶ analyses (IC, static, dynamic, linear)
//!                                              └─▶ <name>.msg, <name>.req, <name>.csv
//! ```
//!
//! Outputs are written as the run goes (each line or output flushed): `<name>.msg` (the
//! message file: each command echoed, the model summary of verify before the first analysis
//! and after every change of the model, the IC, static and linear reports, integrator
//! statistics per run, errors), `<name>.req` (every REQUEST at every output, Adams' layout)
//! and `<name>.csv`. A command linkage does not carry out stops the run with an error naming
//! it; nothing is skipped silently.

pub mod commands;
pub mod error;
pub mod listing;
pub mod msg;
pub mod records;
pub mod session;
pub mod step_table;
pub mod watch;

pub use error::RunError;

use commands::{Place, Sinks};
use linkage_adm::commands::{Command, CommandEntry, Linear, SimulateKind, TypedCommandFile};
use linkage_adm::{CommandFile, Statement};
use msg::MessageFile;
use records::Records;
use session::Session;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// Deepest nesting of `FILE/COMMAND` (a command file that reads itself is an error, not a
/// loop).
pub const MAX_NESTING: usize = 8;

/// Where the outputs go.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// Directory of the output files (the working directory when `None`, as Adams).
    pub out_dir: Option<PathBuf>,
    /// The dataset to run, in place of the one the command file names (and for command files
    /// that name none: templates whose line 1 is a comment).
    pub model: Option<PathBuf>,
    /// Set (by a signal handler) to stop the run at the next output: the files keep every
    /// output written, the message file says where the run stopped.
    pub interrupt: Option<Arc<AtomicBool>>,
    /// Statements to leave out of the dataset (`--deactivate`, as [`linkage_adm::amend::select`]
    /// reads them), as if the command file deactivated them first.
    pub deactivate: Vec<String>,
    /// Accept an unstable static equilibrium (`--allow-unstable`); otherwise it stops the run,
    /// as `linkage static` refuses it.
    pub allow_unstable: bool,
    /// How the dataset is read (`--lenient-arguments`).
    pub read: linkage_adm::ReadOptions,
    /// Libraries (or folders of them) of the dataset's user subroutines (`--user-lib`).
    pub user_libraries: Vec<PathBuf>,
    /// Files the caller writes after the run (`--html`): refused, as the run's own outputs
    /// are, when one is a file the run reads.
    pub also_writes: Vec<PathBuf>,
    /// Wall-clock seconds each dynamic simulation may take (`--time-limit`; `None`: the
    /// default of [`linkage_api::budget::DEFAULT_SIMULATE_TIME_LIMIT`]): a run that reaches it
    /// fails saying so, the outputs up to there written.
    pub time_limit: Option<f64>,
    /// Told how far each dynamic simulation has come (a terminal's progress bar).
    pub watch: watch::Watch,
}

impl RunOptions {
    /// Whether the run was asked to stop.
    pub fn interrupted(&self) -> bool {
        self.interrupt
            .as_ref()
            .is_some_and(|f| f.load(Ordering::Relaxed))
    }
}

/// What a run wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct RunSummary {
    pub msg: PathBuf,
    pub req: Option<PathBuf>,
    pub csv: Option<PathBuf>,
    /// Outputs written to the request and CSV files.
    pub outputs: usize,
    /// Commands carried out.
    pub commands: usize,
    /// The dataset the run opened (as the session names it).
    pub dataset: Option<PathBuf>,
    /// A SENSOR's HALT ended the command file (`SENSOR_1 at time 2.5`): the commands after
    /// the analysis it stopped were not run.
    pub halted: Option<String>,
    /// How many times the analyses compiled and assembled a model (an analysis that continues
    /// on the last one's assembly does not).
    pub assemblies: usize,
}

/// A run that stopped: why, and what it wrote up to there.
#[derive(Debug)]
pub struct Stopped {
    pub error: RunError,
    pub summary: Option<RunSummary>,
}

/// The state of a run between commands.
struct Runner {
    options: RunOptions,
    out_name: Option<String>,
    msg: Option<MessageFile>,
    session: Option<Session>,
    records: Option<Records>,
    /// The model changed since the last model summary (or none was written).
    changed: bool,
    /// DOF and redundant equations at the last model summary.
    counts: Option<(i64, usize)>,
    commands: usize,
    /// Assemblies of the models closed before the current one.
    assemblies: usize,
    /// Every file the run has read (command files, datasets, their MATRIX files and meshes)
    /// and every file it writes: no output may be an input ([`linkage_api::files`]).
    inputs: Vec<PathBuf>,
    outputs: Vec<PathBuf>,
}

fn with_extension(name: &str, ext: &str) -> String {
    if Path::new(name).extension().is_some() {
        name.to_string()
    } else {
        format!("{name}.{ext}")
    }
}

/// Runs the command file at `path`.
pub fn run_command_file(path: &Path, options: &RunOptions) -> Result<RunSummary, Box<Stopped>> {
    let stop = |error| {
        Box::new(Stopped {
            error,
            summary: None,
        })
    };
    let (cf, typed) = read(path).map_err(stop)?;
    let file = path.display().to_string();
    if typed.model.is_none() && options.model.is_none() && !names_a_model(&typed) {
        return Err(stop(RunError::Empty {
            file,
            why: "the command file names no dataset (line 1, FILE/MODEL) and --model gives none",
        }));
    }
    if !typed.commands.iter().any(|e| {
        matches!(
            e.command,
            Command::Simulate(_) | Command::Linear(_) | Command::File(_)
        )
    }) {
        return Err(stop(RunError::Empty {
            file,
            why: "the command file has no analysis (SIMULATE, LINEAR) to run",
        }));
    }
    let out_name = typed
        .output_prefix
        .clone()
        .or_else(|| typed.model.as_deref().map(stem_of));
    let mut runner = Runner {
        options: options.clone(),
        out_name,
        msg: None,
        session: None,
        records: None,
        changed: true,
        counts: None,
        commands: 0,
        assemblies: 0,
        inputs: Vec::new(),
        outputs: options.also_writes.clone(),
    };
    if let Err(e) = runner.reads(&[path.to_path_buf()]) {
        return Err(stop(e));
    }
    let result = runner
        .start(path, &typed)
        .and_then(|_| runner.execute(path, &cf, &typed, 0));
    let summary = runner.summary();
    if let (Err(e), Some(msg)) = (&result, runner.msg.as_mut()) {
        let _ = msg.write(&format!("\n ---- ERROR ----\n {e}"));
    }
    if let Some(records) = runner.records.take() {
        let model = runner.session.as_ref().map(|s| &s.loaded.model);
        if let Err(e) = records.finish(model) {
            return Err(Box::new(Stopped { error: e, summary }));
        }
    }
    match result {
        Ok(()) => {
            if let Some(msg) = runner.msg.as_mut() {
                let _ = msg.write(&match summary.as_ref().and_then(|s| s.halted.as_ref()) {
                    Some(by) => format!(
                        "\n Finished: ended by the HALT of {by}; the commands after it were not \
                         run."
                    ),
                    None => "\n Finished: every command was carried out.".into(),
                });
            }
            summary.ok_or_else(|| stop(RunError::Input(linkage_adm::Diagnostics(vec![]))))
        }
        Err(error) => Err(Box::new(Stopped { error, summary })),
    }
}

/// Whether a FILE/MODEL of the command file names a dataset.
fn names_a_model(typed: &TypedCommandFile) -> bool {
    typed
        .commands
        .iter()
        .any(|e| matches!(&e.command, Command::File(f) if f.model.is_some() || f.command.is_some()))
}

fn read(path: &Path) -> Result<(CommandFile, TypedCommandFile), RunError> {
    let cf = linkage_adm::read_commands(path).map_err(RunError::Input)?;
    let typed = linkage_adm::type_commands(&cf).map_err(RunError::Input)?;
    Ok((cf, typed))
}

impl Runner {
    /// The run reads `files`: refused when one is a file it writes.
    fn reads(&mut self, files: &[PathBuf]) -> Result<(), RunError> {
        linkage_api::check_outputs(&self.outputs, files).map_err(|e| {
            // Named the other way round: the output is the input.
            RunError::OutputIsInput(linkage_api::OutputIsInput {
                output: e.input,
                input: e.output,
            })
        })?;
        self.inputs.extend_from_slice(files);
        Ok(())
    }

    /// The run writes `file`: refused when it is a file the run reads.
    fn writes(&mut self, file: PathBuf) -> Result<(), RunError> {
        linkage_api::check_outputs(&self.inputs, [&file])?;
        self.outputs.push(file);
        Ok(())
    }

    fn out_path(&self, ext: &str) -> PathBuf {
        let name = format!("{}.{ext}", self.out_name.as_deref().unwrap_or("linkage"));
        match &self.options.out_dir {
            Some(d) => d.join(name),
            None => PathBuf::from(name),
        }
    }

    fn summary(&self) -> Option<RunSummary> {
        let msg = self.msg.as_ref()?.path().to_path_buf();
        let have_records = self.records.is_some();
        Some(RunSummary {
            msg,
            req: have_records.then(|| self.out_path("req")),
            csv: have_records.then(|| self.out_path("csv")),
            outputs: self.records.as_ref().map_or(0, |r| r.written),
            commands: self.commands,
            dataset: self.session.as_ref().map(|s| PathBuf::from(s.file())),
            halted: self
                .session
                .as_ref()
                .and_then(|s| s.progress.halted.clone()),
            assemblies: self.assemblies,
        })
    }

    /// Opens the message file and the dataset of line 1.
    fn start(&mut self, path: &Path, typed: &TypedCommandFile) -> Result<(), RunError> {
        if let Some(d) = &self.options.out_dir {
            std::fs::create_dir_all(d).map_err(|cause| RunError::Write {
                path: d.display().to_string(),
                cause,
            })?;
        }
        if let Some(model) = self.options.model.clone() {
            self.open_dataset(path, &model)?;
        } else if let Some(model) = &typed.model {
            self.open_model(path, model).map_err(|e| match e {
                RunError::Input(d) => RunError::Refused {
                    place: format!("{}:1:1", path.display()),
                    command: "the dataset of line 1".into(),
                    why: d.to_string(),
                },
                other => other,
            })?;
        }
        Ok(())
    }

    /// Reads the dataset `name` (relative to the command file `path`) and opens the output
    /// files.
    fn open_model(&mut self, path: &Path, name: &str) -> Result<(), RunError> {
        self.open_dataset(path, &dataset_path(path, name))
    }

    /// Reads the dataset at `dataset` for the command file `path` and opens the output files.
    fn open_dataset(&mut self, path: &Path, dataset: &Path) -> Result<(), RunError> {
        if self.out_name.is_none() {
            self.out_name = Some(
                dataset
                    .file_stem()
                    .map_or("linkage".to_string(), |s| s.to_string_lossy().into()),
            );
        }
        self.reads(&[dataset.to_path_buf()])?;
        // Read before the message file is created, so that no file the dataset reads is
        // overwritten by it; its errors still go to the message file.
        let session = Session::open(dataset, &self.options);
        if let Ok(s) = &session {
            self.reads(&linkage_api::dataset_files(&s.loaded))?;
        }
        if self.msg.is_none() {
            self.writes(self.out_path("msg"))?;
            let mut msg = MessageFile::create(&self.out_path("msg"))?;
            msg.write(&format!(
                " linkage {} — command file {}\n dataset {}",
                env!("CARGO_PKG_VERSION"),
                path.display(),
                dataset.display()
            ))?;
            self.msg = Some(msg);
        } else if let Some(msg) = self.msg.as_mut() {
            msg.write(&format!(
                " dataset {} (outputs {}.req, {}.csv)",
                dataset.display(),
                self.out_name.as_deref().unwrap_or("linkage"),
                self.out_name.as_deref().unwrap_or("linkage")
            ))?;
        }
        let session = session?;
        self.writes(self.out_path("req"))?;
        self.writes(self.out_path("csv"))?;
        let stem = self.out_path("stem");
        let records = match Records::create(&stem, &session.loaded.dataset, &session.loaded.model) {
            Ok(r) => r,
            // The REQUESTs cannot be written: listed with every statement the analyses
            // refuse, so that one run names everything to leave out (as `simulate` does).
            Err(RunError::Input(mut d)) => {
                d.0.extend(
                    session
                        .loaded
                        .refusals(linkage_solve::coverage::Analysis::Ic),
                );
                d.0.sort_by_key(|x| x.span);
                d.0.dedup_by(|a, b| a.span == b.span && a.message == b.message);
                return Err(RunError::Input(d));
            }
            Err(e) => return Err(e),
        };
        self.session = Some(session);
        self.records = Some(records);
        self.changed = true;
        Ok(())
    }

    fn place(file: &Path, entry: &CommandEntry) -> String {
        format!("{}:{}:{}", file.display(), entry.span.line, entry.span.col)
    }

    /// Carries out the commands of one command file (`depth` levels of FILE/COMMAND deep).
    fn execute(
        &mut self,
        path: &Path,
        cf: &CommandFile,
        typed: &TypedCommandFile,
        depth: usize,
    ) -> Result<(), RunError> {
        let text = std::fs::read_to_string(path).unwrap_or_default();
        let lines: Vec<&str> = text.lines().collect();
        for entry in &typed.commands {
            if self.options.interrupted() {
                let time = self.session.as_ref().map_or(0.0, Session::time);
                return Err(RunError::Interrupted { time });
            }
            let echo: String = (entry.lines.0..=entry.lines.1)
                .filter_map(|l| lines.get(l as usize - 1))
                .map(|l| l.trim_end())
                .collect::<Vec<_>>()
                .join("\n          ");
            if let Some(msg) = self.msg.as_mut() {
                msg.write(&format!("\n command: {echo}"))?;
            }
            let place_at = Runner::place(path, entry);
            let name = entry.command.name().to_string();
            let place = Place {
                at: place_at,
                command: &name,
            };
            let generic = cf.commands.iter().find(|s| s.lines == entry.lines);
            if matches!(entry.command, Command::Stop) {
                self.commands += 1;
                return Ok(());
            }
            if let Command::File(f) = &entry.command {
                if let Some(model) = &f.model {
                    match (&self.session, &self.options.model) {
                        // --model replaces the dataset the command file names.
                        (Some(_), Some(_)) => {}
                        (Some(_), None) => {
                            // Another model: its own request and CSV files (OUTPUT_PREFIX, or
                            // the dataset's name), the same message file.
                            if let Some(records) = self.records.take() {
                                records.finish(self.session.as_ref().map(|s| &s.loaded.model))?;
                            }
                            self.session = None;
                            self.out_name =
                                f.output_prefix.clone().or_else(|| Some(stem_of(model)));
                            self.counts = None;
                            self.open_model(path, model)?;
                        }
                        (None, _) => {
                            if let Some(prefix) = &f.output_prefix {
                                self.out_name = Some(prefix.clone());
                            }
                            self.open_model(path, model)?;
                        }
                    }
                }
                if let Some(command) = &f.command {
                    if depth >= MAX_NESTING {
                        return Err(refused(
                            &place,
                            format!("FILE/COMMAND nested more than {MAX_NESTING} deep"),
                        ));
                    }
                    let dir = path.parent().unwrap_or(Path::new("."));
                    let nested = dir.join(with_extension(command, "acf"));
                    self.reads(std::slice::from_ref(&nested))?;
                    let (ncf, ntyped) = read(&nested)?;
                    self.execute(&nested, &ncf, &ntyped, depth + 1)?;
                }
                self.commands += 1;
                if self.halted() {
                    return Ok(());
                }
                continue;
            }
            self.command(entry, generic, &place)?;
            self.commands += 1;
            // A SENSOR's HALT ends the command file, as STOP does.
            if self.halted() {
                return Ok(());
            }
        }
        Ok(())
    }

    /// Whether a SENSOR's HALT ended the last simulation.
    fn halted(&self) -> bool {
        self.session
            .as_ref()
            .is_some_and(|s| s.progress.halted.is_some())
    }

    fn command(
        &mut self,
        entry: &CommandEntry,
        generic: Option<&Statement>,
        place: &Place,
    ) -> Result<(), RunError> {
        let (Some(session), Some(msg), Some(records)) = (
            self.session.as_mut(),
            self.msg.as_mut(),
            self.records.as_mut(),
        ) else {
            return Err(refused(
                place,
                "no dataset is loaded: line 1 of the command file or FILE/MODEL names it, or \
                 give one with --model",
            ));
        };
        match &entry.command {
            Command::Simulate(_) | Command::Linear(_) => {
                let changed = self.changed;
                let result = analysis(
                    session,
                    (msg, records),
                    (&mut self.counts, &mut self.assemblies),
                    &self.options,
                    (entry, place, changed),
                );
                self.changed = false;
                return result;
            }
            Command::Integrator(_)
            | Command::Equilibrium(_)
            | Command::Ic(_)
            | Command::Kinematics(_)
            | Command::Accgrav(_) => {
                let Some(st) = generic else {
                    return Err(refused(place, "the command's arguments could not be found"));
                };
                commands::settings::settings(session, msg, place, st)?;
            }
            Command::Redefine(r) => {
                commands::settings::redefine(session, place, &r.statement)?;
                self.changed = true;
            }
            Command::Activate(a) | Command::Deactivate(a) => {
                let active = matches!(entry.command, Command::Activate(_));
                commands::settings::activation(session, msg, place, a, active)?;
                self.changed = true;
            }
            Command::Output(_)
            | Command::Debug(_)
            | Command::Preferences(_)
            | Command::Lsolver(_)
            | Command::Environment(_)
            | Command::Information(_) => {
                msg.write(&format!(
                    " Note: {} is accepted and changes nothing in linkage (outputs are always \
                     the .msg, .req and .csv files; one linear solver).",
                    place.command
                ))?;
            }
            Command::Save(_) | Command::Reload(_) => {
                return Err(refused(
                    place,
                    "linkage does not save or reload solver states; the command file must run \
                     without them",
                ))
            }
            Command::Control(_) => {
                return Err(refused(
                    place,
                    "CONTROL hands the run to a user subroutine, which linkage cannot call",
                ))
            }
            Command::File(_) | Command::Stop => {}
        }
        Ok(())
    }
}

/// An analysis command (`SIMULATE`, `LINEAR`) of `entry` at `place`, on the session's model;
/// `changed`: the model changed since the last model summary (one is written when the
/// analysis assembles).
fn analysis(
    session: &mut Session,
    (msg, records): (&mut MessageFile, &mut Records),
    (counts, assemblies): (&mut Option<(i64, usize)>, &mut usize),
    options: &RunOptions,
    (entry, place, changed): (&CommandEntry, &Place, bool),
) -> Result<(), RunError> {
    let t0 = session.time();
    // The plant inputs and outputs of LINEAR/STATEMAT, from the amended statements.
    let io = match &entry.command {
        Command::Linear(Linear::Statemat(m)) => Some(commands::linear::PlantIo {
            inputs: commands::linear::plant_variables(session, "PINPUT", m.pinput)
                .map_err(|why| refused(place, why.to_string()))?,
            outputs: commands::linear::plant_variables(session, "POUTPUT", m.poutput)
                .map_err(|why| refused(place, why.to_string()))?,
        }),
        _ => None,
    };
    // The times first: an error in them is the command's, before anything runs.
    let times = match &entry.command {
        Command::Simulate(sim) => {
            let end = sim.end.or(sim.duration.map(|d| t0 + d));
            let steps = sim.steps.map(|n| n as usize);
            match sim.kind {
                SimulateKind::InitialConditions(_) => None,
                SimulateKind::Static => match end.filter(|e| *e > t0) {
                    None => None,
                    Some(e) => Some(
                        linkage_api::output_times_after(t0, e, steps, sim.dtout)
                            .map_err(|e| refused(place, e.to_string()))?,
                    ),
                },
                _ => {
                    let Some(end) = end.filter(|e| *e > t0) else {
                        return Err(refused(
                            place,
                            format!("END (or DURATION) must lie after the current time {t0}"),
                        ));
                    };
                    Some(
                        linkage_api::output_times_after(t0, end, steps, sim.dtout)
                            .map_err(|e| refused(place, e.to_string()))?,
                    )
                }
            }
        }
        _ => None,
    };
    let Session {
        loaded, progress, ..
    } = session;
    let mut sinks = Sinks {
        msg,
        records,
        counts,
        interrupt: options.interrupt.clone(),
        time_limit: options.time_limit,
        summary: changed,
        loaded,
        assembled: false,
        failed_write: None,
        need_kinematic: false,
        refusal: None,
        steps: None,
        watch: options.watch.clone(),
    };
    let sinks = &mut sinks;
    let result = match &entry.command {
        Command::Simulate(sim) => match sim.kind {
            SimulateKind::InitialConditions(_) => {
                commands::simulate::initial_conditions(progress, sinks, place)
            }
            SimulateKind::Static => {
                commands::simulate::statics(progress, sinks, place, times, options.allow_unstable)
            }
            kind => commands::simulate::dynamics(
                progress,
                sinks,
                place,
                kind,
                times.as_deref().unwrap_or_default(),
            ),
        },
        Command::Linear(Linear::Eigensol(e)) => {
            let opts = linkage_solve::stages::linearize::LinearOptions {
                damping: !e.nodamping,
                vectors: !e.novector,
                method: linkage_solve::stages::linearize::EigenMethod::Auto,
            };
            commands::linear::eigensolution(progress, sinks, place, opts)
        }
        Command::Linear(Linear::Statemat(m)) => {
            if m.pstate.is_some() {
                return Err(refused(
                    place,
                    "PSTATE (user-chosen states) is not modelled by linkage: the states are \
                     the independent coordinates and their rates",
                ));
            }
            if m.format == Some(linkage_adm::commands::MatrixFormat::Matrixx) {
                return Err(refused(
                    place,
                    "FORMAT = MATRIXX is not written by linkage; FORMAT = MATLAB writes plain \
                     text matrices",
                ));
            }
            let io = io.unwrap_or_default();
            let file = match &options.out_dir {
                Some(d) => d.join(&m.file),
                None => PathBuf::from(&m.file),
            };
            commands::linear::state_matrices(progress, sinks, place, &file, &io)
        }
        Command::Linear(Linear::Mkb(_)) => Err(refused(
            place,
            "linkage does not export mass, stiffness and damping matrices; LINEAR/STATEMAT \
             writes the state matrix, LINEAR/EIGENSOL the modes",
        )),
        _ => Ok(()),
    };
    *assemblies += usize::from(sinks.assembled);
    result
}

/// The file name of a dataset named in a command file, without folders (also those of another
/// machine: `C:\\Users\\…\\model`) and extension.
fn stem_of(name: &str) -> String {
    let file = name.rsplit(['\\', '/']).next().unwrap_or(name);
    Path::new(file)
        .file_stem()
        .map_or(file.to_string(), |s| s.to_string_lossy().into_owned())
}

/// The dataset `name` of the command file `path`: relative to the command file's folder, with
/// `.adm` added when it has no extension. In a flattened collection, where every file of a
/// project folder carries the folder path as a prefix (`owner__repo__dir__model.acf`), a
/// dataset missing under its own name is looked for with the command file's prefix.
fn dataset_path(path: &Path, name: &str) -> PathBuf {
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut name = name.to_string();
    // A path written on another machine (`C:\Users\…\model`): its file name, here.
    if !dir.join(&name).exists() && !dir.join(with_extension(&name, "adm")).exists() {
        if let Some(k) = name.rfind(['\\', '/']) {
            name = name[k + 1..].to_string();
        }
    }
    let file = with_extension(&name, "adm");
    let direct = dir.join(&file);
    if direct.exists() {
        return direct;
    }
    let stem = path
        .file_name()
        .map_or(String::new(), |f| f.to_string_lossy().into_owned());
    match stem.rfind("__") {
        Some(k) => {
            let prefixed = dir.join(format!("{}__{file}", &stem[..k]));
            if prefixed.exists() {
                prefixed
            } else {
                direct
            }
        }
        _ => direct,
    }
}

fn refused(place: &Place, why: impl Into<String>) -> RunError {
    RunError::Refused {
        place: place.at.clone(),
        command: place.command.to_string(),
        why: why.into(),
    }
}
