//! The arguments of one command: resolved against the command's complete argument table and
//! read as typed values, every problem an error at its line:column.
//!
//! Contract:
//! - A key resolves like every keyword of the language ([`keywords::lookup`]): case-insensitive,
//!   an exact spelling wins, otherwise an unambiguous prefix. The parser may already have
//!   canonicalised it (its command tables are partial); either way the result is the same.
//! - An unknown or ambiguous key, a bare keyword given a value, a valued keyword given none, a
//!   value of the wrong shape: errors naming the command and the argument.
//! - An argument given twice: a warning, the first one is used (as in datasets).

use crate::diagnostic::{Diagnostic, Span};
use crate::keywords::{self, Lookup};
use crate::statement::{Argument, Statement, Value};
use std::sync::Arc;

/// How an argument is written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Kind {
    /// Bare keyword.
    Flag,
    /// One real number, no `D`.
    Real,
    /// One real number, `D` (degrees) allowed.
    Angle,
    /// One non-negative integer.
    Count,
    /// One or more positive integers (ids, mode numbers).
    Ids,
    /// One keyword value.
    Word,
    /// Free text (file names, comments).
    Text,
    /// `T:F:…` Jacobian pattern.
    Pattern,
}

/// One argument of a command's table.
#[derive(Clone, Copy, Debug)]
pub(super) struct Spec {
    pub spelling: &'static str,
    pub canonical: &'static str,
    pub kind: Kind,
}

pub(super) const fn spec(name: &'static str, kind: Kind) -> Spec {
    Spec {
        spelling: name,
        canonical: name,
        kind,
    }
}

pub(super) const fn alias(spelling: &'static str, canonical: &'static str, kind: Kind) -> Spec {
    Spec {
        spelling,
        canonical,
        kind,
    }
}

/// Collects the diagnostics of a command file.
pub(super) struct Sink {
    pub file: Arc<str>,
    pub list: Vec<Diagnostic>,
}

impl Sink {
    pub fn error(&mut self, span: Span, msg: impl Into<String>) {
        self.list
            .push(Diagnostic::error(self.file.clone(), Some(span), msg));
    }

    pub fn warning(&mut self, span: Span, msg: impl Into<String>) {
        self.list
            .push(Diagnostic::warning(self.file.clone(), Some(span), msg));
    }

    pub fn errors(&self) -> usize {
        self.list.iter().filter(|d| d.is_error()).count()
    }
}

/// The resolved arguments of one command.
pub(super) struct Args<'s> {
    /// `COMMAND` or `COMMAND/id`, for messages.
    pub label: String,
    pub items: Vec<(&'static Spec, &'s Argument)>,
    /// Whether every argument resolved (when not, "missing argument" errors would only repeat
    /// the error already given).
    pub resolved: bool,
}

/// Resolves every argument of `st` against `table`; problems go to `sink`.
pub(super) fn resolve<'s>(
    st: &'s Statement,
    name: &str,
    table: &'static [Spec],
    sink: &mut Sink,
) -> Args<'s> {
    let label = match st.id {
        Some(id) => format!("{name}/{id}"),
        None => name.to_string(),
    };
    let mut items: Vec<(&'static Spec, &'s Argument)> = Vec::new();
    let before = sink.errors();
    for arg in &st.args {
        let spec = match keywords::lookup(&arg.key, table, |s| s.spelling, |s| s.canonical) {
            Lookup::Found(s) => s,
            Lookup::Ambiguous(names) => {
                let msg = format!(
                    "ambiguous argument '{}' of {label}: could be {}",
                    arg.key,
                    names.join(", ")
                );
                sink.error(arg.span, msg);
                continue;
            }
            Lookup::NotFound => {
                let mut known: Vec<&str> = table.iter().map(|s| s.canonical).collect();
                known.dedup();
                let msg = format!("unknown argument '{}' of {label}", arg.key);
                let d = Diagnostic::error(sink.file.clone(), Some(arg.span), msg)
                    .with_hint(format!("{name} takes {}", known.join(", ")));
                sink.list.push(d);
                continue;
            }
        };
        if items.iter().any(|(s, _)| s.canonical == spec.canonical) {
            let msg = format!(
                "'{}' given more than once in {label}; the first one is used",
                spec.canonical
            );
            sink.warning(arg.span, msg);
            continue;
        }
        match (spec.kind, arg.values.is_empty()) {
            (Kind::Flag, false) => {
                sink.error(
                    arg.span,
                    format!("'{}' of {label} takes no value", spec.canonical),
                );
                continue;
            }
            (Kind::Flag, true) | (_, false) => {}
            (_, true) => {
                let msg = format!("'{0}' of {label} needs a value ('{0} = …')", spec.canonical);
                sink.error(arg.span, msg);
                continue;
            }
        }
        items.push((spec, arg));
    }
    let resolved = sink.errors() == before;
    Args {
        label,
        items,
        resolved,
    }
}

