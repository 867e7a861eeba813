//! `linkage` — verify, assemble and solve Adams multibody datasets.
//!
//! Exit codes, one verdict per run (the same in the text, the JSON `errors` list and the exit
//! code): 0 when the analysis ran and found what was asked (`errors` empty), 1 when it ran and
//! failed (an inconsistent redundant equation, a failed assembly, an unstable equilibrium unless
//! `--allow-unstable`, non-convergence, a non-finite result: the failure is the last line of
//! the text report and is in `errors`), 2 for input errors (syntax, references, values).
//! `compare` exits with 1 when some signal differs by more than the tolerance.

mod common;
mod compare_cmd;
mod fmu_cmd;
mod html_out;
mod ic_cmd;
mod linear_cmd;
mod plot_cmd;
mod run_cmd;
mod simulate_cmd;
mod static_cmd;
mod sweep_cmd;
mod verify_cmd;

use clap::{Parser, Subcommand};
use common::Format;
use linkage_solve::stages::dynamics::Start;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "linkage",
    version,
    about = "Multibody model checker and solver for Adams datasets (.adm)"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Read on when a statement has an argument it does not take (a misspelling such as
    /// `MASSS = 1` in a PART): a warning, the argument ignored. Without it that is an input
    /// error with a "did you mean" suggestion, as Adams stops on it.
    #[arg(long, global = true)]
    lenient_arguments: bool,
    /// A shared library of Adams user subroutines (Fortran or C), or a folder of them, for the
    /// dataset's `FUNCTION = USER(…)` calls; repeatable. Libraries load only from these, the
    /// dataset's folder and LD_LIBRARY_PATH, never from a path the dataset spells alone.
    #[arg(long, global = true, value_name = "PATH")]
    user_lib: Vec<PathBuf>,
}

