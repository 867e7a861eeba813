//! Reading argument values: numbers, words, strings, lists and expressions.
//!
//! Contract (ADM-REFERENCE §1.2–1.4):
//! - Numbers are Fortran-style reals with an optional `D` suffix meaning degrees; the value is
//!   then stored in radians ([`parse_number`]).
//! - A list is `v1, v2, …` (a comma continues it only when a number or string follows) or
//!   `a:b:c`; a trailing comma plus a continuation comma count as one separator.
//! - An expression is collected up to an unnested `\`, a same-line comma at depth 0, a
//!   continuation line that starts another argument, or the end of the statement; continuation
//!   commas inside it are dropped and every character keeps its source position.

use super::StatementParser;
use crate::diagnostic::{Diagnostic, Span};
use crate::keywords::{self, ArgKind, Lookup};
use crate::lexer::Mark;
use crate::statement::{ExprText, Value};

/// The elements of `buffer` moved into a new allocation of exactly their number; `buffer` keeps
/// its capacity for the next statement. The statements of a dataset are kept whole (a large
/// model has hundreds of thousands of argument and value lists): no spare capacity in them,
/// and no growth while reading them.
pub(super) fn move_exact<T>(buffer: &mut Vec<T>) -> Vec<T> {
    let mut out = Vec::with_capacity(buffer.len());
    out.append(buffer);
    out
}

/// How [`StatementParser::expr`] collects text.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum ExprMode {
    /// A function expression: unbalanced brackets are errors, `\` ends it.
    Expression,
    /// Free text: `\` is text, brackets need not balance.
    Text,
    /// A value that is not a plain list: like an expression, but brackets need not balance.
    Fallback,
    /// One item of a text list: also ends at a continuation comma at depth 0.
    ListItem,
}

impl ExprMode {
    fn strict(self) -> bool {
        self == ExprMode::Expression
    }

    fn stops_at_backslash(self) -> bool {
        matches!(self, ExprMode::Expression | ExprMode::Fallback)
    }
}

/// Why a value list could not be read as a plain list.
pub(super) enum ListError {
    /// Not a plain list: read the value as expression-like text instead.
    NotPlain,
    Fatal(Diagnostic),
}

/// Characters that end a number or word token.
pub(super) fn is_delimiter(c: char) -> bool {
    c.is_whitespace() || matches!(c, ',' | ':' | ';' | '\\' | '"' | '=' | '!')
}

/// `1.0D0`, `2.5d-3`: a Fortran double-precision exponent, which Adams does not accept.
fn fortran_double_exponent(token: &str) -> bool {
    token
        .find(['d', 'D'])
        .and_then(|k| token.get(k + 1..))
        .is_some_and(|rest| {
            let digits = rest.trim_start_matches(['+', '-']);
            !digits.is_empty() && digits.chars().all(|c| c.is_ascii_digit())
        })
}

fn is_word_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || matches!(c, '_' | '.' | '$')
}

/// Parses a Fortran-style real with an optional `D` (degrees) suffix: `(value, degrees)`, the
/// value in radians when `degrees`. `None` for anything else (`1.0D0`, `inf`, `2x`).
pub(crate) fn parse_number(token: &str) -> Option<(f64, bool)> {
    let (body, degrees) = match token.strip_suffix(['d', 'D']) {
        Some(b) => (b, true),
        None => (token, false),
    };
    let bytes = body.as_bytes();
    let mut k = usize::from(matches!(bytes.first(), Some(b'+' | b'-')));
    let int_digits = bytes
        .iter()
        .skip(k)
        .take_while(|b| b.is_ascii_digit())
        .count();
    k += int_digits;
    let mut frac_digits = 0;
    if bytes.get(k) == Some(&b'.') {
        k += 1;
        frac_digits = bytes
            .iter()
            .skip(k)
            .take_while(|b| b.is_ascii_digit())
            .count();
        k += frac_digits;
    }
    if int_digits + frac_digits == 0 {
        return None;
    }
    if matches!(bytes.get(k), Some(b'e' | b'E')) {
        k += 1;
        k += usize::from(matches!(bytes.get(k), Some(b'+' | b'-')));
        let exp_digits = bytes
            .iter()
            .skip(k)
            .take_while(|b| b.is_ascii_digit())
            .count();
        if exp_digits == 0 {
            return None;
        }
        k += exp_digits;
    }
    if k != bytes.len() {
        return None;
    }
    let value: f64 = match exact_decimal(bytes) {
        Some(v) => v,
        None => body.parse().ok().filter(|v: &f64| v.is_finite())?,
    };
    Some(if degrees {
        (value.to_radians(), true)
    } else {
        (value, false)
    })
}

