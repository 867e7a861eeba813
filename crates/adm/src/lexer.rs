//! Lexer: physical lines → logical statements (ADM-REFERENCE §1.2).
//!
//! Contract:
//! - Lines end with `\n`, `\r\n` or a lone `\r`. Line 1 (the title, or an ACF's model name) is
//!   never lexed: the caller says at which line statements start.
//! - `!` starts a comment that runs to the end of the line, except inside double quotes.
//!   Comment-only and blank lines are skipped. The last `adams_view_name='…'` found in the comment
//!   lines since the previous statement becomes the next statement's view name.
//! - A statement continues on the next non-blank, non-comment line when that line starts with a
//!   comma (its *continuation comma*, marked [`Mark::ContinuationComma`]) or when the current line
//!   ends with a comma or with the continuation mark `&` (which is removed).
//! - `;` outside quotes ends a statement; text after it on the same line starts a new one.
//! - A statement whose first word is the stop word (`END` in datasets, `STOP` in command files)
//!   is returned alone, without looking at the following lines, so that nothing after it is read.
//! - Problems found here (unterminated string, continuation line with no statement before it)
//!   are errors; they never abort lexing.

use crate::diagnostic::{Diagnostic, Span};
use std::sync::Arc;

/// Role of a character of a logical statement.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Mark {
    /// A character of the source.
    Plain,
    /// The comma that starts a continuation line (a separator, or dropped inside expressions).
    ContinuationComma,
    /// A boundary between two physical lines (no source character; spans the end of the line).
    LineBreak,
}

/// One character of a logical statement and where it was written.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct SrcChar {
    pub ch: char,
    pub span: Span,
    pub mark: Mark,
}

/// A statement with its continuation lines joined, comments and `&` removed.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct RawStatement {
    pub chars: Vec<SrcChar>,
    /// First and last physical line.
    pub lines: (u32, u32),
    pub view_name: Option<String>,
    /// Lexical errors inside the statement (unterminated string).
    pub errors: Vec<Diagnostic>,
}

/// What [`Lexer::next_item`] yields.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum LexItem {
    Statement(RawStatement),
    /// An error outside any statement (a continuation line with nothing to continue).
    Error(Diagnostic),
}

/// Splits text into lines without their line endings (`\n`, `\r\n`, lone `\r`).
pub(crate) fn split_lines(text: &str) -> Vec<&str> {
    let bytes = text.as_bytes();
    // Most lines are short: one line per 40 bytes is a fair first guess.
    let mut lines = Vec::with_capacity(bytes.len() / 40 + 1);
    let mut start = 0;
    while start < bytes.len() {
        match memchr::memchr2(b'\n', b'\r', &bytes[start..]) {
            Some(k) => {
                let end = start + k;
                lines.push(&text[start..end]);
                let crlf = bytes[end] == b'\r' && bytes.get(end + 1) == Some(&b'\n');
                start = end + if crlf { 2 } else { 1 };
            }
            None => {
                lines.push(&text[start..]);
                start = bytes.len();
            }
        }
    }
    lines
}

/// The code part of one physical line.
struct LineScan<'a> {
    /// Text before the comment (the whole line when there is none).
    code: &'a str,
    comment: Option<&'a str>,
    /// Byte offsets of `;` outside quotes in `code`.
    semicolons: Vec<usize>,
    /// Byte offset of a quote left open at the end of the line.
    open_quote: Option<usize>,
}

fn scan_line(line: &str) -> LineScan<'_> {
    let bytes = line.as_bytes();
    let mut in_quote: Option<usize> = None;
    let mut semicolons = Vec::new();
    // The characters looked for are ASCII, and no byte of a multi-byte UTF-8 character is
    // ASCII: searching bytes finds them at character boundaries.
    for k in memchr::memchr3_iter(b'"', b'!', b';', bytes) {
        match (bytes[k], in_quote) {
            (b'"', None) => in_quote = Some(k),
            (b'"', Some(_)) => in_quote = None,
            (b'!', None) => {
                return LineScan {
                    code: &line[..k],
                    comment: Some(&line[k + 1..]),
                    semicolons,
                    open_quote: None,
                }
            }
            (b';', None) => semicolons.push(k),
            _ => {}
        }
    }
    LineScan {
        code: line,
        comment: None,
        semicolons,
        open_quote: in_quote,
    }
}

