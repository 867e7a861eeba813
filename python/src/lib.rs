//! The `linkage` Python module: `linkage.load(path)` gives a [`Model`] whose analyses return
//! the CLI's JSON reports as dicts (numeric lists as numpy arrays) and whose `simulate`
//! returns the CSV's columns as numpy arrays; `linkage.run_acf(path)` runs a command file.
//!
//! Every analysis is `linkage_api`'s, the same code the `linkage` binary runs. Errors are
//! exceptions: `InputError` (the CLI's exit code 2: file:line:column messages in `.messages`)
//! and `AnalysisError` (exit code 1: the report in `.report`), both `LinkageError`s. Their
//! messages name keyword arguments where the CLI's name its flags ([`terms::python_terms`]).

mod convert;
mod terms;

use terms::python_terms;

use linkage_api::job::{Job, Outcome};
use linkage_api::simulate::CsvTarget;
use linkage_api::{ArgValue, Source};
use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::path::PathBuf;
use std::sync::{Arc, Mutex};

create_exception!(linkage, LinkageError, PyException, "Any error of linkage.");
create_exception!(
    linkage,
    InputError,
    LinkageError,
    "The dataset, command file or an argument is wrong (the CLI's exit code 2); `.messages` \
     lists the diagnostics, each with file:line:column."
);
create_exception!(
    linkage,
    AnalysisError,
    LinkageError,
    "The analysis ran and failed (the CLI's exit code 1); `.report` holds its report."
);

/// An `InputError` carrying `messages` (joined as its text).
fn input_error(py: Python<'_>, messages: Vec<String>) -> PyErr {
    let messages: Vec<String> = messages.iter().map(|m| python_terms(m)).collect();
    let err = InputError::new_err(messages.join("\n"));
    if let Ok(list) = PyList::new(py, &messages) {
        let _ = err.value(py).setattr("messages", list);
    }
    err
}

/// An `AnalysisError` with the report's errors as its text and the report as `.report`.
fn analysis_error(py: Python<'_>, report: &serde_json::Value, extra: &[(&str, PyObject)]) -> PyErr {
    let messages: Vec<String> = report
        .get("errors")
        .and_then(|e| e.as_array())
        .map(|e| {
            e.iter()
                .filter_map(|m| m.as_str().map(python_terms))
                .collect()
        })
        .unwrap_or_default();
    let err = AnalysisError::new_err(messages.join("\n"));
    let value = err.value(py);
    if let Ok(r) = convert::to_python(py, report) {
        let _ = value.setattr("report", r);
    }
    let _ = value.setattr("messages", messages);
    for (name, obj) in extra {
        let _ = value.setattr(*name, obj);
    }
    err
}

/// A dataset loaded from a file, with the argument changes made by `set`.
#[pyclass(module = "linkage")]
struct Model {
    source: Source,
    deactivate: Vec<String>,
    /// The report of the last analysis (for `simulate`, its summary).
    last_report: Option<PyObject>,
    /// The unit of each column of the last `simulate` ({"time": "s", "crank.x": "m", …}).
    units: Option<PyObject>,
}

/// A value for `Model.set`: a number, a sequence of numbers or an expression.
fn arg_value(value: &Bound<'_, PyAny>) -> PyResult<ArgValue> {
    if let Ok(text) = value.extract::<String>() {
        return Ok(ArgValue::Expression(text));
    }
    if let Ok(x) = value.extract::<f64>() {
        return Ok(ArgValue::Number(x));
    }
    if let Ok(xs) = value.extract::<Vec<f64>>() {
        return Ok(ArgValue::Numbers(xs));
    }
    Err(pyo3::exceptions::PyTypeError::new_err(
        "a value is a number, a sequence of numbers or an expression (str)",
    ))
}

impl Model {
    /// Runs `job` (its CSV to `csv`) and returns the report, raising on errors.
    fn run(
        &mut self,
        py: Python<'_>,
        job: &Job,
        csv: Option<CsvTarget>,
    ) -> PyResult<(serde_json::Value, u8)> {
        let source = &self.source;
        let deactivate = &self.deactivate;
        let result = py.allow_threads(|| {
            let loaded = source.load(deactivate, job.analysis())?;
            job.run(&loaded, csv)
        });
        match result {
            Ok(Outcome { report, exit_code }) => {
                self.last_report = Some(convert::to_python(py, &report)?);
                Ok((report, exit_code))
            }
            Err(e) => Err(input_error(py, e.messages())),
        }
    }

