//! `linkage sweep merge DIR`: every shard's run records gathered into `DIR/summary.csv`, one
//! row per run in index order: `index`, the varied values, `status`, `exit_code`, `message`,
//! then the scalar results found in the reports (see [`scalars`]).
//!
//! The merge refuses (and writes nothing) when a run is recorded by more than one shard
//! (shards of two different splits in one DIR) or when a run of the plan has no record.

use super::{run_file, Plan, RunRecord};
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Why the summary was not written.
#[derive(Debug, thiserror::Error)]
pub enum MergeError {
    #[error("{dir} has no readable plan.json ({why}): it is not the --out of a sweep")]
    NoPlan { dir: String, why: String },
    #[error("cannot read {path}: {why}")]
    Read { path: String, why: String },
    /// Runs recorded by more than one shard folder.
    #[error("refusing to merge runs recorded twice: {0}")]
    Twice(String),
    /// Runs of the plan without a record (`count` of them; the first ones listed).
    #[error("{count} of {total} runs have no record (not run yet, or their shard failed): {listed}; run their shards again, then merge")]
    Missing {
        count: usize,
        total: usize,
        listed: String,
    },
    #[error("cannot write {path}: {why}")]
    Write { path: String, why: String },
}

/// What the merge wrote.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Merged {
    pub summary: PathBuf,
    pub runs: usize,
    pub failed: usize,
}

/// The scalar results of a report, in order: `dof`, `redundant` (the number of redundant
/// equations), `frequency_N` (undamped natural frequency of mode N, cycles per time unit),
/// and each part's final state (`simulate`'s `final_state`; the equilibrium or assembled
/// `parts` of static and ic) as `PART x`, `y`, `z`, `psi`, `theta`, `phi`, `vx`, `vy`, `vz`,
/// `wx`, `wy`, `wz` (those the report has).
pub fn scalars(report: &Value) -> Vec<(String, String)> {
    let mut out = Vec::new();
    if let Some(dof) = report.get("dof").filter(|v| v.is_number()) {
        out.push(("dof".to_string(), dof.to_string()));
    }
    if let Some(r) = report.get("redundant").and_then(Value::as_array) {
        out.push(("redundant".to_string(), r.len().to_string()));
    }
    for mode in report
        .get("modes")
        .and_then(Value::as_array)
        .into_iter()
        .flatten()
    {
        if let (Some(n), Some(f)) = (mode.get("number"), mode.get("frequency")) {
            out.push((format!("frequency_{n}"), f.to_string()));
        }
    }
    let parts = report
        .get("final_state")
        .or_else(|| report.get("parts"))
        .and_then(Value::as_array);
    const FIELDS: [(&str, [&str; 3]); 4] = [
        ("position", ["x", "y", "z"]),
        ("reuler", ["psi", "theta", "phi"]),
        ("velocity", ["vx", "vy", "vz"]),
        ("angular_velocity", ["wx", "wy", "wz"]),
    ];
    for part in parts.into_iter().flatten() {
        let Some(name) = part.get("name").and_then(Value::as_str) else {
            continue;
        };
        for (field, names) in FIELDS {
            if let Some(xyz) = part.get(field).and_then(Value::as_array) {
                for (v, c) in xyz.iter().zip(names) {
                    out.push((format!("{name} {c}"), v.to_string()));
                }
            }
        }
    }
    out
}

/// A CSV field, quoted when it holds a comma, a quote or a line break (RFC 4180).
fn field(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

fn read(path: &Path) -> Result<String, MergeError> {
    std::fs::read_to_string(path).map_err(|e| MergeError::Read {
        path: path.display().to_string(),
        why: e.to_string(),
    })
}

fn parse<T: serde::de::DeserializeOwned>(path: &Path) -> Result<T, MergeError> {
    serde_json::from_str(&read(path)?).map_err(|e| MergeError::Read {
        path: path.display().to_string(),
        why: e.to_string(),
    })
}

/// Where each run's records are: run index → the `runs` folders holding its status file.
fn locate(dir: &Path) -> Result<BTreeMap<usize, Vec<PathBuf>>, MergeError> {
    let listing = |p: &Path| {
        std::fs::read_dir(p).map_err(|e| MergeError::Read {
            path: p.display().to_string(),
            why: e.to_string(),
        })
    };
    let mut found: BTreeMap<usize, Vec<PathBuf>> = BTreeMap::new();
    let mut shards: Vec<PathBuf> = listing(dir)?
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| {
            p.is_dir()
                && p.file_name()
                    .and_then(|n| n.to_str())
                    .is_some_and(|n| n.starts_with("shard-") && n.contains("-of-"))
        })
        .collect();
    shards.sort();
    for shard in shards {
        let runs = shard.join("runs");
        if !runs.is_dir() {
            continue;
        }
        for entry in listing(&runs)?.filter_map(Result::ok) {
            let name = entry.file_name();
            let Some(index) = name
                .to_str()
                .and_then(|n| n.strip_suffix(".status.json"))
                .and_then(|n| n.parse::<usize>().ok())
            else {
                continue;
            };
            found.entry(index).or_default().push(runs.clone());
        }
    }
    Ok(found)
}

