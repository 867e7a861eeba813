//! Typing of FLEX_BODY (ADM-ELEMENTS §19), a linear flexible body: six BCS coordinates plus
//! modal amplitudes, its modal data in MATRIX statements (or an MNF / MD DB file), and the
//! node references of markers on it (`MARKER/id, FLEX_BODY = f, NODE_ID = n`).
//!
//! Contract:
//! - Typed on demand from the dataset's statements ([`type_flex_bodies`]), as FE_PART is.
//! - `MATRICES`: MATRIX ids (which names the builder reads is its business); `MNF_FILE`,
//!   `DB_FILE` (or `MD_DB_FILE`), `BDF_FILE`: file names as written (quotes removed).
//! - `INVARIANTS`: nine `T`/`F` words separated by colons (default all `T`).
//! - `DMODE`, `VMODE`: initial modal coordinates and rates, one per selected mode (checked
//!   against the mode count by the builder); `QG`, `REULER`, `VX … WZ`, `EXACT` as for PART.
//! - `CHAR_LEN` > 0; `CRATIO` an expression (kept as written).

use super::Typer;
use crate::diagnostic::{Diagnostic, Span};
use crate::statement::{Statement, Value};
use crate::typed::{Dataset, ExactCoord, Function, Header, IdRef, Located, MarkerCarrier};

/// `FLEX_BODY/id, …`.
#[derive(Clone, Debug, PartialEq)]
pub struct FlexBodyStatement {
    pub header: Header,
    /// MATRIX ids holding the modal data.
    pub matrices: Vec<IdRef>,
    /// `MNF_FILE`, `DB_FILE` / `MD_DB_FILE` or `BDF_FILE`: the modal data file named.
    pub data_file: Option<(&'static str, Located<String>)>,
    /// The nine inertia invariants switched on (`INVARIANTS`, default all on).
    pub invariants: [bool; 9],
    pub invariants_span: Option<Span>,
    pub qg: Option<Located<[f64; 3]>>,
    pub reuler: Option<Located<[f64; 3]>>,
    /// `VX, VY, VZ, WX, WY, WZ` (`None` = not given).
    pub velocity: [Option<f64>; 6],
    pub dmode: Option<Located<Vec<f64>>>,
    pub vmode: Option<Located<Vec<f64>>>,
    pub exact: Vec<ExactCoord>,
    pub char_len: Option<Located<f64>>,
    pub cratio: Option<Located<Function>>,
}

/// FLEX_BODY statements and the node each marker on a flex body names.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FlexData {
    pub bodies: Vec<FlexBodyStatement>,
    /// Per marker id on a FLEX_BODY: its `NODE_ID` (`None`: on the body's reference frame).
    pub marker_nodes: Vec<(u64, Option<Located<u64>>)>,
}

/// Types every FLEX_BODY of `ds` and the NODE_ID of the markers on them. Returns the data and
/// the diagnostics; a statement with an error is left out.
pub fn type_flex_bodies(ds: &Dataset) -> (FlexData, Vec<Diagnostic>) {
    let mut t = Typer {
        file: ds.file.clone(),
        diagnostics: Vec::new(),
        ds: Dataset::empty(ds.file.clone()),
        carrier: None,
    };
    let mut out = FlexData::default();
    for (index, st) in ds.statements.iter().enumerate() {
        if st.known && st.keyword == "FLEX_BODY" {
            out.bodies.extend(t.flex_body(st, index));
        }
    }
    out.marker_nodes = ds
        .markers
        .iter()
        .filter(|m| matches!(m.carrier, Some(MarkerCarrier::FlexBody(_))))
        .map(|m| {
            let node = match &m.fe_node {
                Some(crate::typed::FeMarkerNode::Label(l)) => Some(l.clone()),
                _ => None,
            };
            (m.header.id, node)
        })
        .collect();
    (out, t.diagnostics)
}

fn file_name(st: &Statement, key: &str) -> Option<Located<String>> {
    let arg = st.arg(key)?;
    let (text, span) = match arg.values.first() {
        Some(Value::Str { text, span }) | Some(Value::Word { text, span }) => (text.clone(), *span),
        Some(Value::Expr(e)) => (e.text.clone(), e.span_at(0)),
        _ => (String::new(), arg.span),
    };
    let value = text
        .trim()
        .trim_matches(|c| c == '\'' || c == '"')
        .to_string();
    Some(Located { value, span })
}

