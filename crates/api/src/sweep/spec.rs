//! The sweep spec (TOML): a dataset, an analysis with its arguments, and the arguments to
//! vary.
//!
//! ```toml
//! model = "spring_mass.adm"        # relative to the spec's folder
//! deactivate = []                  # optional, as --deactivate
//! lenient_arguments = false        # optional, as --lenient-arguments
//! user_lib = ["libforces.so"]      # optional, as --user-lib (relative to the spec's folder)
//! [analysis]
//! kind = "linear"                  # verify | ic | static | linear | simulate, + CLI options
//! [sampling]                       # only with distributions
//! count = 100
//! seed = 7
//! [[vary]]
//! statement = "SPRINGDAMPER/1"
//! argument = "K"
//! values = [200.0, 800.0]          # or range = { start, stop, count } (count values, both ends)
//!                                  # or distribution = { kind = "uniform", low, high }
//!                                  #                 | { kind = "normal", mean, sd }
//! ```

use crate::job::Job;
use std::path::{Path, PathBuf};

/// Why a spec cannot be used (an input error: exit code 2).
#[derive(Debug, thiserror::Error)]
pub enum SpecError {
    #[error("cannot read {path}: {source}")]
    Read {
        path: String,
        source: std::io::Error,
    },
    /// The TOML parser's message names the line and column.
    #[error("{path}: {message}")]
    Syntax { path: String, message: String },
    /// A `[[vary]]` table (numbered from 1) that cannot be.
    #[error("{path}: [[vary]] table {number} ({statement}, {argument}): {why}")]
    Vary {
        path: String,
        number: usize,
        statement: String,
        argument: String,
        why: String,
    },
    #[error("{path}: {why}")]
    Invalid { path: String, why: String },
}

/// `range = { start, stop, count }`: `count` values from `start` to `stop`, both included.
#[derive(Clone, Debug, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct Range {
    pub start: f64,
    pub stop: f64,
    pub count: usize,
}

/// A distribution one value per sample is drawn from.
#[derive(Clone, Debug, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
pub enum Distribution {
    /// Uniform on `[low, high)`.
    Uniform { low: f64, high: f64 },
    /// Normal with mean `mean` and standard deviation `sd`.
    Normal { mean: f64, sd: f64 },
}

/// One `[[vary]]` table, as written.
#[derive(Clone, Debug, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct Vary {
    pub statement: String,
    pub argument: String,
    pub values: Option<Vec<f64>>,
    pub range: Option<Range>,
    pub distribution: Option<Distribution>,
}

/// `[sampling]`: how many samples are drawn from the distributions, and the seed.
#[derive(Clone, Copy, Debug, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct Sampling {
    pub count: usize,
    pub seed: u64,
}

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct SpecFile {
    model: PathBuf,
    #[serde(default)]
    deactivate: Vec<String>,
    #[serde(default)]
    lenient_arguments: bool,
    #[serde(default)]
    user_lib: Vec<PathBuf>,
    analysis: Job,
    sampling: Option<Sampling>,
    #[serde(default)]
    vary: Vec<Vary>,
}

/// What a varied argument takes: a list of values, or draws from a distribution.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub enum Values {
    List(Vec<f64>),
    Drawn(Distribution),
}

/// A varied argument, checked.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Varied {
    pub statement: String,
    pub argument: String,
    pub values: Values,
}

impl Varied {
    /// The summary's column name: `SPRINGDAMPER/1 K`.
    pub fn label(&self) -> String {
        format!("{} {}", self.statement, self.argument)
    }
}

/// A checked sweep spec.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Spec {
    /// The dataset (relative paths resolved against the spec's folder).
    pub model: PathBuf,
    pub deactivate: Vec<String>,
    /// An argument a statement does not take is a warning, not an input error
    /// (`--lenient-arguments`).
    pub lenient_arguments: bool,
    /// Libraries (or folders) of the model's user subroutines (`--user-lib`).
    pub user_libraries: Vec<PathBuf>,
    pub analysis: Job,
    pub sampling: Option<Sampling>,
    pub vary: Vec<Varied>,
}

/// The most runs a sweep may have (a mistyped count is refused rather than filling a disk).
pub const MAX_RUNS: usize = 10_000_000;

