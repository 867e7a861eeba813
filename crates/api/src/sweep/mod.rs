//! Parameter sweeps: `linkage sweep SPEC.toml --out DIR [--shard K/N] [--jobs J]` and
//! `linkage sweep merge DIR`.
//!
//! A sweep runs one analysis ([`crate::job::Job`]) on a dataset with some statement
//! arguments changed per run ([`crate::Source::set`], the command files' redefinition), over
//! the Cartesian product of value lists or a seeded sample ([`plan`]). Each shard
//! ([`shard`]) writes under `DIR/shard-K-of-N/runs/`, for each of its runs `i` (six digits):
//! - `i.json`: the analysis's JSON report, as the CLI prints it (for input errors,
//!   `{"errors": […], "warnings": []}` as the CLI prints them);
//! - `i.csv`: the time histories (simulate);
//! - `i.status.json`: `{index, values, status, exit_code, message}` — `status` is `ok` or
//!   `failed`, `exit_code` the CLI's (1: the analysis ran and failed, 2: input errors, e.g. a
//!   value the model refuses) and `message` the run's errors, one per line.
//!
//! and `DIR/plan.json` (the model, analysis, varied arguments and the number of runs), the
//! same for every shard: a shard refuses a DIR that holds another sweep's plan. A failing run
//! is recorded and the sweep goes on. [`merge`] gathers every shard's records into
//! `DIR/summary.csv`.

pub mod merge;
pub mod plan;
pub mod shard;
pub mod spec;

use crate::job::Job;
use crate::simulate::CsvTarget;
use crate::source::{ArgValue, Source};
use shard::Shard;
use spec::Spec;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;

/// Why a sweep did not run (or stopped).
#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    /// The dataset, or the first run's changes to it, have input errors (exit code 2).
    #[error("{0}")]
    Input(linkage_adm::Diagnostics),
    /// DIR holds the plan of another sweep (exit code 2).
    #[error("{dir} holds another sweep (its plan.json differs from this spec's): choose another --out, or remove it")]
    OtherSweep { dir: String },
    /// DIR holds the records of another split of the same sweep (exit code 2): the two
    /// splits would record some runs twice.
    #[error("{dir} holds {found}, a split of this sweep into {other} shards; this shard splits it into {count}: use --shard K/{other}, or another --out")]
    OtherSplit {
        dir: String,
        found: String,
        other: usize,
        count: usize,
    },
    /// A file could not be written or read (exit code 1).
    #[error("{0}")]
    Io(String),
}

/// What happened to one run.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RunRecord {
    pub index: usize,
    /// The varied values, in `[[vary]]` order.
    pub values: Vec<f64>,
    /// `ok` or `failed`.
    pub status: String,
    /// The CLI's exit code for this run: 0, 1 or 2.
    pub exit_code: u8,
    /// The run's errors, one per line (empty when it succeeded).
    pub message: String,
}

/// `DIR/plan.json`: what every shard of one sweep agrees on.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Plan {
    pub model: String,
    pub deactivate: Vec<String>,
    pub analysis: Job,
    /// The summary's columns of varied values (`SPRINGDAMPER/1 K`).
    pub columns: Vec<String>,
    /// The varied values as the spec gives them (lists, ranges expanded, distributions).
    pub vary: serde_json::Value,
    pub sampling: Option<spec::Sampling>,
    pub runs: usize,
}

impl Plan {
    pub fn of(spec: &Spec) -> Plan {
        Plan {
            model: spec.model.display().to_string(),
            deactivate: spec.deactivate.clone(),
            analysis: spec.analysis.clone(),
            columns: spec.vary.iter().map(spec::Varied::label).collect(),
            vary: serde_json::to_value(&spec.vary).unwrap_or(serde_json::Value::Null),
            sampling: spec.sampling,
            runs: spec.run_count().unwrap_or(0),
        }
    }
}

/// What a shard did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SweepDone {
    pub runs: usize,
    pub failed: usize,
}

/// The file of run `index` with extension `ext` in `runs`.
pub fn run_file(runs: &Path, index: usize, ext: &str) -> PathBuf {
    runs.join(format!("{index:06}.{ext}"))
}

/// Writes `text` to `path` through a temporary file and a rename, so that a reader (another
/// shard, a merge) sees the old file or the new one, never a part.
fn write_whole(path: &Path, text: &str) -> Result<(), SweepError> {
    let tmp = path.with_extension(format!("tmp{}", std::process::id()));
    std::fs::write(&tmp, text)
        .and_then(|()| std::fs::rename(&tmp, path))
        .map_err(|e| SweepError::Io(format!("cannot write {}: {e}", path.display())))
}

fn pretty<T: serde::Serialize>(v: &T) -> Result<String, SweepError> {
    serde_json::to_string_pretty(v)
        .map(|s| s + "\n")
        .map_err(|e| SweepError::Io(format!("cannot write JSON: {e}")))
}

/// The source of run `index`: `base` with the run's values set.
fn amended(base: &Source, spec: &Spec, values: &[f64]) -> Result<Source, linkage_adm::Diagnostics> {
    let mut source = base.clone();
    for (v, x) in spec.vary.iter().zip(values) {
        source.set(&v.statement, &v.argument, &ArgValue::Number(*x))?;
    }
    Ok(source)
}

