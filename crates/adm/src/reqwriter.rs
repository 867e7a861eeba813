//! Writing Adams request files (`.req`), the counterpart of [`crate::reqfile`]: a header,
//! then one block per output time, streamed (each block is flushed as it is written, so a
//! long run can be followed, and a run that stops leaves every finished output readable).
//!
//! Layout (the FORTRAN formats of files written by Adams Solver, reproduced column for
//! column in [`Precision::Adams`]; see [`crate::reqfile`] for the meaning of each record):
//!
//! | record | FORTRAN format | example |
//! |---|---|---|
//! | 1: tag, date, `0 0 3D` | `1X, A4, 4X, A19, I16, I10, 2X, A2` | ` A.R3    2014-11-18 09:13:44               0         0  3D` |
//! | 2: title | `A80` (blank-padded) | `ADAMS/View model name: test_Revolute_Case01` |
//! | 3: requests, units, scale | `I5, 5X, A12, 1X, 1PE21.15` | `    5     M_KGS_N_RACA 1.000000000000000E+00` |
//! | per request: id, type, I, J, comment size | `I11, 4I14` | `          1             1           201           101            13` |
//! | its comment (absent when the size is 0) | `A(4·size)` | `VELOCITY X Y Z WX WY WZ ` |
//! | per output: time | `1X, 1PE13.5` | `   1.00000E-02` |
//! | then per request, its six values | `1X, 1P6E13.5` | `   2.00000E+00  0.00000E+00 -4.78373E-04 …` |
//!
//! Numbers are written as FORTRAN's `1PEw.d` writes them: one digit before the point, `d`
//! after, exponent `E±dd`, and for exponents of three digits the letter dropped
//! (`1.00000-100`, as FORTRAN does when the exponent does not fit two digits). Negative zero is
//! written as zero. Integers wider than their field are written whole, after one blank.
//!
//! **Precision.** Adams writes `E13.5`: six significant digits, a relative rounding of at
//! most 5·10⁻⁶ of each value. That is the default ([`Precision::Adams`]): files have the
//! column widths tools reading request files by columns expect, and six digits are far
//! finer than any comparison tolerance of results (`linkage compare` defaults to 10⁻³ of a
//! signal's range). [`Precision::Full`] writes `E24.16` (seventeen significant digits, so
//! every `f64` is read back exactly) for files meant only for comparisons between linkage
//! runs. [`crate::reqfile`] reads both (it splits records at blanks).

use crate::reqfile::{RequestFile, RequestHistory, VALUES_PER_REQUEST};
use std::fmt::Write as _;
use std::io::Write;
use std::time::{SystemTime, UNIX_EPOCH};

/// How many digits numbers get.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Precision {
    /// `1PE13.5`, six significant digits: the layout of Adams' files, column for column.
    #[default]
    Adams,
    /// `1PE24.16`, seventeen significant digits: every `f64` reads back exactly.
    Full,
}

impl Precision {
    /// Digits after the point and the field width.
    fn digits_and_width(self) -> (usize, usize) {
        match self {
            Precision::Adams => (5, 13),
            Precision::Full => (16, 24),
        }
    }
}

/// The first three records of a request file.
#[derive(Clone, Debug, PartialEq)]
pub struct RequestFileHeader {
    /// Date and time on line 1, `YYYY-MM-DD HH:MM:SS` as Adams writes it
    /// ([`utc_timestamp`] gives it for the current time).
    pub date: String,
    /// The dataset's title (its first line).
    pub title: String,
    /// The units code of line 3 (`M_KGS_N_RACA`: two characters each for length, mass,
    /// time, force, then `RACA`); one word, not empty.
    pub units: String,
    /// The number after the units (1 for metres, 39.37… for inches: length units per metre).
    pub scale: f64,
}

impl RequestFileHeader {
    /// A header dated now (UTC).
    pub fn now(title: impl Into<String>, units: impl Into<String>, scale: f64) -> Self {
        RequestFileHeader {
            date: utc_timestamp(SystemTime::now()),
            title: title.into(),
            units: units.into(),
            scale,
        }
    }
}

