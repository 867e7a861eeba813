//! Adams request files (`.req`): the text file Adams Solver writes with `OUTPUT/REQSAVE`
//! (ADM-REFERENCE §7.6), read back as one time history per REQUEST.
//!
//! Layout, as observed in files written by Adams Solver (FORTRAN-style fixed format):
//!
//! ```text
//!  A.R3    2014-11-18 09:13:44               0         0  3D      line 1: version, date
//! ADAMS/View model name: test_Revolute_Case01                     line 2: dataset title
//!     5     M_KGS_N_RACA 1.000000000000000E+00                   line 3: requests, units, scale
//!           1             1           201           101            13    per request: id,
//! DISPLACEMENT: X Y Z PSI THETA PHI (body-fixed-3-1-3)            type, I, J, comment size;
//!   …                                                              then the COMMENT line
//!    0.00000E+00                                                   per output: the time,
//!    2.00000E+00  0.00000E+00  0.00000E+00  1.80000E+02  9.00000E+01  1.80000E+02
//!   …                                                              then 6 values per request
//! ```
//!
//! - The type codes are 1 DISPLACEMENT, 2 VELOCITY, 3 ACCELERATION, 4 FORCE, 5 function
//!   request (F1…F8); I and J are 0 for function requests.
//! - The comment size is the number of 4-character words of the COMMENT (the comment padded
//!   with blanks to a multiple of 4): 13 for the 52 characters of
//!   `DISPLACEMENT: X Y Z PSI THETA PHI (body-fixed-3-1-3)`. When it is 0 the comment line is
//!   absent (a blank line there is skipped).
//! - Each output block is a line with the time and then six values per request, in request
//!   order, six to a line. The six values are the request's components 2, 3, 4, 6, 7, 8:
//!   x, y, z, ψ, θ, φ (degrees) for a displacement, vx … wz for a velocity, ax … ẇz for an
//!   acceleration, fx … tz for a force, and F2, F3, F4, F6, F7, F8 for a function request (the
//!   magnitudes F1 and F5 of Adams' eight-component layout are not stored).
//! - Values are in the dataset's units (line 3 names them, e.g. `M_KGS_N_RACA` for metre,
//!   kilogram, second, newton; the number after is kept as written). The same time may appear
//!   twice (an initial-conditions output and the first step); every block is kept.
//!
//! Numbers are read as written, also FORTRAN's exponent without `E` (`1.23456-100`) and `D`
//! exponents. Problems are [`Diagnostic`]s with the line and column.

use crate::diagnostic::{Diagnostic, Diagnostics, Span};
use crate::lexer::split_lines;
use crate::typed::RequestKind;
use std::path::Path;
use std::sync::Arc;

/// Values stored per request and output time.
pub const VALUES_PER_REQUEST: usize = 6;

/// One request of a request file and its time history.
#[derive(Clone, Debug, PartialEq)]
pub struct RequestHistory {
    pub id: u64,
    /// The type code as written (1 displacement, 2 velocity, 3 acceleration, 4 force, 5
    /// function request).
    pub type_code: u32,
    /// I and J marker ids (0 for function requests).
    pub i: u64,
    pub j: u64,
    /// The COMMENT, trailing blanks removed.
    pub comment: String,
    /// The six stored components at every output time (same length as
    /// [`RequestFile::times`]).
    pub values: Vec<[f64; VALUES_PER_REQUEST]>,
}

impl RequestHistory {
    /// The standard quantity of type codes 1–4; `None` for function requests.
    pub fn kind(&self) -> Option<RequestKind> {
        match self.type_code {
            1 => Some(RequestKind::Displacement),
            2 => Some(RequestKind::Velocity),
            3 => Some(RequestKind::Acceleration),
            4 => Some(RequestKind::Force),
            _ => None,
        }
    }

    /// Names of the six stored components: `x y z psi theta phi`, `vx … wz`, `ax … wdz`,
    /// `fx … tz`, or `f2 f3 f4 f6 f7 f8`.
    pub fn component_names(&self) -> [&'static str; VALUES_PER_REQUEST] {
        match self.kind() {
            Some(RequestKind::Displacement) => ["x", "y", "z", "psi", "theta", "phi"],
            Some(RequestKind::Velocity) => ["vx", "vy", "vz", "wx", "wy", "wz"],
            Some(RequestKind::Acceleration) => ["ax", "ay", "az", "wdx", "wdy", "wdz"],
            Some(RequestKind::Force) => ["fx", "fy", "fz", "tx", "ty", "tz"],
            None => ["f2", "f3", "f4", "f6", "f7", "f8"],
        }
    }

