//! What coverage says about FLEX_BODY statements: a flex body is modelled from the MATRIX
//! data it lists (`linkage_model::flex_bodies`); one whose modal data are in a file linkage
//! cannot use is a finding naming the file, refused by every force analysis (verify's DOF
//! count leaves the body out):
//! - an MNF (`MNF_FILE`), MD DB (`DB_FILE`, `MD_DB_FILE`) or Nastran (`BDF_FILE`) file
//!   without MATRICES: missing, or present in a format linkage does not read;
//! - a listed MATRIX whose FILE is missing or not an ADAMSMAT text file.

use super::Reason;
use linkage_adm::flex_body::FlexBodyStatement;
use linkage_adm::{Dataset, MatrixData, Span};
use std::path::Path;

/// The unusable modal data of FLEX_BODY `st`: place, reason, detail.
pub(super) fn problems(ds: &Dataset, st: &FlexBodyStatement) -> Vec<(Span, Reason, String)> {
    let mut out = Vec::new();
    let leave_out = "the flex body cannot be modelled (verify's DOF count leaves it out)";
    if st.matrices.is_empty() {
        if let Some((key, f)) = &st.data_file {
            let path = linkage_model::controls::matrix_file_path(&ds.file, &f.value);
            let (reason, why) = if Path::new(&path).exists() {
                (
                    Reason::NotModelled,
                    format!(
                        "its modal data are in the file '{}' ({key}), a format linkage does not \
                         read: give them as MATRIX data (SELNOD, GENSTIFF, INVAR1 … INVAR9, \
                         T_MODES, R_MODES)",
                        f.value
                    ),
                )
            } else {
                (
                    Reason::ExternalFileMissing,
                    format!("its modal data file '{}' ({key}) does not exist", f.value),
                )
            };
            // At the statement: the body as a whole is refused (the detail names the file).
            out.push((st.header.span, reason, format!("{why}; {leave_out}")));
        }
        return out;
    }
    for r in &st.matrices {
        let Some(m) = ds.controls.matrices.iter().find(|m| m.header.id == r.id) else {
            continue;
        };
        let MatrixData::File { name, matrix, .. } = &m.data else {
            continue;
        };
        let path = linkage_model::controls::matrix_file_path(&ds.file, name);
        let problem = match std::fs::read_to_string(&path) {
            Err(_) if !path.exists() => Some((
                Reason::ExternalFileMissing,
                format!("the file '{name}' of its MATRIX/{} does not exist", r.id),
            )),
            Err(e) => Some((
                Reason::NotModelled,
                format!(
                    "the file '{name}' of its MATRIX/{} cannot be read ({e})",
                    r.id
                ),
            )),
            Ok(text) => linkage_model::build::read_adamsmat(&text, matrix.as_deref())
                .err()
                .map(|e| {
                    (
                        Reason::NotModelled,
                        format!("the file '{name}' of its MATRIX/{}: {e}", r.id),
                    )
                }),
        };
        if let Some((reason, why)) = problem {
            out.push((r.span, reason, format!("{why}; {leave_out}")));
        }
    }
    out
}