/// The `adams_view_name='…'` value of a comment, if it has one.
pub(crate) fn view_name_in(comment: &str) -> Option<String> {
    const KEY: &[u8] = b"adams_view_name";
    // Case-insensitive search without a lower-case copy (one comment per element in files
    // written by Adams View). The key is ASCII, so a match starts at a character boundary.
    let at = comment
        .as_bytes()
        .windows(KEY.len())
        .position(|w| w.eq_ignore_ascii_case(KEY))?;
    let rest = comment.get(at + KEY.len()..)?.trim_start();
    let rest = rest.strip_prefix('=')?.trim_start();
    let quote = rest.chars().next().filter(|q| *q == '\'' || *q == '"')?;
    let body = rest.get(1..)?;
    let end = body.find(quote)?;
    body.get(..end).map(str::to_string)
}

/// 1-based column of byte offset `byte` in `line` (columns count characters).
fn col_of(line: &str, byte: usize) -> u32 {
    let chars = line.get(..byte).map_or(0, |s| {
        if s.is_ascii() {
            s.len()
        } else {
            s.chars().count()
        }
    });
    u32::try_from(chars)
        .unwrap_or(u32::MAX - 1)
        .saturating_add(1)
}

fn line_number(index: usize) -> u32 {
    u32::try_from(index)
        .unwrap_or(u32::MAX - 1)
        .saturating_add(1)
}

/// Reads logical statements one at a time, so that the caller can stop at `END`.
pub(crate) struct Lexer<'a> {
    file: Arc<str>,
    lines: Vec<&'a str>,
    /// Index of the next line to read.
    next: usize,
    /// Remainder of a line after a `;`: (line index, byte offset).
    resume: Option<(usize, usize)>,
    /// View name waiting for the next statement.
    view_name: Option<String>,
    stop_word: &'static str,
    /// The character buffer of a statement the caller is done with ([`Self::recycle`]), reused
    /// for the next statement.
    spare: Vec<SrcChar>,
}

/// One piece of a physical line that belongs to a statement.
struct Piece {
    line: usize,
    start: usize,
    end: usize,
    /// Whether the piece ended at a `;`.
    closed: bool,
}

impl<'a> Lexer<'a> {
    /// A lexer over `text` starting at 0-based line index `first_line`.
    pub(crate) fn new(
        file: Arc<str>,
        text: &'a str,
        first_line: usize,
        stop_word: &'static str,
    ) -> Self {
        Lexer {
            file,
            lines: split_lines(text),
            next: first_line,
            resume: None,
            view_name: None,
            stop_word,
            spare: Vec::new(),
        }
    }

    /// The next statement (or stray error), `None` at the end of the text.
    pub(crate) fn next_item(&mut self) -> Option<LexItem> {
        if let Some((line, start)) = self.resume.take() {
            let scan = scan_line(self.lines.get(line).copied().unwrap_or(""));
            return Some(LexItem::Statement(self.statement_from(line, start, &scan)));
        }
        while let Some(text) = self.lines.get(self.next).copied() {
            let index = self.next;
            self.next += 1;
            let scan = scan_line(text);
            if scan.code.trim().is_empty() {
                if let Some(name) = scan.comment.and_then(view_name_in) {
                    self.view_name = Some(name);
                }
                continue;
            }
            let lead = scan.code.len() - scan.code.trim_start().len();
            if scan.code[lead..].starts_with(',') {
                let span = Span::new(line_number(index), col_of(text, lead));
                return Some(LexItem::Error(Diagnostic::error(
                    self.file.clone(),
                    Some(span),
                    "continuation line (starting with ',') has no statement to continue",
                )));
            }
            return Some(LexItem::Statement(self.statement_from(index, 0, &scan)));
        }
        None
    }