/// The text of a value as written (a number as its value).
pub(super) fn value_text(v: &Value) -> String {
    match v {
        Value::Expr(e) => e.text.trim().to_string(),
        Value::Str { text, .. } | Value::Word { text, .. } => text.clone(),
        Value::Number { value, .. } => value.to_string(),
    }
}

impl<'s> Args<'s> {
    fn find(&self, key: &str) -> Option<&'s Argument> {
        self.items
            .iter()
            .find(|(s, _)| s.canonical == key)
            .map(|(_, a)| *a)
    }

    /// Whether `key` was given.
    pub fn has(&self, key: &str) -> bool {
        self.find(key).is_some()
    }

    /// Whether none of `keys` is given although every argument resolved: the command lacks one.
    pub fn lacks(&self, keys: &[&str]) -> bool {
        self.resolved && keys.iter().all(|k| !self.has(k))
    }

    /// Span of the argument `key` (the command's first argument otherwise).
    pub fn span_of(&self, key: &str) -> Option<Span> {
        self.find(key).map(|a| a.span)
    }

    /// The keys given among `keys`, in the order written; an error at the second one when
    /// several are given (`what` names the choice, e.g. "analysis").
    pub fn one_of(
        &self,
        keys: &[&'static str],
        what: &str,
        sink: &mut Sink,
    ) -> Option<&'static str> {
        let given: Vec<(&'static Spec, &Argument)> = self
            .items
            .iter()
            .filter(|(s, _)| keys.contains(&s.canonical))
            .copied()
            .collect();
        match given.as_slice() {
            [] => None,
            [(s, _)] => Some(s.canonical),
            [(first, _), (second, a), ..] => {
                let msg = format!(
                    "{} names more than one {what} ('{}' and '{}')",
                    self.label, first.canonical, second.canonical
                );
                sink.error(a.span, msg);
                None
            }
        }
    }

    /// One real number (`D` allowed only for [`Kind::Angle`]).
    pub fn real(&self, key: &str, sink: &mut Sink) -> Option<f64> {
        let (spec, arg) = self.items.iter().find(|(s, _)| s.canonical == key)?;
        match arg.values.as_slice() {
            [Value::Number {
                value,
                degrees,
                span,
            }] => {
                if *degrees && spec.kind != Kind::Angle {
                    let msg = format!(
                        "'{key}' of {} is not an angle: the 'D' (degrees) suffix is not allowed",
                        self.label
                    );
                    sink.error(*span, msg);
                    None
                } else if !value.is_finite() {
                    sink.error(*span, format!("'{key}' of {} is not finite", self.label));
                    None
                } else {
                    Some(*value)
                }
            }
            _ => {
                sink.error(
                    arg.span,
                    format!("'{key}' of {} needs one number", self.label),
                );
                None
            }
        }
    }

    /// A non-negative integer that fits `u32`.
    pub fn count(&self, key: &str, sink: &mut Sink) -> Option<u32> {
        let arg = self.find(key)?;
        match arg.values.as_slice() {
            [Value::Number {
                value,
                degrees: false,
                ..
            }] if value.fract() == 0.0 && *value >= 0.0 && *value <= f64::from(u32::MAX) => {
                Some(*value as u32)
            }
            _ => {
                let msg = format!("'{key}' of {} needs one non-negative integer", self.label);
                sink.error(arg.span, msg);
                None
            }
        }
    }

    /// Positive integers (ids); `counts` lists the allowed numbers of values.
    pub fn ids(&self, key: &str, counts: &[usize], sink: &mut Sink) -> Option<Vec<u64>> {
        let arg = self.find(key)?;
        let mut out = Vec::with_capacity(arg.values.len());
        for v in &arg.values {
            match v {
                Value::Number {
                    value,
                    degrees: false,
                    ..
                } if value.fract() == 0.0
                    && *value >= 1.0
                    && *value <= 9.007_199_254_740_992e15 =>
                {
                    out.push(*value as u64)
                }
                other => {
                    let msg = format!(
                        "'{key}' of {} needs positive integers, found '{}'",
                        self.label,
                        value_text(other)
                    );
                    sink.error(other.span(), msg);
                    return None;
                }
            }
        }
        if !counts.is_empty() && !counts.contains(&out.len()) {
            let expected: Vec<String> = counts.iter().map(usize::to_string).collect();
            let msg = format!(
                "'{key}' of {} needs {} value(s), found {}",
                self.label,
                expected.join(" or "),
                out.len()
            );
            sink.error(arg.span, msg);
            return None;
        }
        Some(out)
    }

    /// One id.
    pub fn id(&self, key: &str, sink: &mut Sink) -> Option<u64> {
        self.ids(key, &[1], sink).and_then(|v| v.first().copied())
    }

    /// `key = NAME` with NAME one of `names` (unambiguous prefix).
    pub fn choice(
        &self,
        key: &str,
        names: &[&'static str],
        sink: &mut Sink,
    ) -> Option<&'static str> {
        let arg = self.find(key)?;
        let word = match arg.values.as_slice() {
            [v @ (Value::Word { .. } | Value::Str { .. } | Value::Expr(_))] => value_text(v),
            _ => String::new(),
        };
        match keywords::lookup_name(&word, names) {
            Lookup::Found(n) => Some(n),
            Lookup::Ambiguous(c) => {
                let msg = format!(
                    "ambiguous value '{word}' of '{key}' in {}: could be {}",
                    self.label,
                    c.join(", ")
                );
                sink.error(arg.span, msg);
                None
            }
            Lookup::NotFound => {
                let msg = format!(
                    "'{key}' of {} must be one of {}",
                    self.label,
                    names.join(", ")
                );
                sink.error(arg.span, msg);
                None
            }
        }
    }

    /// `key = ON | OFF`.
    pub fn on_off(&self, key: &str, sink: &mut Sink) -> Option<bool> {
        self.choice(key, &["ON", "OFF"], sink).map(|w| w == "ON")
    }

    /// Free text: the values as written, joined with `, `.
    pub fn text(&self, key: &str, sink: &mut Sink) -> Option<String> {
        let arg = self.find(key)?;
        let text: Vec<String> = arg.values.iter().map(value_text).collect();
        let text = text.join(", ");
        if text.is_empty() {
            sink.error(arg.span, format!("'{key}' of {} needs a value", self.label));
            return None;
        }
        Some(text)
    }

    /// `key = T:F:…` (also `TRUE`/`FALSE`); true = re-evaluate the Jacobian.
    pub fn pattern(&self, key: &str, sink: &mut Sink) -> Option<Vec<bool>> {
        let arg = self.find(key)?;
        let mut out = Vec::new();
        for v in &arg.values {
            for item in value_text(v).split(':') {
                match item.trim().to_ascii_uppercase().as_str() {
                    "T" | "TRUE" => out.push(true),
                    "F" | "FALSE" => out.push(false),
                    _ => {
                        let msg = format!(
                            "'{key}' of {} is a list of T and F separated by ':', found '{}'",
                            self.label,
                            item.trim()
                        );
                        sink.error(v.span(), msg);
                        return None;
                    }
                }
            }
        }
        Some(out)
    }
}
