//! Typing of `FRICTION/id, JOINT=id, MU_STATIC=μs, MU_DYNAMIC=μd [, STICTION_TRANSITION_VELOCITY=vs]
//! [, TRANSITION_VELOCITY_COEFFICIENT=β] [, MAX_STICTION_DEFORMATION=Δmax]
//! [, FRICTION_FORCE_PRELOAD=Fp] [, FRICTION_TORQUE_PRELOAD=Tp] [, PIN_RADIUS=Rp]
//! [, BALL_RADIUS=Rb] [, FRICTION_ARM=Rn] [, BENDING_REACTION_ARM=Rb] [, REACTION_ARM=Rr]
//! [, INITIAL_OVERLAP=Xs0] [, OVERLAP_DELTA=INCREASE|DECREASE|CONSTANT]
//! [, EFFECT=ALL|STICTION|SLIDING] [, INACTIVE_DURING=STATIC]
//! [, INPUTS=ALL|NONE|item:item…]` (ADM-ELEMENTS §4).
//!
//! Contract (in addition to the module contract of [`super`]): JOINT, MU_STATIC and
//! MU_DYNAMIC are required (an error at the statement, and the friction is dropped). The
//! coefficients, preloads and INITIAL_OVERLAP must be finite and not negative; velocities,
//! the stiction deformation, radii and arms must be positive; TRANSITION_VELOCITY_COEFFICIENT
//! must exceed 1 (the dynamic regime starts at β·vs, after the stiction one ends at vs). Each
//! bad value is an error at the value. INPUTS items are PRELOAD, REACTION_FORCE,
//! BENDING_MOMENT and TORSIONAL_MOMENT, colon-separated, or ALL or NONE alone. Defaults are
//! filled in by the model builder, not here: `None` means "not written".

use super::{header, label, Typer};
use crate::diagnostic::Span;
use crate::statement::{Statement, Value};
use crate::typed::{Friction, FrictionEffect, FrictionInputs, Located, OverlapDelta};

/// What a numeric argument must be.
#[derive(Clone, Copy)]
enum Bound {
    NotNegative,
    Positive,
    AboveOne,
}

impl Bound {
    fn holds(self, x: f64) -> bool {
        x.is_finite()
            && match self {
                Bound::NotNegative => x >= 0.0,
                Bound::Positive => x > 0.0,
                Bound::AboveOne => x > 1.0,
            }
    }

    fn words(self) -> &'static str {
        match self {
            Bound::NotNegative => "must not be negative",
            Bound::Positive => "must be positive",
            Bound::AboveOne => "must be greater than 1",
        }
    }
}

impl Typer {
    /// `key` as a number within `bound`; an error at the value otherwise.
    fn bounded(&mut self, st: &Statement, key: &str, bound: Bound) -> Option<Located<f64>> {
        let r = self.real(st, key)?;
        if bound.holds(r.value) {
            return Some(r);
        }
        let msg = format!(
            "{key} of {} {} (it is {})",
            label(st),
            bound.words(),
            r.value
        );
        self.error(r.span, msg);
        None
    }