impl Typer {
    fn flex_body(&mut self, st: &Statement, index: usize) -> Option<FlexBodyStatement> {
        let header = super::header(st, index);
        let matrices = match st.arg("MATRICES") {
            Some(arg) => {
                let mut ids = Vec::with_capacity(arg.values.len());
                for v in &arg.values {
                    ids.push(self.as_id(st, "MATRICES", v)?);
                }
                ids
            }
            None => Vec::new(),
        };
        let data_file = [
            ("MNF_FILE", "MNF_FILE"),
            ("DB_FILE", "DB_FILE"),
            ("MD_DB_FILE", "DB_FILE"),
            ("BDF_FILE", "BDF_FILE"),
        ]
        .iter()
        .find_map(|(key, kind)| file_name(st, key).map(|f| (*kind, f)));
        if matrices.is_empty() && data_file.is_none() {
            let msg = format!(
                "{}: a FLEX_BODY needs its modal data: MATRICES, MNF_FILE or DB_FILE",
                header.name
            );
            self.error(st.span, msg);
            return None;
        }
        let (invariants, invariants_span) = self.invariants(st)?;
        let mut velocity = [None; 6];
        for (v, key) in velocity
            .iter_mut()
            .zip(["VX", "VY", "VZ", "WX", "WY", "WZ"])
        {
            *v = self.real(st, key).map(|r| r.value);
        }
        let list = |t: &mut Typer, key: &str| -> Option<Located<Vec<f64>>> {
            let arg = st.arg(key)?;
            let nums = t.numbers(st, arg)?;
            Some(Located {
                value: nums.iter().map(|(v, _)| *v).collect(),
                span: arg.span,
            })
        };
        let dmode = list(self, "DMODE");
        let vmode = list(self, "VMODE");
        let char_len = self.real(st, "CHAR_LEN");
        if let Some(c) = &char_len {
            if c.value.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
                let msg = format!("{}: CHAR_LEN must be positive", header.name);
                self.error(c.span, msg);
                return None;
            }
        }
        Some(FlexBodyStatement {
            matrices,
            data_file,
            invariants,
            invariants_span,
            qg: self.vec3(st, "QG"),
            reuler: self.vec3(st, "REULER"),
            velocity,
            dmode,
            vmode,
            exact: self.exact(st),
            char_len,
            cratio: self.function(st, "CRATIO"),
            header,
        })
    }

    fn invariants(&mut self, st: &Statement) -> Option<([bool; 9], Option<Span>)> {
        let Some(arg) = st.arg("INVARIANTS") else {
            return Some(([true; 9], None));
        };
        let mut out = [true; 9];
        let words: Vec<&Value> = arg.values.iter().collect();
        if words.len() != 9 {
            let msg = format!(
                "{}: INVARIANTS needs 9 T/F entries separated by colons, found {}",
                super::label(st),
                words.len()
            );
            self.error(arg.span, msg);
            return None;
        }
        for (k, v) in words.iter().enumerate() {
            out[k] = match v {
                Value::Word { text, .. } if text.eq_ignore_ascii_case("T") => true,
                Value::Word { text, .. } if text.eq_ignore_ascii_case("F") => false,
                other => {
                    let msg = format!("{}: INVARIANTS entries are T or F", super::label(st));
                    self.error(other.span(), msg);
                    return None;
                }
            };
        }
        Some((out, Some(arg.span)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::parse_dataset;
    use std::sync::Arc;

    fn data(text: &str) -> (FlexData, Vec<Diagnostic>) {
        let ds = parse_dataset(Arc::from("m.adm"), text).unwrap_or_else(|e| panic!("{e}"));
        type_flex_bodies(&ds)
    }

    #[test]
    fn flex_body_arguments_are_read() {
        let (d, diags) = data(
            "t\nPART/1, GROUND\nFLEX_BODY/5, MATRICES = 1, 2, 3, INVARIANTS = T:T:F:F:F:T:T:T:F\n\
             , QG = 1, 2, 3, DMODE = 0.1, 0.2, VMODE = 0, 3, WZ = 2, EXACT = X:Y, CHAR_LEN = 4\n\
             , CRATIO = 0.02\nMARKER/9, FLEX_BODY = 5, NODE_ID = 12\nMARKER/10, FLEX_BODY = 5\nEND\n",
        );
        assert!(diags.is_empty(), "{diags:?}");
        let b = &d.bodies[0];
        assert_eq!(
            b.matrices.iter().map(|m| m.id).collect::<Vec<_>>(),
            [1, 2, 3]
        );
        assert_eq!(
            b.invariants,
            [true, true, false, false, false, true, true, true, false]
        );
        assert_eq!(
            b.dmode.as_ref().map(|x| x.value.clone()),
            Some(vec![0.1, 0.2])
        );
        assert_eq!(
            b.vmode.as_ref().map(|x| x.value.clone()),
            Some(vec![0.0, 3.0])
        );
        assert_eq!(b.velocity[5], Some(2.0));
        assert_eq!(b.exact, [ExactCoord::X, ExactCoord::Y]);
        assert_eq!(b.char_len.as_ref().map(|c| c.value), Some(4.0));
        assert_eq!(
            b.cratio.as_ref().map(|c| c.value.expr.text.trim()),
            Some("0.02")
        );
        assert_eq!(d.marker_nodes[0].0, 9);
        assert_eq!(d.marker_nodes[0].1.as_ref().map(|n| n.value), Some(12));
        assert_eq!(d.marker_nodes[1], (10, None));
    }

    #[test]
    fn flex_body_without_modal_data_or_with_bad_invariants_is_an_error() {
        let (d, diags) = data("t\nPART/1, GROUND\nFLEX_BODY/5, QG = 0, 0, 0\nEND\n");
        assert!(d.bodies.is_empty());
        assert!(
            diags[0].message.contains("needs its modal data"),
            "{diags:?}"
        );
        let (_, diags) =
            data("t\nPART/1, GROUND\nFLEX_BODY/5, MATRICES = 1, INVARIANTS = T:F\nEND\n");
        assert!(diags[0].message.contains("9 T/F entries"), "{diags:?}");
        let (d, diags) = data("t\nPART/1, GROUND\nFLEX_BODY/5, MNF_FILE = 'beam.mnf'\nEND\n");
        assert!(diags.is_empty(), "{diags:?}");
        let (kind, f) = d.bodies[0].data_file.clone().unwrap();
        assert_eq!((kind, f.value.as_str()), ("MNF_FILE", "beam.mnf"));
    }
}
