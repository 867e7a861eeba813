//! Typing of force elements (SFORCE, SPRINGDAMPER, BUSHING, FIELD, BEAM, VFORCE, VTORQUE,
//! GFORCE) and data elements (VARIABLE, ARRAY, SPLINE); ADM-REFERENCE §2.10–2.11.
//!
//! Contract (in addition to the module contract of [`super`]):
//! - The marker arguments an element cannot exist without (`I`, `J`, `JFLOAT`, `RM`) are
//!   required: an error at the statement when missing, and the element is dropped.
//! - Value counts are checked (`BUSHING K` 3 values, `FIELD KMATRIX` 36, `BEAM CMATRIX` 21,
//!   …); physical values (positive lengths and moduli) are checked by `linkage-model`.
//! - Two exclusive choices given together (`TRANSLATIONAL` and `ROTATIONAL`, `CMATRIX` and
//!   `CRATIO`, two ARRAY types, `NUMBERS` and `VARIABLES`) are errors at the second one.
//! - Defaults are not filled in here (`None` = not written), except the SFORCE/SPRINGDAMPER
//!   kind, which is TRANSLATIONAL when neither keyword is written.

use super::{header, keywords, label, Lookup, Typer};
use crate::statement::{Statement, Value};
use crate::typed::*;

impl Typer {
    /// `key = r1, …, rN` with exactly `N` values.
    fn fixed<const N: usize>(&mut self, st: &Statement, key: &str) -> Option<Located<[f64; N]>> {
        let r = self.reals(st, key, &[N])?;
        let value: [f64; N] = r.value.try_into().ok()?;
        Some(Located {
            value,
            span: r.span,
        })
    }

    fn force_dof(&mut self, st: &Statement) -> Option<ForceDof> {
        let kinds = [
            ("TRANSLATIONAL", ForceDof::Translational),
            ("ROTATIONAL", ForceDof::Rotational),
        ];
        self.one_of(st, &kinds, "kind (TRANSLATIONAL, ROTATIONAL)")
            .ok()
            .map(Option::unwrap_or_default)
    }

    /// The two markers `I` and `J` (both reported when missing).
    fn i_j(&mut self, st: &Statement) -> Option<(IdRef, IdRef)> {
        let i = self.required_id(st, "I", "marker");
        let j = self.required_id(st, "J", "marker");
        Some((i?, j?))
    }

    /// `I`, `JFLOAT` and `RM` of VFORCE, VTORQUE and GFORCE.
    fn i_jfloat_rm(&mut self, st: &Statement) -> Option<(IdRef, IdRef, IdRef)> {
        let i = self.required_id(st, "I", "marker");
        let jfloat = self.required_id(st, "JFLOAT", "floating marker");
        let rm = self.required_id(st, "RM", "marker");
        Some((i?, jfloat?, rm?))
    }

    /// An error at the second of two exclusive arguments given together.
    fn exclusive(&mut self, st: &Statement, a: &str, b: &str) -> bool {
        if let (Some(_), Some(second)) = (st.arg(a), st.arg(b)) {
            let msg = format!("{} gives both {a} and {b}; use one", label(st));
            self.error(second.span, msg);
            return false;
        }
        true
    }

    fn functions<const N: usize>(
        &mut self,
        st: &Statement,
        keys: [&str; N],
    ) -> [Option<Located<Function>>; N] {
        keys.map(|k| self.function(st, k))
    }

    pub(super) fn sforce(&mut self, st: &Statement, index: usize) -> Option<Sforce> {
        let dof = self.force_dof(st);
        let (i, j) = self.i_j(st)?;
        Some(Sforce {
            header: header(st, index),
            i,
            j,
            dof: dof?,
            action_only: Self::flag(st, "ACTIONONLY"),
            function: self.function(st, "FUNCTION"),
        })
    }

