//! `linkage verify`.

use crate::common::{input_error, load, print_json, Format};
use linkage_solve::tolerances::Tolerances;
use std::path::Path;
use std::process::ExitCode;

/// Options of `linkage verify`.
pub struct VerifyArgs<'a> {
    pub model: &'a Path,
    pub format: Format,
}

pub fn run(args: &VerifyArgs) -> ExitCode {
    let loaded = match load(args.model) {
        Ok(l) => l,
        Err(d) => return input_error(&d, args.format),
    };
    let v = linkage_solve::verify::verify(&loaded.model, &loaded.drivers, &Tolerances::default());
    let report = linkage_report::verify::to_json(&loaded.model, &v, &loaded.warnings);
    match args.format {
        Format::Text => print!("{}", linkage_report::verify::to_text(&report)),
        Format::Json => {
            if !print_json(&report) {
                return ExitCode::from(1);
            }
        }
    }
    ExitCode::SUCCESS
}
