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

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
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
                Format::Json => match serde_json::to_string_pretty(&report) {
                    Ok(s) => println!("{s}"),
                    Err(e) => {
                        eprintln!("error: cannot write JSON: {e}");
                        return ExitCode::from(1);
                    }
                },
            }
            ExitCode::SUCCESS
        }
    }
}