/// Runs run `index` and writes its files into `runs`.
fn run_one(base: &Source, spec: &Spec, index: usize, runs: &Path) -> Result<RunRecord, SweepError> {
    let values = spec.values(index);
    let csv_path = run_file(runs, index, "csv");
    let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        let loaded =
            amended(base, spec, &values)?.load(&spec.deactivate, spec.analysis.analysis())?;
        let csv = spec.analysis.writes_csv().then(|| {
            let path = csv_path.clone();
            CsvTarget {
                name: path.display().to_string(),
                open: Box::new(move || {
                    std::fs::File::create(&path)
                        .map(|f| Box::new(std::io::BufWriter::new(f)) as Box<dyn std::io::Write>)
                }),
            }
        });
        spec.analysis.run(&loaded, csv)
    }));
    let (report, exit_code) = match outcome {
        Ok(Ok(o)) => (o.report, o.exit_code),
        Ok(Err(e)) => (
            serde_json::json!({ "errors": e.messages(), "warnings": [] }),
            e.exit_code(),
        ),
        Err(panic) => {
            let why = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown".into());
            (
                serde_json::json!({ "errors": [format!("internal error: the run panicked: {why}")], "warnings": [] }),
                1,
            )
        }
    };
    let message = report
        .get("errors")
        .and_then(|e| e.as_array())
        .map(|errors| {
            errors
                .iter()
                .filter_map(|e| e.as_str())
                .collect::<Vec<_>>()
                .join("\n")
        })
        .unwrap_or_default();
    let record = RunRecord {
        index,
        values,
        status: if exit_code == 0 { "ok" } else { "failed" }.to_string(),
        exit_code,
        message,
    };
    write_whole(&run_file(runs, index, "json"), &pretty(&report)?)?;
    write_whole(&run_file(runs, index, "status.json"), &pretty(&record)?)?;
    Ok(record)
}

/// Writes `DIR/plan.json`, or checks that the one there is this sweep's.
fn settle_plan(out: &Path, plan: &Plan) -> Result<(), SweepError> {
    let path = out.join("plan.json");
    let text = pretty(plan)?;
    match std::fs::read_to_string(&path) {
        Ok(existing) => {
            let same = serde_json::from_str::<Plan>(&existing).is_ok_and(|p| p == *plan);
            if same {
                Ok(())
            } else {
                Err(SweepError::OtherSweep {
                    dir: out.display().to_string(),
                })
            }
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => write_whole(&path, &text),
        Err(e) => Err(SweepError::Io(format!(
            "cannot read {}: {e}",
            path.display()
        ))),
    }
}

/// Refuses a shard whose DIR holds the folder of a shard of a different split
/// (`shard-K-of-M`, M ≠ N): a merge could not tell which records count.
fn same_split(out: &Path, shard: Shard) -> Result<(), SweepError> {
    let Ok(entries) = std::fs::read_dir(out) else {
        return Ok(());
    };
    for entry in entries.filter_map(Result::ok) {
        let name = entry.file_name();
        let Some(name) = name.to_str() else { continue };
        let other = name
            .strip_prefix("shard-")
            .and_then(|rest| rest.split_once("-of-"))
            .and_then(|(k, m)| Some((k.parse::<usize>().ok()?, m.parse::<usize>().ok()?)));
        if let Some((_, m)) = other {
            if m != shard.count && entry.path().is_dir() {
                return Err(SweepError::OtherSplit {
                    dir: out.display().to_string(),
                    found: name.to_string(),
                    other: m,
                    count: shard.count,
                });
            }
        }
    }
    Ok(())
}

/// Runs this shard's runs of `spec` with `jobs` threads, writing under `out` (see the module
/// documentation); `done` is told of each run as it ends (from the worker threads).
pub fn run(
    spec: &Spec,
    out: &Path,
    shard: Shard,
    jobs: usize,
    done: &(dyn Fn(&RunRecord) + Sync),
) -> Result<SweepDone, SweepError> {
    let options = linkage_adm::ReadOptions {
        lenient_arguments: spec.lenient_arguments,
    };
    let base = Source::read_with(&spec.model, options)
        .and_then(|s| s.with_user_libraries(&spec.user_libraries))
        .map_err(SweepError::Input)?;
    // The first run's changes are checked before any run: a statement or argument that
    // cannot be changed is a mistake in the spec, not a result.
    amended(&base, spec, &spec.values(0)).map_err(SweepError::Input)?;
    std::fs::create_dir_all(out)
        .map_err(|e| SweepError::Io(format!("cannot create {}: {e}", out.display())))?;
    settle_plan(out, &Plan::of(spec))?;
    same_split(out, shard)?;
    let runs_dir = out.join(shard.folder()).join("runs");
    std::fs::create_dir_all(&runs_dir)
        .map_err(|e| SweepError::Io(format!("cannot create {}: {e}", runs_dir.display())))?;
    let total = spec.run_count().unwrap_or(0);
    let mine: Vec<usize> = (0..total).filter(|&i| shard.has(i)).collect();
    let next = AtomicUsize::new(0);
    let failed = AtomicUsize::new(0);
    let stop = AtomicBool::new(false);
    let error: Mutex<Option<SweepError>> = Mutex::new(None);
    let worker = || {
        while !stop.load(Ordering::Relaxed) {
            let Some(&index) = mine.get(next.fetch_add(1, Ordering::Relaxed)) else {
                break;
            };
            match run_one(&base, spec, index, &runs_dir) {
                Ok(record) => {
                    if record.exit_code != 0 {
                        failed.fetch_add(1, Ordering::Relaxed);
                    }
                    done(&record);
                }
                Err(e) => {
                    stop.store(true, Ordering::Relaxed);
                    if let Ok(mut slot) = error.lock() {
                        slot.get_or_insert(e);
                    }
                }
            }
        }
    };
    std::thread::scope(|s| {
        for _ in 1..jobs.max(1) {
            s.spawn(worker);
        }
        worker();
    });
    if let Some(e) = error.into_inner().ok().flatten() {
        return Err(e);
    }
    Ok(SweepDone {
        runs: mine.len(),
        failed: failed.into_inner(),
    })
}