/// Merges the records under `dir` into `dir/summary.csv` (see the module documentation).
pub fn merge(dir: &Path) -> Result<Merged, MergeError> {
    let plan_path = dir.join("plan.json");
    let plan: Plan = serde_json::from_str(&std::fs::read_to_string(&plan_path).map_err(|e| {
        MergeError::NoPlan {
            dir: dir.display().to_string(),
            why: e.to_string(),
        }
    })?)
    .map_err(|e| MergeError::NoPlan {
        dir: dir.display().to_string(),
        why: e.to_string(),
    })?;
    let found = locate(dir)?;
    let twice: Vec<String> = found
        .iter()
        .filter(|(_, at)| at.len() > 1)
        .map(|(i, at)| {
            let folders: Vec<String> = at
                .iter()
                .filter_map(|p| p.parent()?.file_name()?.to_str().map(str::to_string))
                .collect();
            format!("run {i} in {}", folders.join(" and "))
        })
        .collect();
    if !twice.is_empty() {
        return Err(MergeError::Twice(format!(
            "{}; remove the folders of the split that should not count",
            twice.join(", ")
        )));
    }
    let missing: Vec<usize> = (0..plan.runs).filter(|i| !found.contains_key(i)).collect();
    if !missing.is_empty() {
        const LISTED: usize = 20;
        let mut listed: Vec<String> = missing.iter().take(LISTED).map(usize::to_string).collect();
        if missing.len() > LISTED {
            listed.push("…".into());
        }
        return Err(MergeError::Missing {
            count: missing.len(),
            total: plan.runs,
            listed: listed.join(", "),
        });
    }
    if let Some((i, at)) = found.iter().find(|(i, _)| **i >= plan.runs) {
        return Err(MergeError::Read {
            path: run_file(&at[0], *i, "status.json").display().to_string(),
            why: format!("run {i} is not in the plan's {} runs", plan.runs),
        });
    }
    // Every run's record and scalars, then the columns: their union in order of first
    // appearance (runs in index order, so the same records give the same table).
    let mut rows = Vec::with_capacity(plan.runs);
    let mut columns: Vec<String> = Vec::new();
    let mut known = std::collections::HashSet::new();
    for (index, at) in &found {
        let record: RunRecord = parse(&run_file(&at[0], *index, "status.json"))?;
        let report: Value = parse(&run_file(&at[0], *index, "json"))?;
        let values = scalars(&report);
        for (name, _) in &values {
            if known.insert(name.clone()) {
                columns.push(name.clone());
            }
        }
        rows.push((record, values.into_iter().collect::<BTreeMap<_, _>>()));
    }
    let mut csv = String::new();
    let header: Vec<String> = ["index".to_string()]
        .into_iter()
        .chain(plan.columns.iter().cloned())
        .chain(["status", "exit_code", "message"].map(String::from))
        .chain(columns.iter().cloned())
        .map(|h| field(&h))
        .collect();
    csv.push_str(&header.join(","));
    csv.push('\n');
    let mut failed = 0;
    for (record, values) in &rows {
        failed += usize::from(record.exit_code != 0);
        let row: Vec<String> = [record.index.to_string()]
            .into_iter()
            .chain(record.values.iter().map(f64::to_string))
            .chain([
                field(&record.status),
                record.exit_code.to_string(),
                field(&record.message),
            ])
            .chain(
                columns
                    .iter()
                    .map(|c| values.get(c).cloned().unwrap_or_default()),
            )
            .collect();
        csv.push_str(&row.join(","));
        csv.push('\n');
    }
    let summary = dir.join("summary.csv");
    super::write_whole(&summary, &csv).map_err(|e| MergeError::Write {
        path: summary.display().to_string(),
        why: e.to_string(),
    })?;
    Ok(Merged {
        summary,
        runs: rows.len(),
        failed,
    })
}
