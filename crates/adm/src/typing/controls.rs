//! Typing of the control and system elements (ADM-ELEMENTS §6–§12): `DIFF`, `LSE`, `TFSISO`,
//! `GSE`, `MATRIX`, `PINPUT` and `POUTPUT`.
//!
//! Contract (in addition to the module contract of [`super`]):
//! - DIFF needs FUNCTION (an error at the statement otherwise); `IC = y0 [, ẏ0]`.
//! - LSE needs X and A; TFSISO needs NUMERATOR, DENOMINATOR, U, X and Y (errors at the
//!   statement). Which arrays and matrices exist, and their sizes, are `linkage-model`'s checks.
//! - GSE is read for its arrays and FUNCTION (a `USER(…)` call in every Adams GSE: linkage
//!   names it as a USER subroutine and models nothing of it).
//! - MATRIX is one of `FULL = RORDER | CORDER, ROWS, COLUMNS, VALUES` (ROWS·COLUMNS values),
//!   `SPARSE, ROWS, COLUMNS, I, J, VALUES` (as many I, J as values, each within the size),
//!   or `FILE = name [, NAME = name]`; anything else is an error at the statement.
//! - PINPUT and POUTPUT need VARIABLES.

use super::{header, label, Typer};
use crate::statement::Statement;
use crate::typed::*;

impl Typer {
    /// Types one control or system statement into `self.ds.controls`; false when `st` is not
    /// one of them.
    pub(super) fn control(&mut self, st: &Statement, index: usize) -> bool {
        match st.keyword.as_str() {
            "DIFF" => {
                if let Some(d) = self.diff(st, index) {
                    self.ds.controls.diffs.push(d);
                }
            }
            "LSE" => {
                if let Some(l) = self.lse(st, index) {
                    self.ds.controls.lses.push(l);
                }
            }
            "TFSISO" => {
                if let Some(t) = self.tfsiso(st, index) {
                    self.ds.controls.tfsisos.push(t);
                }
            }
            "GSE" => {
                let g = Gse {
                    header: header(st, index),
                    function: self.function(st, "FUNCTION"),
                };
                self.ds.controls.gses.push(g);
            }
            "MATRIX" => {
                if let Some(m) = self.matrix(st, index) {
                    self.ds.controls.matrices.push(m);
                }
            }
            "PINPUT" | "POUTPUT" => {
                if let Some(l) = self.plant_list(st, index) {
                    if st.keyword == "PINPUT" {
                        self.ds.controls.pinputs.push(l);
                    } else {
                        self.ds.controls.poutputs.push(l);
                    }
                }
            }
            _ => return false,
        }
        true
    }

    /// An error at the statement naming a missing argument.
    fn needs(&mut self, st: &Statement, key: &str, what: &str) {
        let msg = format!("{} needs {key} = <{what}>", label(st));
        self.error(st.span, msg);
    }

    fn diff(&mut self, st: &Statement, index: usize) -> Option<Diff> {
        let function = self.function(st, "FUNCTION");
        if st.arg("FUNCTION").is_none() {
            self.needs(st, "FUNCTION", "expression");
        }
        let ic = self.reals(st, "IC", &[1, 2]);
        Some(Diff {
            header: header(st, index),
            function: function?,
            ic,
            implicit: Self::flag(st, "IMPLICIT"),
            static_hold: Self::flag(st, "STATIC_HOLD"),
        })
    }

    fn lse(&mut self, st: &Statement, index: usize) -> Option<Lse> {
        let x = self.required_id(st, "X", "ARRAY");
        let a = self.required_id(st, "A", "MATRIX");
        let optional = |t: &mut Typer, key: &str| t.id_ref(st, key);
        let (u, b, y) = (
            optional(self, "U"),
            optional(self, "B"),
            optional(self, "Y"),
        );
        let (c, d, ic) = (
            optional(self, "C"),
            optional(self, "D"),
            optional(self, "IC"),
        );
        Some(Lse {
            header: header(st, index),
            x: x?,
            a: a?,
            u,
            b,
            y,
            c,
            d,
            ic,
            static_hold: Self::flag(st, "STATIC_HOLD"),
        })
    }

