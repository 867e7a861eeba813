//! What every command shares: loading a dataset, reporting input errors, printing JSON.

use clap::ValueEnum;
use linkage_adm::{Dataset, Diagnostic, Diagnostics};
use linkage_model::Model;
use linkage_solve::drivers::ExpressionDrivers;
use std::path::Path;
use std::process::ExitCode;

#[derive(Clone, Copy, ValueEnum, PartialEq, Eq, Debug)]
pub enum Format {
    Text,
    Json,
}

/// A dataset read, built and with its functions parsed.
pub struct Loaded {
    pub dataset: Dataset,
    pub model: Model,
    pub drivers: ExpressionDrivers,
    /// Dataset, model and function warnings.
    pub warnings: Vec<Diagnostic>,
}

/// Reads, builds and checks the functions of a dataset.
pub fn load(path: &Path) -> Result<Loaded, Diagnostics> {
    let dataset = linkage_adm::read_dataset(path)?;
    let built = linkage_model::build_model(&dataset)?;
    let drivers = ExpressionDrivers::new(&built.model)?;
    let mut warnings = built.warnings;
    warnings.extend(drivers.warnings().iter().cloned());
    Ok(Loaded {
        dataset,
        model: built.model,
        drivers,
        warnings,
    })
}

/// Prints input errors (and, for JSON, an object with `errors`) and returns exit code 2.
pub fn input_error(d: &Diagnostics, format: Format) -> ExitCode {
    if format == Format::Json {
        let errors: Vec<String> = d.0.iter().map(|e| e.to_string()).collect();
        println!(
            "{}",
            serde_json::json!({ "errors": errors, "warnings": [] })
        );
    }
    eprintln!("{d}");
    ExitCode::from(2)
}

/// Pretty JSON on stdout; false (after a message) when serialisation fails.
pub fn print_json<T: serde::Serialize>(v: &T) -> bool {
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

/// The applied force elements of a loaded model (none yet: gravity is applied by the analyses).
pub fn applied_forces(
    _loaded: &Loaded,
) -> Result<Box<dyn linkage_solve::applied::AppliedForces>, Diagnostics> {
    Ok(Box::new(linkage_solve::applied::NoForces))
}
