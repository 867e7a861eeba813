//! The output times of a run from `--end` with `--steps` or `--dtout`.

/// The most output times a run may ask for: every output keeps each part's state, so a
/// mistyped count (`--dtout 1e-9` over `--end 1e9`) is refused rather than exhausting memory.
pub const MAX_OUTPUT_TIMES: usize = 1_000_000;

/// Slack on the number of `--dtout` intervals in `--end` (a count, so relative to one
/// interval): an `--end` that is a multiple of `--dtout` up to rounding (`0.3 / 0.1` is
/// 2.9999999999999996) gets no extra sliver interval at its end.
pub const INTERVAL_COUNT_SLACK: f64 = 1e-9;

/// Why `--end`, `--steps` or `--dtout` cannot give output times (an input error: exit code 2).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum OutputTimesError {
    #[error("--end must be a positive time, not {end}")]
    EndNotPositive { end: f64 },
    #[error("--dtout must be a positive time, not {dtout}")]
    DtoutNotPositive { dtout: f64 },
    /// `count` outputs (more than [`MAX_OUTPUT_TIMES`]) every `dtout` up to `end`.
    #[error(
        "--dtout {dtout} over --end {end} asks for {} outputs; at most {} are allowed",
        linkage_adm::num::sci(*.count, 4),
        MAX_OUTPUT_TIMES
    )]
    TooManyIntervals { dtout: f64, end: f64, count: f64 },
    #[error("--steps must be at least 1")]
    NoSteps,
    #[error(
        "--steps {steps} asks for more than the {} outputs allowed",
        MAX_OUTPUT_TIMES
    )]
    TooManySteps { steps: usize },
}

/// Output times from 0 to `end`, 0 included: `steps` equal intervals, or every `dtout` (the
/// last one shortened to land on `end`); 100 intervals when neither is given (the CLI's
/// default). See [`output_times_after`].
pub fn output_times(
    end: f64,
    steps: Option<usize>,
    dtout: Option<f64>,
) -> Result<Vec<f64>, OutputTimesError> {
    let steps = match (steps, dtout) {
        (None, None) => Some(100),
        _ => steps,
    };
    let mut times = vec![0.0];
    times.extend(output_times_after(0.0, end, steps, dtout)?);
    Ok(times)
}

/// Output times after `t0` up to `end` (`t0` excluded): `steps` equal intervals, or every
/// `dtout` from `t0` (the last one shortened to land on `end`; `steps` wins when both are
/// given), one interval when neither is given (a command file's SIMULATE without STEPS or
/// DTOUT). The one definition of output times: the CLI, command files, Python and sweeps
/// all use it. An input error (for exit code 2) when `end` is not a finite time after `t0`,
/// `dtout` is not a positive finite time, `steps` is 0, or the run would have more than
/// [`MAX_OUTPUT_TIMES`] outputs.
pub fn output_times_after(
    t0: f64,
    end: f64,
    steps: Option<usize>,
    dtout: Option<f64>,
) -> Result<Vec<f64>, OutputTimesError> {
    let span = end - t0;
    if !(span > 0.0 && end.is_finite() && span.is_finite()) {
        return Err(OutputTimesError::EndNotPositive { end });
    }
    let intervals = match (steps, dtout) {
        (None, Some(dtout)) => {
            if !(dtout > 0.0 && dtout.is_finite()) {
                return Err(OutputTimesError::DtoutNotPositive { dtout });
            }
            let n = (span / dtout - INTERVAL_COUNT_SLACK).ceil().max(1.0);
            if n > MAX_OUTPUT_TIMES as f64 {
                return Err(OutputTimesError::TooManyIntervals {
                    dtout,
                    end,
                    count: n,
                });
            }
            return Ok((1..=n as usize)
                .map(|k| (t0 + k as f64 * dtout).min(end))
                .collect());
        }
        (Some(0), _) => return Err(OutputTimesError::NoSteps),
        (Some(n), _) => n,
        (None, None) => 1,
    };
    if intervals > MAX_OUTPUT_TIMES {
        return Err(OutputTimesError::TooManySteps { steps: intervals });
    }
    // The fraction first: `span * k` overflows for an `end` near the largest f64.
    Ok((1..=intervals)
        .map(|k| t0 + span * (k as f64 / intervals as f64))
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn output_times_up_to_the_largest_finite_end_are_finite_and_end_on_it() {
        let end = 1.797e308;
        let t = output_times(end, Some(10), None).unwrap();
        assert_eq!(t.len(), 11);
        assert!(t.iter().all(|x| x.is_finite()), "{t:?}");
        assert!(t.windows(2).all(|w| w[1] > w[0]), "{t:?}");
        assert_eq!(t[10], end);
        assert!((t[1] - end / 10.0).abs() <= 1e-15 * end);
    }

    #[test]
    fn counts_over_the_output_cap_are_refused_not_allocated() {
        assert!(matches!(
            output_times(1e23, None, Some(0.01)),
            Err(OutputTimesError::TooManyIntervals { .. })
        ));
        assert!(matches!(
            output_times(1.0, Some(4_000_000_000), None),
            Err(OutputTimesError::TooManySteps { .. })
        ));
        assert!(matches!(
            output_times(f64::INFINITY, Some(10), None),
            Err(OutputTimesError::EndNotPositive { .. })
        ));
    }
}
