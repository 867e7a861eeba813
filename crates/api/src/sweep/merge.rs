//! `linkage sweep merge DIR`: every shard's run records gathered into `DIR/summary.csv`, one
//! row per run in index order: `index`, the varied values, `status`, `exit_code`, `message`,
//! then the scalar results found in the reports (see [`scalars`]).
//!
//! The merge refuses when a run is recorded by more than one shard (shards of two different
//! splits in one DIR) or when a run of the plan has no record; it then removes the
//! `summary.csv` of an earlier merge, which no longer describes DIR. A summary is written
//! whole (a temporary file renamed), so a reader never sees a part of one.
//!
//! Numbers: the varied values in their shortest text that reads back to the same double
//! (`0.1`, `2.5E+20`); the results with at most [`CSV_DIGITS`] significant digits, as every
//! CSV of linkage ([`linkage_adm::num::general`]); `-0` is written `0`.

use super::{run_file, Plan, RunRecord};
use linkage_adm::num::{general, CSV_DIGITS};
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

/// A varied value: the shortest text that reads back to `x`, plain for magnitudes in
/// [1e-4, 1e16), `mantissaE±XX` otherwise; `-0` is `0`.
fn shortest(x: f64) -> String {
    if x == 0.0 {
        return "0".to_string();
    }
    if !x.is_finite() {
        return general(x, 17);
    }
    if (1e-4..1e16).contains(&x.abs()) {
        return format!("{x}");
    }
    let s = format!("{x:e}");
    let (mantissa, exponent) = s.split_once('e').unwrap_or((&s, "0"));
    let e: i32 = exponent.parse().unwrap_or(0);
    let sign = if e < 0 { '-' } else { '+' };
    format!("{mantissa}E{sign}{:02}", e.unsigned_abs())
}

/// A result of a report as the summary writes it: numbers with at most [`CSV_DIGITS`]
/// significant digits (`-0` as `0`), anything else as JSON.
fn result(v: &Value) -> String {
    match v.as_f64() {
        Some(x) if v.is_f64() => general(x, CSV_DIGITS),
        _ => v.to_string(),
    }
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
            out.push((format!("frequency_{n}"), result(f)));
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
                    out.push((format!("{name} {c}"), result(v)));
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

/// Merges the records under `dir` into `dir/summary.csv` (see the module documentation); a
/// refused merge removes the summary of an earlier one.
pub fn merge(dir: &Path) -> Result<Merged, MergeError> {
    let merged = merge_records(dir);
    if merged.is_err() {
        let summary = dir.join("summary.csv");
        match std::fs::remove_file(&summary) {
            Ok(()) => {}
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
            Err(e) => {
                return Err(MergeError::Write {
                    path: summary.display().to_string(),
                    why: format!(
                        "the merge was refused and the old summary cannot be removed: {e}"
                    ),
                })
            }
        }
    }
    merged
}

fn merge_records(dir: &Path) -> Result<Merged, MergeError> {
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
            .chain(record.values.iter().map(|&x| shortest(x)))
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn varied_values_are_their_shortest_round_trip_text_and_never_minus_zero() {
        for (x, text) in [
            (0.1, "0.1"),
            (0.1 + 0.2, "0.30000000000000004"),
            (-0.0, "0"),
            (2.5e20, "2.5E+20"),
            (1e-7, "1E-07"),
            (200.0, "200"),
        ] {
            assert_eq!(shortest(x), text);
            if x != 0.0 {
                assert_eq!(text.parse::<f64>().unwrap(), x, "{text} reads back");
            }
        }
    }

    #[test]
    fn results_keep_the_csv_digits_and_write_minus_zero_as_zero() {
        let v: Value = serde_json::from_str("[-0.0, 0.30000000000000004, 3.0, 12]").unwrap();
        let texts: Vec<String> = v.as_array().unwrap().iter().map(result).collect();
        assert_eq!(texts, ["0", "0.3", "3", "12"]);
    }
}