impl Spec {
    /// Reads and checks the spec at `path`.
    pub fn read(path: &Path) -> Result<Spec, SpecError> {
        let text = std::fs::read_to_string(path).map_err(|source| SpecError::Read {
            path: path.display().to_string(),
            source,
        })?;
        let base = path.parent().unwrap_or(Path::new(""));
        Spec::parse(&path.display().to_string(), &text, base)
    }

    /// Parses and checks spec text; `name` is used in messages, `base` resolves the model.
    pub fn parse(name: &str, text: &str, base: &Path) -> Result<Spec, SpecError> {
        let file: SpecFile = toml::from_str(text).map_err(|e| SpecError::Syntax {
            path: name.to_string(),
            message: e.to_string().trim_end().to_string(),
        })?;
        let invalid = |why: String| SpecError::Invalid {
            path: name.to_string(),
            why,
        };
        if file.vary.is_empty() {
            return Err(invalid("a sweep needs at least one [[vary]] table".into()));
        }
        let mut vary = Vec::with_capacity(file.vary.len());
        for (k, v) in file.vary.into_iter().enumerate() {
            let bad = |why: String| SpecError::Vary {
                path: name.to_string(),
                number: k + 1,
                statement: v.statement.clone(),
                argument: v.argument.clone(),
                why,
            };
            let values = match (&v.values, &v.range, &v.distribution) {
                (Some(list), None, None) => {
                    if list.is_empty() {
                        return Err(bad("`values` is empty".into()));
                    }
                    Values::List(list.clone())
                }
                (None, Some(r), None) => {
                    if r.count == 0 {
                        return Err(bad("a range needs count >= 1".into()));
                    }
                    if r.count == 1 && r.start != r.stop {
                        return Err(bad("a range of one value needs start = stop".into()));
                    }
                    let step = if r.count > 1 {
                        (r.stop - r.start) / (r.count - 1) as f64
                    } else {
                        0.0
                    };
                    Values::List(
                        (0..r.count)
                            .map(|i| {
                                if i + 1 == r.count {
                                    r.stop
                                } else {
                                    r.start + step * i as f64
                                }
                            })
                            .collect(),
                    )
                }
                (None, None, Some(d)) => {
                    let ok = match *d {
                        Distribution::Uniform { low, high } => {
                            low.is_finite() && high.is_finite() && low < high
                        }
                        Distribution::Normal { mean, sd } => {
                            mean.is_finite() && sd.is_finite() && sd >= 0.0
                        }
                    };
                    if !ok {
                        return Err(bad("a uniform distribution needs low < high, a normal one sd >= 0 (finite)".into()));
                    }
                    if file.sampling.is_none() {
                        return Err(bad(
                            "a distribution needs a [sampling] table (count and seed)".into(),
                        ));
                    }
                    Values::Drawn(d.clone())
                }
                _ => {
                    return Err(bad(
                        "give exactly one of `values`, `range` and `distribution`".into(),
                    ))
                }
            };
            if let Values::List(list) = &values {
                if let Some(x) = list.iter().find(|x| !x.is_finite()) {
                    return Err(bad(format!("{x} is not a finite number")));
                }
            }
            vary.push(Varied {
                statement: v.statement,
                argument: v.argument,
                values,
            });
        }
        let sampled = vary.iter().any(|v| matches!(v.values, Values::Drawn(_)));
        match file.sampling {
            Some(s) if !sampled => {
                return Err(invalid(format!(
                    "[sampling] (count {}) needs a [[vary]] table with a distribution",
                    s.count
                )))
            }
            Some(s) if s.count == 0 => {
                return Err(invalid("[sampling] count must be at least 1".into()))
            }
            _ => {}
        }
        let spec = Spec {
            model: base.join(&file.model),
            deactivate: file.deactivate,
            lenient_arguments: file.lenient_arguments,
            user_libraries: file.user_lib.iter().map(|p| base.join(p)).collect(),
            analysis: file.analysis,
            sampling: file.sampling,
            vary,
        };
        if spec.run_count().is_none_or(|n| n > MAX_RUNS) {
            return Err(invalid(format!("the sweep has more than {MAX_RUNS} runs")));
        }
        Ok(spec)
    }

    /// The number of runs: the product of the value lists' lengths, times the sample count.
    pub fn run_count(&self) -> Option<usize> {
        let samples = self.sampling.map_or(1, |s| s.count);
        self.vary.iter().try_fold(samples, |n, v| match &v.values {
            Values::List(l) => n.checked_mul(l.len()),
            Values::Drawn(_) => Some(n),
        })
    }
}
