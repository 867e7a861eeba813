//! `linkage run FILE.acf`: an Adams command file, with its message, request and CSV files.

use std::path::Path;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// Runs the command file and prints where its outputs are; exit 0 when every command was
/// carried out, 1 when an analysis failed, 2 for input errors and commands linkage refuses,
/// 130 when interrupted (Ctrl-C stops the run at its next output; the files keep every output
/// written and the message file says where it stopped).
pub fn run(
    command_file: &Path,
    out_dir: Option<&Path>,
    model: Option<&Path>,
    deactivate: &[String],
) -> ExitCode {
    let interrupt = Arc::new(AtomicBool::new(false));
    let flag = Arc::clone(&interrupt);
    // Without a handler (another one is installed) Ctrl-C ends the process as usual.
    let _ = ctrlc::set_handler(move || flag.store(true, Ordering::Relaxed));
    let options = linkage_run::RunOptions {
        out_dir: out_dir.map(Path::to_path_buf),
        model: model.map(Path::to_path_buf),
        interrupt: Some(interrupt),
        deactivate: deactivate.to_vec(),
    };
    let (summary, error) = match linkage_run::run_command_file(command_file, &options) {
        Ok(s) => (Some(s), None),
        Err(stopped) => (stopped.summary, Some(stopped.error)),
    };
    if let Some(s) = &summary {
        println!(
            "{} command(s) carried out, {} output(s)",
            s.commands, s.outputs
        );
        println!("message file: {}", s.msg.display());
        if let (Some(req), Some(csv)) = (&s.req, &s.csv) {
            println!("request file: {}", req.display());
            println!("time histories: {}", csv.display());
        }
    }
    match error {
        None => ExitCode::SUCCESS,
        Some(e) => {
            eprintln!("error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}
