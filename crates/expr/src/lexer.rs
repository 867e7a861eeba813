//! Tokenizer: expression text → tokens with byte offsets.
//!
//! Numbers follow FORTRAN conventions (`1`, `.4`, `1.`, `1.0E-04`, `5.0E-002`, `4.32E+09`) with
//! an optional `D`/`d` suffix meaning degrees (`30.0d`). A `D` directly followed by a digit
//! (`1.0D0`, a FORTRAN double-precision exponent) is rejected because in Adams datasets `D`
//! means degrees. Names are ASCII letters, digits and `_`, starting with a letter, and are
//! upper-cased. Whitespace (including newlines) separates tokens and is otherwise ignored.

use crate::error::ParseError;

#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Tok {
    Number { value: f64, degrees: bool },
    Name(String),
    Plus,
    Minus,
    Star,
    Slash,
    Percent,
    Power,
    LParen,
    RParen,
    LBracket,
    RBracket,
    Comma,
    Colon,
    End,
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Token {
    pub tok: Tok,
    /// Byte offset of the first character.
    pub offset: usize,
    /// Length in bytes.
    pub len: usize,
}

impl Token {
    /// Describes the token for error messages, quoting the source text.
    pub fn describe(&self, src: &str) -> String {
        let text = src.get(self.offset..self.offset + self.len).unwrap_or("?");
        match self.tok {
            Tok::End => "end of expression".to_string(),
            Tok::Number { .. } => format!("number '{text}'"),
            Tok::Name(_) => format!("name '{text}'"),
            _ => format!("'{text}'"),
        }
    }
}

fn char_at(src: &str, offset: usize) -> char {
    src.get(offset..)
        .and_then(|s| s.chars().next())
        .unwrap_or('?')
}

/// Splits `src` into tokens; the last token is always [`Tok::End`] at `src.len()`.
pub(crate) fn tokenize(src: &str) -> Result<Vec<Token>, ParseError> {
    let b = src.as_bytes();
    let at = |i: usize| b.get(i).copied().unwrap_or(0);
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        if c.is_ascii_whitespace() {
            i += 1;
            continue;
        }
        let start = i;
        let simple = match c {
            b'+' => Some(Tok::Plus),
            b'-' => Some(Tok::Minus),
            b'/' => Some(Tok::Slash),
            b'%' => Some(Tok::Percent),
            b'(' => Some(Tok::LParen),
            b')' => Some(Tok::RParen),
            b'[' => Some(Tok::LBracket),
            b']' => Some(Tok::RBracket),
            b',' => Some(Tok::Comma),
            b':' => Some(Tok::Colon),
            _ => None,
        };
        if let Some(tok) = simple {
            out.push(Token {
                tok,
                offset: start,
                len: 1,
            });
            i += 1;
            continue;
        }
        if c == b'*' {
            let (tok, len) = if at(i + 1) == b'*' {
                (Tok::Power, 2)
            } else {
                (Tok::Star, 1)
            };
            out.push(Token {
                tok,
                offset: start,
                len,
            });
            i += len;
            continue;
        }
        if c.is_ascii_digit() || (c == b'.' && at(i + 1).is_ascii_digit()) {
            let (tok, end) = lex_number(src, start)?;
            out.push(Token {
                tok,
                offset: start,
                len: end - start,
            });
            i = end;
            continue;
        }
        if c.is_ascii_alphabetic() {
            while at(i).is_ascii_alphanumeric() || at(i) == b'_' {
                i += 1;
            }
            let name = src.get(start..i).unwrap_or_default().to_ascii_uppercase();
            out.push(Token {
                tok: Tok::Name(name),
                offset: start,
                len: i - start,
            });
            continue;
        }
        let what = char_at(src, start);
        let message = if c == b'\\' {
            "unexpected '\\' (an expression argument ends at '\\'; strip it before parsing)"
                .to_string()
        } else {
            format!("unexpected character '{what}'")
        };
        return Err(ParseError::new(start, message));
    }
    out.push(Token {
        tok: Tok::End,
        offset: b.len(),
        len: 0,
    });
    Ok(out)
}

