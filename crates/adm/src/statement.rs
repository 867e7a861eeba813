//! The generic form of a statement: keyword, id, arguments, and where each came from.
//!
//! Every statement of a dataset is kept in this form (also the ones linkage types), so that
//! later work can type more statements and the writer can reproduce the file.

use crate::diagnostic::Span;

/// `JOINT_7` (`separator` `_`) or `JOINT/7` (`/`): a statement keyword and an id, written
/// without the formatting machinery (a large model names hundreds of thousands of elements).
pub fn keyword_id(keyword: &str, separator: char, id: u64) -> String {
    let mut digits = [0u8; 20];
    let mut k = digits.len();
    let mut n = id;
    loop {
        k -= 1;
        digits[k] = b'0' + (n % 10) as u8;
        n /= 10;
        if n == 0 {
            break;
        }
    }
    let mut s = String::with_capacity(keyword.len() + 1 + digits.len() - k);
    s.push_str(keyword);
    s.push(separator);
    // ASCII digits only.
    s.extend(digits[k..].iter().map(|&d| char::from(d)));
    s
}

#[cfg(test)]
mod keyword_id_tests {
    #[test]
    fn writes_the_id_in_decimal() {
        assert_eq!(super::keyword_id("JOINT", '_', 7), "JOINT_7");
        assert_eq!(super::keyword_id("PART", '/', 0), "PART/0");
        assert_eq!(
            super::keyword_id("M", '_', u64::MAX),
            format!("M_{}", u64::MAX)
        );
        assert_eq!(
            super::keyword_id("MARKER", '/', 1_000_200),
            "MARKER/1000200"
        );
    }
}

/// One logical statement (all its continuation lines joined).
#[derive(Clone, Debug, PartialEq)]
pub struct Statement {
    /// Canonical upper-case statement name (`"PART"`, `"JOINT"`) when the keyword matched a
    /// statement of the language (by unambiguous prefix); otherwise the keyword as written,
    /// upper-cased.
    pub keyword: String,
    /// Whether `keyword` is a statement of the Adams language (ADM-REFERENCE §1.5).
    pub known: bool,
    /// The id after the slash (`PART/02` gives 2); `None` for `UNITS/`, `ACCGRAV/`, ….
    pub id: Option<u64>,
    /// Arguments in the order written.
    pub args: Vec<Argument>,
    /// Position of the statement keyword.
    pub span: Span,
    /// First and last physical line (1-based, inclusive) of the statement, continuation lines
    /// included, comments before it excluded.
    pub lines: (u32, u32),
    /// Display name from the `adams_view_name='…'` comment just before the statement.
    pub view_name: Option<String>,
}

impl Statement {
    /// The first argument whose canonical key is `key` (keys are canonicalised by the typing
    /// layer; see [`Argument::key`]).
    pub fn arg(&self, key: &str) -> Option<&Argument> {
        self.args.iter().find(|a| a.key == key)
    }
}

/// One argument: `KEY`, `KEY = v1, v2, …`, `KEY = a:b:c`, or `KEY = expression`.
#[derive(Clone, Debug, PartialEq)]
pub struct Argument {
    /// The keyword, upper-cased. For arguments of typed statements it is replaced by the full
    /// canonical keyword once the prefix is resolved (`FUN` → `FUNCTION`).
    pub key: String,
    /// The values (empty for a conditional keyword such as `GROUND`).
    pub values: Vec<Value>,
    /// Position of the keyword.
    pub span: Span,
}

/// A value of an argument.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// A number. `degrees` is true when written with the `D` suffix (`90D`); `value` is then
    /// already converted to radians.
    Number {
        value: f64,
        degrees: bool,
        span: Span,
    },
    /// A bare word (`NEWTON`, `T`, a colon-list item, …), upper-cased.
    Word { text: String, span: Span },
    /// A quoted string, without its quotes.
    Str { text: String, span: Span },
    /// An expression (`FUNCTION=`, `F1=`, `FX=`, …): its text with continuations joined.
    Expr(ExprText),
}

impl Value {
    pub fn span(&self) -> Span {
        match self {
            Value::Number { span, .. } | Value::Word { span, .. } | Value::Str { span, .. } => {
                *span
            }
            Value::Expr(e) => e.span_at(0),
        }
    }
}

/// The text of an expression argument with a map back to the source.
///
/// Continuation lines are joined with their leading comma dropped (ADM-REFERENCE §1.2), so one
/// expression may come from several physical lines; `origins` maps text offsets to positions.
#[derive(Clone, Debug, PartialEq)]
pub struct ExprText {
    pub text: String,
    /// `(byte offset in text, source position of that byte)`, sorted by offset; the first entry
    /// has offset 0. Bytes after an entry's offset map to the same line at increasing columns.
    pub origins: Vec<(usize, Span)>,
}

impl ExprText {
    /// Source position of the byte at `offset` in `text`.
    pub fn span_at(&self, offset: usize) -> Span {
        let k = self.origins.partition_point(|(o, _)| *o <= offset);
        match k.checked_sub(1).and_then(|i| self.origins.get(i)) {
            Some((o, s)) => {
                let chars = self
                    .text
                    .get(*o..offset.min(self.text.len()))
                    .map_or(0, |t| t.chars().count());
                Span::new(s.line, s.col + chars as u32)
            }
            None => Span::default(),
        }
    }
}
