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
use linkage_adm::reqwriter::{Precision, RequestDescription, RequestFileHeader, RequestFileWriter};
use linkage_adm::Dataset;
use linkage_api::sink::{CsvSink, OutputSink, RequestFailure, RequestValues, SinkError};
use linkage_model::Model;
use linkage_solve::physics::requests::RequestSet;
use linkage_solve::pipeline::Assembled;
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

/// The streams of a run's time histories.
pub struct Records {
    csv: CsvSink<BufWriter<File>>,
    req_path: PathBuf,
    req: RequestFileWriter<BufWriter<File>>,
    /// The REQUESTs of the model the file was opened for (the layout of its blocks).
    requests: RequestSet,
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
        let requests = RequestSet::new(model).map_err(RunError::Input)?;
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
            csv: CsvSink::new(
                BufWriter::new(csv),
                csv_path.display().to_string(),
                model,
                Some(&requests),
                RequestFailure::Stop,
            ),
            req_path,
            req,
            requests,
            written: 0,
        })
    }

    /// Flushes both files; a CSV without rows gets the header of `model` alone, so that it
    /// says which columns it lacks (as `linkage simulate --out` writes it).
    pub fn finish(self, model: Option<&Model>) -> Result<(), RunError> {
        let mut csv = self.csv;
        let path = PathBuf::from(&csv.path);
        if let (0, Some(model)) = (self.written, model) {
            csv.finish_empty(model).map_err(write_error(&path))?;
        }
        csv.flush().map_err(write_error(&path))?;
        self.req.finish().map_err(|e| RunError::Write {
            path: self.req_path.display().to_string(),
            cause: std::io::Error::other(e.to_string()),
        })?;
        Ok(())
    }
}

impl OutputSink for Records {
    fn wants_requests(&self) -> bool {
        true
    }

    /// One output: a CSV row (the REQUEST columns, then each FRICTION's, curve contact's and
    /// control state's, [`linkage_api::sink::row_values`]) and a request-file block. A
    /// request that cannot be evaluated stops the analysis, naming it.
    fn output(&mut self, a: &Assembled, o: &Output, r: RequestValues) -> Result<(), SinkError> {
        let values = match r {
            Some(Ok(v)) => v.as_slice(),
            Some(Err(e)) => return Err(SinkError::Request(e.clone())),
            None => &[],
        };
        self.csv.output(a, o, r)?;
        let six = self.requests.stored_values(values);
        self.req
            .write_output(o.time, &six)
            .map_err(|e| SinkError::Write {
                path: self.req_path.display().to_string(),
                cause: std::io::Error::other(e.to_string()),
            })?;
        self.written += 1;
        Ok(())
    }
}
