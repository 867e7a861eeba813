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

#[cfg(test)]
mod tests {
    use crate::diagnostic::Span;
    use crate::typed::*;
    use crate::{parse_dataset, Diagnostics};
    use std::sync::Arc;

    fn read(body: &str) -> Result<Dataset, Diagnostics> {
        parse_dataset(Arc::from("t.adm"), &format!("title line\n{body}\nEND\n"))
    }

    fn ok(body: &str) -> Dataset {
        read(body).unwrap_or_else(|e| panic!("{e}"))
    }

    /// Errors as `(line, col, message)`.
    fn errors(body: &str) -> Vec<(u32, u32, String)> {
        match read(body) {
            Ok(ds) => panic!("expected errors, got {ds:#?}"),
            Err(d) => {
                d.0.into_iter()
                    .map(|d| {
                        let s = d.span.unwrap_or_default();
                        (s.line, s.col, d.message)
                    })
                    .collect()
            }
        }
    }

    fn text(f: &Option<Located<Function>>) -> Option<&str> {
        f.as_ref().map(|f| f.value.expr.text.as_str())
    }

    #[test]
    fn sforce_kinds_flags_and_multiline_function() {
        let ds = ok("SFORCE/3\n, ROTATIONAL\n, I = 207\n, J = 208\n, FUNCTION = -1.0*AZ(207,208)\n, - 5.0E-002*WZ(207,208,208)\nSFORCE/4, I=1, J=2, ACTIONONLY, FUN = 10\\\nSFORCE/5, I=1, J=2, TRANSLATION, FUNCTION = USER(1, 2)");
        let s = &ds.sforces[0];
        assert_eq!((s.header.id, s.header.name.as_str()), (3, "SFORCE_3"));
        assert_eq!(s.header.span, Span::new(2, 1));
        assert_eq!((s.i.id, s.j.id, s.dof), (207, 208, ForceDof::Rotational));
        assert_eq!(s.i.span, Span::new(4, 7));
        assert!(!s.action_only);
        assert_eq!(
            text(&s.function),
            Some("-1.0*AZ(207,208) - 5.0E-002*WZ(207,208,208)")
        );
        assert_eq!(s.function.as_ref().map(|f| f.span), Some(Span::new(6, 14)));
        let a = &ds.sforces[1];
        assert!(
            a.action_only && a.dof == ForceDof::Translational,
            "default kind"
        );
        assert_eq!(text(&a.function), Some("10"));
        let u = &ds.sforces[2];
        assert!(u.function.as_ref().is_some_and(|f| f.value.user));
        assert_eq!(u.dof, ForceDof::Translational);
    }

    #[test]
    fn sforce_needs_markers_and_one_kind() {
        assert_eq!(
            errors("SFORCE/1, J=2, FUNCTION=1"),
            [(2, 1, "SFORCE/1 needs I = <marker id>".to_string())]
        );
        let e = errors("SFORCE/1, I=1, J=2, TRANSLATIONAL, ROTATIONAL, FUNCTION=1");
        assert_eq!((e[0].0, e[0].1), (2, 36));
        assert!(e[0].2.contains("more than one kind"), "{}", e[0].2);
    }

    #[test]
    fn springdamper_translational_and_rotational_values() {
        let ds = ok("SPRINGDAMPER/1, I=1, J=2, TRANSLATIONAL, K=100, C=2, LENGTH=0.5, FORCE=3\nSPRING/2, I=3, J=4, ROTATION, KT=10, CT=0.1, ANGLE=90D, TORQUE=1");
        let t = &ds.springdampers[0];
        assert_eq!(t.dof, ForceDof::Translational);
        let v = |x: &Option<Located<f64>>| x.as_ref().map(|l| l.value);
        assert_eq!(
            [v(&t.k), v(&t.c), v(&t.length), v(&t.force)],
            [Some(100.0), Some(2.0), Some(0.5), Some(3.0)]
        );
        assert_eq!(t.k.as_ref().map(|l| l.span), Some(Span::new(2, 42)));
        let r = &ds.springdampers[1];
        assert_eq!(r.dof, ForceDof::Rotational);
        assert_eq!(r.header.name, "SPRINGDAMPER_2");
        assert_eq!(
            [v(&r.kt), v(&r.ct), v(&r.torque)],
            [Some(10.0), Some(0.1), Some(1.0)]
        );
        assert!(v(&r.angle).is_some_and(|a| (a - std::f64::consts::FRAC_PI_2).abs() < 1e-15));
        assert!(r.k.is_none() && r.length.is_none());
    }

    #[test]
    fn springdamper_value_of_the_other_kind_is_a_warning() {
        let ds = ok("SPRINGDAMPER/1, I=1, J=2, K=100, KT=5");
        assert_eq!(ds.warnings.len(), 1);
        assert_eq!(ds.warnings[0].span, Some(Span::new(2, 34)));
        assert!(ds.warnings[0].message.contains("'KT' does not apply"));
    }

