//! Parser: logical statements (from the lexer) → generic [`Statement`]s.
//!
//! Contract:
//! - A statement is `NAME[/id][, ARG]…` where ARG is `KEY`, `KEY = v1, v2`, `KEY = a:b:c` or
//!   `KEY = expression` (ADM-REFERENCE §1.3–1.4). Names and keys are case-insensitive and may be
//!   abbreviated to an unambiguous prefix ([`crate::keywords`]); known ones are stored under their
//!   canonical name.
//! - Unknown statement names give a warning and the statement is kept with `known = false`
//!   (whatever could be read of its arguments; nothing in it is an error).
//! - An ambiguous name, a bad id, a bad number in a numeric argument, an unbalanced expression,
//!   … are errors at their line:column; the statement is then dropped (one error per statement).
//! - Reading stops at the stop statement (`END` in datasets, `STOP` in command files).
//! - Numbers are Fortran-style reals with an optional `D` suffix (degrees, converted to radians).
//! - Expressions are collected as described in ADM-REFERENCE §1.2 (see `values.rs`).

use crate::diagnostic::{Diagnostic, Span};
use crate::keywords::{self, ArgKind, IdRule, Lookup, StatementDef};
use crate::lexer::{LexItem, Lexer, Mark, RawStatement, SrcChar};
use crate::statement::{Argument, Statement, Value};
use std::sync::Arc;
use values::{is_delimiter, ExprMode, ListError};

/// Which language a text is written in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Language {
    /// A dataset (`.adm`): statements until `END`.
    Dataset,
    /// A command file (`.acf`): commands until `STOP`.
    Commands,
}

impl Language {
    fn table(self) -> &'static [StatementDef] {
        match self {
            Language::Dataset => keywords::DATASET_STATEMENTS,
            Language::Commands => keywords::COMMANDS,
        }
    }

    fn stop_word(self) -> &'static str {
        match self {
            Language::Dataset => "END",
            Language::Commands => "STOP",
        }
    }
}

/// The statements of a text, and what was found wrong with it.
#[derive(Clone, Debug)]
pub(crate) struct Parsed {
    /// Every statement read before the stop statement, except those with errors.
    pub statements: Vec<Statement>,
    /// Line of the stop statement (`END` / `STOP`), if reached.
    pub stop_line: Option<u32>,
    /// Errors and warnings, in the order found.
    pub diagnostics: Vec<Diagnostic>,
}

/// Parses the statements of `text` from 0-based line index `first_line` on. An argument that
/// a statement with a complete table does not take is an error (Adams stops on it), or with
/// `lenient_arguments` a warning and the argument kept as written.
pub(crate) fn parse(
    file: Arc<str>,
    text: &str,
    first_line: usize,
    lang: Language,
    lenient_arguments: bool,
) -> Parsed {
    let mut lexer = Lexer::new(file.clone(), text, first_line, lang.stop_word());
    let mut parsed = Parsed {
        statements: Vec::new(),
        stop_line: None,
        diagnostics: Vec::new(),
    };
    let mut scratch = Scratch::default();
    while let Some(item) = lexer.next_item() {
        match item {
            LexItem::Error(d) => parsed.diagnostics.push(d),
            LexItem::Statement(raw) => {
                let (statement, diagnostics) =
                    parse_statement(&file, &raw, lang, lenient_arguments, &mut scratch);
                lexer.recycle(raw);
                parsed.diagnostics.extend(diagnostics);
                if let Some(st) = statement {
                    if st.known && st.keyword == lang.stop_word() {
                        parsed.stop_line = Some(st.span.line);
                        break;
                    }
                    parsed.statements.push(st);
                }
            }
        }
    }
    parsed
}

