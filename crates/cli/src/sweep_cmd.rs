//! `linkage sweep SPEC.toml --out DIR [--shard K/N] [--jobs J]` and `linkage sweep merge DIR`
//! (the sweep itself is `linkage_api::sweep`).

use linkage_api::sweep::{self, shard::Shard, spec::Spec};
use std::path::Path;
use std::process::ExitCode;

/// Runs this shard's runs of the sweep `spec`; exit 0 when each was run and recorded (a
/// failing run is a result: its status says so), 1 when a record could not be written, 2
/// for an invalid spec, dataset or shard.
pub fn run(spec: &Path, out: &Path, shard: Option<&str>, jobs: Option<usize>) -> ExitCode {
    let mut spec = match Spec::read(spec) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    spec.user_libraries
        .extend(crate::common::user_libraries().iter().cloned());
    let shard = match Shard::choose(shard, |name| std::env::var(name).ok()) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let jobs = jobs.unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    let total = spec.run_count().unwrap_or(0);
    let report = |r: &sweep::RunRecord| {
        let first_line = r.message.lines().next().unwrap_or("");
        eprintln!(
            "run {} of {total}: {}{}{first_line}",
            r.index,
            r.status,
            if first_line.is_empty() { "" } else { ": " }
        );
    };
    match sweep::run(&spec, out, shard, jobs, &report) {
        Ok(done) => {
            println!(
                "shard {}/{}: {} run(s), {} failed; records in {}",
                shard.number,
                shard.count,
                done.runs,
                done.failed,
                out.join(shard.folder()).display()
            );
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(match e {
                sweep::SweepError::Io(_) => 1,
                _ => 2,
            })
        }
    }
}

/// Writes `DIR/summary.csv`; exit 1 (nothing written) when a run is missing or recorded
/// twice.
pub fn merge(dir: &Path) -> ExitCode {
    match sweep::merge::merge(dir) {
        Ok(m) => {
            println!(
                "{} run(s), {} failed: {}",
                m.runs,
                m.failed,
                m.summary.display()
            );
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(1)
        }
    }
}