    /// `key = NAME` with NAME one of `table`'s names: its value.
    fn choice<T: Copy>(
        &mut self,
        st: &Statement,
        key: &str,
        table: &[(&'static str, T)],
    ) -> Option<T> {
        let names: Vec<&'static str> = table.iter().map(|(n, _)| *n).collect();
        let found = self.named(st, key, &names)?;
        table
            .iter()
            .find(|(n, _)| *n == found.value)
            .map(|(_, v)| *v)
    }

    /// The colon list of INPUTS.
    fn friction_inputs(&mut self, st: &Statement) -> FrictionInputs {
        let Some(arg) = st.arg("INPUTS") else {
            return FrictionInputs::ALL;
        };
        let mut inputs = FrictionInputs::NONE;
        let words: Vec<(String, Span)> = arg
            .values
            .iter()
            .map(|v| match v {
                Value::Word { text, span } => (text.to_ascii_uppercase(), *span),
                other => (String::new(), other.span()),
            })
            .collect();
        for (text, span) in &words {
            match text.as_str() {
                "ALL" | "NONE" if words.len() == 1 => {
                    if text == "ALL" {
                        inputs = FrictionInputs::ALL;
                    }
                }
                "PRELOAD" => inputs.preload = true,
                "REACTION_FORCE" => inputs.reaction_force = true,
                "BENDING_MOMENT" => inputs.bending_moment = true,
                "TORSIONAL_MOMENT" => inputs.torsional_moment = true,
                _ => {
                    let msg = format!(
                        "INPUTS of {} are ALL, NONE, or PRELOAD, REACTION_FORCE, BENDING_MOMENT, \
                         TORSIONAL_MOMENT separated by colons",
                        label(st)
                    );
                    self.error(*span, msg);
                }
            }
        }
        inputs
    }

    pub(super) fn friction(&mut self, st: &Statement, index: usize) -> Option<Friction> {
        let joint = self.required_id(st, "JOINT", "joint");
        let required = |t: &mut Typer, key: &str| {
            if st.arg(key).is_none() {
                let msg = format!("{} needs {key} = <number>", label(st));
                t.error(st.span, msg);
            }
            t.bounded(st, key, Bound::NotNegative)
        };
        let mu_static = required(self, "MU_STATIC");
        let mu_dynamic = required(self, "MU_DYNAMIC");
        use Bound::*;
        let effect = [
            ("ALL", FrictionEffect::All),
            ("STICTION", FrictionEffect::Stiction),
            ("SLIDING", FrictionEffect::Sliding),
        ];
        let overlap = [
            ("CONSTANT", OverlapDelta::Constant),
            ("INCREASE", OverlapDelta::Increase),
            ("DECREASE", OverlapDelta::Decrease),
        ];
        let effect = self.choice(st, "EFFECT", &effect).unwrap_or_default();
        let overlap_delta = self
            .choice(st, "OVERLAP_DELTA", &overlap)
            .unwrap_or_default();
        let inactive_static = self.named(st, "INACTIVE_DURING", &["STATIC"]).is_some();
        let vs = self.bounded(st, "STICTION_TRANSITION_VELOCITY", Positive);
        let beta = self.bounded(st, "TRANSITION_VELOCITY_COEFFICIENT", AboveOne);
        let dmax = self.bounded(st, "MAX_STICTION_DEFORMATION", Positive);
        let force_preload = self.bounded(st, "FRICTION_FORCE_PRELOAD", NotNegative);
        let torque_preload = self.bounded(st, "FRICTION_TORQUE_PRELOAD", NotNegative);
        let pin_radius = self.bounded(st, "PIN_RADIUS", Positive);
        let ball_radius = self.bounded(st, "BALL_RADIUS", Positive);
        let friction_arm = self.bounded(st, "FRICTION_ARM", Positive);
        let bending_reaction_arm = self.bounded(st, "BENDING_REACTION_ARM", Positive);
        let reaction_arm = self.bounded(st, "REACTION_ARM", Positive);
        let initial_overlap = self.bounded(st, "INITIAL_OVERLAP", Positive);
        let inputs = self.friction_inputs(st);
        let friction = Friction {
            header: header(st, index),
            joint: joint?,
            mu_static: mu_static?,
            mu_dynamic: mu_dynamic?,
            stiction_transition_velocity: vs,
            transition_velocity_coefficient: beta,
            max_stiction_deformation: dmax,
            force_preload,
            torque_preload,
            pin_radius,
            ball_radius,
            friction_arm,
            bending_reaction_arm,
            reaction_arm,
            initial_overlap,
            overlap_delta,
            effect,
            inactive_static,
            inputs,
            inputs_span: st.arg("INPUTS").map_or(st.span, |a| a.span),
        };
        Some(friction)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::parse_dataset;
    use std::sync::Arc;

    fn parse(body: &str) -> Result<crate::Dataset, String> {
        let text = format!("t\nPART/1, GROUND\n{body}\nEND\n");
        parse_dataset(Arc::from("m.adm"), &text).map_err(|d| d.to_string())
    }

    /// The FAST brake (Test02) and a fully written friction read as written.
    #[test]
    fn friction_reads_its_coefficients_inputs_and_effect() {
        let ds = parse(
            "FRICTION/3151, JOINT = 3150, MU_STATIC = 1, MU_DYNAMIC = 1\n\
             , STICTION_TRANSITION_VELOCITY = 9.999E-04, EFFECT = ALL, INPUTS = PRELOAD\n\
             , FRICTION_TORQUE_PRELOAD = 1.35E+02\n\
             FRICTION/2, JOINT = 18, MU_STATIC = 0.3, MU_DYNAMIC = 0.2, INACTIVE_DURING = STATIC\n\
             , INPUTS = REACTION_FORCE:BENDING_MOMENT, EFFECT = SLIDING, PIN_RADIUS = 8\n\
             , TRANSITION_VELOCITY_COEFFICIENT = 2, OVERLAP_DELTA = DECREASE, INITIAL_OVERLAP = 5",
        )
        .unwrap_or_else(|e| panic!("{e}"));
        let [brake, other] = ds.frictions.as_slice() else {
            panic!("{:?}", ds.frictions);
        };
        assert_eq!((brake.header.id, brake.joint.id), (3151, 3150));
        assert_eq!(brake.torque_preload.as_ref().map(|v| v.value), Some(135.0));
        assert_eq!(
            brake.inputs,
            FrictionInputs {
                preload: true,
                ..FrictionInputs::NONE
            }
        );
        assert_eq!(brake.effect, FrictionEffect::All);
        assert!(!brake.inactive_static);
        assert!(other.inactive_static);
        assert_eq!(other.effect, FrictionEffect::Sliding);
        assert_eq!(other.overlap_delta, OverlapDelta::Decrease);
        assert_eq!(
            other.inputs,
            FrictionInputs {
                reaction_force: true,
                bending_moment: true,
                ..FrictionInputs::NONE
            }
        );
        assert_eq!(other.pin_radius.as_ref().map(|v| v.value), Some(8.0));
        assert_eq!(
            other
                .transition_velocity_coefficient
                .as_ref()
                .map(|v| v.value),
            Some(2.0)
        );
    }

    /// Missing coefficients, a negative coefficient, a zero radius, β ≤ 1 and an unknown input
    /// are each an error at their place.
    #[test]
    fn friction_values_out_of_range_are_errors() {
        let e = parse(
            "FRICTION/1, JOINT = 2, MU_STATIC = 0.3\n\
             FRICTION/2, JOINT = 2, MU_STATIC = -0.1, MU_DYNAMIC = 0.1, PIN_RADIUS = 0\n\
             , TRANSITION_VELOCITY_COEFFICIENT = 1, INPUTS = PRELOAD:WEIGHT",
        )
        .err()
        .unwrap_or_default();
        assert!(e.contains("FRICTION/1 needs MU_DYNAMIC"), "{e}");
        assert!(
            e.contains("MU_STATIC of FRICTION/2 must not be negative"),
            "{e}"
        );
        assert!(
            e.contains("PIN_RADIUS of FRICTION/2 must be positive"),
            "{e}"
        );
        assert!(
            e.contains("TRANSITION_VELOCITY_COEFFICIENT of FRICTION/2 must be greater than 1"),
            "{e}"
        );
        assert!(e.contains("INPUTS of FRICTION/2 are ALL, NONE"), "{e}");
        let none = parse("FRICTION/4, JOINT = 2, MU_STATIC = 0.3, MU_DYNAMIC = 0.2, INPUTS = NONE")
            .unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(none.frictions[0].inputs, FrictionInputs::NONE);
    }
}