    /// Builds the statement that starts at byte `start` of line `index`, with its continuations.
    /// `scan` is [`scan_line`] of that line.
    fn statement_from(&mut self, index: usize, start: usize, scan: &LineScan) -> RawStatement {
        let mut chars = std::mem::take(&mut self.spare);
        chars.clear();
        let mut raw = RawStatement {
            chars,
            lines: (line_number(index), line_number(index)),
            view_name: self.view_name.take(),
            errors: Vec::new(),
        };
        let (piece, mut continues) = self.piece(index, start, scan, &mut raw.errors);
        self.push_piece(&mut raw, &piece, false);
        if piece.closed || self.starts_with_stop_word(&raw) {
            return raw;
        }
        let mut pending_view: Option<String> = None;
        while let Some(text) = self.lines.get(self.next).copied() {
            let scan = scan_line(text);
            if scan.code.trim().is_empty() {
                if let Some(name) = scan.comment.and_then(view_name_in) {
                    pending_view = Some(name);
                }
                self.next += 1;
                continue;
            }
            let leading_comma = scan.code.trim_start().starts_with(',');
            if !(continues || leading_comma) {
                break;
            }
            let index = self.next;
            self.next += 1;
            pending_view = None;
            let (piece, more) = self.piece(index, 0, &scan, &mut raw.errors);
            raw.lines.1 = line_number(index);
            self.push_piece(&mut raw, &piece, true);
            if piece.closed {
                break;
            }
            continues = more;
        }
        if pending_view.is_some() {
            self.view_name = pending_view;
        }
        raw
    }

    /// The part of line `index` from byte `start` up to a `;` or the comment; whether the next
    /// line continues it (trailing `,` or `&`). Schedules the text after a `;` as a new statement.
    /// `scan` is [`scan_line`] of line `index`.
    fn piece(
        &mut self,
        index: usize,
        start: usize,
        scan: &LineScan,
        errors: &mut Vec<Diagnostic>,
    ) -> (Piece, bool) {
        let text = self.lines.get(index).copied().unwrap_or("");
        if let Some(q) = scan.open_quote.filter(|q| *q >= start) {
            let span = Span::new(line_number(index), col_of(text, q));
            errors.push(Diagnostic::error(
                self.file.clone(),
                Some(span),
                "unterminated string (missing closing '\"')",
            ));
        }
        if let Some(&semi) = scan.semicolons.iter().find(|&&s| s >= start) {
            let after = semi + 1;
            let rest_blank = scan.code.get(after..).unwrap_or("").trim().is_empty();
            if !rest_blank {
                self.resume = Some((index, after));
            }
            let piece = Piece {
                line: index,
                start,
                end: semi,
                closed: true,
            };
            return (piece, false);
        }
        let mut end = scan.code.trim_end().len().max(start);
        let mut continues = false;
        if let Some(before) = scan.code.get(start..end).and_then(|s| s.strip_suffix('&')) {
            end = start + before.trim_end().len();
            continues = true;
        }
        if scan.code.get(start..end).is_some_and(|s| s.ends_with(',')) {
            continues = true;
        }
        let piece = Piece {
            line: index,
            start,
            end,
            closed: false,
        };
        (piece, continues)
    }