/// Parses one logical statement: the statement (unless it has errors) and its diagnostics.
fn parse_statement(
    file: &Arc<str>,
    raw: &RawStatement,
    lang: Language,
    lenient_arguments: bool,
    scratch: &mut Scratch,
) -> (Option<Statement>, Vec<Diagnostic>) {
    scratch.args.clear();
    let mut p = StatementParser {
        file,
        chars: &raw.chars,
        pos: 0,
        lang,
        lenient_arguments,
        def: None,
        warnings: Vec::new(),
        scratch,
    };
    p.skip_ws();
    let span = p.span_here();
    let Some(word) = p.ident() else {
        let found = p.describe_here();
        let e = p.error(span, format!("expected a statement name, found {found}"));
        return (None, vec![e]);
    };
    let (keyword, known) = match keywords::lookup_statement(&word, lang.table()) {
        Lookup::Found(def) => {
            p.def = Some(def);
            (def.name.to_string(), true)
        }
        Lookup::Ambiguous(names) => {
            let msg = format!(
                "ambiguous statement name '{word}': could be {}",
                names.join(", ")
            );
            return (None, vec![p.error(span, msg)]);
        }
        Lookup::NotFound => (word.to_ascii_uppercase(), false),
    };
    p.recycle(word);
    let mut st = Statement {
        keyword,
        known,
        id: None,
        args: Vec::new(),
        span,
        lines: raw.lines,
        view_name: raw.view_name.clone(),
    };
    if known && st.keyword == lang.stop_word() {
        // `END` (or `STOP`) ends the text whatever follows it on its line.
        return (Some(st), Vec::new());
    }
    let body = p.body(&mut st);
    // Built in the lent buffer, kept in an allocation of exactly their number.
    st.args = values::move_exact(&mut p.scratch.args);
    if !known {
        let msg = format!("unknown statement '{}' ignored", st.keyword);
        return (
            Some(st),
            vec![Diagnostic::warning(file.clone(), Some(span), msg)],
        );
    }
    let mut diagnostics = raw.errors.clone();
    if let Err(e) = body {
        diagnostics.push(e);
    }
    diagnostics.append(&mut p.warnings);
    let ok = !diagnostics.iter().any(Diagnostic::is_error);
    (ok.then_some(st), diagnostics)
}

/// Buffers the statements of a text share, so that reading one allocates only what it keeps.
#[derive(Default)]
struct Scratch {
    /// Lent out by [`StatementParser::token`] and [`StatementParser::ident`], given back with
    /// [`StatementParser::recycle`].
    text: String,
    /// The arguments of the statement being read.
    args: Vec<Argument>,
    /// The values of the list being read.
    values: Vec<Value>,
}

/// Cursor over the characters of one logical statement.
struct StatementParser<'a> {
    file: &'a Arc<str>,
    chars: &'a [SrcChar],
    pos: usize,
    lang: Language,
    /// Unknown arguments of complete tables are warnings, not errors.
    lenient_arguments: bool,
    def: Option<&'static StatementDef>,
    /// Findings that do not stop the argument list (warnings; unknown-argument errors, so
    /// that every misspelling of a statement is reported at once).
    warnings: Vec<Diagnostic>,
    /// Buffers shared with the other statements of the text.
    scratch: &'a mut Scratch,
}