    fn tfsiso(&mut self, st: &Statement, index: usize) -> Option<Tfsiso> {
        let coefficients = |t: &mut Typer, key: &str| {
            let Some(a) = st.arg(key) else {
                t.needs(st, key, "coefficients");
                return None;
            };
            let n = a.values.len();
            t.reals(st, key, &[n])
        };
        let numerator = coefficients(self, "NUMERATOR");
        let denominator = coefficients(self, "DENOMINATOR");
        let u = self.required_id(st, "U", "ARRAY");
        let x = self.required_id(st, "X", "ARRAY");
        let y = self.required_id(st, "Y", "ARRAY");
        Some(Tfsiso {
            header: header(st, index),
            numerator: numerator?,
            denominator: denominator?,
            u: u?,
            x: x?,
            y: y?,
            static_hold: Self::flag(st, "STATIC_HOLD"),
        })
    }

    /// A non-negative whole number `key = n`.
    fn whole(&mut self, st: &Statement, key: &str) -> Option<usize> {
        let r = self.real(st, key)?;
        if r.value.fract() == 0.0 && (0.0..=1e9).contains(&r.value) {
            // Exact: a small non-negative integral value.
            Some(r.value as usize)
        } else {
            let msg = format!(
                "'{key}' of {} must be a non-negative integer, found {}",
                label(st),
                r.value
            );
            self.error(r.span, msg);
            None
        }
    }

    fn matrix(&mut self, st: &Statement, index: usize) -> Option<Matrix> {
        let head = header(st, index);
        if let Some(a) = st.arg("FILE") {
            let (name, span) = match a.values.first() {
                Some(crate::statement::Value::Str { text, span })
                | Some(crate::statement::Value::Word { text, span }) => (text.clone(), *span),
                Some(crate::statement::Value::Expr(e)) => (e.text.trim().to_string(), e.span_at(0)),
                _ => {
                    self.needs(st, "FILE", "file name");
                    return None;
                }
            };
            let matrix = match st.arg("NAME") {
                Some(_) => Some(self.word(st, "NAME")?.0.to_string()),
                None => None,
            };
            return Some(Matrix {
                header: head,
                data: MatrixData::File { name, span, matrix },
            });
        }
        let (Some(rows), Some(columns)) = (self.whole(st, "ROWS"), self.whole(st, "COLUMNS"))
        else {
            let msg = format!(
                "{} needs ROWS and COLUMNS (or FILE = <file name>)",
                label(st)
            );
            self.error(st.span, msg);
            return None;
        };
        let count = st.arg("VALUES").map_or(0, |a| a.values.len());
        let values = self.reals(st, "VALUES", &[count])?;
        if Self::flag(st, "SPARSE") {
            let ids = |t: &mut Typer, key: &str| -> Option<Vec<usize>> {
                let Some(list) = t.id_list(st, key, &[count]) else {
                    if st.arg(key).is_none() {
                        t.needs(st, key, "1-based indices");
                    }
                    return None;
                };
                Some(list.iter().map(|r| r.id as usize).collect())
            };
            let (i, j) = (ids(self, "I")?, ids(self, "J")?);
            let mut entries = Vec::with_capacity(count);
            for ((i, j), v) in i.into_iter().zip(j).zip(values.value.iter().copied()) {
                if i == 0 || j == 0 || i > rows || j > columns {
                    let msg = format!(
                        "{}: entry ({i}, {j}) is outside the {rows} × {columns} matrix (indices \
                         are 1-based)",
                        label(st)
                    );
                    self.error(values.span, msg);
                    return None;
                }
                entries.push((i, j, v));
            }
            return Some(Matrix {
                header: head,
                data: MatrixData::Sparse {
                    rows,
                    columns,
                    entries,
                },
            });
        }
        let order = match self.named(st, "FULL", &["RORDER", "CORDER"]) {
            Some(o) if o.value == "CORDER" => MatrixOrder::Columns,
            Some(_) => MatrixOrder::Rows,
            None => {
                if st.arg("FULL").is_none() {
                    let msg = format!(
                        "{} needs FULL = RORDER | CORDER, SPARSE or FILE = <file name>",
                        label(st)
                    );
                    self.error(st.span, msg);
                }
                return None;
            }
        };
        if values.value.len() != rows * columns {
            let msg = format!(
                "{}: a {rows} × {columns} matrix needs {} VALUES, found {}",
                label(st),
                rows * columns,
                values.value.len()
            );
            self.error(values.span, msg);
            return None;
        }
        Some(Matrix {
            header: head,
            data: MatrixData::Full {
                order,
                rows,
                columns,
                values: values.value,
            },
        })
    }