    pub(super) fn springdamper(&mut self, st: &Statement, index: usize) -> Option<SpringDamper> {
        let dof = self.force_dof(st)?;
        let (i, j) = self.i_j(st)?;
        let ignored = match dof {
            ForceDof::Translational => ["KT", "CT", "ANGLE", "TORQUE"],
            ForceDof::Rotational => ["K", "C", "LENGTH", "FORCE"],
        };
        for key in ignored {
            if let Some(a) = st.arg(key) {
                let kind = match dof {
                    ForceDof::Translational => "TRANSLATIONAL",
                    ForceDof::Rotational => "ROTATIONAL",
                };
                let msg = format!("'{key}' does not apply to a {kind} {}; ignored", label(st));
                self.warning(a.span, msg);
            }
        }
        Some(SpringDamper {
            header: header(st, index),
            i,
            j,
            dof,
            k: self.real(st, "K"),
            c: self.real(st, "C"),
            length: self.real(st, "LENGTH"),
            force: self.real(st, "FORCE"),
            kt: self.real(st, "KT"),
            ct: self.real(st, "CT"),
            angle: self.real(st, "ANGLE"),
            torque: self.real(st, "TORQUE"),
        })
    }

    pub(super) fn bushing(&mut self, st: &Statement, index: usize) -> Option<Bushing> {
        let (i, j) = self.i_j(st)?;
        Some(Bushing {
            header: header(st, index),
            i,
            j,
            k: self.fixed(st, "K"),
            c: self.fixed(st, "C"),
            kt: self.fixed(st, "KT"),
            ct: self.fixed(st, "CT"),
            force: self.fixed(st, "FORCE"),
            torque: self.fixed(st, "TORQUE"),
        })
    }

    pub(super) fn field(&mut self, st: &Statement, index: usize) -> Option<Field> {
        let (i, j) = self.i_j(st)?;
        if !self.exclusive(st, "CMATRIX", "CRATIO") {
            return None;
        }
        Some(Field {
            header: header(st, index),
            i,
            j,
            kmatrix: self.fixed(st, "KMATRIX"),
            cmatrix: self.fixed(st, "CMATRIX"),
            cratio: self.real(st, "CRATIO"),
            length: self.fixed(st, "LENGTH"),
            force: self.fixed(st, "FORCE"),
            function: self.function(st, "FUNCTION"),
        })
    }

    pub(super) fn beam(&mut self, st: &Statement, index: usize) -> Option<Beam> {
        let (i, j) = self.i_j(st)?;
        if !self.exclusive(st, "CMATRIX", "CRATIO") {
            return None;
        }
        let formulation = match self.word(st, "FORMULATION") {
            None => None,
            Some((word, span)) => {
                let names = ["LINEAR", "STRING", "NONLINEAR"];
                let value = match keywords::lookup_name(word, &names) {
                    Lookup::Found("LINEAR") => BeamFormulation::Linear,
                    Lookup::Found("STRING") => BeamFormulation::String,
                    Lookup::Found(_) => BeamFormulation::Nonlinear,
                    _ => {
                        let msg = format!(
                            "unknown value '{word}' of 'FORMULATION' (expected one of {})",
                            names.join(", ")
                        );
                        self.error(span, msg);
                        return None;
                    }
                };
                Some(Located { value, span })
            }
        };
        Some(Beam {
            header: header(st, index),
            i,
            j,
            length: self.real(st, "LENGTH"),
            ixx: self.real(st, "IXX"),
            iyy: self.real(st, "IYY"),
            izz: self.real(st, "IZZ"),
            area: self.real(st, "AREA"),
            asy: self.real(st, "ASY"),
            asz: self.real(st, "ASZ"),
            emodulus: self.real(st, "EMODULUS"),
            gmodulus: self.real(st, "GMODULUS"),
            cratio: self.real(st, "CRATIO"),
            cmatrix: self.fixed(st, "CMATRIX"),
            formulation,
        })
    }

    pub(super) fn vforce(&mut self, st: &Statement, index: usize) -> Option<Vforce> {
        let (i, jfloat, rm) = self.i_jfloat_rm(st)?;
        Some(Vforce {
            header: header(st, index),
            i,
            jfloat,
            rm,
            force: self.functions(st, ["FX", "FY", "FZ"]),
            function: self.function(st, "FUNCTION"),
        })
    }