/// The value of `[+-]digits[.digits]` with at most 15 digits and no exponent, computed
/// directly: the digits form an integer below 2^53 and 10^f (f ≤ 15) is exact, so one
/// division gives the correctly rounded value, the same as `str::parse` (Clinger's fast path).
/// `None` for anything else.
fn exact_decimal(bytes: &[u8]) -> Option<f64> {
    const POWERS: [f64; 16] = [
        1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
    ];
    let (negative, digits) = match bytes.split_first() {
        Some((b'-', rest)) => (true, rest),
        Some((b'+', rest)) => (false, rest),
        _ => (false, bytes),
    };
    let mut mantissa: u64 = 0;
    let mut count = 0usize;
    let mut fraction: Option<usize> = None;
    for &b in digits {
        match b {
            b'0'..=b'9' => {
                mantissa = mantissa * 10 + u64::from(b - b'0');
                count += 1;
                if let Some(f) = fraction.as_mut() {
                    *f += 1;
                }
            }
            b'.' if fraction.is_none() => fraction = Some(0),
            _ => return None,
        }
        if count > 15 {
            return None;
        }
    }
    if count == 0 {
        return None;
    }
    let value = mantissa as f64 / POWERS[fraction.unwrap_or(0)];
    Some(if negative { -value } else { value })
}