    fn plant_list(&mut self, st: &Statement, index: usize) -> Option<PlantList> {
        let Some(a) = st.arg("VARIABLES") else {
            self.needs(st, "VARIABLES", "VARIABLE ids");
            return None;
        };
        let n = a.values.len();
        Some(PlantList {
            header: header(st, index),
            variables: self.id_list(st, "VARIABLES", &[n])?,
        })
    }
}

#[cfg(test)]
mod tests {
    use crate::parse_dataset;
    use crate::typed::{MatrixData, MatrixOrder};
    use std::sync::Arc;

    fn read(body: &str) -> Result<crate::Dataset, String> {
        parse_dataset(
            Arc::from("m.adm"),
            &format!("t\nPART/1, GROUND\n{body}\nEND\n"),
        )
        .map_err(|e| e.to_string())
    }

    #[test]
    fn control_statements_read_their_arguments() {
        let ds = read(
            "DIFF/1, IC = 2, 0.5, IMPLICIT, STATIC_HOLD, FUNCTION = DIF(1) + 1\n\
             LSE/2, X = 20, A = 11, STATIC_HOLD, IC = 21, U = 40, B = 50, D = 51\n\
             TFSISO/3, NUMERATOR = 1, DENOMINATOR = 1, 0.5, U = 5, X = 6, Y = 7\n\
             MATRIX/11, FULL = CORDER, ROWS = 2, COLUMNS = 2, VALUES = 1, 2, 3, 4\n\
             MATRIX/12, SPARSE, ROWS = 3, COLUMNS = 3, I = 1, 3, J = 2, 3, VALUES = 5, 6\n\
             MATRIX/13, FILE = m.mat, NAME = VALK\n\
             PINPUT/1, VARIABLES = 4, 5\nPOUTPUT/2, VARIABLES = 6",
        )
        .unwrap_or_else(|e| panic!("{e}"));
        let c = &ds.controls;
        let d = &c.diffs[0];
        assert!(d.implicit && d.static_hold);
        assert_eq!(d.ic.as_ref().map(|l| l.value.clone()), Some(vec![2.0, 0.5]));
        let l = &c.lses[0];
        assert_eq!((l.x.id, l.a.id, l.u.map(|r| r.id)), (20, 11, Some(40)));
        assert!(l.y.is_none() && l.static_hold);
        assert_eq!(c.tfsisos[0].denominator.value, vec![1.0, 0.5]);
        assert_eq!(
            c.matrices[0].data,
            MatrixData::Full {
                order: MatrixOrder::Columns,
                rows: 2,
                columns: 2,
                values: vec![1.0, 2.0, 3.0, 4.0]
            }
        );
        assert_eq!(
            c.matrices[1].data,
            MatrixData::Sparse {
                rows: 3,
                columns: 3,
                entries: vec![(1, 2, 5.0), (3, 3, 6.0)]
            }
        );
        assert!(
            matches!(&c.matrices[2].data, MatrixData::File { name, matrix: Some(m), .. }
            if name == "m.mat" && m == "VALK")
        );
        assert_eq!(c.pinputs[0].variables.len(), 2);
        assert_eq!(c.poutputs[0].variables[0].id, 6);
    }

    #[test]
    fn malformed_control_statements_are_errors_at_their_place() {
        let e = read(
            "DIFF/1, IC = 0\nLSE/2, X = 3\n\
             MATRIX/4, FULL = RORDER, ROWS = 2, COLUMNS = 2, VALUES = 1, 2, 3\n\
             MATRIX/5, SPARSE, ROWS = 2, COLUMNS = 2, I = 3, J = 1, VALUES = 1",
        )
        .err()
        .unwrap_or_default();
        assert!(e.contains("DIFF/1 needs FUNCTION"), "{e}");
        assert!(e.contains("LSE/2 needs A"), "{e}");
        assert!(e.contains("needs 4 VALUES, found 3"), "{e}");
        assert!(e.contains("entry (3, 1) is outside"), "{e}");
    }
}