    /// The report of `job` as a Python dict, or `AnalysisError`.
    fn report(&mut self, py: Python<'_>, job: Job) -> PyResult<PyObject> {
        let (report, code) = self.run(py, &job, None)?;
        if code != 0 {
            return Err(analysis_error(py, &report, &[]));
        }
        convert::to_python(py, &report)
    }
}

#[pymethods]
impl Model {
    /// Sets argument `argument` of statement `statement` ("SPRINGDAMPER/1", or a settings
    /// statement such as "EQUILIBRIUM") to `value` for the analyses that follow, as a command
    /// file's redefinition does.
    fn set(
        &mut self,
        py: Python<'_>,
        statement: &str,
        argument: &str,
        value: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        let value = arg_value(value)?;
        self.source
            .set(statement, argument, &value)
            .map_err(|d| input_error(py, d.0.iter().map(ToString::to_string).collect()))
    }

    /// `linkage verify --format json`: DOF, redundant and misaligned constraints.
    fn verify(&mut self, py: Python<'_>) -> PyResult<PyObject> {
        self.report(py, Job::Verify)
    }

    /// `linkage ic --format json`: assembly, velocities, accelerations, reactions.
    fn ic(&mut self, py: Python<'_>) -> PyResult<PyObject> {
        self.report(py, Job::Ic)
    }

    /// `linkage static --format json` (a quasi-static series with `end` and `steps`).
    /// `time_limit`: wall-clock seconds for settling (`settle=True`; default 3600 s).
    #[pyo3(signature = (end=None, steps=None, settle=false, allow_unstable=false, time_limit=None))]
    fn r#static(
        &mut self,
        py: Python<'_>,
        end: Option<f64>,
        steps: Option<usize>,
        settle: bool,
        allow_unstable: bool,
        time_limit: Option<f64>,
    ) -> PyResult<PyObject> {
        self.report(
            py,
            Job::Static {
                end,
                steps,
                settle,
                allow_unstable,
                time_limit,
            },
        )
    }

    /// `linkage linear --format json`: eigenvalues, frequencies, damping ratios, mode shapes.
    #[pyo3(signature = (static_first=false, no_damping=false, no_vectors=false, modes=None, shift=None, allow_unstable=false))]
    #[allow(clippy::too_many_arguments)]
    fn linear(
        &mut self,
        py: Python<'_>,
        static_first: bool,
        no_damping: bool,
        no_vectors: bool,
        modes: Option<usize>,
        shift: Option<f64>,
        allow_unstable: bool,
    ) -> PyResult<PyObject> {
        self.report(
            py,
            Job::Linear {
                static_first,
                no_damping,
                no_vectors,
                modes,
                shift,
                allow_unstable,
            },
        )
    }

    /// `linkage simulate --out`: the time histories as {column name: numpy array}, the names
    /// plain (`"time"`, `"crank.x"`: the CSV header's unit suffix is in `units`); the summary
    /// report is then `last_report`. `time_limit`: wall-clock seconds after which the run
    /// stops (default 3600 s), raising `AnalysisError` with the outputs up to there.
    #[pyo3(signature = (end, steps=None, dtout=None, start_at_equilibrium=false, settle=false, allow_unstable=false, time_limit=None))]
    #[allow(clippy::too_many_arguments)]
    fn simulate(
        &mut self,
        py: Python<'_>,
        end: f64,
        steps: Option<usize>,
        dtout: Option<f64>,
        start_at_equilibrium: bool,
        settle: bool,
        allow_unstable: bool,
        time_limit: Option<f64>,
    ) -> PyResult<PyObject> {
        let job = Job::Simulate {
            end,
            steps,
            dtout,
            start_at_equilibrium,
            settle,
            allow_unstable,
            time_limit,
        };
        let buffer = Arc::new(Mutex::new(Vec::<u8>::new()));
        let sink = SharedBuffer(Arc::clone(&buffer));
        let csv = CsvTarget {
            name: "the time histories".into(),
            open: Box::new(move || Ok(Box::new(sink) as Box<dyn std::io::Write>)),
        };
        let (report, code) = self.run(py, &job, Some(csv))?;
        let text = buffer
            .lock()
            .map(|b| String::from_utf8_lossy(&b).into_owned())
            .unwrap_or_default();
        let (columns, units) = convert::csv_columns(py, &text)?;
        self.units = Some(units);
        if code != 0 {
            return Err(analysis_error(py, &report, &[("columns", columns)]));
        }
        Ok(columns)
    }

    /// The report of the last analysis run (`None` before the first).
    #[getter]
    fn last_report(&self, py: Python<'_>) -> Option<PyObject> {
        self.last_report.as_ref().map(|r| r.clone_ref(py))
    }

    /// The unit of each column the last `simulate` returned, {"time": "s", "crank.x": "m",
    /// …} (a column without a stated unit is absent); `None` before the first.
    #[getter]
    fn units(&self, py: Python<'_>) -> Option<PyObject> {
        self.units.as_ref().map(|u| u.clone_ref(py))
    }

    /// The dataset's file name.
    #[getter]
    fn file(&self) -> String {
        self.source.file().to_string()
    }

    fn __repr__(&self) -> String {
        format!("linkage.Model({:?})", self.source.file())
    }
}

