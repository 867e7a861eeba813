//! `linkage` — verify, assemble and solve Adams multibody datasets.
//!
//! Exit codes: 0 when the analysis ran (whatever it found), 1 when it ran and failed (e.g. an
//! inconsistent model or non-convergence), 2 for input errors (syntax, references, values).

use clap::{Parser, Subcommand, ValueEnum};
use linkage_adm::Diagnostics;
use linkage_model::build::Built;
use std::path::{Path, PathBuf};
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
}

#[derive(Clone, Copy, ValueEnum, PartialEq, Eq)]
enum Format {
    Text,
    Json,
}

#[derive(Subcommand)]
enum Command {
    /// Verify a model: parts, constraints, Gruebler count, DOF, redundant and misaligned
    /// constraints, unconstrained and massless parts.
    Verify {
        /// The dataset (.adm).
        model: PathBuf,
        /// Output format.
        #[arg(long, value_enum, default_value = "text")]
        format: Format,
    },
    /// Initial conditions: assemble the model (least change), then velocities, accelerations
    /// and reaction forces at the start time.
    Ic {
        /// The dataset (.adm).
        model: PathBuf,
        /// Output format.
        #[arg(long, value_enum, default_value = "text")]
        format: Format,
        /// Write the assembled configuration as a new dataset (only moved parts' QG/REULER
        /// change).
        #[arg(long, value_name = "OUT.adm")]
        save: Option<PathBuf>,
    },
}

fn load(path: &Path) -> Result<Built, Diagnostics> {
    let ds = linkage_adm::read_dataset(path)?;
    linkage_model::build_model(&ds)
}

fn input_error(d: &Diagnostics, format: Format) -> ExitCode {
    match format {
        Format::Text => eprintln!("{d}"),
        Format::Json => {
            let errors: Vec<String> = d.0.iter().map(|e| e.to_string()).collect();
            println!(
                "{}",
                serde_json::json!({ "errors": errors, "warnings": [] })
            );
            eprintln!("{d}");
        }
    }
    ExitCode::from(2)
}

fn print_json<T: serde::Serialize>(v: &T) -> bool {
    match serde_json::to_string_pretty(v) {
        Ok(s) => {
            println!("{s}");
            true
        }
        Err(e) => {
            eprintln!("error: cannot write JSON: {e}");
            false
        }
    }
}

fn run_ic(model: &Path, format: Format, save: Option<&Path>) -> ExitCode {
    let ds = match linkage_adm::read_dataset(model) {
        Ok(d) => d,
        Err(d) => return input_error(&d, format),
    };
    let built = match linkage_model::build_model(&ds) {
        Ok(b) => b,
        Err(d) => return input_error(&d, format),
    };
    let drivers = match linkage_solve::drivers::ExpressionDrivers::new(&built.model) {
        Ok(d) => d,
        Err(d) => return input_error(&d, format),
    };
    let tol = linkage_solve::tolerances::Tolerances::default();
    let ic = linkage_solve::ic::initial_conditions(&built.model, &drivers, &tol);
    let mut warnings = built.warnings.clone();
    warnings.extend(drivers.warnings().iter().cloned());
    let mut report = linkage_report::ic::to_json(&built.model, &ic, &warnings);
    let failed = !ic.assembly.converged || ic.inconsistent();
    if let Some(out) = save {
        if failed {
            report.errors.push(format!(
                "{} not written: the model could not be assembled",
                out.display()
            ));
        } else {
            match save_assembled(&ds, &built.model, &ic.assembly.state, out) {
                Ok(()) => {}
                Err(e) => {
                    report
                        .errors
                        .push(format!("cannot write {}: {e}", out.display()));
                    emit_ic(&report, format);
                    return ExitCode::from(1);
                }
            }
        }
    }
    emit_ic(&report, format);
    if failed {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}

fn emit_ic(report: &linkage_report::ic::IcJson, format: Format) {
    match format {
        Format::Text => print!("{}", linkage_report::ic::to_text(report)),
        Format::Json => {
            print_json(report);
        }
    }
    for e in &report.errors {
        eprintln!("error: {e}");
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::Ic {
            model,
            format,
            save,
        } => run_ic(&model, format, save.as_deref()),
        Command::Verify { model, format } => {
            let built = match load(&model) {
                Ok(b) => b,
                Err(d) => return input_error(&d, format),
            };
            let tol = linkage_solve::tolerances::Tolerances::default();
            let drivers = match linkage_solve::drivers::ExpressionDrivers::new(&built.model) {
                Ok(d) => d,
                Err(d) => return input_error(&d, format),
            };
            let v = linkage_solve::verify::verify(&built.model, &drivers, &tol);
            let mut warnings = built.warnings.clone();
            warnings.extend(drivers.warnings().iter().cloned());
            let report = linkage_report::verify::to_json(&built.model, &v, &warnings);
            match format {
                Format::Text => print!("{}", linkage_report::verify::to_text(&report)),
                Format::Json => {
                    if !print_json(&report) {
                        return ExitCode::from(1);
                    }
                }
            }
            ExitCode::SUCCESS
        }
    }
}

/// Writes the dataset with every moved part's QG/REULER at the assembled configuration
/// (markers keep their place on their part because they are given in the part's frame).
fn save_assembled(
    ds: &linkage_adm::Dataset,
    model: &linkage_model::Model,
    state: &linkage_solve::state::State,
    out: &Path,
) -> Result<(), String> {
    let poses: Vec<linkage_adm::writer::PartPose> = model
        .parts
        .iter()
        .enumerate()
        .filter(|(k, p)| {
            let s = state.poses[*k];
            (s.p - p.p_gb).length() > 0.0 || s.r != p.r_gb
        })
        .map(|(k, p)| {
            let s = state.poses[k];
            let qg = s.p + s.r * p.p_b_bcs;
            linkage_adm::writer::PartPose {
                statement: p.origin.statement_index,
                qg: qg.to_array(),
                reuler: linkage_model::frames::matrix_to_euler313(&s.r),
            }
        })
        .collect();
    let text = linkage_adm::writer::write_part_poses(ds, &poses).map_err(|d| d.to_string())?;
    linkage_adm::writer::write_atomically(out, &text).map_err(|e| e.to_string())
}
