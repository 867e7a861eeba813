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

/// Input errors for elements linkage cannot evaluate in a force analysis.
pub fn unmodelled_elements(loaded: &Loaded) -> Result<(), Diagnostics> {
    let errors: Vec<Diagnostic> = loaded
        .dataset
        .statements
        .iter()
        .filter(|st| linkage_solve::forces::UNMODELLED_STATEMENTS.contains(&st.keyword.as_str()))
        .map(|st| {
            let name = st.view_name.clone().unwrap_or_else(|| format!("{}_{}", st.keyword, st.id.unwrap_or(0)));
            Diagnostic::error(
                loaded.dataset.file.clone(),
                Some(st.span),
                format!("{name}: linkage does not model {} elements; a force analysis of this model would be wrong", st.keyword),
            )
        })
        .collect();
    if errors.is_empty() {
        Ok(())
    } else {
        Err(Diagnostics(errors))
    }
}

/// The applied force elements of a loaded model (gravity is applied by the analyses).
pub fn applied_forces(
    loaded: &Loaded,
) -> Result<Box<dyn linkage_solve::applied::AppliedForces>, Diagnostics> {
    unmodelled_elements(loaded)?;
    let forces = linkage_solve::forces::ForceSet::new(&loaded.model)?;
    Ok(Box::new(forces))
}