/// One request as described in the header.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RequestDescription {
    pub id: u64,
    /// 1 displacement, 2 velocity, 3 acceleration, 4 force, 5 function request.
    pub type_code: u32,
    /// I and J marker ids (0 for function requests).
    pub i: u64,
    pub j: u64,
    /// The COMMENT (one line; trailing blanks are not kept).
    pub comment: String,
}

impl From<&RequestHistory> for RequestDescription {
    fn from(r: &RequestHistory) -> Self {
        RequestDescription {
            id: r.id,
            type_code: r.type_code,
            i: r.i,
            j: r.j,
            comment: r.comment.clone(),
        }
    }
}

/// Why a request file cannot be written.
#[derive(Debug, thiserror::Error)]
pub enum RequestWriteError {
    #[error("cannot write the request file: {0}")]
    Io(#[from] std::io::Error),
    /// A title, date or comment that would take more than one line.
    #[error("the {what} of a request file must be one line, not {text:?}")]
    LineBreak { what: String, text: String },
    /// Units that the reader could not find again on line 3.
    #[error("the units code of a request file must be one word, not {units:?}")]
    BadUnits { units: String },
    #[error("the scale of a request file must be a finite number, not {scale}")]
    BadScale { scale: f64 },
    /// An output block with another number of requests than the header describes.
    #[error("output at time {}: values of {given} requests given, the file has {expected}", crate::num::time_text(*.time))]
    RequestCount {
        time: f64,
        given: usize,
        expected: usize,
    },
    /// A time or value that is NaN or infinite (nothing of the block is written).
    #[error("output at time {}: {what} is {value}, not a finite number", crate::num::time_text(*.time))]
    NotFinite { time: f64, what: String, value: f64 },
}

/// A request file being written: the header at creation, then [`write_output`] once per
/// output time, then [`finish`].
///
/// [`write_output`]: RequestFileWriter::write_output
/// [`finish`]: RequestFileWriter::finish
pub struct RequestFileWriter<W: Write> {
    out: W,
    precision: Precision,
    /// Request ids, for the messages about values.
    ids: Vec<u64>,
    /// The block being formatted (reused: one allocation for the whole run).
    line: String,
}

impl<W: Write> RequestFileWriter<W> {
    /// Writes the header (records 1–3 and two records per request) and flushes it.
    pub fn new(
        out: W,
        header: &RequestFileHeader,
        requests: &[RequestDescription],
        precision: Precision,
    ) -> Result<Self, RequestWriteError> {
        one_line("date", &header.date)?;
        one_line("title", &header.title)?;
        if header.units.is_empty() || header.units.contains(char::is_whitespace) {
            return Err(RequestWriteError::BadUnits {
                units: header.units.clone(),
            });
        }
        if !header.scale.is_finite() {
            return Err(RequestWriteError::BadScale {
                scale: header.scale,
            });
        }
        for r in requests {
            one_line(&format!("comment of request {}", r.id), &r.comment)?;
        }
        let mut s = String::new();
        let _ = writeln!(s, " A.R3    {:<19}{:>16}{:>10}  3D", header.date, 0, 0);
        let _ = writeln!(s, "{:<80}", header.title.trim_end());
        push_integer(&mut s, requests.len() as u64, 5);
        let _ = write!(s, "     {:>12} ", header.units);
        push_fortran_e(&mut s, header.scale, 15, 21);
        s.push('\n');
        for r in requests {
            push_integer(&mut s, r.id, 11);
            for v in [u64::from(r.type_code), r.i, r.j] {
                push_integer(&mut s, v, 14);
            }
            let comment = r.comment.trim_end();
            let words = comment.chars().count().div_ceil(4);
            push_integer(&mut s, words as u64, 14);
            s.push('\n');
            if words > 0 {
                let _ = writeln!(s, "{comment:<0$}", 4 * words);
            }
        }
        let mut writer = RequestFileWriter {
            out,
            precision,
            ids: requests.iter().map(|r| r.id).collect(),
            line: s,
        };
        writer.emit()?;
        Ok(writer)
    }