/// A `Write` into a buffer shared with the caller (the CSV of a Python `simulate`).
struct SharedBuffer(Arc<Mutex<Vec<u8>>>);

impl std::io::Write for SharedBuffer {
    fn write(&mut self, data: &[u8]) -> std::io::Result<usize> {
        self.0
            .lock()
            .map_err(|_| std::io::Error::other("buffer poisoned"))?
            .extend_from_slice(data);
        Ok(data.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// Reads the dataset at `path` (`deactivate`: statements to leave out; `lenient_arguments`:
/// an argument a statement does not take is a warning, not an `InputError`; `user_lib`:
/// libraries or folders of the dataset's user subroutines, as `--user-lib`).
#[pyfunction]
#[pyo3(signature = (path, deactivate=None, lenient_arguments=false, user_lib=None))]
fn load(
    py: Python<'_>,
    path: PathBuf,
    deactivate: Option<Vec<String>>,
    lenient_arguments: bool,
    user_lib: Option<Vec<PathBuf>>,
) -> PyResult<Model> {
    let options = linkage_adm::ReadOptions { lenient_arguments };
    let user_lib = user_lib.unwrap_or_default();
    let source = py
        .allow_threads(|| {
            Source::read_with(&path, options).and_then(|s| s.with_user_libraries(&user_lib))
        })
        .map_err(|d| input_error(py, d.0.iter().map(ToString::to_string).collect()))?;
    let model = Model {
        source,
        deactivate: deactivate.unwrap_or_default(),
        last_report: None,
        units: None,
    };
    // A name that leaves nothing out is an input error now rather than at the first analysis.
    if !model.deactivate.is_empty() {
        model
            .source
            .load(&model.deactivate, None)
            .map_err(|d| input_error(py, d.0.iter().map(ToString::to_string).collect()))?;
    }
    Ok(model)
}

/// `linkage run PATH`: runs the command file, writing its .msg, .req and .csv files (in
/// `out_dir`, default the working directory); returns {commands, outputs, halted, msg, req, csv}
/// (`halted`: `SENSOR_1 at time 2.5` when a SENSOR's HALT ended the file, else None).
#[pyfunction]
#[pyo3(signature = (path, out_dir=None, model=None, deactivate=None, allow_unstable=false, lenient_arguments=false, user_lib=None))]
#[allow(clippy::too_many_arguments)]
fn run_acf(
    py: Python<'_>,
    path: PathBuf,
    out_dir: Option<PathBuf>,
    model: Option<PathBuf>,
    deactivate: Option<Vec<String>>,
    allow_unstable: bool,
    lenient_arguments: bool,
    user_lib: Option<Vec<PathBuf>>,
) -> PyResult<PyObject> {
    let options = linkage_run::RunOptions {
        out_dir,
        model,
        interrupt: None,
        deactivate: deactivate.unwrap_or_default(),
        allow_unstable,
        read: linkage_adm::ReadOptions { lenient_arguments },
        user_libraries: user_lib.unwrap_or_default(),
        also_writes: Vec::new(),
        time_limit: None,
        watch: Default::default(),
    };
    let result = py.allow_threads(|| linkage_run::run_command_file(&path, &options));
    let summary = |s: &linkage_run::RunSummary| -> PyResult<PyObject> {
        let d = PyDict::new(py);
        d.set_item("commands", s.commands)?;
        d.set_item("outputs", s.outputs)?;
        d.set_item("halted", s.halted.as_deref())?;
        d.set_item("msg", s.msg.display().to_string())?;
        d.set_item("req", s.req.as_ref().map(|p| p.display().to_string()))?;
        d.set_item("csv", s.csv.as_ref().map(|p| p.display().to_string()))?;
        Ok(d.into_any().unbind())
    };
    match result {
        Ok(s) => summary(&s),
        Err(stopped) => {
            let message = python_terms(&stopped.error.to_string());
            let err = if stopped.error.exit_code() == 2 {
                input_error(py, vec![message])
            } else {
                AnalysisError::new_err(message)
            };
            if let Some(s) = &stopped.summary {
                let _ = err.value(py).setattr("summary", summary(s)?);
            }
            Err(err)
        }
    }
}

/// `linkage fmu PATH --out OUT`: writes the dataset as a co-simulation FMU (FMI 3.0, or 2.0
/// with `fmi=2`): inputs the PINPUT VARIABLEs (or those of PINPUT `pinput`), outputs the
/// POUTPUT ones, `parameters` (`"SPRINGDAMPER/1.K"`, …) settable before the initialisation,
/// `initial_static` the start of the parameter of that name. The FMU's binary is `binary`,
/// else $LINKAGE_FMU_BINARY, else liblinkage_fmu_binary.so beside `linkage` on the PATH. Returns
/// {model_identifier, inputs, outputs, parameters, files, bytes}.
#[pyfunction]
#[pyo3(signature = (path, out, fmi=3, pinput=None, poutput=None, parameters=None, initial_static=false, binary=None))]
#[allow(clippy::too_many_arguments)]
fn export_fmu(
    py: Python<'_>,
    path: PathBuf,
    out: PathBuf,
    fmi: u8,
    pinput: Option<u64>,
    poutput: Option<u64>,
    parameters: Option<Vec<String>>,
    initial_static: bool,
    binary: Option<PathBuf>,
) -> PyResult<PyObject> {
    use linkage_fmu::description::FmiVersion;
    use linkage_fmu::export::{export, linkage_on_path, locate_binary, ExportError, ExportOptions};
    let version = match fmi {
        2 => FmiVersion::V2,
        3 => FmiVersion::V3,
        _ => return Err(input_error(py, vec![format!("fmi={fmi}: FMI 2 or 3")])),
    };
    let options = ExportOptions {
        version,
        pinput,
        poutput,
        parameters: parameters.unwrap_or_default(),
        initial_static,
    };
    let binary = locate_binary(binary.as_deref(), linkage_on_path().as_deref());
    let done = py.allow_threads(|| export(&path, &binary, &out, &options));
    let done = done.map_err(|e| match e {
        ExportError::Input(_)
        | ExportError::Ports(_)
        | ExportError::Parameter { .. }
        | ExportError::Resource { .. } => input_error(py, vec![python_terms(&e.to_string())]),
        ExportError::Analysis(a) if a.exit_code() == 2 => {
            input_error(py, vec![python_terms(&a.to_string())])
        }
        other => AnalysisError::new_err(python_terms(&other.to_string())),
    })?;
    let d = PyDict::new(py);
    let names = |ports: &[linkage_api::cosim::Port]| -> Vec<String> {
        ports.iter().map(|p| p.name.clone()).collect()
    };
    d.set_item("model_identifier", &done.model_identifier)?;
    d.set_item("inputs", names(&done.ports.inputs))?;
    d.set_item("outputs", names(&done.ports.outputs))?;
    let params: Vec<String> = done.parameters.iter().map(|p| p.name()).collect();
    d.set_item("parameters", params)?;
    d.set_item("files", &done.files)?;
    d.set_item("bytes", done.bytes)?;
    Ok(d.into_any().unbind())
}

#[pymodule]
fn linkage(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("LinkageError", py.get_type::<LinkageError>())?;
    m.add("InputError", py.get_type::<InputError>())?;
    m.add("AnalysisError", py.get_type::<AnalysisError>())?;
    m.add_class::<Model>()?;
    m.add_function(wrap_pyfunction!(load, m)?)?;
    m.add_function(wrap_pyfunction!(run_acf, m)?)?;
    m.add_function(wrap_pyfunction!(export_fmu, m)?)?;
    Ok(())
}
