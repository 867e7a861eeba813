//! `linkage linear`: eigenvalues and modes about an operating point.

use crate::common::{applied_forces, input_error, load, print_json, Format};
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::linearize::{run, EigenMethod, LinearOptions, DEFAULT_MODES};
use linkage_solve::tolerances::Tolerances;
use std::path::Path;
use std::process::ExitCode;

/// Options of `linkage linear`.
pub struct LinearArgs<'a> {
    pub model: &'a Path,
    pub format: Format,
    pub static_first: bool,
    pub damping: bool,
    pub vectors: bool,
    /// `--modes K`: the K modes nearest the shift, by shift-invert.
    pub modes: Option<usize>,
    /// `--shift F` in cycles per time unit.
    pub shift: Option<f64>,
}

pub fn run_linear(args: &LinearArgs) -> ExitCode {
    let loaded = match load(args.model) {
        Ok(l) => l,
        Err(d) => return input_error(&d, args.format),
    };
    let forces = match applied_forces(&loaded) {
        Ok(f) => f,
        Err(d) => return input_error(&d, args.format),
    };
    if args.shift.is_some_and(|f| !f.is_finite()) {
        eprintln!("error: --shift must be a finite frequency");
        return ExitCode::from(2);
    }
    let method = match (args.modes, args.shift) {
        (None, None) => EigenMethod::Auto,
        (modes, shift) => EigenMethod::ShiftInvert {
            modes: modes.unwrap_or(DEFAULT_MODES),
            shift: shift.map(|f| f * std::f64::consts::TAU),
        },
    };
    let opts = LinearOptions {
        damping: args.damping,
        vectors: args.vectors,
        method,
    };
    let assembled = Assembled::new(
        &loaded.model,
        &loaded.drivers,
        forces.as_ref(),
        &Tolerances::default(),
    );
    let result = run(&assembled, args.static_first, opts);
    let report = linkage_report::linear::to_json(
        &loaded.model,
        &result,
        args.static_first,
        &loaded.warnings,
    );
    match args.format {
        Format::Text => print!("{}", linkage_report::linear::to_text(&report)),
        Format::Json => {
            print_json(&report);
        }
    }
    for e in &report.errors {
        eprintln!("error: {e}");
    }
    if report.errors.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}