    /// The history of stored component `c` (0..6).
    pub fn component(&self, c: usize) -> Vec<f64> {
        self.values
            .iter()
            .map(|v| v.get(c).copied().unwrap_or(f64::NAN))
            .collect()
    }
}

/// A whole request file.
#[derive(Clone, Debug, PartialEq)]
pub struct RequestFile {
    /// File name used in diagnostics.
    pub file: Arc<str>,
    /// Line 1 (solver version and date), trimmed.
    pub header: String,
    /// Line 2 (the dataset title), trailing blanks removed.
    pub title: String,
    /// The units word of line 3 (`M_KGS_N_RACA`).
    pub units: String,
    /// The number after the units on line 3, as written.
    pub scale: f64,
    /// Output times, in file order.
    pub times: Vec<f64>,
    /// Requests in file order.
    pub requests: Vec<RequestHistory>,
}

impl RequestFile {
    /// The request with dataset id `id`.
    pub fn request(&self, id: u64) -> Option<&RequestHistory> {
        self.requests.iter().find(|r| r.id == id)
    }
}

/// Reads a request file. I/O failures become a diagnostic naming the file.
pub fn read_request_file(path: &Path) -> Result<RequestFile, Diagnostics> {
    let file: Arc<str> = Arc::from(path.display().to_string());
    match crate::input::read_input(path) {
        Ok(bytes) => parse_request_file(file, &String::from_utf8_lossy(&bytes)),
        Err(e) => Err(Diagnostics(vec![Diagnostic::error(
            file,
            None,
            format!("cannot read request file: {e}"),
        )])),
    }
}

/// A number as FORTRAN writes it: `1.5E+00`, `1.5D+00`, `1.5-100` (exponent without letter).
fn fortran_number(word: &str) -> Option<f64> {
    if let Ok(v) = word.parse::<f64>() {
        return v.is_finite().then_some(v);
    }
    let w = word.replace(['D', 'd'], "E");
    if let Ok(v) = w.parse::<f64>() {
        return v.is_finite().then_some(v);
    }
    // A sign after the mantissa without an exponent letter.
    let split = w
        .char_indices()
        .skip(1)
        .find(|(k, c)| {
            matches!(c, '+' | '-')
                && !w[..*k].ends_with(['E', 'e'])
                && w[..*k].ends_with(|p: char| p.is_ascii_digit() || p == '.')
        })
        .map(|(k, _)| k)?;
    let v = format!("{}E{}", &w[..split], &w[split..])
        .parse::<f64>()
        .ok()?;
    v.is_finite().then_some(v)
}

/// Reads a request file's text. `file` is the name used in diagnostics.
pub fn parse_request_file(file: Arc<str>, text: &str) -> Result<RequestFile, Diagnostics> {
    Reader {
        file,
        lines: split_lines(text),
        next: 0,
    }
    .read()
}

struct Reader<'t> {
    file: Arc<str>,
    lines: Vec<&'t str>,
    /// Index of the next line to read.
    next: usize,
}

impl<'t> Reader<'t> {
    fn error(&self, line: usize, col: usize, msg: impl Into<String>) -> Diagnostics {
        let span = Span::new(
            u32::try_from(line + 1).unwrap_or(u32::MAX),
            u32::try_from(col + 1).unwrap_or(u32::MAX),
        );
        Diagnostics(vec![Diagnostic::error(self.file.clone(), Some(span), msg)])
    }

    /// The next line and its index, or an error naming what was expected.
    fn line(&mut self, what: &str) -> Result<(usize, &'t str), Diagnostics> {
        match self.lines.get(self.next) {
            Some(l) => {
                self.next += 1;
                Ok((self.next - 1, l))
            }
            None => Err(self.error(
                self.lines.len().saturating_sub(1),
                0,
                format!("the request file ends where {what} was expected"),
            )),
        }
    }

    /// The blank-separated words of a line with their starting columns.
    fn words(line: &str) -> Vec<(usize, &str)> {
        let mut out = Vec::new();
        let mut start = None;
        for (k, c) in line.char_indices() {
            match (c.is_whitespace(), start) {
                (false, None) => start = Some(k),
                (true, Some(s)) => {
                    out.push((s, &line[s..k]));
                    start = None;
                }
                _ => {}
            }
        }
        if let Some(s) = start {
            out.push((s, &line[s..]));
        }
        out
    }

    fn numbers(&self, index: usize, line: &str) -> Result<Vec<f64>, Diagnostics> {
        Self::words(line)
            .into_iter()
            .map(|(col, w)| {
                fortran_number(w)
                    .ok_or_else(|| self.error(index, col, format!("'{w}' is not a number")))
            })
            .collect()
    }