/// Lexes a number starting at `start`; returns the token and the end offset.
fn lex_number(src: &str, start: usize) -> Result<(Tok, usize), ParseError> {
    let b = src.as_bytes();
    let at = |i: usize| b.get(i).copied().unwrap_or(0);
    let mut i = start;
    while at(i).is_ascii_digit() {
        i += 1;
    }
    if at(i) == b'.' {
        i += 1;
        while at(i).is_ascii_digit() {
            i += 1;
        }
    }
    if matches!(at(i), b'e' | b'E') {
        let mut j = i + 1;
        if matches!(at(j), b'+' | b'-') {
            j += 1;
        }
        if !at(j).is_ascii_digit() {
            return Err(ParseError::new(
                i,
                "malformed number: expected the digits of an exponent after 'E'",
            ));
        }
        while at(j).is_ascii_digit() {
            j += 1;
        }
        i = j;
    }
    let text = src.get(start..i).unwrap_or_default();
    let value: f64 = text
        .parse()
        .map_err(|_| ParseError::new(start, format!("malformed number '{text}'")))?;
    if !value.is_finite() {
        return Err(ParseError::new(
            start,
            format!("number '{text}' is out of range"),
        ));
    }
    let mut degrees = false;
    if matches!(at(i), b'd' | b'D') {
        if at(i + 1).is_ascii_digit() {
            return Err(ParseError::new(
                i,
                "'D' after a number means degrees; FORTRAN exponents such as 1.0D0 are not \
                 supported (write 1.0E0)",
            ));
        }
        degrees = true;
        i += 1;
    }
    let next = at(i);
    if next.is_ascii_alphanumeric() || next == b'_' || next == b'.' {
        return Err(ParseError::new(
            i,
            format!("unexpected '{}' after number", char_at(src, i)),
        ));
    }
    Ok((Tok::Number { value, degrees }, i))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn toks(s: &str) -> Vec<Tok> {
        tokenize(s).unwrap().into_iter().map(|t| t.tok).collect()
    }

    fn num(value: f64, degrees: bool) -> Tok {
        Tok::Number { value, degrees }
    }

    #[test]
    fn numbers() {
        assert_eq!(toks("1.0E-04"), vec![num(1.0e-4, false), Tok::End]);
        assert_eq!(toks("5.0E-002"), vec![num(0.05, false), Tok::End]);
        assert_eq!(toks("4.32E+09"), vec![num(4.32e9, false), Tok::End]);
        assert_eq!(toks(".4"), vec![num(0.4, false), Tok::End]);
        assert_eq!(toks("1."), vec![num(1.0, false), Tok::End]);
        assert_eq!(toks("1.e2"), vec![num(100.0, false), Tok::End]);
        assert_eq!(toks("30.0d"), vec![num(30.0, true), Tok::End]);
        assert_eq!(toks("180D"), vec![num(180.0, true), Tok::End]);
        assert_eq!(
            toks("1.0D-3"),
            vec![num(1.0, true), Tok::Minus, num(3.0, false), Tok::End]
        );
    }

    #[test]
    fn bad_numbers() {
        assert_eq!(tokenize("1.0D0").unwrap_err().offset, 3);
        assert_eq!(tokenize("2E").unwrap_err().offset, 1);
        assert_eq!(tokenize("2E+").unwrap_err().offset, 1);
        assert_eq!(tokenize("2PI").unwrap_err().offset, 1);
        assert_eq!(tokenize("1.5.3").unwrap_err().offset, 3);
        assert!(tokenize("1e999")
            .unwrap_err()
            .message
            .contains("out of range"));
    }

    #[test]
    fn operators_and_names() {
        assert_eq!(
            toks("a**-b * c%[d]:,"),
            vec![
                Tok::Name("A".into()),
                Tok::Power,
                Tok::Minus,
                Tok::Name("B".into()),
                Tok::Star,
                Tok::Name("C".into()),
                Tok::Percent,
                Tok::LBracket,
                Tok::Name("D".into()),
                Tok::RBracket,
                Tok::Colon,
                Tok::Comma,
                Tok::End
            ]
        );
        let e = tokenize("1 + é").unwrap_err();
        assert_eq!(e.offset, 4);
        assert!(e.message.contains('é'));
        assert_eq!(tokenize("1\\").unwrap_err().offset, 1);
    }
}