impl StatementParser<'_> {
    /// `KEY =` at the end of a line with the value on the continuation line: skips that line's
    /// continuation comma (unless the line starts another argument).
    pub(super) fn value_on_next_line(&mut self) {
        self.skip_ws();
        let at_comma = self
            .peek()
            .is_some_and(|c| c.mark == Mark::ContinuationComma);
        if at_comma && !self.continuation_starts_argument(self.pos + 1, &[]) {
            self.pos += 1;
        }
    }

    /// Comma-separated text items, continuing over commas (same-line or continuation) until
    /// a comma followed by another argument.
    pub(super) fn text_list(&mut self) -> Result<Vec<Value>, Diagnostic> {
        let mut values = Vec::new();
        loop {
            let (item, _) = self.expr(ExprMode::ListItem)?;
            if !item.text.is_empty() {
                values.push(Value::Expr(item));
            }
            self.skip_ws();
            let more = self.peek_char() == Some(',')
                && !self.continuation_starts_argument(self.pos + 1, &[]);
            if !more {
                return Ok(values);
            }
            self.pos += 1;
        }
    }

    /// A value that is a plain list when it is one (if `try_list`), else text read in `mode`.
    pub(super) fn lenient_value(
        &mut self,
        try_list: bool,
        mode: ExprMode,
    ) -> Result<(Vec<Value>, bool), Diagnostic> {
        let start = self.pos;
        if try_list {
            match self.list(ArgKind::Any, "") {
                Ok(v) => return Ok((v, false)),
                Err(ListError::Fatal(d)) => return Err(d),
                Err(ListError::NotPlain) => self.pos = start,
            }
        }
        let (expr, sep) = self.expr(mode)?;
        Ok((vec![Value::Expr(expr)], sep))
    }

    /// Reads `v1, v2, …` or `a:b:c`. Strict kinds (Numbers, Words) report bad items as errors;
    /// `Any` reports [`ListError::NotPlain`] so that the caller reads text instead.
    pub(super) fn list(&mut self, kind: ArgKind, key: &str) -> Result<Vec<Value>, ListError> {
        let strict = kind != ArgKind::Any;
        let fail = |p: &Self, span: Span, msg: String| {
            if strict {
                ListError::Fatal(p.error(span, msg))
            } else {
                ListError::NotPlain
            }
        };
        // Read into the lent buffer; kept in an allocation of exactly their number.
        let mut values = std::mem::take(&mut self.scratch.values);
        values.clear();
        let mut after_colon = false;
        loop {
            self.skip_ws();
            let here = self.span_here();
            match self.item(kind)? {
                Some(v) => values.push(v),
                None if values.is_empty()
                    && !after_colon
                    && !strict
                    && matches!(self.peek_char(), None | Some(',') | Some('\\')) =>
                {
                    return Ok(values)
                }
                None => {
                    let msg = match self.peek_char() {
                        None | Some(',') => format!("missing value after '{key} ='"),
                        Some(c) => format!("expected a value of '{key}', found '{c}'"),
                    };
                    return Err(fail(self, here, msg));
                }
            }
            self.skip_ws();
            let Some(c) = self.peek() else { break };
            match c.ch {
                ':' if c.mark == Mark::Plain => {
                    self.pos += 1;
                    after_colon = true;
                }
                ',' => match self.list_continues_after_comma() {
                    Some(next) => {
                        self.pos = next;
                        after_colon = false;
                    }
                    None => break,
                },
                '\\' => break,
                other => {
                    let msg =
                        format!("expected ',' or ':' before '{other}' in the value of '{key}'");
                    return Err(fail(self, c.span, msg));
                }
            }
        }
        let out = move_exact(&mut values);
        self.scratch.values = values;
        Ok(out)
    }

    /// At a comma in a list: when the next item is another value (a number or a string) rather
    /// than the next argument, the index of that item. A trailing comma followed by a
    /// continuation comma (`1,` / `, 2`) is one separator.
    fn list_continues_after_comma(&self) -> Option<usize> {
        let first = self.chars.get(self.pos)?;
        let mut k = self.skip_ws_from(self.pos + 1);
        let doubled = self
            .chars
            .get(k)
            .is_some_and(|c| c.mark == Mark::ContinuationComma);
        if first.mark == Mark::Plain && doubled {
            k = self.skip_ws_from(k + 1);
        }
        let c = self.chars.get(k)?;
        let value = c.mark == Mark::Plain
            && (c.ch.is_ascii_digit() || matches!(c.ch, '+' | '-' | '.' | '"'));
        value.then_some(k)
    }

    /// One list item: a string, a number or a word; `None` when nothing item-like is here.
    fn item(&mut self, kind: ArgKind) -> Result<Option<Value>, ListError> {
        let Some(c) = self.peek().filter(|c| c.mark == Mark::Plain) else {
            return Ok(None);
        };
        let span = c.span;
        if c.ch == '"' {
            self.pos += 1;
            let mut text = String::new();
            while let Some(d) = self.peek().filter(|d| d.mark == Mark::Plain) {
                self.pos += 1;
                if d.ch == '"' {
                    break;
                }
                text.push(d.ch);
            }
            return Ok(Some(Value::Str { text, span }));
        }
        let numeric = c.ch.is_ascii_digit() || matches!(c.ch, '+' | '-' | '.');
        let wordy = c.ch.is_ascii_alphabetic() || c.ch == '_';
        if !numeric && !wordy {
            return Ok(None);
        }
        let token = self.token();
        let value = self.token_value(&token, kind, span);
        self.recycle(token);
        value.map(Some)
    }

    /// The value of a number or word `token` read at `span` (see [`Self::item`]).
    fn token_value(&mut self, token: &str, kind: ArgKind, span: Span) -> Result<Value, ListError> {
        let strict = kind != ArgKind::Any;
        let numeric =
            token.starts_with(|c: char| c.is_ascii_digit() || matches!(c, '+' | '-' | '.'));
        let word_like = !token.is_empty() && token.chars().all(is_word_char);
        if numeric {
            if let Some((value, degrees)) = parse_number(token) {
                let degrees = degrees || self.detached_degree_suffix(span);
                let value = if degrees && !token.ends_with(['d', 'D']) {
                    value.to_radians()
                } else {
                    value
                };
                return Ok(Value::Number {
                    value,
                    degrees,
                    span,
                });
            }
            if strict || !word_like {
                let msg = format!("invalid number '{token}'");
                return Err(if strict {
                    let mut d = self.error(span, msg);
                    if fortran_double_exponent(token) {
                        d = d.with_hint(
                            "'D' is the degree suffix in Adams; write exponents with 'E' (1.0E0)",
                        );
                    }
                    ListError::Fatal(d)
                } else {
                    ListError::NotPlain
                });
            }
        } else if !word_like {
            return Err(if strict {
                ListError::Fatal(self.error(span, format!("invalid value '{token}'")))
            } else {
                ListError::NotPlain
            });
        } else if kind == ArgKind::Numbers {
            let msg = format!("expected a number, found '{token}'");
            return Err(ListError::Fatal(self.error(span, msg)));
        }
        Ok(Value::Word {
            text: token.to_ascii_uppercase(),
            span,
        })
    }

    /// `20 D`: a degree suffix separated from its number by blanks (seen in hand-written files).
    /// Consumes it and warns.
    fn detached_degree_suffix(&mut self, number: Span) -> bool {
        let mut k = self.pos;
        while self
            .chars
            .get(k)
            .is_some_and(|c| c.mark == Mark::Plain && (c.ch == ' ' || c.ch == '\t'))
        {
            k += 1;
        }
        let is_d = self
            .chars
            .get(k)
            .is_some_and(|c| c.mark == Mark::Plain && matches!(c.ch, 'd' | 'D'));
        let then_delimiter = self
            .chars
            .get(k + 1)
            .filter(|c| c.mark == Mark::Plain && !is_delimiter(c.ch))
            .is_none();
        if k == self.pos || !is_d || !then_delimiter {
            return false;
        }
        self.pos = k + 1;
        self.warn(
            number,
            "degree suffix 'D' separated from its number by a blank",
        );
        true
    }

    /// Collects an expression (or free text) from the current position.
    ///
    /// Characters are taken, continuation lines joined with their leading comma dropped, until
    /// an unnested `\` (consumed; not in text modes), a same-line comma at nesting depth 0, a
    /// continuation comma at depth 0 that starts another argument
    /// ([`Self::continuation_starts_argument`]; any one for a list item), or the end of the
    /// statement. Commas inside `()`/`[]` belong to the expression. In
    /// [`ExprMode::Expression`], unbalanced brackets are errors.
    /// Returns the text and whether a `\` was consumed.
    pub(super) fn expr(&mut self, mode: ExprMode) -> Result<(ExprText, bool), Diagnostic> {
        let strict = mode.strict();
        let mut out: Vec<(char, Span)> = Vec::new();
        let mut open: Vec<(char, Span)> = Vec::new();
        let mut in_string = false;
        let mut separated = false;
        while let Some(c) = self.peek() {
            match c.mark {
                Mark::LineBreak => {
                    self.pos += 1;
                    continue;
                }
                Mark::ContinuationComma => {
                    let ends = mode == ExprMode::ListItem
                        || self.continuation_starts_argument(self.pos + 1, &out);
                    if open.is_empty() && !in_string && ends {
                        break;
                    }
                    self.pos += 1;
                    continue;
                }
                Mark::Plain => {}
            }
            if in_string {
                in_string = c.ch != '"';
            } else {
                match c.ch {
                    '"' => in_string = true,
                    '(' | '[' => open.push((c.ch, c.span)),
                    ')' | ']' => match open.pop() {
                        Some((o, _)) if (o == '(') == (c.ch == ')') => {}
                        Some((o, at)) if strict => {
                            let msg = format!(
                                "'{}' does not match '{o}' opened at {}:{}",
                                c.ch, at.line, at.col
                            );
                            return Err(self.error(c.span, msg));
                        }
                        None if strict => {
                            let msg = format!("unbalanced '{}' in expression", c.ch);
                            return Err(self.error(c.span, msg));
                        }
                        _ => {}
                    },
                    ',' if open.is_empty() => break,
                    '\\' if mode.stops_at_backslash() && open.is_empty() => {
                        self.pos += 1;
                        separated = true;
                        break;
                    }
                    _ => {}
                }
            }
            out.push((c.ch, c.span));
            self.pos += 1;
        }
        if strict {
            if let Some((o, at)) = open.last() {
                return Err(self.error(*at, format!("unclosed '{o}' in expression")));
            }
        }
        Ok((build_expr(&out), separated))
    }

    /// At a continuation comma at depth 0 inside an expression (`k` = index after the comma):
    /// whether the continuation line starts another argument: `KEYWORD =`, or a conditional
    /// keyword of this statement standing alone — unless the expression so far ends with an
    /// operator and so must go on.
    fn continuation_starts_argument(&self, k: usize, so_far: &[(char, Span)]) -> bool {
        let k = self.skip_ws_from(k);
        let Some((word, end)) = self.ident_at(k) else {
            return false;
        };
        let after = self.skip_ws_from(end);
        if self.char_at(after) == Some('=') && self.char_at(after + 1) != Some('=') {
            return true;
        }
        let last = so_far
            .iter()
            .rev()
            .map(|(c, _)| *c)
            .find(|c| !c.is_whitespace());
        if last.is_some_and(|c| "+-*/(,:^%[=<>".contains(c)) {
            return false;
        }
        let is_flag = self.def.is_some_and(|d| {
            matches!(keywords::lookup_arg(&word, d),
                Lookup::Found(a) if matches!(a.kind, ArgKind::Flag | ArgKind::FlagOrExpr))
        });
        is_flag && matches!(self.char_at(after), None | Some(',') | Some('\\'))
    }
}

