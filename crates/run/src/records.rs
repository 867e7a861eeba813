//! The time histories of a command file, written as the run goes: `<name>.req` (the Adams
//! request file: every REQUEST at every output of every analysis, in order) and `<name>.csv`
//! (the columns of `linkage simulate --out`: each part's CM position, 3-1-3 angles in degrees
//! and velocities, each constraint element's reaction on its I marker, then the request
//! components; the same header, each column with its unit as a suffix, `PART_2.x [mm]`).
//!
//! Contract:
//! - The columns and requests are those of the model at the first output; an element
//!   deactivated later writes zeros (it carries no load); a part cannot come or go.
//! - Each output is written whole and flushed before the next one is computed: a run that stops
//!   leaves complete rows and blocks.

use crate::error::RunError;
use linkage_adm::reqfile::VALUES_PER_REQUEST;
use linkage_adm::reqwriter::{Precision, RequestDescription, RequestFileHeader, RequestFileWriter};
use linkage_adm::Dataset;
use linkage_model::Model;
use linkage_report::element_columns;
use linkage_report::simulate::CsvHistory;
use linkage_solve::constraints::system::System;
use linkage_solve::physics::applied::AppliedForces;
use linkage_solve::physics::requests::{RequestAngles, RequestSet};
use linkage_solve::stages::dynamics::Output;
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

/// Two-letter codes of the units word of a request file (`M_KGS_N_RACA`: length, mass, time,
/// force, then the angle code); a unit without a code gets its first two letters.
fn unit_code(name: &str) -> String {
    let code = match name {
        "METER" => "M_",
        "MILLIMETER" => "MM",
        "CENTIMETER" => "CM",
        "KILOMETER" => "KM",
        "INCH" => "IN",
        "FOOT" => "FT",
        "KILOGRAM" => "KG",
        "GRAM" => "G_",
        "TONNE" => "MG",
        "POUND_MASS" => "LB",
        "SLUG" => "SL",
        "SECOND" => "S_",
        "MILLISECOND" => "MS",
        "MINUTE" => "MI",
        "HOUR" => "H_",
        "NEWTON" => "N_",
        "KNEWTON" => "KN",
        "MILLINEWTON" => "MN",
        "DYNE" => "DY",
        "POUND_FORCE" => "LB",
        "KILOGRAM_FORCE" => "KF",
        other => return format!("{:_<2}", other.chars().take(2).collect::<String>()),
    };
    code.to_string()
}

/// The units word and scale of line 3 of a request file for `model`.
fn units_word(model: &Model) -> (String, f64) {
    let [force, mass, length, time] = model.units.names;
    let word = format!(
        "{}{}{}{}RACA",
        unit_code(length),
        unit_code(mass),
        unit_code(time),
        unit_code(force)
    );
    (word, 1.0 / model.units.length)
}

/// The header records of every REQUEST of the dataset `ds`, in order.
fn descriptions(ds: &Dataset) -> Vec<RequestDescription> {
    ds.requests
        .iter()
        .map(|r| RequestDescription {
            id: r.header.id,
            type_code: match r.kind {
                Some(linkage_adm::RequestKind::Displacement) => 1,
                Some(linkage_adm::RequestKind::Velocity) => 2,
                Some(linkage_adm::RequestKind::Acceleration) => 3,
                Some(linkage_adm::RequestKind::Force) => 4,
                None => 5,
            },
            i: r.i.as_ref().map_or(0, |m| m.id),
            j: r.j.as_ref().map_or(0, |m| m.id),
            comment: r
                .comment
                .as_ref()
                .map_or(String::new(), |c| c.value.clone()),
        })
        .collect()
}