#[derive(Subcommand)]
enum Command {
    /// Verify a model: parts, constraints, Gruebler count, DOF, redundant and misaligned
    /// constraints, unconstrained and massless parts.
    Verify {
        /// The dataset(s) (.adm), verified in turn.
        #[arg(required = true, num_args = 1..)]
        model: Vec<PathBuf>,
        /// Leave these statements out: KEYWORD/id (SENSOR/3), a statement kind (SENSOR: all of
        /// them) or an element's name; comma-separated or repeated. The report names them.
        #[arg(long, value_name = "NAME", value_delimiter = ',')]
        deactivate: Vec<String>,
        /// Also write the report as one self-contained HTML page (tables, plots, 3-D view).
        #[arg(long, value_name = "OUT.html")]
        html: Option<PathBuf>,
        /// Output format.
        #[arg(long, value_enum, default_value = "text")]
        format: Format,
        /// Explain the redundancy: which reactions are determinate, whether the pose is
        /// singular, conflicting motions and initial conditions, and changes of joints that
        /// remove the redundant equations (each checked by a rank analysis).
        #[arg(long)]
        explain: bool,
        /// Apply proposal K (numbered from 1 as in the report) and write the model to --save.
        #[arg(long, value_name = "K", requires = "save")]
        apply: Option<usize>,
        /// Where --apply writes the changed dataset.
        #[arg(long, value_name = "OUT.adm", requires = "apply")]
        save: Option<PathBuf>,
    },
    /// Initial conditions: assemble the model (least change), then velocities, accelerations
    /// and reaction forces at the start time.
    Ic {
        /// The dataset (.adm).
        model: PathBuf,
        /// Leave these statements out: KEYWORD/id (SENSOR/3), a statement kind (SENSOR: all of
        /// them) or an element's name; comma-separated or repeated. The report names them.
        #[arg(long, value_name = "NAME", value_delimiter = ',')]
        deactivate: Vec<String>,
        /// Also write the report as one self-contained HTML page (tables, plots, 3-D view).
        #[arg(long, value_name = "OUT.html")]
        html: Option<PathBuf>,
        /// Output format.
        #[arg(long, value_enum, default_value = "text")]
        format: Format,
        /// Write the assembled configuration as a new dataset (only moved parts' QG/REULER
        /// change).
        #[arg(long, value_name = "OUT.adm")]
        save: Option<PathBuf>,
    },
    /// Static equilibrium at the start time, or a quasi-static series with --end/--steps.
    Static {
        /// The dataset (.adm).
        model: PathBuf,
        /// Leave these statements out: KEYWORD/id (SENSOR/3), a statement kind (SENSOR: all of
        /// them) or an element's name; comma-separated or repeated. The report names them.
        #[arg(long, value_name = "NAME", value_delimiter = ',')]
        deactivate: Vec<String>,
        /// Also write the report as one self-contained HTML page (tables, plots, 3-D view).
        #[arg(long, value_name = "OUT.html")]
        html: Option<PathBuf>,
        /// Output format (csv: one row per output time).
        #[arg(long, value_enum, default_value = "text")]
        format: static_cmd::StaticFormat,
        /// End time of a quasi-static series.
        #[arg(long, requires = "steps", allow_negative_numbers = true)]
        end: Option<f64>,
        /// Number of output steps of the series.
        #[arg(long, requires = "end")]
        steps: Option<usize>,
        /// Write the (last) equilibrium configuration as a new dataset.
        #[arg(long, value_name = "OUT.adm")]
        save: Option<PathBuf>,
        /// Find the equilibrium by damped dynamics (EQUILIBRIUM/DYNAMIC settings), then
        /// polish it with Newton statics.
        #[arg(long, conflicts_with = "end")]
        settle: bool,
        /// Accept an unstable equilibrium (exit 0); without it an unstable equilibrium is the
        /// run's failure (exit 1).
        #[arg(long)]
        allow_unstable: bool,
        /// Stop damped settling after this many seconds of wall-clock time (after the step
        /// it is in); the run then fails (exit 1) saying so. Default: 600 s.
        #[arg(long, value_name = "SECONDS")]
        time_limit: Option<f64>,
    },
    /// Linearize about the assembled configuration (or static equilibrium with --static-first):
    /// eigenvalues, natural frequencies, damping ratios and mode shapes.
    Linear {
        /// The dataset (.adm).
        model: PathBuf,
        /// Leave these statements out: KEYWORD/id (SENSOR/3), a statement kind (SENSOR: all of
        /// them) or an element's name; comma-separated or repeated. The report names them.
        #[arg(long, value_name = "NAME", value_delimiter = ',')]
        deactivate: Vec<String>,
        /// Also write the report as one self-contained HTML page (tables, plots, 3-D view).
        #[arg(long, value_name = "OUT.html")]
        html: Option<PathBuf>,
        /// Output format.
        #[arg(long, value_enum, default_value = "text")]
        format: Format,
        /// Find static equilibrium first and linearize about it.
        #[arg(long)]
        static_first: bool,
        /// Drop damping (Adams NODAMPIN).
        #[arg(long)]
        no_damping: bool,
        /// Skip mode shapes (Adams NOVECTOR).
        #[arg(long)]
        no_vectors: bool,
        /// Compute only the K modes nearest the shift (lowest first) by sparse shift-invert
        /// Arnoldi, instead of every mode (large models do this by default).
        #[arg(long, value_name = "K", value_parser = clap::value_parser!(u64).range(1..))]
        modes: Option<u64>,
        /// Shift in cycles per time unit: compute the modes nearest this frequency (sparse
        /// shift-invert; default just below zero, i.e. the lowest modes).
        #[arg(long, value_name = "F", allow_negative_numbers = true)]
        shift: Option<f64>,
        /// Accept an unstable equilibrium (exit 0); without it an unstable equilibrium is the
        /// run's failure (exit 1).
        #[arg(long, requires = "static_first")]
        allow_unstable: bool,
    },
    /// Run an Adams command file (.acf): its dataset (line 1), output name (line 2) and
    /// commands, writing <name>.msg, <name>.req and <name>.csv as the run goes.
    Run {
        /// The command file (.acf).
        command_file: PathBuf,
        /// Directory of the output files (default: the working directory, as Adams).
        #[arg(long, value_name = "DIR")]
        out_dir: Option<PathBuf>,
        /// Leave these statements of the dataset out, as if the command file deactivated
        /// them first: KEYWORD/id, a statement kind or an element's name (as for simulate).
        #[arg(long, value_name = "NAME", value_delimiter = ',')]
        deactivate: Vec<String>,
        /// Also write the report as one self-contained HTML page (tables, plots, 3-D view).
        #[arg(long, value_name = "OUT.html")]
        html: Option<PathBuf>,
        /// The dataset to run, in place of the one the command file names (or for a command
        /// file that names none).
        #[arg(long, value_name = "MODEL.adm")]
        model: Option<PathBuf>,
        /// Accept an unstable static equilibrium (SIMULATE/STATIC); otherwise it stops the
        /// run, as `linkage static` refuses it.
        #[arg(long)]
        allow_unstable: bool,
        /// Stop each SIMULATE/DYNAMIC after this many seconds of wall-clock time (after the
        /// step it is in): the outputs up to there are written, and the run fails (exit 1)
        /// saying so. Default: 3600 s.
        #[arg(long, value_name = "SECONDS")]
        time_limit: Option<f64>,
    },
    /// Dynamic simulation to --end with output every --dtout or in --steps intervals.
    Simulate {
        /// The dataset (.adm).
        model: PathBuf,
        /// Leave these statements out: KEYWORD/id (SENSOR/3), a statement kind (SENSOR: all of
        /// them) or an element's name; comma-separated or repeated. The report names them.
        #[arg(long, value_name = "NAME", value_delimiter = ',')]
        deactivate: Vec<String>,
        /// Also write the report as one self-contained HTML page (tables, plots, 3-D view).
        #[arg(long, value_name = "OUT.html")]
        html: Option<PathBuf>,
        /// Output format of the summary.
        #[arg(long, value_enum, default_value = "text")]
        format: Format,
        /// End time.
        #[arg(long, allow_negative_numbers = true)]
        end: f64,
        /// Number of output intervals.
        #[arg(long, conflicts_with = "dtout")]
        steps: Option<usize>,
        /// Output interval.
        #[arg(long, allow_negative_numbers = true)]
        dtout: Option<f64>,
        /// Write the time histories as CSV.
        #[arg(long, value_name = "FILE.csv")]
        out: Option<PathBuf>,
        /// Find static equilibrium first and start from it at rest: by Newton statics, or by
        /// damped dynamics when the dataset says EQUILIBRIUM/DYNAMIC.
        #[arg(long)]
        start_at_equilibrium: bool,
        /// With --start-at-equilibrium: find it by damped dynamics (settling with the
        /// EQUILIBRIUM statement's GLOBAL_DAMPING, SETTLING_TIME and limits, then the Newton
        /// polish), whatever the dataset says.
        #[arg(long, requires = "start_at_equilibrium")]
        settle: bool,
        /// Accept an unstable equilibrium (exit 0); without it an unstable equilibrium is the
        /// run's failure (exit 1).
        #[arg(long, requires = "start_at_equilibrium")]
        allow_unstable: bool,
        /// Stop the run after this many seconds of wall-clock time (after the step it is in):
        /// the outputs up to there are written, and the run fails (exit 1) saying so.
        /// Default: 3600 s.
        #[arg(long, value_name = "SECONDS")]
        time_limit: Option<f64>,
        /// With --html: plot these columns (one plot each: PART.x|y|z|vx|vy|vz,
        /// ELEMENT.fx|fy|fz, REQUEST columns) instead of the default plots.
        #[arg(long, value_name = "COLUMN", value_delimiter = ',', requires = "html")]
        plot: Vec<String>,
    },
    /// Plot columns of a time history (CSV written by `simulate --out` or `run`, or an Adams
    /// .req file) against time, as SVG or PNG (by the extension of --out). The axes carry
    /// the columns' units from the CSV header; columns of different units are refused.
    Plot {
        /// The time history (.csv or .req).
        file: PathBuf,
        /// The columns to plot, comma-separated: CSV column names without the unit suffix
        /// (`crank.x,crank.y` for the header `crank.x [m]`), or in a .req file
        /// `REQUEST_<id>.<component>` (`REQUEST_3.x`; `3.x` also works), as `compare`
        /// names them. All of one unit.
        #[arg(long, value_delimiter = ',', required = true)]
        columns: Vec<String>,
        /// The image to write: .svg or .png (anti-aliased).
        #[arg(long, value_name = "plot.svg|plot.png")]
        out: PathBuf,
        /// Image width in pixels.
        #[arg(long, default_value_t = plot_cmd::WIDTH)]
        width: u32,
        /// Image height in pixels.
        #[arg(long, default_value_t = plot_cmd::HEIGHT)]
        height: u32,
        /// Line width in pixels.
        #[arg(long, default_value_t = 2)]
        line_width: u32,
    },
    /// Parameter sweep: run SPEC.toml's analysis over its varied arguments, each run's JSON
    /// report (and CSV for simulate) under --out DIR; `linkage sweep merge DIR` writes
    /// DIR/summary.csv. Shards (--shard K/N, or from SLURM_ARRAY_TASK_ID/COUNT or a
    /// Kubernetes indexed Job's JOB_COMPLETION_INDEX with JOB_COMPLETIONS) run the indices
    /// i ≡ K−1 (mod N).
    #[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
    Sweep {
        #[command(subcommand)]
        action: Option<SweepAction>,
        /// The sweep spec (.toml): model, [analysis], [[vary]] tables, [sampling].
        #[arg(required = true, value_name = "SPEC.toml")]
        spec: Option<PathBuf>,
        /// Directory of the runs' records (shared by every shard of the sweep).
        #[arg(long, value_name = "DIR", required = true)]
        out: Option<PathBuf>,
        /// Run only the indices i with i mod N = K − 1 (default: from the job scheduler's
        /// environment, else every run).
        #[arg(long, value_name = "K/N")]
        shard: Option<String>,
        /// Runs at once on this machine (threads; default: the number of CPUs).
        #[arg(long, value_name = "J", value_parser = clap::value_parser!(u64).range(1..))]
        jobs: Option<u64>,
    },
    /// Export an Adams Controls plant (a dataset with PINPUT/POUTPUT) as a co-simulation FMU
    /// (FMI 3.0, or 2.0 with --fmi 2): inputs the PINPUT's VARIABLEs, outputs the POUTPUT's,
    /// the dataset in resources/ and this platform's binary (liblinkage_fmu_binary.so beside the
    /// linkage executable, built by `cargo build --release`).
    Fmu {
        /// The dataset (.adm).
        model: PathBuf,
        /// The FMU to write.
        #[arg(long, value_name = "PLANT.fmu")]
        out: PathBuf,
        /// FMI version: 3 (3.0) or 2 (2.0).
        #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u8).range(2..=3))]
        fmi: u8,
        /// The PINPUT whose VARIABLEs are the inputs (default: the last in the dataset).
        #[arg(long, value_name = "ID")]
        pinput: Option<u64>,
        /// The POUTPUT whose VARIABLEs are the outputs (default: the last in the dataset).
        #[arg(long, value_name = "ID")]
        poutput: Option<u64>,
        /// A statement argument the importer may set before the initialisation, as a
        /// parameter named KEYWORD/id.ARGUMENT (SPRINGDAMPER/1.K); comma-separated or repeated.
        #[arg(long, value_name = "KEYWORD/ID.ARG", value_delimiter = ',')]
        parameter: Vec<String>,
        /// Start the parameter initial_static at true: the static equilibrium (as the
        /// dataset's EQUILIBRIUM says) before the first step.
        #[arg(long)]
        initial_static: bool,
        /// The FMU binary to pack (default: liblinkage_fmu_binary.so beside this executable).
        #[arg(long, value_name = "LIB.so")]
        binary: Option<PathBuf>,
    },
    /// Compare two time histories signal by signal: request files (.req, Adams or linkage) or
    /// CSV files written by `simulate --out`, matched by request id and component or by column
    /// name, at B's output times (A interpolated linearly in time). Exit code 1 when a signal's
    /// largest difference exceeds --tol times its range in A (at least --floor).
    Compare {
        /// The reference file (.req or .csv).
        a: PathBuf,
        /// The file compared with it (.req or .csv).
        b: PathBuf,
        /// Bound on max |B - A| / max(range of A, --floor), per signal.
        #[arg(long, default_value_t = compare_cmd::DEFAULT_TOLERANCE)]
        tol: f64,
        /// Ranges below this (in the signal's units) count as this, so that a constant signal
        /// is compared absolutely.
        #[arg(long, default_value_t = compare_cmd::DEFAULT_RANGE_FLOOR)]
        floor: f64,
        /// Output format.
        #[arg(long, value_enum, default_value = "text")]
        format: Format,
    },
}

