//! Motion functions `f(t)` from the dataset's expressions.
//!
//! Each MOTION's FUNCTION is parsed once. A syntax error is an input error located at the line
//! and column inside the expression; a `USER(...)` subroutine cannot be run by linkage, so its
//! value is unknown (a warning; analyses that need it report it as such).

use crate::measures::{MarkerFrames, PositionEnv};
use crate::state::State;
use crate::verify::Drivers;
use linkage_adm::{Diagnostic, Diagnostics, MotionLevel};
use linkage_expr::{evaluate, evaluate_time_series, parse, Expr, TimeEnv};
use linkage_model::{ConstraintKind, Model};

/// Parsed motion functions of a model.
pub struct ExpressionDrivers {
    /// Per constraint element: the displacement-level function, if any.
    functions: Vec<Option<(Expr, MotionLevel, Option<f64>)>>,
    warnings: Vec<Diagnostic>,
}

impl ExpressionDrivers {
    /// Parses every motion function of `model`.
    pub fn new(model: &Model) -> Result<ExpressionDrivers, Diagnostics> {
        let mut functions = Vec::with_capacity(model.constraints.len());
        let mut errors = Vec::new();
        let mut warnings = Vec::new();
        let frames = MarkerFrames::new(model);
        let input = State::input(model);
        for c in &model.constraints {
            if let ConstraintKind::Gcon {
                function: Some(f), ..
            } = &c.kind
            {
                let text = &f.value.expr;
                let problem = match parse(&text.text) {
                    Err(pe) => Some((
                        text.span_at(pe.offset),
                        format!("in FUNCTION: {}", pe.message),
                    )),
                    Ok(e) if e.contains_user() => Some((
                        f.span,
                        "FUNCTION is a USER subroutine, which linkage cannot run".to_string(),
                    )),
                    Ok(e) => evaluate(
                        &e,
                        &PositionEnv {
                            frames: &frames,
                            state: &input,
                        },
                    )
                    .err()
                    .map(|err| {
                        (
                            f.span,
                            format!(
                                "FUNCTION cannot be evaluated at the input configuration: {}",
                                err.message
                            ),
                        )
                    }),
                };
                if let Some((span, msg)) = problem {
                    errors.push(Diagnostic::error(
                        model.file.clone(),
                        Some(span),
                        format!("{}: {msg}", c.origin.name),
                    ));
                }
            }
            let ConstraintKind::Motion {
                function: Some(f),
                level,
                icdisp,
                ..
            } = &c.kind
            else {
                functions.push(None);
                continue;
            };
            let text = &f.value.expr;
            match parse(&text.text) {
                Ok(e) if e.contains_user() => {
                    warnings.push(Diagnostic::warning(
                        model.file.clone(),
                        Some(f.span),
                        format!("{}: FUNCTION is a USER subroutine, which linkage cannot run; its value is unknown", c.origin.name),
                    ));
                    functions.push(None);
                }
                Ok(e) => functions.push(Some((e, *level, *icdisp))),
                Err(pe) => {
                    errors.push(Diagnostic::error(
                        model.file.clone(),
                        Some(text.span_at(pe.offset)),
                        format!("{}: in FUNCTION: {}", c.origin.name, pe.message),
                    ));
                    functions.push(None);
                }
            }
        }
        if errors.is_empty() {
            Ok(ExpressionDrivers {
                functions,
                warnings,
            })
        } else {
            Err(Diagnostics(errors))
        }
    }

    /// Non-fatal findings (USER subroutines).
    pub fn warnings(&self) -> &[Diagnostic] {
        &self.warnings
    }

    /// `[f, ḟ, f̈]` of a displacement-level motion at time `t`.
    pub fn series(&self, element: usize, t: f64) -> Option<Result<[f64; 3], String>> {
        let (e, level, _) = self.functions.get(element)?.as_ref()?;
        if *level != MotionLevel::Displacement {
            return None;
        }
        Some(evaluate_time_series(e, &TimeEnv { time: t, mode: 0 }).map_err(|err| err.message))
    }
}

impl Drivers for ExpressionDrivers {
    /// Displacement motions: `f(t)`. Velocity and acceleration motions: their ICDISP at t = 0
    /// when given, otherwise unknown (the start displacement is free).
    fn value(&self, element: usize, t: f64) -> Option<f64> {
        let (_, level, icdisp) = self.functions.get(element)?.as_ref()?;
        match level {
            MotionLevel::Displacement => self.series(element, t)?.ok().map(|s| s[0]),
            _ if t == 0.0 => *icdisp,
            _ => None,
        }
    }
}
