//! New numbers for any numeric argument of any statement (FE_PART `COORDINATES`, a marker's
//! `QP`/`REULER`, FLEX_BODY `QG`/`REULER`/`DMODE`, …), patched into the original text the
//! way [`super::write_part_poses`] patches a part's pose.
//!
//! Contract:
//! - Every `KEY = …` of the statement gets its numbers replaced in place, token by token,
//!   in the order written (a repeated argument is rewritten too); [`NewValue::Keep`] leaves a
//!   token as it is (an FE node's label in `COORDINATES`). The argument must have exactly
//!   as many numbers as values are given, otherwise nothing is written (an error).
//! - An argument the statement does not have is added as a continuation line
//!   `, KEY = v1, v2, …` (every value must then be new: a `Keep` has nothing to keep).
//! - Lengths and radians ([`NewValue::Number`]) are rounded to [`super::WRITE_RESOLUTION`]
//!   of their magnitude (at least 1), angles given as [`NewValue::Degrees`] (radians in, `D`
//!   suffix out) to it of a turn, [`NewValue::Scaled`] to it of its own magnitude, so no
//!   rounding noise is written.
//! - After writing, the text is read again and every argument must read back with its new
//!   numbers (to 1e-9 of their magnitude): a mismatch is an error, never a wrong file.

use super::{error, format_real, resolved, statement_label, Edit, Planner, WRITE_RESOLUTION};
use crate::diagnostic::Diagnostic;
use crate::statement::Value;
use crate::typed::Dataset;

/// One new number of an argument.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NewValue {
    /// Keep the number written there.
    Keep,
    /// A length, a count or an angle in radians, written as a plain real.
    Number(f64),
    /// An angle, given in radians, written in degrees with the `D` suffix.
    Degrees(f64),
    /// A number without a natural scale (a modal coordinate: its size depends on how the
    /// modes are normalised), rounded to [`WRITE_RESOLUTION`] of its own magnitude.
    Scaled(f64),
}

/// New numbers for `key` of the statement at `statement` (an index into
/// [`Dataset::statements`]).
#[derive(Clone, Debug, PartialEq)]
pub struct ArgumentValues {
    pub statement: usize,
    /// The argument's keyword as the reader stores it (upper case, full name).
    pub key: String,
    pub values: Vec<NewValue>,
}

impl NewValue {
    /// The text written for a new value (`None` for [`NewValue::Keep`]).
    fn text(self) -> Option<String> {
        match self {
            NewValue::Keep => None,
            NewValue::Number(v) => Some(format_real(resolved(
                v,
                WRITE_RESOLUTION * v.abs().max(1.0),
            ))),
            NewValue::Scaled(v) => Some(format_real(resolved(v, WRITE_RESOLUTION * v.abs()))),
            NewValue::Degrees(a) => Some(format!(
                "{}D",
                format_real(resolved(a.to_degrees(), WRITE_RESOLUTION * 360.0))
            )),
        }
    }

    /// The value the reader should get back (radians for angles).
    fn read_back(self) -> Option<f64> {
        match self {
            NewValue::Keep => None,
            NewValue::Number(v) | NewValue::Degrees(v) | NewValue::Scaled(v) => Some(v),
        }
    }
}

impl Planner<'_> {
    /// Plans the edits of one argument.
    pub(super) fn plan_argument(&mut self, change: &ArgumentValues) {
        let ds = self.ds;
        let Some(st) = self.statement_at(change.statement) else {
            return;
        };
        let label = statement_label(st);
        let texts: Vec<Option<String>> = change.values.iter().map(|v| v.text()).collect();
        if change
            .values
            .iter()
            .any(|v| v.read_back().is_some_and(|x| !x.is_finite()))
        {
            let msg = format!("the new {} of {label} has a non-finite value", change.key);
            self.errors.push(error(ds, Some(st.span), msg));
            return;
        }
        let mut found = false;
        for arg in st.args.iter().filter(|a| a.key == change.key) {
            found = true;
            if arg.values.len() != texts.len() {
                let msg = format!(
                    "'{}' of {label} has {} values instead of {}; cannot rewrite it",
                    change.key,
                    arg.values.len(),
                    texts.len()
                );
                self.errors.push(error(ds, Some(arg.span), msg));
                continue;
            }
            for (value, text) in arg.values.iter().zip(&texts) {
                let Some(text) = text else { continue };
                let Value::Number {
                    value,
                    degrees,
                    span,
                } = value
                else {
                    let msg = format!(
                        "'{}' of {label} has a value that is not a number; cannot rewrite it",
                        change.key
                    );
                    self.errors.push(error(ds, Some(value.span()), msg));
                    continue;
                };
                match self.lines.number_range(&ds.text, *span, *value, *degrees) {
                    Some((start, end)) => self.edits.push(Edit {
                        start,
                        end,
                        text: text.clone(),
                        span: *span,
                    }),
                    None => {
                        let msg = format!(
                            "the number of '{}' of {label} is not found in the text at its \
                             position; cannot rewrite it",
                            change.key
                        );
                        self.errors.push(error(ds, Some(*span), msg));
                    }
                }
            }
        }
        if found {
            return;
        }
        let Some(new): Option<Vec<String>> = texts.into_iter().collect() else {
            let msg = format!(
                "{label} has no '{}' whose numbers could be kept; cannot add it",
                change.key
            );
            self.errors.push(error(ds, Some(st.span), msg));
            return;
        };
        self.insert_arguments(st, &[format!(", {} = {}", change.key, new.join(", "))]);
    }
}

/// Whether every changed argument reads back from `written` with its new numbers.
pub(super) fn check_arguments(
    ds: &Dataset,
    written: &Dataset,
    changes: &[ArgumentValues],
) -> Vec<Diagnostic> {
    let mut errors = Vec::new();
    for change in changes {
        let (Some(old), Some(new)) = (
            ds.statements.get(change.statement),
            written.statements.get(change.statement),
        ) else {
            continue;
        };
        let reads_back = new.keyword == old.keyword
            && new.id == old.id
            && new
                .args
                .iter()
                .filter(|a| a.key == change.key)
                .count()
                .max(1)
                == old
                    .args
                    .iter()
                    .filter(|a| a.key == change.key)
                    .count()
                    .max(1)
            && new.args.iter().filter(|a| a.key == change.key).all(|arg| {
                arg.values.len() == change.values.len()
                    && arg.values.iter().zip(&change.values).all(|(v, c)| {
                        match (v, c.read_back()) {
                            (_, None) => true,
                            (Value::Number { value, .. }, Some(x)) => {
                                (value - x).abs() <= 1e-9 * value.abs().max(x.abs()).max(1.0)
                            }
                            _ => false,
                        }
                    })
            })
            && new.args.iter().any(|a| a.key == change.key);
        if !reads_back {
            let msg = format!(
                "internal error: '{}' of {} does not read back with its new values",
                change.key,
                statement_label(old)
            );
            errors.push(error(ds, Some(old.span), msg));
        }
    }
    errors
}