#[derive(Subcommand)]
enum SweepAction {
    /// Gather every shard's records into DIR/summary.csv (one row per run); refuses when a
    /// run is missing or recorded twice.
    Merge {
        /// The --out directory of the sweep.
        dir: PathBuf,
    },
}

/// The input and output files of a command, for the check that no output overwrites its input.
fn input_and_output(command: &Command) -> Vec<(&std::path::Path, &std::path::Path)> {
    fn pairs<'a>(
        inputs: Vec<&'a std::path::Path>,
        outputs: Vec<Option<&'a PathBuf>>,
    ) -> Vec<(&'a std::path::Path, &'a std::path::Path)> {
        inputs
            .into_iter()
            .flat_map(|i| outputs.iter().flatten().map(move |o| (i, o.as_path())))
            .collect()
    }
    match command {
        Command::Verify {
            model, save, html, ..
        } => pairs(
            model.iter().map(PathBuf::as_path).collect(),
            vec![save.as_ref(), html.as_ref()],
        ),
        Command::Ic {
            model, save, html, ..
        }
        | Command::Static {
            model, save, html, ..
        } => pairs(vec![model.as_path()], vec![save.as_ref(), html.as_ref()]),
        Command::Simulate {
            model, out, html, ..
        } => pairs(vec![model.as_path()], vec![out.as_ref(), html.as_ref()]),
        Command::Linear { model, html, .. } => pairs(vec![model.as_path()], vec![html.as_ref()]),
        Command::Run {
            command_file,
            model,
            html,
            ..
        } => {
            let mut inputs = vec![command_file.as_path()];
            inputs.extend(model.as_deref());
            pairs(inputs, vec![html.as_ref()])
        }
        Command::Plot { file, out, .. }
        | Command::Fmu {
            model: file, out, ..
        } => vec![(file.as_path(), out.as_path())],
        Command::Compare { .. } | Command::Sweep { .. } => Vec::new(),
    }
}

