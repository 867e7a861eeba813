//! The wall-clock budget of an analysis: every road (the CLI, command files, Python, sweeps)
//! gives a run a deadline, so that no run goes on without end (a MOTION of `EXP(1000*TIME)`,
//! an `--end` of 1e200 that the step size can never reach).

use std::time::{Duration, Instant};

/// A wall-clock limit that is not a positive finite number of seconds up to
/// [`MAX_TIME_LIMIT`] (an input error: exit code 2).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("--time-limit must be a positive number of seconds up to {MAX_TIME_LIMIT}, not {secs}")]
pub struct TimeLimitError {
    pub secs: f64,
}

/// Wall-clock seconds after which a dynamic simulation stops when no time limit is given
/// (`--time-limit`, a command file run's `--time-limit`, Python's and a sweep's
/// `time_limit`): the outputs up to there are kept and the run fails saying so.
pub const DEFAULT_SIMULATE_TIME_LIMIT: f64 = 3600.0;

/// The longest time limit accepted: a year of wall-clock time (anything longer is a typing
/// slip, and an instant that far ahead may not be representable).
pub const MAX_TIME_LIMIT: f64 = 365.0 * 24.0 * 3600.0;

/// The deadline `time_limit` seconds (else `default`) from now; an argument error for a time
/// limit that is not a positive finite number of seconds up to [`MAX_TIME_LIMIT`].
pub fn deadline(time_limit: Option<f64>, default: f64) -> Result<Instant, TimeLimitError> {
    let secs = check_time_limit(time_limit)?.unwrap_or(default);
    Instant::now()
        .checked_add(Duration::from_secs_f64(secs))
        .ok_or(TimeLimitError { secs })
}

/// `time_limit` when it is a positive finite number of seconds up to [`MAX_TIME_LIMIT`].
pub fn check_time_limit(time_limit: Option<f64>) -> Result<Option<f64>, TimeLimitError> {
    match time_limit {
        Some(secs) if !(secs > 0.0 && secs <= MAX_TIME_LIMIT) => Err(TimeLimitError { secs }),
        other => Ok(other),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_time_limit_that_is_not_a_positive_finite_number_of_seconds_is_refused() {
        for secs in [f64::NAN, f64::INFINITY, 1e20, 0.0, -1.0] {
            let e = deadline(Some(secs), 1.0).unwrap_err();
            assert!(e.to_string().contains("--time-limit"), "{e}");
        }
        let now = Instant::now();
        let d = deadline(Some(2.0), 1.0).unwrap();
        assert!(d >= now + Duration::from_secs_f64(2.0));
        assert!(deadline(None, DEFAULT_SIMULATE_TIME_LIMIT).is_ok());
    }
}