/// Builds an [`ExprText`] from collected characters, trimming blanks at both ends.
fn build_expr(chars: &[(char, Span)]) -> ExprText {
    let start = chars
        .iter()
        .position(|(c, _)| !c.is_whitespace())
        .unwrap_or(chars.len());
    let end = chars
        .iter()
        .rposition(|(c, _)| !c.is_whitespace())
        .map_or(start, |k| k + 1);
    let mut text = String::new();
    let mut origins: Vec<(usize, Span)> = Vec::new();
    let mut previous: Option<Span> = None;
    for (c, span) in chars.get(start..end).unwrap_or(&[]) {
        let contiguous =
            previous.is_some_and(|p| p.line == span.line && p.col.saturating_add(1) == span.col);
        if !contiguous {
            origins.push((text.len(), *span));
        }
        text.push(*c);
        previous = Some(*span);
    }
    ExprText { text, origins }
}

#[cfg(test)]
mod exact_decimal_tests {
    use super::{exact_decimal, parse_number};

    /// The fast path gives the bits `str::parse` gives, and declines what it cannot do exactly.
    #[test]
    fn agrees_with_the_standard_parser() {
        for text in [
            "0",
            "-0",
            "+7",
            "1.5",
            "-0.25",
            "123456789012345",
            "0.1",
            "0.3",
            "2.675",
            ".5",
            "5.",
            "-12345.6789",
            "999999999999999",
            "0.00000000000001",
            "3.14159265358979",
        ] {
            let fast = exact_decimal(text.as_bytes()).expect(text);
            let std: f64 = text.parse().expect(text);
            assert_eq!(fast.to_bits(), std.to_bits(), "{text}");
            assert_eq!(
                parse_number(text).map(|(v, _)| v.to_bits()),
                Some(std.to_bits())
            );
        }
        for text in [
            "1234567890123456",
            "0.000000000000001",
            "1e3",
            "1.2.3",
            "",
            "-",
            ".",
        ] {
            assert_eq!(exact_decimal(text.as_bytes()), None, "{text}");
        }
    }
}