    fn integer(
        &self,
        index: usize,
        col: usize,
        word: &str,
        what: &str,
    ) -> Result<u64, Diagnostics> {
        word.parse::<u64>().map_err(|_| {
            self.error(
                index,
                col,
                format!("{what} '{word}' is not a non-negative integer"),
            )
        })
    }

    fn read(mut self) -> Result<RequestFile, Diagnostics> {
        let (_, header) = self.line("the header line")?;
        let (_, title) = self.line("the title line")?;
        let (k, counts) = self.line("the line with the number of requests")?;
        let words = Self::words(counts);
        let (nreq, units, scale) = match words.as_slice() {
            [(c0, n), (_, units), (c2, scale), ..] => (
                self.integer(k, *c0, n, "the number of requests")?,
                units.to_string(),
                fortran_number(scale)
                    .ok_or_else(|| self.error(k, *c2, format!("'{scale}' is not a number")))?,
            ),
            [(c0, n)] => (
                self.integer(k, *c0, n, "the number of requests")?,
                String::new(),
                1.0,
            ),
            _ => {
                return Err(self.error(
                    k,
                    0,
                    "line 3 should hold the number of requests, the units and a scale",
                ))
            }
        };
        let mut requests = Vec::new();
        for r in 0..nreq {
            let (k, line) = self.line(&format!("the description of request {}", r + 1))?;
            let w = Self::words(line);
            let [(c0, id), (c1, code), (c2, i), (c3, j), (c4, size)] = w.as_slice() else {
                return Err(self.error(
                    k,
                    0,
                    format!(
                        "request {} should be described by 5 integers (id, type, I, J, comment \
                         size), found {} words",
                        r + 1,
                        w.len()
                    ),
                ));
            };
            let id = self.integer(k, *c0, id, "the request id")?;
            let type_code = self.integer(k, *c1, code, "the request type")?;
            let i = self.integer(k, *c2, i, "the I marker")?;
            let j = self.integer(k, *c3, j, "the J marker")?;
            let size = self.integer(k, *c4, size, "the comment size")?;
            let comment = if size > 0 {
                self.line("a request comment")?.1.trim_end().to_string()
            } else {
                if self
                    .lines
                    .get(self.next)
                    .is_some_and(|l| l.trim().is_empty())
                {
                    self.next += 1;
                }
                String::new()
            };
            requests.push(RequestHistory {
                id,
                type_code: u32::try_from(type_code).unwrap_or(u32::MAX),
                i,
                j,
                comment,
                values: Vec::new(),
            });
        }
        let per_block = requests.len() * VALUES_PER_REQUEST;
        let mut times = Vec::new();
        while self.next < self.lines.len() {
            let (k, line) = self.line("an output time")?;
            if line.trim().is_empty() {
                continue;
            }
            let t = match self.numbers(k, line)?.as_slice() {
                [t] => *t,
                other => {
                    return Err(self.error(
                        k,
                        0,
                        format!(
                            "expected an output time (one number), found {} numbers",
                            other.len()
                        ),
                    ))
                }
            };
            let mut values = Vec::with_capacity(per_block);
            while values.len() < per_block {
                let what = format!("the request values at time {t}");
                let (k, line) = self.line(&what)?;
                let nums = self.numbers(k, line)?;
                if nums.is_empty() || values.len() + nums.len() > per_block {
                    return Err(self.error(
                        k,
                        0,
                        format!(
                            "at time {t}: expected {} more request values, found {}",
                            per_block - values.len(),
                            nums.len()
                        ),
                    ));
                }
                values.extend(nums);
            }
            for (r, chunk) in requests.iter_mut().zip(values.chunks(VALUES_PER_REQUEST)) {
                let mut six = [0.0; VALUES_PER_REQUEST];
                six.copy_from_slice(chunk);
                r.values.push(six);
            }
            times.push(t);
        }
        Ok(RequestFile {
            file: self.file,
            header: header.trim().to_string(),
            title: title.trim_end().to_string(),
            units,
            scale,
            times,
            requests,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SMALL: &str = " A.R3    2014-11-18 09:13:44               0         0  3D
Test model
    2     M_KGS_N_RACA 1.000000000000000E+00
          1             1           201           101             3
DISP X Y Z
          7             5             0             0             0
   0.00000E+00
   2.00000E+00  0.00000E+00  0.00000E+00  1.80000E+02  9.00000E+01  1.80000E+02
  -1.00000E+00  2.50000E-01  0.00000E+00  0.00000E+00  0.00000E+00  1.00000-100
   1.00000E-02
   1.99000E+00  0.00000E+00 -4.78373E-04  1.80000E+02  9.00000E+01 -1.79986E+02
  -2.00000E+00  5.00000E-01  0.00000E+00  0.00000E+00  0.00000E+00  3.00000D+00
";

    fn parse(text: &str) -> Result<RequestFile, Diagnostics> {
        parse_request_file(Arc::from("t.req"), text)
    }

    #[test]
    fn small_file_gives_one_history_per_request() {
        let f = parse(SMALL).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(f.title, "Test model");
        assert_eq!(f.units, "M_KGS_N_RACA");
        assert_eq!(f.scale, 1.0);
        assert_eq!(f.times, [0.0, 0.01]);
        assert_eq!(f.requests.len(), 2);
        let d = f.request(1).unwrap_or_else(|| panic!("request 1"));
        assert_eq!((d.type_code, d.i, d.j), (1, 201, 101));
        assert_eq!(d.kind(), Some(RequestKind::Displacement));
        assert_eq!(d.comment, "DISP X Y Z");
        assert_eq!(d.component(0), [2.0, 1.99]);
        assert_eq!(d.component(2), [0.0, -4.78373e-4]);
        assert_eq!(d.component(5), [180.0, -179.986]);
        assert_eq!(d.component_names()[3], "psi");
        let g = f.request(7).unwrap_or_else(|| panic!("request 7"));
        assert_eq!(g.kind(), None);
        assert_eq!(g.comment, "");
        assert_eq!(g.component(0), [-1.0, -2.0]);
        assert_eq!(g.component(1), [0.25, 0.5]);
        // FORTRAN exponents: without a letter, and with D.
        assert_eq!(g.component(5), [1e-100, 3.0]);
        assert_eq!(g.component_names(), ["f2", "f3", "f4", "f6", "f7", "f8"]);
        assert!(f.request(3).is_none());
    }

    #[test]
    fn values_may_wrap_over_lines_and_files_may_have_no_requests() {
        let wrapped = SMALL.replace(
            "  -1.00000E+00  2.50000E-01  0.00000E+00",
            "  -1.00000E+00  2.50000E-01\n  0.00000E+00",
        );
        let f = parse(&wrapped).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(f.request(7).map(|r| r.component(2)), Some(vec![0.0, 0.0]));
        let none = " A.R3\nSOLIDWORKS Motion Mechanism\n    0     M_KGS_N_RACA 1.0E+00\n   0.00000E+00\n   0.00000E+00\n   5.00000E-03\n";
        let f = parse(none).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(f.times, [0.0, 0.0, 0.005]);
        assert!(f.requests.is_empty());
    }

    #[test]
    fn malformed_files_are_located_errors() {
        let first = |text: &str| -> (u32, u32, String) {
            match parse(text) {
                Ok(_) => panic!("no error for {text:?}"),
                Err(d) => {
                    let e = &d.0[0];
                    let s = e.span.unwrap_or_default();
                    (s.line, s.col, e.message.clone())
                }
            }
        };
        // A truncated block.
        let cut: String = SMALL.lines().take(11).collect::<Vec<_>>().join("\n");
        let (line, _, msg) = first(&cut);
        assert_eq!(line, 11);
        assert!(msg.contains("at time 0.01"), "{msg}");
        // A bad number.
        let bad = SMALL.replace("1.99000E+00", "1.99x00E+00");
        let (line, col, msg) = first(&bad);
        assert_eq!((line, col), (11, 4));
        assert_eq!(msg, "'1.99x00E+00' is not a number");
        // A request description with 4 integers.
        let short = SMALL.replace("101             3", "101");
        let (line, _, msg) = first(&short);
        assert_eq!(line, 4);
        assert!(msg.contains("5 integers"), "{msg}");
        // Too many values in a block.
        let long = SMALL.replace("1.00000-100", "1.0 2.0");
        assert_eq!(first(&long).0, 9);
        assert_eq!(
            first("").2,
            "the request file ends where the header line was expected"
        );
        assert_eq!(
            first(" A.R3\n").2,
            "the request file ends where the title line was expected"
        );
    }

    #[test]
    fn fortran_numbers() {
        assert_eq!(fortran_number("-2.39187E-01"), Some(-0.239187));
        assert_eq!(fortran_number("1.5D+02"), Some(150.0));
        assert_eq!(fortran_number("-1.5-100"), Some(-1.5e-100));
        assert_eq!(fortran_number("2.0+100"), Some(2.0e100));
        assert_eq!(fortran_number("E-5"), None);
        assert_eq!(fortran_number("-"), None);
        assert_eq!(fortran_number("NaN"), None);
    }
}