    #[test]
    fn bushing_three_values_each() {
        let ds = ok("BUSHING/1\n, I = 4481\n, J = 238\n, C = 1000, 1000, 1000\n, K = 1.0E+05, 2.0E+05, 3.0E+05\n, CT = 1, 2, 3\n, KT = 4, 5, 6\n, FORCE = 7, 8, 9\n, TORQUE = 10, 11, 12");
        let b = &ds.bushings[0];
        assert_eq!((b.i.id, b.j.id), (4481, 238));
        let v = |x: &Option<Located<[f64; 3]>>| x.as_ref().map(|l| l.value);
        assert_eq!(v(&b.k), Some([1e5, 2e5, 3e5]));
        assert_eq!(v(&b.c), Some([1000.0; 3]));
        assert_eq!(v(&b.ct), Some([1.0, 2.0, 3.0]));
        assert_eq!(v(&b.kt), Some([4.0, 5.0, 6.0]));
        assert_eq!(v(&b.force), Some([7.0, 8.0, 9.0]));
        assert_eq!(v(&b.torque), Some([10.0, 11.0, 12.0]));
        assert_eq!(
            errors("BUSHING/1, I=1, J=2, K=1, 2"),
            [(
                2,
                22,
                "'K' of BUSHING/1 needs 3 values, found 2".to_string()
            )]
        );
    }

    #[test]
    fn field_matrices_lengths_and_exclusive_damping() {
        let k: Vec<String> = (1..=36).map(|n| n.to_string()).collect();
        let body = format!(
            "FIELD/7, I=1, J=2\n, KMATRIX = {}\n, CRATIO = 0.01, LENGTH = 1, 2, 3, 0, 0, 0\n, FORCE = 0, 0, 5, 0, 0, 1",
            k.join(", ")
        );
        let ds = ok(&body);
        let f = &ds.fields[0];
        let km = f.kmatrix.as_ref().map(|l| l.value).unwrap_or([0.0; 36]);
        assert_eq!((km[0], km[6], km[35]), (1.0, 7.0, 36.0));
        assert_eq!(f.cratio.as_ref().map(|l| l.value), Some(0.01));
        assert_eq!(
            f.length.as_ref().map(|l| l.value),
            Some([1.0, 2.0, 3.0, 0.0, 0.0, 0.0])
        );
        assert_eq!(f.force.as_ref().map(|l| l.value[2]), Some(5.0));
        assert!(f.cmatrix.is_none() && f.function.is_none());
        let e = errors(&format!("{body}\n, CMATRIX = {}", k.join(", ")));
        assert!(e[0].2.contains("both CMATRIX and CRATIO"), "{e:?}");
        assert_eq!(
            errors("FIELD/7, I=1, J=2, KMATRIX = 1, 2")[0].2,
            "'KMATRIX' of FIELD/7 needs 36 values, found 2"
        );
        let u = ok("FIELD/8, I=1, J=2, FUNCTION = USER(1, 2)");
        assert!(u.fields[0].function.as_ref().is_some_and(|f| f.value.user));
    }

    #[test]
    fn beam_section_properties_by_prefix() {
        let ds = ok("BEAM/1,I=10,J=20,AREA=100,LENGTH=+40.0e+03,IX=1E04,IY=2E04,IZ=3E04,\nEMOD=21E06,GMOD=5E05, ASY=1.2, ASZ=1.1, CRATIO=0.001, FORMULATION=LIN");
        let b = &ds.beams[0];
        let v = |x: &Option<Located<f64>>| x.as_ref().map(|l| l.value);
        assert_eq!(
            [v(&b.length), v(&b.ixx), v(&b.iyy), v(&b.izz), v(&b.area)],
            [Some(4e4), Some(1e4), Some(2e4), Some(3e4), Some(100.0)]
        );
        assert_eq!(
            [
                v(&b.emodulus),
                v(&b.gmodulus),
                v(&b.asy),
                v(&b.asz),
                v(&b.cratio)
            ],
            [Some(21e6), Some(5e5), Some(1.2), Some(1.1), Some(0.001)]
        );
        assert_eq!(
            b.formulation.as_ref().map(|f| f.value),
            Some(BeamFormulation::Linear)
        );
        let c: Vec<String> = (1..=21).map(|n| n.to_string()).collect();
        let ds = ok(&format!("BEAM/2, I=1, J=2, CMATRIX = {}", c.join(",")));
        assert_eq!(
            ds.beams[0].cmatrix.as_ref().map(|l| l.value[20]),
            Some(21.0)
        );
        assert_eq!(
            ok("BEAM/3, I=1, J=2, FORMULATION = NONLINEAR").beams[0]
                .formulation
                .as_ref()
                .map(|f| f.value),
            Some(BeamFormulation::Nonlinear)
        );
        let e = errors("BEAM/3, I=1, J=2, FORMULATION = CURVED");
        assert_eq!((e[0].0, e[0].1), (2, 33));
    }