    /// Writes the output block of `time`: the time, then each request's six values
    /// (`values[k]` for the k-th request of the header), and flushes. Nothing is written
    /// when the count is wrong or a number is not finite.
    pub fn write_output(
        &mut self,
        time: f64,
        values: &[[f64; VALUES_PER_REQUEST]],
    ) -> Result<(), RequestWriteError> {
        if values.len() != self.ids.len() {
            return Err(RequestWriteError::RequestCount {
                time,
                given: values.len(),
                expected: self.ids.len(),
            });
        }
        if !time.is_finite() {
            return Err(RequestWriteError::NotFinite {
                time,
                what: "the time".into(),
                value: time,
            });
        }
        for (id, six) in self.ids.iter().zip(values) {
            if let Some(c) = six.iter().position(|v| !v.is_finite()) {
                return Err(RequestWriteError::NotFinite {
                    time,
                    what: format!("value {} of request {id}", c + 1),
                    value: six[c],
                });
            }
        }
        let (digits, width) = self.precision.digits_and_width();
        self.line.clear();
        self.line.push(' ');
        push_fortran_e(&mut self.line, time, digits, width);
        self.line.push('\n');
        for six in values {
            self.line.push(' ');
            for &v in six {
                push_fortran_e(&mut self.line, v, digits, width);
            }
            self.line.push('\n');
        }
        self.emit()
    }

    /// Flushes and gives the output back.
    pub fn finish(mut self) -> Result<W, RequestWriteError> {
        self.out.flush()?;
        Ok(self.out)
    }

    /// Writes and flushes the formatted text.
    fn emit(&mut self) -> Result<(), RequestWriteError> {
        self.out.write_all(self.line.as_bytes())?;
        self.out.flush()?;
        Ok(())
    }
}

/// Writes a whole [`RequestFile`] (e.g. one read by [`crate::reqfile`]) with `date`.
pub fn write_request_file<W: Write>(
    out: W,
    file: &RequestFile,
    date: &str,
    precision: Precision,
) -> Result<W, RequestWriteError> {
    let header = RequestFileHeader {
        date: date.to_string(),
        title: file.title.clone(),
        units: file.units.clone(),
        scale: file.scale,
    };
    let requests: Vec<RequestDescription> = file.requests.iter().map(Into::into).collect();
    let mut w = RequestFileWriter::new(out, &header, &requests, precision)?;
    let mut block = vec![[0.0; VALUES_PER_REQUEST]; file.requests.len()];
    for (k, &t) in file.times.iter().enumerate() {
        for (slot, r) in block.iter_mut().zip(&file.requests) {
            *slot = r.values.get(k).copied().unwrap_or([f64::NAN; 6]);
        }
        w.write_output(t, &block)?;
    }
    w.finish()
}

/// `YYYY-MM-DD HH:MM:SS` in UTC (Adams writes local time; linkage has no time zone data).
pub fn utc_timestamp(t: SystemTime) -> String {
    let secs = t
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| d.as_secs() as i64);
    let (days, rem) = (secs.div_euclid(86_400), secs.rem_euclid(86_400));
    let (y, m, d) = civil_from_days(days);
    format!(
        "{y:04}-{m:02}-{d:02} {:02}:{:02}:{:02}",
        rem / 3600,
        rem / 60 % 60,
        rem % 60
    )
}

/// Proleptic Gregorian date of `days` after 1970-01-01 (counting 400-year eras of 146 097
/// days from 0000-03-01, so that leap days fall at the end of a year).
fn civil_from_days(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let month = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    let year = yoe + era * 400 + i64::from(month <= 2);
    (year, month, day)
}

fn one_line(what: &str, text: &str) -> Result<(), RequestWriteError> {
    if text.contains(['\n', '\r']) {
        return Err(RequestWriteError::LineBreak {
            what: what.to_string(),
            text: text.to_string(),
        });
    }
    Ok(())
}

/// `Iw`: right-justified in `width` columns; wider numbers after one blank.
fn push_integer(s: &mut String, v: u64, width: usize) {
    let digits = v.checked_ilog10().unwrap_or(0) as usize + 1;
    if digits >= width {
        s.push(' ');
    }
    let _ = write!(s, "{v:>width$}");
}