fn main() -> ExitCode {
    common::restore_sigpipe();
    common::keep_freed_memory();
    let cli = Cli::parse();
    common::set_read_options(linkage_adm::ReadOptions {
        lenient_arguments: cli.lenient_arguments,
    });
    common::set_user_libraries(cli.user_lib.clone());
    for (input, output) in input_and_output(&cli.command) {
        if let Err(e) = common::check_output(input, output) {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    }
    match cli.command {
        Command::Run {
            command_file,
            out_dir,
            model,
            deactivate,
            html,
            allow_unstable,
            time_limit,
        } => run_cmd::run(
            &command_file,
            run_cmd::Paths {
                out_dir: out_dir.as_deref(),
                model: model.as_deref(),
                html: html.as_deref(),
            },
            run_cmd::Options {
                deactivate: &deactivate,
                allow_unstable,
                time_limit,
            },
        ),
        Command::Plot {
            file,
            columns,
            out,
            width,
            height,
            line_width,
        } => plot_cmd::run(&plot_cmd::PlotArgs {
            file: &file,
            columns: &columns,
            out: &out,
            width,
            height,
            line_width,
        }),
        Command::Verify {
            model,
            format,
            explain,
            apply,
            save,
            deactivate,
            html,
        } => verify_cmd::run(&verify_cmd::VerifyArgs {
            models: &model,
            format,
            explain,
            apply,
            save: save.as_deref(),
            deactivate: &deactivate,
            html: html.as_deref(),
        }),
        Command::Ic {
            model,
            format,
            save,
            deactivate,
            html,
        } => ic_cmd::run(
            &model,
            format,
            save.as_deref(),
            html.as_deref(),
            &deactivate,
        ),
        Command::Linear {
            model,
            format,
            static_first,
            no_damping,
            no_vectors,
            modes,
            shift,
            allow_unstable,
            deactivate,
            html,
        } => linear_cmd::run_linear(&linear_cmd::LinearArgs {
            model: &model,
            format,
            static_first,
            damping: !no_damping,
            vectors: !no_vectors,
            modes: modes.map(|k| usize::try_from(k).unwrap_or(usize::MAX)),
            shift,
            allow_unstable,
            deactivate: &deactivate,
            html: html.as_deref(),
        }),
        Command::Simulate {
            model,
            format,
            end,
            steps,
            dtout,
            out,
            start_at_equilibrium,
            settle,
            allow_unstable,
            time_limit,
            deactivate,
            html,
            plot,
        } => simulate_cmd::run_simulate(&simulate_cmd::SimulateArgs {
            model: &model,
            format,
            end,
            steps,
            dtout,
            out: out.as_deref(),
            start: match (start_at_equilibrium, settle) {
                (false, _) => Start::InitialConditions,
                (true, false) => Start::Equilibrium,
                (true, true) => Start::SettledEquilibrium,
            },
            allow_unstable,
            time_limit,
            deactivate: &deactivate,
            html: html.as_deref(),
            plot: &plot,
        }),
        Command::Static {
            model,
            format,
            end,
            steps,
            save,
            settle,
            allow_unstable,
            time_limit,
            deactivate,
            html,
        } => static_cmd::run_static(&static_cmd::StaticArgs {
            model: &model,
            format,
            series: end.zip(steps),
            save: save.as_deref(),
            settle,
            allow_unstable,
            time_limit,
            deactivate: &deactivate,
            html: html.as_deref(),
        }),
        Command::Sweep {
            action: Some(SweepAction::Merge { dir }),
            ..
        } => sweep_cmd::merge(&dir),
        Command::Fmu {
            model,
            out,
            fmi,
            pinput,
            poutput,
            parameter,
            initial_static,
            binary,
        } => fmu_cmd::run(
            &model,
            &out,
            binary.as_deref(),
            &linkage_fmu::export::ExportOptions {
                version: if fmi == 2 {
                    linkage_fmu::description::FmiVersion::V2
                } else {
                    linkage_fmu::description::FmiVersion::V3
                },
                pinput,
                poutput,
                parameters: parameter,
                initial_static,
            },
        ),
        Command::Sweep {
            action: None,
            spec,
            out,
            shard,
            jobs,
        } => match (spec, out) {
            (Some(spec), Some(out)) => sweep_cmd::run(
                &spec,
                &out,
                shard.as_deref(),
                jobs.map(|j| usize::try_from(j).unwrap_or(usize::MAX)),
            ),
            _ => {
                eprintln!("error: linkage sweep needs SPEC.toml and --out DIR");
                ExitCode::from(2)
            }
        },
        Command::Compare {
            a,
            b,
            tol,
            floor,
            format,
        } => compare_cmd::run(&compare_cmd::CompareArgs {
            a: &a,
            b: &b,
            tol,
            floor,
            format,
        }),
    }
}
