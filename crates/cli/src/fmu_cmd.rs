//! `linkage fmu`: a dataset as a co-simulation FMU ([`linkage_fmu::export`]).
//!
//! The FMU's binary is the `linkage-fmu` crate built as a shared library, which
//! `cargo build --release` puts beside the `linkage` executable (`liblinkage_fmu_binary.so`):
//! that is where it is looked for unless `--binary` or `$LINKAGE_FMU_BINARY` names another.

use linkage_fmu::export::{export, locate_binary, ExportError, ExportOptions};
use std::path::Path;
use std::process::ExitCode;

pub fn run(model: &Path, out: &Path, binary: Option<&Path>, options: &ExportOptions) -> ExitCode {
    // Beside the running executable unless --binary or $LINKAGE_FMU_BINARY names another.
    let exe = std::env::current_exe().ok();
    let binary = locate_binary(binary, exe.as_deref().and_then(Path::parent));
    match export(model, &binary, out, options) {
        Ok(done) => {
            let names = |ports: &[linkage_api::cosim::Port]| {
                let v: Vec<String> = ports
                    .iter()
                    .map(|p| format!("{} (VARIABLE/{})", p.name, p.id))
                    .collect();
                if v.is_empty() {
                    "none".to_string()
                } else {
                    v.join(", ")
                }
            };
            println!(
                "wrote {} (FMI {}, model identifier {}, {} bytes)",
                out.display(),
                match options.version {
                    linkage_fmu::description::FmiVersion::V2 => "2.0",
                    linkage_fmu::description::FmiVersion::V3 => "3.0",
                },
                done.model_identifier,
                done.bytes
            );
            let list = |keyword: &str, id: Option<u64>| {
                id.map_or(format!("every {keyword}"), |i| format!("{keyword}/{i}"))
            };
            println!(
                "  inputs ({}): {}",
                list("PINPUT", done.ports.pinput),
                names(&done.ports.inputs)
            );
            println!(
                "  outputs ({}): {}",
                list("POUTPUT", done.ports.poutput),
                names(&done.ports.outputs)
            );
            let params: Vec<String> = done
                .parameters
                .iter()
                .map(|p| format!("{} = {}", p.name(), p.start))
                .chain([format!("initial_static = {}", options.initial_static)])
                .collect();
            println!("  parameters: {}", params.join(", "));
            ExitCode::SUCCESS
        }
        Err(e) => {
            let code = match &e {
                ExportError::Input(_)
                | ExportError::Ports(_)
                | ExportError::Parameter { .. }
                | ExportError::Resource { .. } => 2,
                ExportError::Analysis(a) => a.exit_code(),
                ExportError::Binary { .. } | ExportError::Zip(_) | ExportError::Write { .. } => 1,
            };
            eprintln!("{}", e.to_string().trim_end());
            ExitCode::from(code)
        }
    }
}