    pub(super) fn vtorque(&mut self, st: &Statement, index: usize) -> Option<Vtorque> {
        let (i, jfloat, rm) = self.i_jfloat_rm(st)?;
        Some(Vtorque {
            header: header(st, index),
            i,
            jfloat,
            rm,
            torque: self.functions(st, ["TX", "TY", "TZ"]),
            function: self.function(st, "FUNCTION"),
        })
    }

    pub(super) fn gforce(&mut self, st: &Statement, index: usize) -> Option<Gforce> {
        let (i, jfloat, rm) = self.i_jfloat_rm(st)?;
        Some(Gforce {
            header: header(st, index),
            i,
            jfloat,
            rm,
            force: self.functions(st, ["FX", "FY", "FZ"]),
            torque: self.functions(st, ["TX", "TY", "TZ"]),
            function: self.function(st, "FUNCTION"),
        })
    }

    pub(super) fn variable(&mut self, st: &Statement, index: usize) -> Variable {
        Variable {
            header: header(st, index),
            function: self.function(st, "FUNCTION"),
            ic: self.real(st, "IC"),
        }
    }

    pub(super) fn array(&mut self, st: &Statement, index: usize) -> Option<Array> {
        let kinds = [
            ("U", ArrayKind::U),
            ("X", ArrayKind::X),
            ("Y", ArrayKind::Y),
            ("IC", ArrayKind::Ic),
        ];
        let kind = self.one_of(st, &kinds, "type (U, X, Y, IC)").ok()?;
        if !self.exclusive(st, "NUMBERS", "VARIABLES") {
            return None;
        }
        let size = match self.real(st, "SIZE") {
            None => None,
            Some(s) if s.value.fract() == 0.0 && (0.0..=1e9).contains(&s.value) => Some(Located {
                // Exact: a small non-negative integral value.
                value: s.value as usize,
                span: s.span,
            }),
            Some(s) => {
                let msg = format!(
                    "'SIZE' of {} must be a non-negative integer, found {}",
                    label(st),
                    s.value
                );
                self.error(s.span, msg);
                return None;
            }
        };
        let variables = match st.arg("VARIABLES") {
            Some(a) => Some(self.id_list(st, "VARIABLES", &[a.values.len()])?),
            None => None,
        };
        let numbers = match st.arg("NUMBERS") {
            Some(a) => Some(self.reals(st, "NUMBERS", &[a.values.len()])?),
            None => None,
        };
        Some(Array {
            header: header(st, index),
            kind,
            size,
            numbers,
            variables,
        })
    }

    pub(super) fn spline(&mut self, st: &Statement, index: usize) -> Option<Spline> {
        let list = |t: &mut Typer, key: &str| match st.arg(key) {
            Some(a) => t.reals(st, key, &[a.values.len()]),
            None => None,
        };
        let x = list(self, "X");
        let z = list(self, "Z");
        let mut y = Vec::new();
        for a in st.args.iter().filter(|a| a.key == "Y") {
            let mut values = Vec::with_capacity(a.values.len());
            for v in &a.values {
                match v {
                    Value::Number { value, .. } => values.push(*value),
                    other => {
                        let msg = format!("'Y' of {} expects numbers", label(st));
                        self.error(other.span(), msg);
                        return None;
                    }
                }
            }
            y.push(Located {
                value: values,
                span: a.span,
            });
        }
        let file = match st.arg("FILE").map(|a| a.values.as_slice()) {
            Some([Value::Expr(e)]) => Some(Located {
                value: e.text.clone(),
                span: e.span_at(0),
            }),
            Some([Value::Str { text, span }]) => Some(Located {
                value: text.clone(),
                span: *span,
            }),
            _ => None,
        };
        Some(Spline {
            header: header(st, index),
            x,
            y,
            z,
            linear_extrapolate: Self::flag(st, "LINEAR_EXTRAPOLATE"),
            file,
        })
    }
}