    fn push_piece(&self, raw: &mut RawStatement, piece: &Piece, continuation: bool) {
        let text = self.lines.get(piece.line).copied().unwrap_or("");
        let line = line_number(piece.line);
        if continuation {
            let span = raw.chars.last().map_or(Span::new(line, 1), |c| {
                Span::new(c.span.line, c.span.col + 1)
            });
            raw.chars.push(SrcChar {
                ch: ' ',
                span,
                mark: Mark::LineBreak,
            });
        }
        // One character per byte at most: one reservation per piece instead of the doublings.
        raw.chars.reserve(piece.end.saturating_sub(piece.start));
        let mut col = col_of(text, piece.start);
        let code = text.get(piece.start..piece.end).unwrap_or("");
        // The first non-blank character of a continuation line, when it is a comma.
        let lead = code.len() - code.trim_start().len();
        let comma_at = (continuation && code[lead..].starts_with(',')).then_some(lead);
        let mark_at = |k: usize| {
            if comma_at == Some(k) {
                Mark::ContinuationComma
            } else {
                Mark::Plain
            }
        };
        if code.is_ascii() {
            // One character per byte, columns in step with the bytes.
            raw.chars
                .extend(code.bytes().enumerate().map(|(k, b)| SrcChar {
                    ch: char::from(b),
                    span: Span::new(line, col.saturating_add(k as u32)),
                    mark: mark_at(k),
                }));
            return;
        }
        for (k, c) in code.char_indices() {
            raw.chars.push(SrcChar {
                ch: c,
                span: Span::new(line, col),
                mark: mark_at(k),
            });
            col = col.saturating_add(1);
        }
    }

    /// Takes back a statement's characters so that the next statement reuses their buffer.
    pub(crate) fn recycle(&mut self, raw: RawStatement) {
        self.spare = raw.chars;
    }

