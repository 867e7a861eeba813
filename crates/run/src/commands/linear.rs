//! `LINEAR/EIGENSOL` and `LINEAR/STATEMAT` about the current operating point: the API's
//! linearization ([`linkage_api::linear`]) from where the last analysis left the model.

use super::{Place, Sinks};
use crate::error::RunError;
use crate::session::Progress;
use linkage_solve::stages::linearize::LinearOptions;
use std::path::{Path, PathBuf};

/// `LINEAR/EIGENSOL`: eigenvalues (and modes) about the current operating point.
pub fn eigensolution(
    progress: &mut Progress,
    sinks: &mut Sinks,
    place: &Place,
    options: LinearOptions,
) -> Result<(), RunError> {
    let args = linkage_api::linear::LinearArgs {
        static_first: false,
        options,
        allow_unstable: true,
    };
    let start = progress.start();
    let run = linkage_api::linear::run(sinks.loaded, start, &args, sinks);
    let run = super::simulate::outcome(sinks, place, run)?;
    sinks
        .msg
        .write(&linkage_report::linear::to_text(&run.report))?;
    progress.leave(run.left);
    if let Some(e) = run.report.errors.first() {
        return Err(place.failed(e.clone()));
    }
    Ok(())
}

/// The plant inputs and outputs of `LINEAR/STATEMAT`: VARIABLE ids.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PlantIo {
    pub inputs: Vec<u32>,
    pub outputs: Vec<u32>,
}

/// Why the plant inputs or outputs of `LINEAR/STATEMAT` cannot be read.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PlantIoError {
    #[error("the dataset has no {keyword}/{id}")]
    Missing { keyword: String, id: u64 },
    #[error("{keyword}/{id} has no VARIABLES = list")]
    NoVariables { keyword: String, id: u64 },
    #[error("{keyword}/{id}: VARIABLES must list VARIABLE ids, not {value}")]
    NotAnId {
        keyword: String,
        id: u64,
        value: String,
    },
}

/// The VARIABLE ids of the dataset's `keyword/id` statement (PINPUT or POUTPUT:
/// `VARIABLES = id, id, …`); none when `id` is `None`.
pub fn plant_variables(
    session: &crate::session::Session,
    keyword: &str,
    id: Option<u64>,
) -> Result<Vec<u32>, PlantIoError> {
    let Some(id) = id else {
        return Ok(Vec::new());
    };
    let keyword_id = || (keyword.to_string(), id);
    let st = session.statement(keyword, id).ok_or_else(|| {
        let (keyword, id) = keyword_id();
        PlantIoError::Missing { keyword, id }
    })?;
    let arg = st
        .args
        .iter()
        .find(|a| a.key.len() >= 3 && "VARIABLES".starts_with(a.key.as_str()))
        .ok_or_else(|| {
            let (keyword, id) = keyword_id();
            PlantIoError::NoVariables { keyword, id }
        })?;
    arg.values
        .iter()
        .map(|v| match v {
            linkage_adm::Value::Number { value, .. }
                if *value >= 0.0 && value.fract() == 0.0 && *value <= f64::from(u32::MAX) =>
            {
                Ok(*value as u32)
            }
            other => {
                let (keyword, id) = keyword_id();
                Err(PlantIoError::NotAnId {
                    keyword,
                    id,
                    value: format!("{other:?}"),
                })
            }
        })
        .collect()
}

/// Plain text matrix: one row per line, numbers separated by blanks (MATLAB's `load` and
/// numpy's `loadtxt` read it); empty without columns.
fn rows(values: &[f64], cols: usize) -> String {
    if cols == 0 {
        return String::new();
    }
    values
        .chunks(cols)
        .map(|r| {
            r.iter()
                .map(|x| format!("{x:.16e}"))
                .collect::<Vec<_>>()
                .join(" ")
                + "\n"
        })
        .collect()
}

/// `LINEAR/STATEMAT`: the state matrices about the current operating point, written as plain
/// text matrices: `<file>a` holds A (`2f × 2f`), `<file>b` B (`2f × inputs`), `<file>c` C
/// (`outputs × 2f`), `<file>d` D (`outputs × inputs`) of `ẋ = A x + B u`, `y = C x + D u`, and
/// `<file>st` the basis N that maps the `f` independent coordinates to part coordinates
/// (`6·parts × f`: CM x, y, z in length units, then rotations about the ground axes in
/// radians, per part), so that the states are `x = [z; ż]` with `q = N z`. The inputs and
/// outputs are VARIABLE values ([`linkage_solve::stages::plant`]); without them B, C and D are
/// empty.
pub fn state_matrices(
    progress: &mut Progress,
    sinks: &mut Sinks,
    place: &Place,
    file: &Path,
    io: &PlantIo,
) -> Result<(), RunError> {
    let start = progress.start();
    let sm =
        linkage_api::linear::state_matrices(sinks.loaded, start, &io.inputs, &io.outputs, sinks);
    let sm = super::simulate::outcome(sinks, place, sm)?;
    let (m, pl) = (&sm.matrix, &sm.plant);
    let f = m.coordinates;
    let states = 2 * f + m.controls;
    let name = file.to_string_lossy();
    let files = [
        ("a", rows(&m.a, states)),
        ("b", rows(&pl.b, pl.inputs)),
        ("c", rows(&pl.c, states)),
        ("d", rows(&pl.d, pl.inputs)),
        ("st", rows(&m.basis, f)),
    ];
    for (suffix, text) in files {
        let path = PathBuf::from(format!("{name}{suffix}"));
        linkage_adm::writer::write_atomically(&path, &text).map_err(|cause| RunError::Write {
            path: path.display().to_string(),
            cause,
        })?;
    }
    sinks.msg.write(&format!(
        " State matrices at time {}: {states} states ({f} independent coordinates and their \
         rates, {} control states), {} input(s), {} output(s); A, B, C, D in {name}a, {name}b, \
         {name}c, {name}d, the coordinate basis in {name}st.",
        linkage_adm::num::time_text(sm.time),
        m.controls,
        pl.inputs,
        pl.outputs
    ))?;
    progress.leave(sm.left);
    Ok(())
}