/// `1PEw.d` with `d = digits`, right-justified in `width` columns: `-1.23456E-05`, and
/// `1.23456-100` for three-digit exponents.
fn push_fortran_e(s: &mut String, v: f64, digits: usize, width: usize) {
    // Negative zero as zero; Rust rounds the mantissa and carries into the exponent.
    let v = if v == 0.0 { 0.0 } else { v };
    let text = format!("{v:.digits$e}");
    let (mantissa, exponent) = text.split_once('e').unwrap_or((&text, "0"));
    let exponent: i32 = exponent.parse().unwrap_or(0);
    let sign = if exponent < 0 { '-' } else { '+' };
    let field = if exponent.abs() < 100 {
        format!("{mantissa}E{sign}{:02}", exponent.abs())
    } else {
        format!("{mantissa}{sign}{:03}", exponent.abs())
    };
    let _ = write!(s, "{field:>width$}");
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reqfile::parse_request_file;
    use std::sync::Arc;

    fn e(v: f64, p: Precision) -> String {
        let (d, w) = p.digits_and_width();
        let mut s = String::new();
        push_fortran_e(&mut s, v, d, w);
        s
    }

    #[test]
    fn numbers_are_written_as_fortran_writes_them() {
        let a = Precision::Adams;
        assert_eq!(e(0.0, a), "  0.00000E+00");
        assert_eq!(e(-0.0, a), "  0.00000E+00");
        assert_eq!(e(2.0, a), "  2.00000E+00");
        assert_eq!(e(-std::f64::consts::FRAC_1_SQRT_2, a), " -7.07107E-01");
        assert_eq!(e(-4.78373e-4, a), " -4.78373E-04");
        assert_eq!(e(180.0, a), "  1.80000E+02");
        // Rounding carries into the exponent.
        assert_eq!(e(9.999_996, a), "  1.00000E+01");
        // Three-digit exponents drop the letter, as in FORTRAN.
        assert_eq!(e(1e-100, a), "  1.00000-100");
        assert_eq!(e(-2.5e300, a), " -2.50000+300");
        assert_eq!(e(5e-324, a), "  4.94066-324");
        let f = Precision::Full;
        assert_eq!(e(0.1, f), "  1.0000000000000001E-01");
        assert_eq!(e(-1.0 / 3.0, f), " -3.3333333333333331E-01");
        assert_eq!(e(-1e-100, f), " -1.0000000000000000-100");
        for v in [0.1, -1.0 / 3.0, 1e-100, f64::MAX, f64::MIN_POSITIVE] {
            assert_eq!(
                crate::reqfile::parse_request_file(
                    Arc::from("t"),
                    &format!(" A.R3\nT\n    0     M_KGS_N_RACA 1.0E+00\n{}\n", e(v, f))
                )
                .map(|r| r.times),
                Ok(vec![v])
            );
        }
    }

    #[test]
    fn integers_keep_a_blank_between_them() {
        let mut s = String::new();
        push_integer(&mut s, 7, 5);
        push_integer(&mut s, 12_345_678_901_234, 14);
        push_integer(&mut s, 123_456_789_012_345, 14);
        assert_eq!(s, "    7 12345678901234 123456789012345");
    }

    #[test]
    fn dates_are_utc_calendar_dates() {
        let at = |s: u64| utc_timestamp(UNIX_EPOCH + std::time::Duration::from_secs(s));
        assert_eq!(at(0), "1970-01-01 00:00:00");
        assert_eq!(at(1_416_302_024), "2014-11-18 09:13:44");
        assert_eq!(at(951_782_400), "2000-02-29 00:00:00");
        assert_eq!(at(4_107_542_399), "2100-02-28 23:59:59");
    }

    fn header() -> RequestFileHeader {
        RequestFileHeader {
            date: "2014-11-18 09:13:44".into(),
            title: "ADAMS/View model name: test_Revolute_Case01".into(),
            units: "M_KGS_N_RACA".into(),
            scale: 1.0,
        }
    }

    #[test]
    fn the_header_has_adams_columns() {
        let reqs = [
            RequestDescription {
                id: 1,
                type_code: 1,
                i: 201,
                j: 101,
                comment: "DISPLACEMENT: X Y Z PSI THETA PHI (body-fixed-3-1-3)".into(),
            },
            RequestDescription {
                id: 2,
                type_code: 2,
                i: 201,
                j: 101,
                comment: "VELOCITY X Y Z WX WY WZ".into(),
            },
            RequestDescription {
                id: 4,
                type_code: 5,
                i: 0,
                j: 0,
                comment: String::new(),
            },
        ];
        let w = RequestFileWriter::new(Vec::new(), &header(), &reqs, Precision::Adams)
            .unwrap_or_else(|e| panic!("{e}"));
        let text = String::from_utf8(w.finish().unwrap_or_else(|e| panic!("{e}")))
            .unwrap_or_else(|e| panic!("{e}"));
        let expected = " A.R3    2014-11-18 09:13:44               0         0  3D
ADAMS/View model name: test_Revolute_Case01                                     
    3     M_KGS_N_RACA 1.000000000000000E+00
          1             1           201           101            13
DISPLACEMENT: X Y Z PSI THETA PHI (body-fixed-3-1-3)
          2             2           201           101             6
VELOCITY X Y Z WX WY WZ 
          4             5             0             0             0
";
        assert_eq!(text, expected);
    }

    #[test]
    fn blocks_are_flushed_and_read_back() {
        /// Counts flushes.
        struct Counting(Vec<u8>, usize);
        impl Write for Counting {
            fn write(&mut self, b: &[u8]) -> std::io::Result<usize> {
                self.0.write(b)
            }
            fn flush(&mut self) -> std::io::Result<()> {
                self.1 += 1;
                Ok(())
            }
        }
        let reqs = [RequestDescription {
            id: 9,
            type_code: 5,
            i: 0,
            j: 0,
            comment: "ABCDE".into(),
        }];
        let mut w =
            RequestFileWriter::new(Counting(Vec::new(), 0), &header(), &reqs, Precision::Adams)
                .unwrap_or_else(|e| panic!("{e}"));
        let six = [1.0, -2.0, 3e-100, -4e150, 5.5, 0.0];
        w.write_output(0.0, &[six])
            .unwrap_or_else(|e| panic!("{e}"));
        w.write_output(0.01, &[six])
            .unwrap_or_else(|e| panic!("{e}"));
        let Counting(bytes, flushes) = w.finish().unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(flushes, 4);
        let text = String::from_utf8(bytes).unwrap_or_else(|e| panic!("{e}"));
        assert!(text.contains("\nABCDE   \n"), "{text}");
        assert!(text.ends_with(
            "   1.00000E-02\n   1.00000E+00 -2.00000E+00  3.00000-100 -4.00000+150  5.50000E+00  0.00000E+00\n"
        ), "{text}");
        let f = parse_request_file(Arc::from("t"), &text).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(f.times, [0.0, 0.01]);
        assert_eq!(f.requests[0].comment, "ABCDE");
        assert_eq!(f.requests[0].values, [six, six]);
    }

    #[test]
    fn bad_values_write_nothing() {
        let reqs = [RequestDescription {
            id: 3,
            type_code: 1,
            i: 1,
            j: 0,
            comment: String::new(),
        }];
        let mut w = RequestFileWriter::new(Vec::new(), &header(), &reqs, Precision::Adams)
            .unwrap_or_else(|e| panic!("{e}"));
        let before = w.out.len();
        let err = w
            .write_output(1.0, &[[0.0, f64::NAN, 0.0, 0.0, 0.0, 0.0]])
            .err()
            .map(|e| e.to_string());
        assert_eq!(
            err.as_deref(),
            Some("output at time 1: value 2 of request 3 is NaN, not a finite number")
        );
        assert!(matches!(
            w.write_output(1.0, &[]),
            Err(RequestWriteError::RequestCount {
                given: 0,
                expected: 1,
                ..
            })
        ));
        assert!(matches!(
            w.write_output(f64::INFINITY, &[[0.0; 6]]),
            Err(RequestWriteError::NotFinite { .. })
        ));
        assert_eq!(w.out.len(), before);
        let mut h = header();
        h.title = "two\nlines".into();
        assert!(matches!(
            RequestFileWriter::new(Vec::new(), &h, &reqs, Precision::Adams),
            Err(RequestWriteError::LineBreak { .. })
        ));
        let mut h = header();
        h.units = "M KG".into();
        assert!(matches!(
            RequestFileWriter::new(Vec::new(), &h, &reqs, Precision::Adams),
            Err(RequestWriteError::BadUnits { .. })
        ));
    }
}