    fn starts_with_stop_word(&self, raw: &RawStatement) -> bool {
        let word: String = raw
            .chars
            .iter()
            .map(|c| c.ch)
            .skip_while(|c| c.is_whitespace())
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect();
        word.eq_ignore_ascii_case(self.stop_word)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lex(text: &str) -> Vec<LexItem> {
        let mut lexer = Lexer::new(Arc::from("t.adm"), text, 1, "END");
        std::iter::from_fn(|| lexer.next_item()).collect()
    }

    fn statements(text: &str) -> Vec<RawStatement> {
        lex(text)
            .into_iter()
            .map(|item| match item {
                LexItem::Statement(s) => s,
                LexItem::Error(d) => panic!("unexpected error {d}"),
            })
            .collect()
    }

    /// The statement's text with line breaks shown as `|` and continuation commas as `^`.
    fn shape(s: &RawStatement) -> String {
        s.chars
            .iter()
            .map(|c| match c.mark {
                Mark::Plain => c.ch,
                Mark::ContinuationComma => '^',
                Mark::LineBreak => '|',
            })
            .collect()
    }

    #[test]
    fn line_endings_crlf_lf_and_cr() {
        assert_eq!(split_lines("a\r\nb\nc\rd"), vec!["a", "b", "c", "d"]);
        assert_eq!(split_lines("a\r\n\r\nb\r\n"), vec!["a", "", "b"]);
        assert!(split_lines("").is_empty());
    }

    #[test]
    fn title_line_is_not_lexed_even_if_it_looks_like_a_statement() {
        let s = statements("PART/1,MASS=40,CM=1;\r\nMARKER/1,PART=1\r\n");
        assert_eq!(s.len(), 1);
        assert_eq!(shape(&s[0]), "MARKER/1,PART=1");
        assert_eq!(s[0].lines, (2, 2));
    }

    #[test]
    fn leading_comma_lines_continue_with_spans() {
        let s = statements("title\r\nPART/02, MASS = 1\r\n  , CM = 0201\r\n\r\nEND\r\n");
        assert_eq!(s.len(), 2);
        assert_eq!(shape(&s[0]), "PART/02, MASS = 1|  ^ CM = 0201");
        assert_eq!(s[0].lines, (2, 3));
        let comma = s[0]
            .chars
            .iter()
            .find(|c| c.mark == Mark::ContinuationComma)
            .map(|c| c.span);
        assert_eq!(comma, Some(Span::new(3, 3)));
    }

    #[test]
    fn trailing_comma_and_ampersand_continue() {
        let s = statements("t\nPART/20, MASS=21,\n QG=0,0,0\nINTEGRATOR/ &\n, HHT &\n, ERROR = 1.0E-05\nint/gstiff, &\n\terror = 1\n");
        assert_eq!(s.len(), 3);
        assert_eq!(shape(&s[0]), "PART/20, MASS=21,| QG=0,0,0");
        assert_eq!(shape(&s[1]), "INTEGRATOR/|^ HHT|^ ERROR = 1.0E-05");
        assert_eq!(shape(&s[2]), "int/gstiff,|\terror = 1");
        assert_eq!(s[2].chars.last().map(|c| c.span), Some(Span::new(8, 10)));
    }

    #[test]
    fn comments_are_removed_but_not_inside_strings() {
        let s = statements("t\nREQUEST/1, CNAMES = \"a!b\", \"\" ! names\n! whole line\n, C=x\n");
        assert_eq!(s.len(), 1);
        assert_eq!(shape(&s[0]), "REQUEST/1, CNAMES = \"a!b\", \"\"|^ C=x");
    }

    #[test]
    fn view_name_comes_from_comments_before_the_statement() {
        let text = "t\n!\n!   adams_view_name='JOINT_1'\nJOINT/1\n, REVOLUTE\n! adams_view_name='inner'\n, I = 1\nPART/1\n!  adams_view_name='m'\n\nMARKER/1\n";
        let s = statements(text);
        assert_eq!(s.len(), 3);
        assert_eq!(s[0].view_name.as_deref(), Some("JOINT_1"));
        assert_eq!(
            s[1].view_name, None,
            "a comment inside a statement names nothing"
        );
        assert_eq!(s[2].view_name.as_deref(), Some("m"));
        assert_eq!(view_name_in("   adams_view_name=\"q\""), Some("q".into()));
        assert_eq!(view_name_in(" adams_view_name='unterminated"), None);
    }

    #[test]
    fn semicolon_ends_a_statement() {
        let s = statements("t\nPART/1,MASS=40,CM=1; MARKER/1,PART=1;\nMARKER/2\n");
        assert_eq!(s.len(), 3);
        assert_eq!(shape(&s[0]), "PART/1,MASS=40,CM=1");
        assert_eq!(shape(&s[1]), " MARKER/1,PART=1");
        assert_eq!(s[1].chars.get(1).map(|c| c.span), Some(Span::new(2, 22)));
        assert_eq!(shape(&s[2]), "MARKER/2");
    }

    #[test]
    fn continuation_without_statement_is_an_error_at_its_comma() {
        let items = lex("t\n\n   , MASS = 1\nPART/1;\n, CM = 2\n");
        let errors: Vec<Span> = items
            .iter()
            .filter_map(|i| match i {
                LexItem::Error(d) => d.span,
                LexItem::Statement(_) => None,
            })
            .collect();
        assert_eq!(errors, vec![Span::new(3, 4), Span::new(5, 1)]);
    }

    #[test]
    fn unterminated_string_is_an_error_at_the_quote() {
        let s = statements("t\nREQUEST/1, C = \"abc\n");
        assert_eq!(s.len(), 1);
        assert_eq!(s[0].errors.len(), 1);
        assert_eq!(s[0].errors[0].span, Some(Span::new(2, 16)));
    }

    #[test]
    fn stop_word_is_returned_without_looking_ahead() {
        let mut lexer = Lexer::new(
            Arc::from("t.adm"),
            "t\nEND\n, garbage \"\nPART/1\n",
            1,
            "END",
        );
        match lexer.next_item() {
            Some(LexItem::Statement(s)) => {
                assert_eq!(shape(&s), "END");
                assert!(s.errors.is_empty());
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn tabs_count_as_one_column() {
        let s = statements("t\n\tPART/1,\tMASS=1\n");
        let m = s[0].chars.iter().find(|c| c.ch == 'M').map(|c| c.span);
        assert_eq!(m, Some(Span::new(2, 10)));
    }
}
