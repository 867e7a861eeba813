//! Typing of `SENSOR/id, FUNCTION=e, VALUE=r [, EQ | GE | LE] [, ERROR=r] [, HALT] [, RETURN]
//! [, PRINT] [, RESTART] [, CODGEN] [, YYDUMP] [, DT=r] [, STEPSIZE=r] [, BISECTION]
//! [, ANGULAR] [, EVALUATE=e]` (ADM-ELEMENTS §5).
//!
//! Contract (in addition to the module contract of [`super`]): FUNCTION and VALUE are
//! required (an error at the statement, and the sensor is dropped); two of EQ, GE, LE is an
//! error at the second; ERROR, STEPSIZE and DT must be positive (an error at the value).

use super::{header, label, Typer};
use crate::statement::Statement;
use crate::typed::*;

impl Typer {
    pub(super) fn sensor(&mut self, st: &Statement, index: usize) -> Option<Sensor> {
        let function = self.function(st, "FUNCTION");
        if st.arg("FUNCTION").is_none() {
            let msg = format!("{} needs FUNCTION = <expression>", label(st));
            self.error(st.span, msg);
        }
        let value = self.real(st, "VALUE");
        if st.arg("VALUE").is_none() {
            let msg = format!("{} needs VALUE = <number>", label(st));
            self.error(st.span, msg);
        }
        let kinds = [
            ("EQ", SensorCompare::Eq),
            ("GE", SensorCompare::Ge),
            ("LE", SensorCompare::Le),
        ];
        let compare = self
            .one_of(st, &kinds, "comparison (EQ, GE, LE)")
            .ok()
            .flatten()
            .unwrap_or_default();
        let mut positive = |key: &str| {
            let r = self.real(st, key)?;
            if r.value > 0.0 && r.value.is_finite() {
                Some(r)
            } else {
                let msg = format!(
                    "{key} of {} must be positive (it is {})",
                    label(st),
                    r.value
                );
                self.error(r.span, msg);
                None
            }
        };
        let error = positive("ERROR");
        let stepsize = positive("STEPSIZE");
        let dt = positive("DT");
        let actions = SensorActions {
            halt: Self::flag(st, "HALT"),
            return_: Self::flag(st, "RETURN"),
            print: Self::flag(st, "PRINT"),
            restart: Self::flag(st, "RESTART"),
            codgen: Self::flag(st, "CODGEN"),
            yydump: Self::flag(st, "YYDUMP"),
        };
        let sensor = Sensor {
            header: header(st, index),
            function: function.clone(),
            value: value.clone(),
            compare,
            error,
            actions,
            stepsize,
            dt,
            bisection: Self::flag(st, "BISECTION"),
            angular: Self::flag(st, "ANGULAR"),
            evaluate: self.function(st, "EVALUATE"),
        };
        (function.is_some() && value.is_some()).then_some(sensor)
    }
}

#[cfg(test)]
mod tests {
    use crate::parse_dataset;
    use crate::typed::SensorCompare;
    use std::sync::Arc;

    #[test]
    fn sensor_reads_its_comparison_actions_and_expressions() {
        let text = "t\nPART/1, GROUND\nSENSOR/7, VALUE = 0.5, GE, ERROR = 1E-4, HALT, PRINT, \
                    STEPSIZE = 1E-3, BISECTION, EVALUATE = TIME\\\n, FUNCTION = DZ(2, 1)\nEND\n";
        let ds = parse_dataset(Arc::from("m.adm"), text).unwrap_or_else(|e| panic!("{e}"));
        let s = &ds.sensors[0];
        assert_eq!(s.header.id, 7);
        assert_eq!(s.value.as_ref().map(|v| v.value), Some(0.5));
        assert_eq!(s.compare, SensorCompare::Ge);
        assert_eq!(s.error.as_ref().map(|v| v.value), Some(1e-4));
        assert!(s.actions.halt && s.actions.print && !s.actions.return_);
        assert_eq!(s.stepsize.as_ref().map(|v| v.value), Some(1e-3));
        assert!(s.bisection);
        let f = s
            .function
            .as_ref()
            .map(|f| f.value.expr.text.trim().to_string());
        assert_eq!(f.as_deref(), Some("DZ(2, 1)"));
        assert!(s.evaluate.is_some());
    }

    #[test]
    fn sensor_needs_function_and_value_and_one_comparison() {
        let e = parse_dataset(
            Arc::from("m.adm"),
            "t\nPART/1, GROUND\nSENSOR/7, HALT\nSENSOR/8, VALUE = 1, GE, LE, ERROR = -1, \
             FUNCTION = TIME\nEND\n",
        )
        .err()
        .map(|d| d.to_string())
        .unwrap_or_default();
        assert!(e.contains("SENSOR/7 needs FUNCTION"), "{e}");
        assert!(e.contains("SENSOR/7 needs VALUE"), "{e}");
        assert!(e.contains("ERROR of SENSOR/8 must be positive"), "{e}");
        assert!(e.contains("GE") && e.contains("LE"), "{e}");
    }
}
