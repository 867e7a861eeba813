//! CURVE, PTCV and CVCV statements linkage cannot use: a CURVE no PTCV, CVCV or GRAPHICS
//! CURVE (contact geometry) reads (data nothing uses), and a PTCV or CVCV on a curve given by
//! a USER subroutine (`FUNCTION = USER(…)`), which linkage cannot evaluate. The USER CURVE
//! itself is named by the USER-call check when a PTCV or CVCV uses it.

use super::{Analysis, Reason, FORCE_ANALYSES};
use linkage_adm::{Dataset, Statement, Value};
use std::collections::HashSet;

/// Which CURVE ids PTCVs, CVCVs and GRAPHICS CURVEs read, and which CURVEs are USER subroutines.
pub(super) struct CurveUse {
    read: HashSet<u64>,
    user: HashSet<u64>,
}

/// The id a statement's argument `key` names (its first number).
fn id_of(st: &Statement, key: &str) -> Option<u64> {
    st.arg(key)?.values.iter().find_map(|v| match v {
        Value::Number { value, .. } if *value >= 0.0 => Some(*value as u64),
        _ => None,
    })
}

impl CurveUse {
    pub(super) fn new(ds: &Dataset) -> CurveUse {
        let mut read = HashSet::new();
        let mut user = HashSet::new();
        for st in &ds.statements {
            match st.keyword.as_str() {
                "PTCV" => read.extend(id_of(st, "CURVE")),
                "CVCV" => read.extend(["ICURVE", "JCURVE"].iter().filter_map(|k| id_of(st, k))),
                "GRAPHICS" if st.arg("CURVE").is_some() => read.extend(id_of(st, "CID")),
                "CURVE" if st.arg("FUNCTION").is_some() => user.extend(st.id),
                _ => {}
            }
        }
        CurveUse { read, user }
    }

    /// The finding for statement `st`, if it is a CURVE nothing reads, or a PTCV or
    /// CVCV on a USER curve: reason, detail, the analyses that refuse it.
    pub(super) fn problem(&self, st: &Statement) -> Option<(Reason, String, &'static [Analysis])> {
        match st.keyword.as_str() {
            "CURVE" if !st.id.is_some_and(|id| self.read.contains(&id)) => Some((
                Reason::NotUsed,
                "curve data no PTCV, CVCV or GRAPHICS CURVE reads".to_string(),
                &[],
            )),
            "PTCV" | "CVCV" => {
                let keys: &[&str] = if st.keyword == "PTCV" {
                    &["CURVE"]
                } else {
                    &["ICURVE", "JCURVE"]
                };
                let c = keys
                    .iter()
                    .filter_map(|k| id_of(st, k))
                    .find(|c| self.user.contains(c))?;
                Some((
                    Reason::NotModelled,
                    format!(
                        "its CURVE/{c} is a USER subroutine, which linkage cannot evaluate; \
                         verify's DOF count leaves the {} out",
                        st.keyword
                    ),
                    FORCE_ANALYSES,
                ))
            }
            _ => None,
        }
    }
}