impl StatementParser<'_> {
    // ---- cursor ------------------------------------------------------------------------------

    fn peek(&self) -> Option<SrcChar> {
        self.chars.get(self.pos).copied()
    }

    fn peek_char(&self) -> Option<char> {
        self.peek().map(|c| c.ch)
    }

    fn char_at(&self, k: usize) -> Option<char> {
        self.chars.get(k).map(|c| c.ch)
    }

    /// Position of the current character, or just after the last one at the end.
    fn span_here(&self) -> Span {
        match (self.chars.get(self.pos), self.chars.last()) {
            (Some(c), _) => c.span,
            (None, Some(last)) => Span::new(last.span.line, last.span.col.saturating_add(1)),
            (None, None) => Span::new(1, 1),
        }
    }

    fn describe_here(&self) -> String {
        match self.peek_char() {
            Some(c) => format!("'{c}'"),
            None => "the end of the statement".to_string(),
        }
    }

    /// Skips blanks and line boundaries (a continuation comma is not skipped).
    fn skip_ws(&mut self) {
        while self.peek().is_some_and(|c| {
            c.mark == Mark::LineBreak || (c.mark == Mark::Plain && c.ch.is_whitespace())
        }) {
            self.pos += 1;
        }
    }

    /// Index of the first non-blank character at or after `k`.
    fn skip_ws_from(&self, mut k: usize) -> usize {
        while self.chars.get(k).is_some_and(|c| {
            c.mark == Mark::LineBreak || (c.mark == Mark::Plain && c.ch.is_whitespace())
        }) {
            k += 1;
        }
        k
    }

    /// Reads `[A-Za-z_][A-Za-z0-9_]*` starting at `k`; returns it and the index after it.
    fn ident_at(&self, k: usize) -> Option<(String, usize)> {
        let end = self.ident_end(k)?;
        let word = self.chars.get(k..end)?.iter().map(|c| c.ch).collect();
        Some((word, end))
    }

    /// The end of the identifier that starts at `k` (see [`Self::ident_at`]).
    fn ident_end(&self, k: usize) -> Option<usize> {
        let first = self.chars.get(k).filter(|c| c.mark == Mark::Plain)?;
        if !(first.ch.is_ascii_alphabetic() || first.ch == '_') {
            return None;
        }
        let mut end = k;
        while self
            .chars
            .get(end)
            .is_some_and(|c| c.mark == Mark::Plain && (c.ch.is_ascii_alphanumeric() || c.ch == '_'))
        {
            end += 1;
        }
        Some(end)
    }

    /// The identifier here, in the scratch buffer (give it back with [`Self::recycle`]).
    fn ident(&mut self) -> Option<String> {
        let end = self.ident_end(self.pos)?;
        let mut word = std::mem::take(&mut self.scratch.text);
        word.clear();
        word.extend(self.chars.get(self.pos..end)?.iter().map(|c| c.ch));
        self.pos = end;
        Some(word)
    }

    /// Gives the buffer of [`Self::token`] or [`Self::ident`] back for the next one.
    fn recycle(&mut self, buffer: String) {
        self.scratch.text = buffer;
    }

    /// Reads the maximal run of plain, non-delimiter characters (in the scratch buffer: give it
    /// back with [`Self::recycle`]).
    fn token(&mut self) -> String {
        let mut s = std::mem::take(&mut self.scratch.text);
        s.clear();
        let start = self.pos;
        let rest = self.chars.get(start..).unwrap_or(&[]);
        let len = rest
            .iter()
            .position(|c| c.mark != Mark::Plain || is_delimiter(c.ch))
            .unwrap_or(rest.len());
        s.extend(rest.iter().take(len).map(|c| c.ch));
        self.pos = start + len;
        s
    }

    fn error(&self, span: Span, msg: impl Into<String>) -> Diagnostic {
        Diagnostic::error(self.file.clone(), Some(span), msg)
    }

    fn warn(&mut self, span: Span, msg: impl Into<String>) {
        self.warnings
            .push(Diagnostic::warning(self.file.clone(), Some(span), msg));
    }

    fn complete(&self) -> bool {
        self.def.is_some_and(|d| d.complete)
    }

    // ---- statement ---------------------------------------------------------------------------

    /// Everything after the statement name: slash, id, arguments.
    fn body(&mut self, st: &mut Statement) -> Result<(), Diagnostic> {
        self.skip_ws();
        let slash = self
            .peek()
            .is_some_and(|c| c.ch == '/' && c.mark == Mark::Plain);
        if slash {
            self.pos += 1;
        } else if self.peek().is_none() {
            return Ok(());
        } else if st.known && self.lang == Language::Dataset {
            let found = self.describe_here();
            let msg = format!("expected '/' after '{}', found {found}", st.keyword);
            return Err(self.error(self.span_here(), msg));
        }
        let rule = self.def.map_or(IdRule::Optional, |d| d.id);
        let mut need_separator = false;
        if slash {
            self.skip_ws();
            let digit_follows = self.peek().is_some_and(|c| c.ch.is_ascii_digit());
            if rule == IdRule::Required || (rule == IdRule::Optional && digit_follows) {
                st.id = Some(self.id(&st.keyword)?);
                need_separator = true;
            }
        }
        self.arguments(need_separator)
    }

    /// The id after the slash: a positive integer, leading zeros allowed.
    fn id(&mut self, keyword: &str) -> Result<u64, Diagnostic> {
        self.skip_ws();
        let span = self.span_here();
        let token = self.token();
        if token.is_empty() {
            let found = self.describe_here();
            return Err(self.error(
                span,
                format!("expected the id of {keyword} after '/', found {found}"),
            ));
        }
        if !token.chars().all(|c| c.is_ascii_digit()) {
            return Err(self.error(
                span,
                format!("invalid id '{token}' of {keyword}: expected a positive integer"),
            ));
        }
        let id = match token.parse::<u64>() {
            Ok(0) => Err(self.error(
                span,
                format!("id of {keyword} must be positive, found '{token}'"),
            )),
            Ok(id) => Ok(id),
            Err(_) => Err(self.error(span, format!("id '{token}' of {keyword} is too large"))),
        };
        self.recycle(token);
        id
    }

    /// The arguments, into the lent buffer (`scratch.args`).
    fn arguments(&mut self, mut need_separator: bool) -> Result<(), Diagnostic> {
        loop {
            self.skip_ws();
            let Some(c) = self.peek() else { return Ok(()) };
            if c.ch == ',' || c.ch == '\\' {
                self.pos += 1;
                need_separator = false;
                continue;
            }
            if need_separator {
                return Err(self.error(c.span, format!("expected ',' before '{}'", c.ch)));
            }
            let (argument, separated) = self.argument()?;
            self.scratch.args.push(argument);
            need_separator = !separated;
        }
    }

    /// One argument; also whether it consumed its own separator (an expression's `\`).
    fn argument(&mut self) -> Result<(Argument, bool), Diagnostic> {
        let span = self.span_here();
        let Some(word) = self.ident() else {
            let found = self.describe_here();
            return Err(self.error(span, format!("expected an argument keyword, found {found}")));
        };
        let resolved = self.resolve_arg(&word, span);
        self.recycle(word);
        let (key, kind) = resolved?;
        self.skip_ws();
        let has_value = self
            .peek()
            .is_some_and(|c| c.ch == '=' && c.mark == Mark::Plain);
        let mut arg = Argument {
            key,
            values: Vec::new(),
            span,
        };
        if !has_value {
            let needs_value = matches!(
                kind,
                ArgKind::Numbers | ArgKind::Words | ArgKind::Expr | ArgKind::Text
            );
            if needs_value && self.complete() {
                let msg = format!("'{0}' needs a value ('{0} = …')", arg.key);
                return Err(self.error(span, msg));
            }
            return Ok((arg, false));
        }
        let equals = self.span_here();
        self.pos += 1;
        self.value_on_next_line();
        let mut separated = false;
        match kind {
            ArgKind::Flag if self.complete() => {
                return Err(self.error(equals, format!("'{}' takes no value", arg.key)));
            }
            ArgKind::Expr | ArgKind::FlagOrExpr => {
                let (expr, sep) = self.expr(ExprMode::Expression)?;
                if expr.text.is_empty() {
                    let msg = format!("missing expression after '{} ='", arg.key);
                    return Err(self.error(equals, msg));
                }
                arg.values.push(Value::Expr(expr));
                separated = sep;
            }
            ArgKind::Text => {
                self.skip_ws();
                let quoted = self.peek_char() == Some('"');
                (arg.values, separated) = self.lenient_value(quoted, ExprMode::Text)?;
            }
            ArgKind::TextList => arg.values = self.text_list()?,
            ArgKind::Numbers | ArgKind::Words => {
                let start = self.span_here();
                arg.values = match self.list(kind, &arg.key) {
                    Ok(v) => v,
                    Err(ListError::Fatal(d)) => return Err(d),
                    Err(ListError::NotPlain) => {
                        return Err(self.error(start, format!("invalid value of '{}'", arg.key)))
                    }
                };
            }
            ArgKind::Flag | ArgKind::Any => {
                (arg.values, separated) = self.lenient_value(true, ExprMode::Fallback)?;
            }
        }
        Ok((arg, separated))
    }

    /// Canonical key and value kind of an argument keyword.
    fn resolve_arg(&mut self, word: &str, span: Span) -> Result<(String, ArgKind), Diagnostic> {
        let as_written = || (word.to_ascii_uppercase(), keywords::default_kind(word));
        let Some(def) = self.def else {
            return Ok(as_written());
        };
        match keywords::lookup_arg(word, def) {
            Lookup::Found(a) => Ok((a.canonical.to_string(), a.kind)),
            Lookup::Ambiguous(names) if def.complete => Err(self.error(
                span,
                format!(
                    "ambiguous argument '{word}' of {}: could be {}",
                    def.name,
                    names.join(", ")
                ),
            )),
            Lookup::NotFound if def.complete => {
                let upper = word.to_ascii_uppercase();
                let guess = keywords::closest_arg(word, def)
                    .map(|g| format!(" (did you mean {g}?)"))
                    .unwrap_or_default();
                let d = if self.lenient_arguments {
                    let msg = format!("unknown argument '{upper}' of {} ignored{guess}", def.name);
                    Diagnostic::warning(self.file.clone(), Some(span), msg)
                } else {
                    let msg = format!("unknown argument '{upper}' of {}{guess}", def.name);
                    let mut takes: Vec<&str> = def.args.iter().map(|a| a.canonical).collect();
                    takes.sort_unstable();
                    takes.dedup();
                    Diagnostic::error(self.file.clone(), Some(span), msg).with_hint(format!(
                        "{} takes {}. Adams stops on an argument a statement does not take; \
                         the lenient-arguments option (`--lenient-arguments`, Python \
                         `lenient_arguments=True`, sweep `lenient_arguments = true`) reads \
                         the dataset anyway, ignoring it with a warning",
                        def.name,
                        takes.join(", ")
                    ))
                };
                self.warnings.push(d);
                Ok(as_written())
            }
            Lookup::Ambiguous(_) | Lookup::NotFound => Ok(as_written()),
        }
    }
}

mod values;

#[cfg(test)]
mod tests;