/// Why an output could not be recorded.
#[derive(Debug, thiserror::Error)]
pub enum RecordError {
    /// A REQUEST cannot be evaluated at the output.
    #[error(transparent)]
    Request(#[from] linkage_solve::physics::requests::RequestError),
    /// A file cannot be written.
    #[error("cannot write {path}: {cause}")]
    Write { path: String, cause: String },
}

/// The streams of a run's time histories.
pub struct Records {
    csv_path: PathBuf,
    csv: CsvHistory<BufWriter<File>>,
    req_path: PathBuf,
    req: RequestFileWriter<BufWriter<File>>,
    /// The request columns of the CSV (fixed at the first output, as its other columns).
    names: Option<Vec<String>>,
    /// The REQUEST angles of the last output written, which the next continues.
    angles: RequestAngles,
    /// Outputs written.
    pub written: usize,
}

fn write_error(path: &Path) -> impl Fn(std::io::Error) -> RunError + '_ {
    move |cause| RunError::Write {
        path: path.display().to_string(),
        cause,
    }
}

impl Records {
    /// Creates `<stem>.csv` and `<stem>.req` and writes the request-file header for the
    /// REQUESTs of `ds`, built into `model`.
    pub fn create(stem: &Path, ds: &Dataset, model: &Model) -> Result<Records, RunError> {
        let csv_path = stem.with_extension("csv");
        let req_path = stem.with_extension("req");
        let csv = File::create(&csv_path).map_err(write_error(&csv_path))?;
        let req_file = File::create(&req_path).map_err(write_error(&req_path))?;
        let (units, scale) = units_word(model);
        let header = RequestFileHeader::now(ds.title.clone(), units, scale);
        let req = RequestFileWriter::new(
            BufWriter::new(req_file),
            &header,
            &descriptions(ds),
            Precision::Adams,
        )
        .map_err(|e| RunError::Write {
            path: req_path.display().to_string(),
            cause: std::io::Error::other(e.to_string()),
        })?;
        Ok(Records {
            csv_path,
            csv: CsvHistory::new(BufWriter::new(csv)),
            req_path,
            req,
            names: None,
            angles: RequestAngles::new(),
            written: 0,
        })
    }

    /// Writes one output of a run of `model` (compiled constraints `sys`, forces `forces`):
    /// a CSV row (the REQUEST columns, then each FRICTION's and control state's,
    /// [`linkage_report::element_columns`]) and a request-file block. A request that cannot
    /// be evaluated is an error naming it.
    pub fn write(
        &mut self,
        model: &Model,
        sys: &System,
        requests: &RequestSet,
        forces: &dyn AppliedForces,
        o: &Output,
    ) -> Result<(), RecordError> {
        let values = requests.evaluate_continuing(model, sys, o, &mut self.angles)?;
        let mut columns = values.clone();
        let frictions = if model.frictions.is_empty() {
            Vec::new()
        } else {
            forces.friction_values(&o.state, &o.velocities)
        };
        let contacts =
            linkage_solve::constraints::curve_contacts::curve_contacts(model, sys, &o.state);
        element_columns::values(model, &frictions, &contacts, &o.state, &mut columns);
        self.csv
            .write(
                model,
                o,
                self.names.get_or_insert_with(|| {
                    let mut names = requests.columns();
                    names.extend(element_columns::names(model));
                    names
                }),
                &columns,
            )
            .map_err(|e| RecordError::Write {
                path: self.csv_path.display().to_string(),
                cause: e.to_string(),
            })?;
        let six = requests.stored_values(&values);
        self.req
            .write_output(o.time, &six)
            .map_err(|e| RecordError::Write {
                path: self.req_path.display().to_string(),
                cause: e.to_string(),
            })?;
        self.written += 1;
        Ok(())
    }

    /// Flushes both files.
    pub fn finish(self) -> Result<(), RunError> {
        let mut csv = self.csv;
        csv.flush().map_err(write_error(&self.csv_path))?;
        self.req.finish().map_err(|e| RunError::Write {
            path: self.req_path.display().to_string(),
            cause: std::io::Error::other(e.to_string()),
        })?;
        Ok(())
    }
}

/// Six stored values per request, as [`RequestSet::stored_values`] gives them.
pub type Stored = Vec<[f64; VALUES_PER_REQUEST]>;
