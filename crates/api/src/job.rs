//! An analysis with its arguments, as data: what a sweep spec's `[analysis]` table or a Python
//! call names. Running one gives the CLI's JSON report for the same arguments and its exit
//! code.

use crate::error::Error;
use crate::simulate::CsvTarget;
use crate::source::Loaded;
use linkage_solve::coverage::Analysis;
use linkage_solve::stages::dynamics::Start;

use linkage_solve::stages::linearize::LinearOptions;

/// An analysis and its arguments, named as the CLI's options (`kind = "linear"`,
/// `static_first = true`, …).
#[derive(Clone, Debug, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
pub enum Job {
    /// `linkage verify`.
    Verify,
    /// `linkage ic`.
    Ic,
    /// `linkage static` (a quasi-static series with `end` and `steps`).
    Static {
        end: Option<f64>,
        steps: Option<usize>,
        #[serde(default)]
        settle: bool,
        #[serde(default)]
        allow_unstable: bool,
        time_limit: Option<f64>,
    },
    /// `linkage linear`.
    Linear {
        #[serde(default)]
        static_first: bool,
        #[serde(default)]
        no_damping: bool,
        #[serde(default)]
        no_vectors: bool,
        modes: Option<usize>,
        shift: Option<f64>,
        #[serde(default)]
        allow_unstable: bool,
    },
    /// `linkage simulate` (its CSV goes where [`Job::run`] is told).
    Simulate {
        end: f64,
        steps: Option<usize>,
        dtout: Option<f64>,
        #[serde(default)]
        start_at_equilibrium: bool,
        #[serde(default)]
        settle: bool,
        #[serde(default)]
        allow_unstable: bool,
        time_limit: Option<f64>,
    },
}

/// A report and its verdict.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    /// The JSON report, as `--format json` prints it.
    pub report: serde_json::Value,
    /// 0 when its `errors` list is empty, 1 otherwise.
    pub exit_code: u8,
}

impl Job {
    /// The CLI command name (`linear`).
    pub fn name(&self) -> &'static str {
        match self {
            Job::Verify => "verify",
            Job::Ic => "ic",
            Job::Static { .. } => "static",
            Job::Linear { .. } => "linear",
            Job::Simulate { .. } => "simulate",
        }
    }

    /// The analysis a model is loaded for (`None`: verify, which refuses nothing).
    pub fn analysis(&self) -> Option<Analysis> {
        match self {
            Job::Verify => None,
            Job::Ic => Some(Analysis::Ic),
            Job::Static { end, steps, .. } => Some(if end.is_some() || steps.is_some() {
                Analysis::QuasiStatic
            } else {
                Analysis::Static
            }),
            Job::Linear { .. } => Some(Analysis::Linear),
            Job::Simulate { .. } => Some(Analysis::Simulate),
        }
    }

    /// Whether the job writes time histories (simulate).
    pub fn writes_csv(&self) -> bool {
        matches!(self, Job::Simulate { .. })
    }

    /// Runs the job on `loaded`; a simulation streams its time histories to `csv`.
    pub fn run(&self, loaded: &Loaded, csv: Option<CsvTarget>) -> Result<Outcome, Error> {
        let report = match self {
            Job::Verify => to_value(&crate::verify::verify(loaded))?,
            Job::Ic => to_value(&crate::ic::ic(loaded)?.report)?,
            Job::Static {
                end,
                steps,
                settle,
                allow_unstable,
                time_limit,
            } => {
                let series = match (end, steps) {
                    (Some(e), Some(s)) => Some(crate::times::output_times(*e, Some(*s), None)?),
                    (None, None) => None,
                    _ => {
                        return Err(Error::Argument(
                            crate::error::ArgumentError::IncompleteSeries,
                        ))
                    }
                };
                let args = crate::statics::StaticArgs {
                    series,
                    settle: *settle,
                    allow_unstable: *allow_unstable,
                    time_limit: *time_limit,
                    interrupt: None,
                };
                let run = crate::statics::statics(loaded, &args, &|_, _| {})?;
                // The CLI's verdict: an equilibrium that was not found fails the run even
                // when the report lists no error.
                return Ok(Outcome {
                    report: to_value(&run.report)?,
                    exit_code: u8::from(!run.ok),
                });
            }
            Job::Linear {
                static_first,
                no_damping,
                no_vectors,
                modes,
                shift,
                allow_unstable,
            } => {
                let method = crate::linear::eigen_method(*modes, *shift)?;
                let args = crate::linear::LinearArgs {
                    static_first: *static_first,
                    options: LinearOptions {
                        damping: !no_damping,
                        vectors: !no_vectors,
                        method,
                    },
                    allow_unstable: *allow_unstable,
                };
                to_value(&crate::linear::linear(loaded, &args)?)?
            }
            Job::Simulate {
                end,
                steps,
                dtout,
                start_at_equilibrium,
                settle,
                allow_unstable,
                time_limit,
            } => {
                let times = crate::times::output_times(*end, *steps, *dtout)?;
                let start = match (start_at_equilibrium, settle) {
                    (false, _) => Start::InitialConditions,
                    (true, false) => Start::Equilibrium,
                    (true, true) => Start::SettledEquilibrium,
                };
                let args = crate::simulate::SimulateArgs {
                    times: &times,
                    start,
                    allow_unstable: *allow_unstable,
                    time_limit: *time_limit,
                    csv,
                    progress: &mut |_| {},
                    interrupted: &|| false,
                    observe: None,
                };
                to_value(&crate::simulate::simulate(loaded, args)?)?
            }
        };
        let failed = report
            .get("errors")
            .and_then(|e| e.as_array())
            .is_some_and(|e| !e.is_empty());
        Ok(Outcome {
            report,
            exit_code: u8::from(failed),
        })
    }
}

fn to_value<T: serde::Serialize>(report: &T) -> Result<serde_json::Value, Error> {
    serde_json::to_value(report)
        .map(linkage_report::with_schema_version)
        .map_err(|e| Error::Output(format!("cannot write JSON: {e}")))
}
