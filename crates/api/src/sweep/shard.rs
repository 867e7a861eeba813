//! Which runs this process does: `--shard K/N` runs the indices `i ≡ K−1 (mod N)`.
//!
//! Without `--shard`, K and N come from the job scheduler:
//! - Slurm array job (`sbatch --array=1-N` or `0-(N-1)`, contiguous): K =
//!   `SLURM_ARRAY_TASK_ID − SLURM_ARRAY_TASK_MIN + 1`, N = `SLURM_ARRAY_TASK_COUNT`;
//! - Kubernetes indexed Job: K = `JOB_COMPLETION_INDEX + 1` (set by Kubernetes), N =
//!   `JOB_COMPLETIONS`, which Kubernetes does not set: the manifest sets it to the Job's
//!   `completions` (see `examples/sweep-job.yaml`);
//! - neither: 1/1, every run.

/// A shard: runs `i` with `i % count == number − 1`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// K, from 1.
    pub number: usize,
    /// N.
    pub count: usize,
}

/// Why a shard cannot be chosen (an input error: exit code 2).
#[derive(Debug, PartialEq, Eq, thiserror::Error)]
pub enum ShardError {
    #[error("--shard {0}: expected K/N with 1 <= K <= N (e.g. 2/8)")]
    Syntax(String),
    #[error("{var} = `{value}` is not a whole number")]
    NotNumber { var: &'static str, value: String },
    #[error("{0}")]
    Environment(String),
}

impl Shard {
    pub const WHOLE: Shard = Shard {
        number: 1,
        count: 1,
    };

    /// Whether run `index` belongs to this shard.
    pub fn has(&self, index: usize) -> bool {
        index % self.count == self.number - 1
    }

    /// The folder name of this shard's outputs: `shard-K-of-N`.
    pub fn folder(&self) -> String {
        format!("shard-{}-of-{}", self.number, self.count)
    }

    fn new(number: usize, count: usize) -> Option<Shard> {
        (number >= 1 && number <= count).then_some(Shard { number, count })
    }

    /// `K/N`.
    pub fn parse(text: &str) -> Result<Shard, ShardError> {
        let bad = || ShardError::Syntax(text.to_string());
        let (k, n) = text.split_once('/').ok_or_else(bad)?;
        let k = k.trim().parse().map_err(|_| bad())?;
        let n = n.trim().parse().map_err(|_| bad())?;
        Shard::new(k, n).ok_or_else(bad)
    }

    /// The shard `given` (`--shard`), else the scheduler's (see the module documentation),
    /// reading variables through `var`.
    pub fn choose(
        given: Option<&str>,
        var: impl Fn(&str) -> Option<String>,
    ) -> Result<Shard, ShardError> {
        if let Some(text) = given {
            return Shard::parse(text);
        }
        let number = |name: &'static str| -> Result<Option<usize>, ShardError> {
            match var(name) {
                None => Ok(None),
                Some(v) => v
                    .trim()
                    .parse()
                    .map(Some)
                    .map_err(|_| ShardError::NotNumber {
                        var: name,
                        value: v,
                    }),
            }
        };
        if let Some(id) = number("SLURM_ARRAY_TASK_ID")? {
            let min = number("SLURM_ARRAY_TASK_MIN")?.unwrap_or(0);
            let count = number("SLURM_ARRAY_TASK_COUNT")?.ok_or_else(|| {
                ShardError::Environment("SLURM_ARRAY_TASK_ID is set but SLURM_ARRAY_TASK_COUNT is not: give --shard K/N".into())
            })?;
            return id
                .checked_sub(min)
                .and_then(|k| Shard::new(k + 1, count))
                .ok_or_else(|| {
                    ShardError::Environment(format!(
                        "Slurm task {id} (first {min}) is not one of {count} tasks: use a contiguous --array (1-{count} or 0-{}) or give --shard K/N",
                        count.saturating_sub(1)
                    ))
                });
        }
        if let Some(index) = number("JOB_COMPLETION_INDEX")? {
            let count = number("JOB_COMPLETIONS")?.ok_or_else(|| {
                ShardError::Environment(
                    "JOB_COMPLETION_INDEX is set but JOB_COMPLETIONS is not: set it in the Job's container env to spec.completions, or give --shard K/N".into(),
                )
            })?;
            return Shard::new(index + 1, count).ok_or_else(|| {
                ShardError::Environment(format!(
                    "JOB_COMPLETION_INDEX {index} is not below JOB_COMPLETIONS {count}"
                ))
            });
        }
        Ok(Shard::WHOLE)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn env<'a>(pairs: &'a [(&'a str, &'a str)]) -> impl Fn(&str) -> Option<String> + 'a {
        move |name| {
            pairs
                .iter()
                .find(|(k, _)| *k == name)
                .map(|(_, v)| v.to_string())
        }
    }

    #[test]
    fn shard_from_option_slurm_or_kubernetes() {
        assert_eq!(
            Shard::choose(Some("2/3"), env(&[])),
            Ok(Shard {
                number: 2,
                count: 3
            })
        );
        assert!(Shard::choose(Some("0/3"), env(&[])).is_err());
        assert!(Shard::choose(Some("4/3"), env(&[])).is_err());
        assert_eq!(Shard::choose(None, env(&[])), Ok(Shard::WHOLE));
        // --array=1-4: task 1 is shard 1.
        let slurm = [
            ("SLURM_ARRAY_TASK_ID", "1"),
            ("SLURM_ARRAY_TASK_MIN", "1"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
        ];
        assert_eq!(
            Shard::choose(None, env(&slurm)),
            Ok(Shard {
                number: 1,
                count: 4
            })
        );
        // --array=0-3: task 3 is shard 4.
        let slurm0 = [
            ("SLURM_ARRAY_TASK_ID", "3"),
            ("SLURM_ARRAY_TASK_MIN", "0"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
        ];
        assert_eq!(
            Shard::choose(None, env(&slurm0)),
            Ok(Shard {
                number: 4,
                count: 4
            })
        );
        let k8s = [("JOB_COMPLETION_INDEX", "0"), ("JOB_COMPLETIONS", "5")];
        assert_eq!(
            Shard::choose(None, env(&k8s)),
            Ok(Shard {
                number: 1,
                count: 5
            })
        );
        let missing = Shard::choose(None, env(&[("JOB_COMPLETION_INDEX", "2")])).unwrap_err();
        assert!(missing.to_string().contains("JOB_COMPLETIONS"), "{missing}");
        // The option wins over the environment.
        assert_eq!(
            Shard::choose(Some("1/2"), env(&k8s)),
            Ok(Shard {
                number: 1,
                count: 2
            })
        );
    }

    #[test]
    fn shards_partition_the_runs() {
        let shards = [
            Shard {
                number: 1,
                count: 3,
            },
            Shard {
                number: 2,
                count: 3,
            },
            Shard {
                number: 3,
                count: 3,
            },
        ];
        for i in 0..20 {
            assert_eq!(shards.iter().filter(|s| s.has(i)).count(), 1);
        }
        assert!(shards[1].has(4) && shards[2].has(2) && shards[0].has(0));
    }
}