    #[test]
    fn vforce_vtorque_gforce_components() {
        let ds = ok("VFORCE/9, I = 5, JFLOAT = 104, RM = 5\n, FX = 0\\\n, FY = 0\\\n, FZ = -1E5*DZ(5,1,1)\n,-1E4*VZ(5,1,1)\nVTORQUE/1,I=14, JFLOAT=2, RM=8, TX=11\\TZ=22\\TY=33;\nGFORCE/88,I=1,RM=1,FX=18\\FY=20+40,JFLOAT=2\nGFORCE/1, I = 5, JFLOAT = 7, RM = 6, FUNCTION = USER(5, 6, 6)\\\n, ROUTINE = tlm::f");
        let v = &ds.vforces[0];
        assert_eq!((v.i.id, v.jfloat.id, v.rm.id), (5, 104, 5));
        assert_eq!(text(&v.force[0]), Some("0"));
        assert_eq!(text(&v.force[2]), Some("-1E5*DZ(5,1,1)-1E4*VZ(5,1,1)"));
        let t = &ds.vtorques[0];
        assert_eq!(
            [text(&t.torque[0]), text(&t.torque[1]), text(&t.torque[2])],
            [Some("11"), Some("33"), Some("22")]
        );
        let g = &ds.gforces[0];
        assert_eq!((g.i.id, g.jfloat.id, g.rm.id), (1, 2, 1));
        assert_eq!(
            [text(&g.force[0]), text(&g.force[1])],
            [Some("18"), Some("20+40")]
        );
        assert!(g.force[2].is_none() && g.torque.iter().all(Option::is_none));
        assert!(ds.gforces[1]
            .function
            .as_ref()
            .is_some_and(|f| f.value.user));
        // ROUTINE = lib::name is kept as written (case matters for a C routine's name).
        assert_eq!(
            ds.gforces[1]
                .function
                .as_ref()
                .and_then(|f| f.value.routine.as_deref()),
            Some("tlm::f")
        );
        assert_eq!(
            ds.gforces[0].force[0]
                .as_ref()
                .map(|f| f.value.routine.clone()),
            Some(None)
        );
        assert_eq!(
            errors("VFORCE/9, I = 5, RM = 5, FX = 1"),
            [(
                2,
                1,
                "VFORCE/9 needs JFLOAT = <floating marker id>".to_string()
            )]
        );
    }

    #[test]
    fn variable_array_spline() {
        let ds = ok("VARIABLE/1, FUNCTION = DM(2,3) - 100.0, IC = 5\nARRAY/1, IC, SIZE = 3, NUMBERS = 0.2, 0.5, 3\nARRAY/2, U, VARIABLES = 1, 2\nARRAY/3, X, SIZE = 2\nSPLINE/8901\n, X = -5000, 0, 5000\n, Y = 1, 2, 4\n, LINEAR_EXTRAPOLATE\nSPLINE/2, X = 0, 1, Z = 0, 1, Y = 0, 1, 2, Y = 1, 3, 4");
        let var = &ds.variables[0];
        assert_eq!(text(&var.function), Some("DM(2,3) - 100.0"));
        assert_eq!(var.ic.as_ref().map(|l| l.value), Some(5.0));
        let a = &ds.arrays[0];
        assert_eq!(a.kind, Some(ArrayKind::Ic));
        assert_eq!(a.size.as_ref().map(|s| s.value), Some(3));
        assert_eq!(
            a.numbers.as_ref().map(|n| n.value.clone()),
            Some(vec![0.2, 0.5, 3.0])
        );
        let u = &ds.arrays[1];
        assert_eq!(u.kind, Some(ArrayKind::U));
        assert_eq!(
            u.variables
                .as_ref()
                .map(|v| v.iter().map(|r| r.id).collect::<Vec<_>>()),
            Some(vec![1, 2])
        );
        assert_eq!(ds.arrays[2].kind, Some(ArrayKind::X));
        let s = &ds.splines[0];
        assert_eq!(
            s.x.as_ref().map(|x| x.value.clone()),
            Some(vec![-5000.0, 0.0, 5000.0])
        );
        assert_eq!(s.y.len(), 1);
        assert_eq!(s.y[0].value, [1.0, 2.0, 4.0]);
        assert!(s.linear_extrapolate && s.z.is_none());
        let s2 = &ds.splines[1];
        assert_eq!(s2.y.len(), 2, "one Y per curve of a 2-D spline");
        assert!(s2.z.is_some() && !s2.linear_extrapolate);
        assert!(ds.warnings.is_empty(), "{:?}", ds.warnings);
        let e = errors("ARRAY/4, IC, NUMBERS = 1, VARIABLES = 2");
        assert!(e[0].2.contains("both NUMBERS and VARIABLES"), "{e:?}");
        assert_eq!(errors("ARRAY/4, SIZE = 2.5")[0].1, 10);
    }
}
