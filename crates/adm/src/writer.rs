//! Writing a dataset back: new part poses (and, by [`write_changes`], new numbers of any
//! statement's arguments, `writer/arguments.rs`) patched into the original text.
//!
//! Contract:
//! - [`write_part_poses`] returns the original text with only the numbers of the listed parts'
//!   `QG` / `REULER` / `XG` / `ZG` replaced (and, where an argument is missing, a new
//!   continuation line inserted). Every other byte — comments, blank lines, line endings
//!   (`\r\n`, `\n` or a lone `\r`), argument order, spacing, everything after `END` — is kept.
//! - A number is replaced as a whole token, found at its span: optional sign, digits with an
//!   optional `.`, an optional exponent (`E-04`), an optional `D` degree suffix (also when the
//!   `D` was written detached, `90 D`, which the reader accepts with a warning). The token read
//!   there must be the number the reader saw, otherwise nothing is written.
//! - New numbers are written so that they read back as the same `f64` (shortest round-trip
//!   form); angles are written in degrees with the `D` suffix.
//! - The writer re-reads its own output and checks that every listed part reads back with the
//!   requested pose; a mismatch is an error, never a silently wrong file.
//! - [`write_atomically`] writes straight to a target that is not a regular file (a device, a
//!   FIFO: `/dev/stdout`), and otherwise
//!   replaces a file through a temporary file in the same directory and a
//!   rename, so a failure never leaves half a file.

use crate::diagnostic::{Diagnostic, Diagnostics, Span};
use crate::statement::{Statement, Value};
use crate::typed::{Dataset, Part};
use std::fs;
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

mod arguments;
pub use arguments::{ArgumentValues, NewValue};

/// New pose of a part's BCS: origin in ground and body 3-1-3 Euler angles in radians.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PartPose {
    /// Index in [`Dataset::statements`] of the `PART` statement (its `header.statement`).
    pub statement: usize,
    /// New `QG`: origin of the BCS in ground coordinates (model length units).
    pub qg: [f64; 3],
    /// New orientation of the BCS as body-fixed 3-1-3 angles (ψ, θ, φ) in radians,
    /// `A = Rz(ψ)·Rx(θ)·Rz(φ)`.
    pub reuler: [f64; 3],
}

/// The dataset text with only the given parts' QG/REULER changed; everything else
/// byte-identical.
///
/// For each pose:
/// - `QG`: every `QG = a, b, c` of the statement gets its three numbers replaced in place (a
///   repeated argument is rewritten too, so that no copy contradicts the new pose); without
///   `QG`, a continuation line `, QG = x, y, z` is added.
/// - Orientation:
///   - with `REULER`: its numbers are replaced (in degrees, `D` suffix); an `XG`/`ZG` given as
///     well is rewritten consistently;
///   - with `XG` and/or `ZG` but no `REULER`: no `REULER` is added (readers that prefer it
///     would then ignore the points, and the file would carry two orientations). Instead
///     `ZG = QG + z` and `XG = QG + x` are written, where `x`, `z` are the first and third
///     columns of `A = Rz(ψ)·Rx(θ)·Rz(φ)`; the one of the two that is missing is added as a
///     new continuation line, because `XG` or `ZG` alone does not fix the orientation;
///   - with neither: a continuation line `, REULER = ψD, θD, φD` is added.
/// - New lines go right after the statement's last physical line, with that line's ending
///   (the file's first line ending when the statement is on the last line and that line has
///   none). A statement closed by `;` gets the new arguments written just before the `;`.
///
/// Errors (every one found is returned; nothing is written then): a statement index out of
/// range or not a PART, the GROUND part, a pose given twice for one statement, a non-finite
/// value, a number whose text cannot be found at its span, or (a bug) output that does not
/// read back with the requested poses.
pub fn write_part_poses(ds: &Dataset, poses: &[PartPose]) -> Result<String, Diagnostics> {
    write_changes(ds, poses, &[])
}

/// [`write_part_poses`] together with new numbers for other statements' arguments
/// ([`ArgumentValues`]: an FE_PART's `COORDINATES`, a marker's `QP`/`REULER`, a FLEX_BODY's
/// `QG`/`REULER`/`DMODE`; contract in `writer/arguments.rs`). An edit of an argument
/// that a part pose also edits is an error (two changes of one number).
pub fn write_changes(
    ds: &Dataset,
    poses: &[PartPose],
    arguments: &[ArgumentValues],
) -> Result<String, Diagnostics> {
    if poses.is_empty() && arguments.is_empty() {
        return Ok(ds.text.clone());
    }
    let lines = LineTable::new(&ds.text);
    let mut edits: Vec<Edit> = Vec::new();
    let mut errors: Vec<Diagnostic> = Vec::new();
    let mut done: Vec<usize> = Vec::new();
    for pose in poses {
        if done.contains(&pose.statement) {
            let span = ds.statements.get(pose.statement).map(|s| s.span);
            errors.push(error(
                ds,
                span,
                format!(
                    "statement {} is given more than one new pose",
                    pose.statement
                ),
            ));
            continue;
        }
        done.push(pose.statement);
        let mut planner = Planner {
            ds,
            lines: &lines,
            edits: Vec::new(),
            errors: Vec::new(),
        };
        planner.plan(pose);
        edits.append(&mut planner.edits);
        errors.append(&mut planner.errors);
    }
    let mut planner = Planner {
        ds,
        lines: &lines,
        edits: Vec::new(),
        errors: Vec::new(),
    };
    for change in arguments {
        planner.plan_argument(change);
    }
    edits.append(&mut planner.edits);
    errors.append(&mut planner.errors);
    if !errors.is_empty() {
        return Err(Diagnostics(errors));
    }
    let text = apply_edits(ds, edits)?;
    verify(ds, &text, poses, arguments)?;
    Ok(text)
}

/// Writes `text` to `path` atomically (temporary file in the same directory, then rename), so
/// a failure never leaves half a file.
///
/// The temporary file is created next to the target (a rename is only atomic within one file
/// system), flushed to disk, given the permissions of the file it replaces (if any), then
/// renamed over the target. When `path` is a symbolic link, the file it points to is
/// replaced and the link kept. On failure the temporary file is removed and the target is
/// untouched.
pub fn write_atomically(path: &Path, text: &str) -> io::Result<()> {
    // A device, FIFO or terminal (`/dev/stdout`, `<(…)`) cannot be replaced: write to it.
    if fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir()) {
        let mut out = fs::OpenOptions::new().write(true).open(path)?;
        out.write_all(text.as_bytes())?;
        return out.flush();
    }
    let target = resolve_symlink(path)?;
    let name = target.file_name().ok_or_else(|| {
        io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("{} does not name a file", path.display()),
        )
    })?;
    let dir = match target.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let (tmp, mut file) = create_temporary(&dir, &name.to_string_lossy())?;
    let result = (|| {
        file.write_all(text.as_bytes())?;
        if let Ok(meta) = fs::metadata(&target) {
            file.set_permissions(meta.permissions())?;
        }
        file.sync_all()?;
        drop(file);
        fs::rename(&tmp, &target)
    })();
    if let Err(e) = result {
        // Best effort: the temporary file is ours and useless now.
        let _ = fs::remove_file(&tmp);
        return Err(e);
    }
    sync_directory(&dir);
    Ok(())
}

// ---- planning ----------------------------------------------------------------------------

/// Replace `start..end` of the original text by `text` (an insertion when `start == end`).
#[derive(Clone, Debug, PartialEq)]
struct Edit {
    start: usize,
    end: usize,
    text: String,
    /// Where the edit comes from, for the overlap diagnostic.
    span: Span,
}

struct Planner<'a> {
    ds: &'a Dataset,
    lines: &'a LineTable,
    edits: Vec<Edit>,
    errors: Vec<Diagnostic>,
}

impl<'a> Planner<'a> {
    /// The statement at `index`, or an error kept for the caller when there is none.
    fn statement_at(&mut self, index: usize) -> Option<&'a Statement> {
        let ds = self.ds;
        let st = ds.statements.get(index);
        if st.is_none() {
            let msg = format!(
                "statement index {index} is out of range (the dataset has {} statements)",
                ds.statements.len()
            );
            self.errors.push(error(ds, None, msg));
        }
        st
    }

    fn plan(&mut self, pose: &PartPose) {
        let ds = self.ds;
        let Some(st) = self.statement_at(pose.statement) else {
            return;
        };
        let Some(part) = ds
            .parts
            .iter()
            .chain(&ds.point_masses)
            .find(|p| p.header.statement == pose.statement)
        else {
            let msg = format!(
                "statement {} ({}) is not a PART; only parts can be given a new pose",
                pose.statement,
                statement_label(st)
            );
            self.errors.push(error(ds, Some(st.span), msg));
            return;
        };
        if part.ground {
            let msg = format!(
                "{} is the GROUND part; its frame is the ground frame and cannot be moved",
                part.header.name
            );
            self.errors.push(error(ds, Some(st.span), msg));
            return;
        }
        if pose.qg.iter().chain(&pose.reuler).any(|v| !v.is_finite()) {
            let msg = format!(
                "the new pose of {} has a non-finite value (QG = {:?}, REULER = {:?})",
                part.header.name, pose.qg, pose.reuler
            );
            self.errors.push(error(ds, Some(st.span), msg));
            return;
        }

        let mut new_lines: Vec<String> = Vec::new();
        // Each coordinate is rounded to WRITE_RESOLUTION of its magnitude (at least the
        // length unit), so no rounding noise is written.
        let position = |v: f64| format_real(resolved(v, WRITE_RESOLUTION * v.abs().max(1.0)));
        let qg_text = pose.qg.map(position);
        if !self.replace_all(st, part, "QG", &qg_text) {
            new_lines.push(format!(", QG = {}", qg_text.join(", ")));
        }

        let axes = euler313_matrix(pose.reuler);
        let point = |axis: usize| {
            let mut p = pose.qg;
            for (k, c) in p.iter_mut().enumerate() {
                *c += axes[k][axis];
            }
            p.map(position)
        };
        let xg_text = point(0);
        let zg_text = point(2);
        let angle_quantum = WRITE_RESOLUTION * 360.0;
        let reuler_text = pose
            .reuler
            .map(|a| format!("{}D", format_real(resolved(a.to_degrees(), angle_quantum))));
        if self.replace_all(st, part, "REULER", &reuler_text) {
            self.replace_all(st, part, "XG", &xg_text);
            self.replace_all(st, part, "ZG", &zg_text);
        } else if st.arg("XG").is_some() || st.arg("ZG").is_some() {
            if !self.replace_all(st, part, "XG", &xg_text) {
                new_lines.push(format!(", XG = {}", xg_text.join(", ")));
            }
            if !self.replace_all(st, part, "ZG", &zg_text) {
                new_lines.push(format!(", ZG = {}", zg_text.join(", ")));
            }
        } else {
            new_lines.push(format!(", REULER = {}", reuler_text.join(", ")));
        }

        if !new_lines.is_empty() {
            self.insert_arguments(st, &new_lines);
        }
    }

    /// Replaces the three numbers of every `key = a, b, c` of the statement by `texts`.
    /// Whether the statement has the argument at all.
    fn replace_all(&mut self, st: &Statement, part: &Part, key: &str, texts: &[String; 3]) -> bool {
        let mut found = false;
        for arg in st.args.iter().filter(|a| a.key == key) {
            found = true;
            if arg.values.len() != 3 {
                let msg = format!(
                    "'{key}' of {} has {} values instead of 3; cannot rewrite it",
                    part.header.name,
                    arg.values.len()
                );
                self.errors.push(error(self.ds, Some(arg.span), msg));
                continue;
            }
            for (value, text) in arg.values.iter().zip(texts) {
                match value {
                    Value::Number {
                        value,
                        degrees,
                        span,
                    } => match self
                        .lines
                        .number_range(&self.ds.text, *span, *value, *degrees)
                    {
                        Some((start, end)) => self.edits.push(Edit {
                            start,
                            end,
                            text: text.clone(),
                            span: *span,
                        }),
                        None => {
                            let msg = format!(
                                "the number of '{key}' of {} is not found in the text at its \
                                 position; cannot rewrite it",
                                part.header.name
                            );
                            self.errors.push(error(self.ds, Some(*span), msg));
                        }
                    },
                    other => {
                        let msg = format!(
                            "'{key}' of {} has a value that is not a number; cannot rewrite it",
                            part.header.name
                        );
                        self.errors.push(error(self.ds, Some(other.span()), msg));
                    }
                }
            }
        }
        found
    }

    /// Adds `args` (each `, KEY = …`) at the end of the statement: as new continuation lines
    /// after its last physical line, or before the `;` that closes it.
    fn insert_arguments(&mut self, st: &Statement, args: &[String]) {
        let text = &self.ds.text;
        let last = st.lines.1;
        let Some(line) = self.lines.line(last) else {
            let msg = format!(
                "{} ends at line {last}, which is not in the text",
                statement_label(st)
            );
            self.errors.push(error(self.ds, Some(st.span), msg));
            return;
        };
        // The statement's piece of its last line starts at the keyword when it has one line.
        let from = if st.lines.0 == last {
            self.lines
                .byte_of(text, st.span)
                .unwrap_or(line.start)
                .max(line.start)
        } else {
            line.start
        };
        let content = text.get(from..line.content_end).unwrap_or("");
        if let Some(semi) = closing_semicolon(content) {
            // `PART/3, MASS = 1; MARKER/…`: write the arguments into the statement itself.
            let code_end = from + content.get(..semi).unwrap_or("").trim_end().len();
            self.edits.push(Edit {
                start: code_end,
                end: code_end,
                text: args.concat(),
                span: st.span,
            });
            return;
        }
        let ending = match text.get(line.content_end..line.end) {
            Some(e) if !e.is_empty() => e,
            _ => self.lines.first_ending(text),
        };
        let mut inserted = String::new();
        if line.end == line.content_end {
            // Last line of the file without a line ending: start a new line, add none at the end.
            for a in args {
                inserted.push_str(ending);
                inserted.push_str(a);
            }
        } else {
            for a in args {
                inserted.push_str(a);
                inserted.push_str(ending);
            }
        }
        self.edits.push(Edit {
            start: line.end,
            end: line.end,
            text: inserted,
            span: st.span,
        });
    }
}

/// Byte offset of a `;` (outside double quotes, before any `!` comment) in a line's code.
fn closing_semicolon(code: &str) -> Option<usize> {
    let mut in_quote = false;
    for (k, c) in code.char_indices() {
        match c {
            '"' => in_quote = !in_quote,
            '!' if !in_quote => return None,
            ';' if !in_quote => return Some(k),
            _ => {}
        }
    }
    None
}

/// Applies non-overlapping edits to the original text.
fn apply_edits(ds: &Dataset, mut edits: Vec<Edit>) -> Result<String, Diagnostics> {
    edits.sort_by_key(|e| (e.start, e.end));
    let text = &ds.text;
    let mut out = String::with_capacity(text.len() + 64 * edits.len());
    let mut at = 0;
    for e in &edits {
        let (Some(keep), true) = (text.get(at..e.start), e.end >= e.start) else {
            let msg = "internal error: two changes of the dataset text overlap";
            return Err(Diagnostics(vec![error(ds, Some(e.span), msg)]));
        };
        out.push_str(keep);
        out.push_str(&e.text);
        at = e.end;
    }
    out.push_str(text.get(at..).unwrap_or(""));
    Ok(out)
}

/// Re-reads the written text and checks that every posed part has its new pose.
fn verify(
    ds: &Dataset,
    text: &str,
    poses: &[PartPose],
    arguments: &[ArgumentValues],
) -> Result<(), Diagnostics> {
    let written = crate::parse_dataset(ds.file.clone(), text).map_err(|d| {
        let mut all = vec![error(
            ds,
            None,
            "internal error: the rewritten dataset does not read back",
        )];
        all.extend(d.0);
        Diagnostics(all)
    })?;
    let mut errors = arguments::check_arguments(ds, &written, arguments);
    for pose in poses {
        let old = ds
            .parts
            .iter()
            .chain(&ds.point_masses)
            .find(|p| p.header.statement == pose.statement);
        let new = written
            .parts
            .iter()
            .chain(&written.point_masses)
            .find(|p| p.header.statement == pose.statement);
        let (Some(old), Some(new)) = (old, new) else {
            errors.push(error(
                ds,
                None,
                format!(
                    "internal error: statement {} is no longer a PART",
                    pose.statement
                ),
            ));
            continue;
        };
        if !pose_matches(new, pose) || old.header.id != new.header.id {
            let msg = format!(
                "internal error: {} does not read back with its new pose",
                old.header.name
            );
            errors.push(error(ds, Some(old.header.span), msg));
        }
    }
    if errors.is_empty() {
        Ok(())
    } else {
        Err(Diagnostics(errors))
    }
}

/// Whether a re-read part has the pose (to a tolerance far above the round-trip error).
fn pose_matches(part: &Part, pose: &PartPose) -> bool {
    let close = |a: &[f64; 3], b: &[f64; 3]| {
        a.iter()
            .zip(b)
            .all(|(x, y)| (x - y).abs() <= 1e-9 * x.abs().max(y.abs()).max(1.0))
    };
    let Some(qg) = &part.qg else { return false };
    if !close(&qg.value, &pose.qg) {
        return false;
    }
    let axes = euler313_matrix(pose.reuler);
    // `XG - QG` loses the digits of the unit axis that `QG`'s magnitude pushes out.
    let scale = qg.value.iter().fold(1.0_f64, |m, v| m.max(v.abs()));
    let offset = |p: &[f64; 3], axis: usize| {
        (0..3).all(|k| {
            let d = p[k] - qg.value[k];
            (d - axes[k][axis]).abs() <= 1e-9 * scale
        })
    };
    let reuler_ok = part.reuler.as_ref().map(|r| close(&r.value, &pose.reuler));
    let xg_ok = part.xg.as_ref().map(|x| offset(&x.value, 0));
    let zg_ok = part.zg.as_ref().map(|z| offset(&z.value, 2));
    let given = [reuler_ok, xg_ok, zg_ok];
    given.iter().all(|g| g.unwrap_or(true))
        && (reuler_ok.is_some() || (xg_ok.is_some() && zg_ok.is_some()))
}

// ---- text positions ----------------------------------------------------------------------

/// One physical line: byte offsets of its start, of the end of its content, and of the end
/// of its line ending.
#[derive(Clone, Copy, Debug)]
struct Line {
    start: usize,
    content_end: usize,
    end: usize,
}

/// The physical lines of a text, split as the lexer does (`\n`, `\r\n`, lone `\r`).
struct LineTable {
    lines: Vec<Line>,
}

impl LineTable {
    fn new(text: &str) -> Self {
        let bytes = text.as_bytes();
        let mut lines = Vec::new();
        let mut start = 0;
        let mut k = 0;
        while k < bytes.len() {
            match bytes.get(k) {
                Some(b'\n') => {
                    lines.push(Line {
                        start,
                        content_end: k,
                        end: k + 1,
                    });
                    k += 1;
                    start = k;
                }
                Some(b'\r') => {
                    let len = if bytes.get(k + 1) == Some(&b'\n') {
                        2
                    } else {
                        1
                    };
                    lines.push(Line {
                        start,
                        content_end: k,
                        end: k + len,
                    });
                    k += len;
                    start = k;
                }
                _ => k += 1,
            }
        }
        if start < bytes.len() {
            lines.push(Line {
                start,
                content_end: bytes.len(),
                end: bytes.len(),
            });
        }
        LineTable { lines }
    }

    /// Line `number` (1-based).
    fn line(&self, number: u32) -> Option<Line> {
        let index = usize::try_from(number).ok()?.checked_sub(1)?;
        self.lines.get(index).copied()
    }

    /// The first line ending of the text (`"\n"` when it has none).
    fn first_ending<'t>(&self, text: &'t str) -> &'t str {
        self.lines
            .iter()
            .find(|l| l.end > l.content_end)
            .and_then(|l| text.get(l.content_end..l.end))
            .unwrap_or("\n")
    }

    /// Byte offset of a span (1-based line and character column).
    fn byte_of(&self, text: &str, span: Span) -> Option<usize> {
        let line = self.line(span.line)?;
        let content = text.get(line.start..line.content_end)?;
        let col = usize::try_from(span.col).ok()?.checked_sub(1)?;
        let (k, _) = content.char_indices().nth(col)?;
        Some(line.start + k)
    }

    /// Byte range of the number token at `span`, checked against the value the reader got.
    ///
    /// The token is: sign, digits, `.`, digits, exponent, `D` suffix; with `degrees` and no
    /// attached `D`, the blanks and the detached `D` after the number belong to it as well.
    fn number_range(
        &self,
        text: &str,
        span: Span,
        value: f64,
        degrees: bool,
    ) -> Option<(usize, usize)> {
        let start = self.byte_of(text, span)?;
        let line = self.line(span.line)?;
        let rest = text.get(start..line.content_end)?.as_bytes();
        let digits = |from: usize| {
            rest.iter()
                .skip(from)
                .take_while(|b| b.is_ascii_digit())
                .count()
        };
        let mut k = usize::from(matches!(rest.first(), Some(b'+' | b'-')));
        let int_digits = digits(k);
        k += int_digits;
        let mut frac_digits = 0;
        if rest.get(k) == Some(&b'.') {
            frac_digits = digits(k + 1);
            k += 1 + frac_digits;
        }
        if int_digits + frac_digits == 0 {
            return None;
        }
        if matches!(rest.get(k), Some(b'e' | b'E')) {
            let sign = usize::from(matches!(rest.get(k + 1), Some(b'+' | b'-')));
            let exp = digits(k + 1 + sign);
            if exp > 0 {
                k += 1 + sign + exp;
            }
        }
        let body_end = k;
        let mut has_d = false;
        if matches!(rest.get(k), Some(b'd' | b'D')) {
            k += 1;
            has_d = true;
        } else if degrees {
            let mut j = k;
            while matches!(rest.get(j), Some(b' ' | b'\t')) {
                j += 1;
            }
            if matches!(rest.get(j), Some(b'd' | b'D')) {
                k = j + 1;
                has_d = true;
            }
        }
        // The token must end here (as the reader's token did).
        if rest
            .get(k)
            .is_some_and(|b| b.is_ascii_alphanumeric() || matches!(b, b'.' | b'_' | b'$'))
        {
            return None;
        }
        let body: f64 = std::str::from_utf8(rest.get(..body_end)?)
            .ok()?
            .parse()
            .ok()?;
        let read = if has_d { body.to_radians() } else { body };
        (has_d == degrees && read.to_bits() == value.to_bits()).then_some((start, start + k))
    }
}

// ---- numbers and angles ------------------------------------------------------------------

/// The resolution of the numbers a saved dataset holds, relative to their scale (the
/// coordinate's magnitude, at least 1 length unit, or a full turn for angles): below the assembly's tolerances (about 1e-10
/// of the model's size), above f64's rounding noise, so `-7.3E-19` is written `0.0` and
/// `59.99999999999999` is written `60.0`.
pub const WRITE_RESOLUTION: f64 = 1e-12;

/// `v` rounded to the significant digits that `quantum` resolves (unchanged when `quantum`
/// is zero): zero when `|v| < quantum/2`, else `v` with `floor(log10(|v|/quantum)) + 1`
/// significant digits.
fn resolved(v: f64, quantum: f64) -> f64 {
    if quantum.is_nan() || quantum <= 0.0 || !v.is_finite() {
        return v;
    }
    if v.abs() < 0.5 * quantum {
        return 0.0;
    }
    let digits = ((v.abs() / quantum).log10().floor() as i32 + 1).clamp(1, 17) as usize;
    format!("{:.*e}", digits - 1, v).parse().unwrap_or(v)
}

/// A real in a form the reader turns back into the same `f64`: the shortest round-trip
/// digits, with a `.0` when there would be no point, in exponent form (`1.5E-12`) for very
/// small or large magnitudes. Zero (also `-0`) is `0.0`.
fn format_real(v: f64) -> String {
    if v == 0.0 {
        return "0.0".to_string();
    }
    let a = v.abs();
    if (1e-4..1e15).contains(&a) {
        let mut s = format!("{v}");
        if !s.contains('.') {
            s.push_str(".0");
        }
        s
    } else {
        let s = format!("{v:E}");
        match s.split_once('E') {
            Some((mantissa, exp)) if !mantissa.contains('.') => format!("{mantissa}.0E{exp}"),
            _ => s,
        }
    }
}

/// `A = Rz(ψ)·Rx(θ)·Rz(φ)` as rows (`a[row][col]`); its columns are the rotated axes.
fn euler313_matrix([psi, theta, phi]: [f64; 3]) -> [[f64; 3]; 3] {
    let rz = |t: f64| {
        let (s, c) = t.sin_cos();
        [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
    };
    let (s, c) = theta.sin_cos();
    let rx = [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]];
    mat_mul(&mat_mul(&rz(psi), &rx), &rz(phi))
}

fn mat_mul(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let mut out = [[0.0; 3]; 3];
    for (i, row) in out.iter_mut().enumerate() {
        for (j, cell) in row.iter_mut().enumerate() {
            *cell = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    out
}

// ---- helpers -----------------------------------------------------------------------------

fn error(ds: &Dataset, span: Option<Span>, message: impl Into<String>) -> Diagnostic {
    Diagnostic::error(ds.file.clone(), span, message)
}

fn statement_label(st: &Statement) -> String {
    match st.id {
        Some(id) => format!("{}/{id}", st.keyword),
        None => format!("{}/", st.keyword),
    }
}

/// The file a path names, following a symbolic link (so that the link is kept).
fn resolve_symlink(path: &Path) -> io::Result<PathBuf> {
    match fs::symlink_metadata(path) {
        Ok(meta) if meta.file_type().is_symlink() => fs::canonicalize(path),
        _ => Ok(path.to_path_buf()),
    }
}

/// Creates a new, unique temporary file `.<name>.<pid>.<n>.tmp` in `dir`.
fn create_temporary(dir: &Path, name: &str) -> io::Result<(PathBuf, fs::File)> {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let mut last_error = None;
    for _ in 0..100 {
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let tmp = dir.join(format!(".{name}.{}.{n}.tmp", std::process::id()));
        match fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&tmp)
        {
            Ok(file) => return Ok((tmp, file)),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => last_error = Some(e),
            Err(e) => return Err(e),
        }
    }
    Err(last_error.unwrap_or_else(|| io::Error::other("cannot create a temporary file")))
}

/// Flushes the directory entry of the rename to disk where the platform allows it.
fn sync_directory(dir: &Path) {
    #[cfg(unix)]
    if let Ok(d) = fs::File::open(dir) {
        // Best effort: the data is already renamed; a failed directory sync loses nothing
        // that a crash would not lose anyway.
        let _ = d.sync_all();
    }
    #[cfg(not(unix))]
    let _ = dir;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::parse_dataset;
    use crate::typed::{Located, MarkerCarrier};
    use std::f64::consts::PI;
    use std::sync::Arc;

    fn read(text: &str) -> Dataset {
        parse_dataset(Arc::from("t.adm"), text).unwrap_or_else(|e| panic!("{e}"))
    }

    fn part(ds: &Dataset, id: u64) -> &Part {
        ds.parts
            .iter()
            .find(|p| p.header.id == id)
            .unwrap_or_else(|| panic!("no PART/{id}"))
    }

    fn pose(ds: &Dataset, id: u64, qg: [f64; 3], reuler: [f64; 3]) -> PartPose {
        PartPose {
            statement: part(ds, id).header.statement,
            qg,
            reuler,
        }
    }

    fn write(ds: &Dataset, poses: &[PartPose]) -> String {
        write_part_poses(ds, poses).unwrap_or_else(|e| panic!("{e}"))
    }

    fn assert_close(a: [f64; 3], b: [f64; 3], what: &str) {
        for (x, y) in a.iter().zip(&b) {
            // Within the writer's resolution (WRITE_RESOLUTION of a full turn for angles).
            assert!((x - y).abs() <= 1e-11, "{what}: {a:?} != {b:?}");
        }
    }

    fn value(v: &Option<Located<[f64; 3]>>, what: &str) -> [f64; 3] {
        v.as_ref()
            .map(|l| l.value)
            .unwrap_or_else(|| panic!("{what} missing"))
    }

    /// x and z axes of Rz(ψ)·Rx(θ)·Rz(φ), written out independently of `euler313_matrix`.
    fn axes_313([psi, theta, phi]: [f64; 3]) -> ([f64; 3], [f64; 3]) {
        let (sp, cp) = psi.sin_cos();
        let (st, ct) = theta.sin_cos();
        let (sf, cf) = phi.sin_cos();
        let x = [cp * cf - sp * ct * sf, sp * cf + cp * ct * sf, st * sf];
        let z = [sp * st, -cp * st, ct];
        (x, z)
    }

    fn minus(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
    }

    /// The text the writer gives coordinates: WRITE_RESOLUTION of their magnitude.
    fn list(v: [f64; 3]) -> String {
        v.map(|x| format_real(resolved(x, WRITE_RESOLUTION * x.abs().max(1.0))))
            .join(", ")
    }

    /// The text the writer gives angles: degrees to WRITE_RESOLUTION of a turn.
    fn degrees(v: [f64; 3]) -> String {
        v.map(|a| {
            let d = resolved(a.to_degrees(), WRITE_RESOLUTION * 360.0);
            format!("{}D", format_real(d))
        })
        .join(", ")
    }

    const CRLF_DATASET: &[&str] = &[
        "Adams View model name: writer_test", // 1
        "!",                                  // 2
        "!-------------------------------- PARTS --------------------------------!", // 3
        "UNITS/",                             // 4
        ", FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND", // 5
        "!",                                  // 6
        "!   adams_view_name='ground'",       // 7
        "PART/01, GROUND",                    // 8
        "",                                   // 9
        "!   adams_view_name='crank'",        // 10
        "PART/02",                            // 11
        ", MASS = 1.5",                       // 12
        ", CM = 0201",                        // 13
        ", IP = 0.04, 0.1, 0.1",              // 14
        ", QG = -0.282842712474619, 1.0E-04, 0   ! origin", // 15
        "  , REULER = 180D, 90D, 180D",       // 16
        ", EXACT = X:Y",                      // 17
        "!",                                  // 18
        "PART/03, MASS = 2, CM = 0301, QG = 1, 2, 3, REULER = 0.5, 0.25, -0.125 ! inline", // 19
        "PART/04, MASS = 1",                  // 20
        ", CM = 0401",                        // 21
        "!   adams_view_name='rocker'",       // 22
        "PART/05, MASS = 1, CM = 0501",       // 23
        ", QG = 0, 0, 0",                     // 24
        ", ZG = 0, 0, 1",                     // 25
        ", XG = 1, 0, 0",                     // 26
        "PART/06, MASS = 1, QG = 0, 0, 0",    // 27
        ", ZG = 0, 0, 1",                     // 28
        "MARKER/0201, PART = 02, QP = 0, 0, 0", // 29
        ", REULER = 180D, 90D, 180D",         // 30
        "END",                                // 31
        "PART/07, QG = 9, 9, 9 ! after END: never touched", // 32
    ];

    #[test]
    fn crlf_dataset_changes_only_the_posed_numbers() {
        let text = format!("{}\r\n", CRLF_DATASET.join("\r\n"));
        let ds = read(&text);
        let p2 = pose(&ds, 2, [0.1, -2.5e-7, 3.0], [0.3, 1.2, -2.9]);
        let p3 = pose(&ds, 3, [-1e-13, 4.75, 1e16], [-PI, PI / 2.0, 0.0]);
        let p4 = pose(&ds, 4, [1.0, 2.0, 3.0], [0.1, 0.2, 0.3]);
        let p5 = pose(&ds, 5, [10.0, -20.0, 30.5], [0.7, 2.1, -0.4]);
        let p6 = pose(&ds, 6, [-1.0, 0.0, 2.0], [1.0, 0.5, 0.25]);
        let poses = [p2, p3, p4, p5, p6];
        let out = write(&ds, &poses);

        // Line endings: every line still ends with CRLF.
        assert!(out.ends_with("\r\n"));
        assert_eq!(out.matches('\n').count(), out.matches("\r\n").count());
        assert_eq!(out.matches('\r').count(), out.matches("\r\n").count());

        // Typed values read back.
        let new = read(&out);
        for p in &poses {
            let np = new
                .parts
                .iter()
                .find(|q| q.header.statement == p.statement)
                .unwrap_or_else(|| panic!("statement {} lost", p.statement));
            assert_close(value(&np.qg, "QG"), p.qg, "QG");
            let (x, z) = axes_313(p.reuler);
            match np.header.id {
                5 | 6 => {
                    assert!(np.reuler.is_none(), "no REULER added to an XG/ZG part");
                    let q = value(&np.qg, "QG");
                    assert_close(minus(value(&np.xg, "XG"), q), x, "XG axis");
                    assert_close(minus(value(&np.zg, "ZG"), q), z, "ZG axis");
                }
                _ => assert_close(value(&np.reuler, "REULER"), p.reuler, "REULER"),
            }
        }
        assert_eq!(new.parts.len(), ds.parts.len());
        assert_eq!(new.statements.len(), ds.statements.len());
        let marker_values = |d: &Dataset| -> Vec<_> {
            d.markers
                .iter()
                .map(|m| {
                    (
                        m.header.id,
                        m.carrier.map(|c| match c {
                            MarkerCarrier::Part(r) => r.id,
                            _ => 0,
                        }),
                        m.qp.as_ref().map(|l| l.value),
                        m.reuler.as_ref().map(|l| l.value),
                    )
                })
                .collect()
        };
        assert_eq!(
            marker_values(&new),
            marker_values(&ds),
            "markers are untouched"
        );

        // Line by line: the inserted lines, then the changed ones, then all the others.
        let orig: Vec<&str> = text.split("\r\n").collect();
        let mut lines: Vec<&str> = out.split("\r\n").collect();
        // Inserted after line 28 (PART/06's last line) and after line 21 (PART/04's).
        let (x6, _) = axes_313(p6.reuler);
        let xg6 = [p6.qg[0] + x6[0], p6.qg[1] + x6[1], p6.qg[2] + x6[2]];
        assert_eq!(lines.remove(28 + 2), format!(", XG = {}", list(xg6)));
        assert_eq!(lines.remove(21), format!(", QG = {}", list(p4.qg)));
        assert_eq!(
            lines.remove(21),
            format!(", REULER = {}", degrees(p4.reuler))
        );
        assert_eq!(lines.len(), orig.len());

        let at = |n: usize| lines[n - 1];
        assert_eq!(at(15), format!(", QG = {}   ! origin", list(p2.qg)));
        assert_eq!(at(16), format!("  , REULER = {}", degrees(p2.reuler)));
        assert_eq!(
            at(19),
            format!(
                "PART/03, MASS = 2, CM = 0301, QG = {}, REULER = {} ! inline",
                list(p3.qg),
                degrees(p3.reuler)
            )
        );
        let (x5, z5) = axes_313(p5.reuler);
        let shifted = |a: [f64; 3]| [p5.qg[0] + a[0], p5.qg[1] + a[1], p5.qg[2] + a[2]];
        assert_eq!(at(24), format!(", QG = {}", list(p5.qg)));
        assert_eq!(at(25), format!(", ZG = {}", list(shifted(z5))));
        assert_eq!(at(26), format!(", XG = {}", list(shifted(x5))));
        assert_eq!(at(27), format!("PART/06, MASS = 1, QG = {}", list(p6.qg)));
        let (_, z6) = axes_313(p6.reuler);
        let zg6 = [p6.qg[0] + z6[0], p6.qg[1] + z6[1], p6.qg[2] + z6[2]];
        assert_eq!(at(28), format!(", ZG = {}", list(zg6)));
        let changed = [15, 16, 19, 24, 25, 26, 27, 28];
        for (k, (o, n)) in orig.iter().zip(&lines).enumerate() {
            if !changed.contains(&(k + 1)) {
                assert_eq!(o, n, "line {} must be untouched", k + 1);
            }
        }
    }

    #[test]
    fn no_poses_returns_the_text_byte_for_byte() {
        let text = format!("{}\r\n", CRLF_DATASET.join("\r\n"));
        let ds = read(&text);
        assert_eq!(write(&ds, &[]).as_bytes(), text.as_bytes());
        let mixed = "t\r\nPART/1, GROUND\nPART/2, QG = 1, 2, 3\r! c\r\nEND\n\ntrailing";
        let ds = read(mixed);
        assert_eq!(write(&ds, &[]).as_bytes(), mixed.as_bytes());
    }

    #[test]
    fn fortran_style_tokens_and_degree_suffixes_are_replaced_whole() {
        let text = "t\n\
                    PART/1, GROUND\n\
                    PART/2, MATERIAL = \"st\u{e9}el\", QG=-0.282842712474619,1.0E-04,+5.0E-002\n\
                    , REULER = 180D, 90 D, -0.282842712474619d ! keep\n\
                    END\n";
        let ds = read(text);
        assert!(!ds.warnings.is_empty(), "the detached D is warned about");
        let p = pose(&ds, 2, [0.5, -2.0, 1e-12], [0.0, -PI / 2.0, 1.0e-4]);
        let out = write(&ds, &[p]);
        let lines: Vec<&str> = out.lines().collect();
        assert_eq!(
            lines[2],
            "PART/2, MATERIAL = \"st\u{e9}el\", QG=0.5,-2.0,1.0E-12"
        );
        assert_eq!(
            lines[3],
            format!(
                // 1e-4 rad = 0.005729577951308232°, written to WRITE_RESOLUTION of a turn.
                ", REULER = 0.0D, {}D, 0.005729578D ! keep",
                format_real((-PI / 2.0).to_degrees()),
            )
        );
        let new = read(&out);
        assert!(new.warnings.is_empty(), "{:?}", new.warnings);
        let np = part(&new, 2);
        assert_close(value(&np.qg, "QG"), p.qg, "QG");
        assert_close(value(&np.reuler, "REULER"), p.reuler, "REULER");
        assert_eq!(value(&np.qg, "QG"), p.qg, "QG is exact");
    }

    #[test]
    fn numbers_are_written_to_round_trip() {
        assert_eq!(format_real(0.5), "0.5");
        assert_eq!(format_real(-2.0), "-2.0");
        assert_eq!(format_real(-0.0), "0.0");
        assert_eq!(format_real(1e-12), "1.0E-12");
        assert_eq!(resolved(-7.3e-19, 1e-12), 0.0);
        assert_eq!(format_real(resolved(59.99999999999999, 360e-12)), "60.0");
        assert_eq!(resolved(0.123_456_789_012_345_67, 1e-12), 0.123456789012);
        assert_eq!(resolved(1.5, 0.0), 1.5);
        assert_eq!(format_real(-1.5e20), "-1.5E20");
        assert_eq!(format_real(123456.789), "123456.789");
        assert_eq!(format_real(180.0), "180.0");
        for v in [
            0.1,
            -0.282842712474619,
            1.0e-4,
            9.99e-5,
            1e15,
            std::f64::consts::E * 1e-300,
            f64::MAX,
            f64::MIN_POSITIVE,
            12.345678901234567,
        ] {
            let s = format_real(v);
            assert_eq!(s.parse::<f64>().ok(), Some(v), "{s}");
            let ds = read("t\nPART/1, GROUND\nPART/2, QG = 0, 0, 0\n");
            let out = write(&ds, &[pose(&ds, 2, [v, -v, 0.0], [0.0; 3])]);
            // Written to WRITE_RESOLUTION of the part's scale (at least 1 length unit).
            let quantum = WRITE_RESOLUTION * v.abs().max(1.0);
            let back = value(&part(&read(&out), 2).qg, "QG");
            for (b, x) in back.iter().zip([v, -v, 0.0]) {
                assert!((b - x).abs() <= quantum, "{b} vs {x}");
            }
        }
    }

    #[test]
    fn semicolons_lone_cr_and_a_last_line_without_ending() {
        let text = "t\rPART/1, GROUND\rPART/2, MASS=1 ; PART/3, MASS=2\rPART/4, MASS=3";
        let ds = read(text);
        let q = [1.0, 2.0, 3.0];
        let r = [0.0; 3];
        let poses = [pose(&ds, 2, q, r), pose(&ds, 3, q, r), pose(&ds, 4, q, r)];
        let out = write(&ds, &poses);
        let args = ", QG = 1.0, 2.0, 3.0, REULER = 0.0D, 0.0D, 0.0D";
        let expected = format!(
            "t\rPART/1, GROUND\rPART/2, MASS=1{args} ; PART/3, MASS=2\r\
             , QG = 1.0, 2.0, 3.0\r, REULER = 0.0D, 0.0D, 0.0D\r\
             PART/4, MASS=3\r, QG = 1.0, 2.0, 3.0\r, REULER = 0.0D, 0.0D, 0.0D"
        );
        assert_eq!(out, expected);
    }

    #[test]
    fn only_zg_gets_an_xg_and_reuler_with_xg_zg_keeps_them_consistent() {
        let text = "t\nPART/1, GROUND\nPART/2\n, ZG = 0, 0, 1 ! z\n\
                    PART/3, REULER = 0, 0, 0, XG = 1, 0, 0, ZG = 0, 0, 1\nEND\n";
        let ds = read(text);
        let q = [1.0, -1.0, 0.5];
        let r = [0.4, 0.9, -1.3];
        let out = write(&ds, &[pose(&ds, 2, q, r), pose(&ds, 3, q, r)]);
        let new = read(&out);
        let (x, z) = axes_313(r);
        for id in [2, 3] {
            let p = part(&new, id);
            assert_close(value(&p.qg, "QG"), q, "QG");
            assert_close(minus(value(&p.xg, "XG"), q), x, "XG");
            assert_close(minus(value(&p.zg, "ZG"), q), z, "ZG");
        }
        assert!(part(&new, 2).reuler.is_none());
        assert_close(value(&part(&new, 3).reuler, "REULER"), r, "REULER");
        let lines: Vec<&str> = out.lines().collect();
        assert!(lines[3].ends_with(" ! z"), "{}", lines[3]);
        assert!(lines[4].starts_with(", QG = "), "{}", lines[4]);
        assert!(lines[5].starts_with(", XG = "), "{}", lines[5]);
    }

    #[test]
    fn bad_poses_are_errors_not_panics() {
        let text = "t\nUNITS/, SYSTEM = MKS\nPART/1, GROUND\nPART/2, QG = 0, 0, 0\nEND\n";
        let ds = read(text);
        let ok = pose(&ds, 2, [1.0; 3], [0.0; 3]);
        let cases = [
            (
                vec![PartPose {
                    statement: 99,
                    ..ok
                }],
                "out of range",
            ),
            (vec![PartPose { statement: 0, ..ok }], "not a PART"),
            (vec![pose(&ds, 1, [1.0; 3], [0.0; 3])], "GROUND"),
            (vec![ok, ok], "more than one new pose"),
            (
                vec![PartPose {
                    qg: [f64::NAN, 0.0, 0.0],
                    ..ok
                }],
                "non-finite",
            ),
        ];
        for (poses, message) in cases {
            match write_part_poses(&ds, &poses) {
                Ok(_) => panic!("expected an error containing '{message}'"),
                Err(d) => assert!(
                    d.0.iter()
                        .any(|e| e.is_error() && e.message.contains(message)),
                    "{message}: {d}"
                ),
            }
        }
    }

    #[test]
    fn a_dataset_whose_text_does_not_match_its_spans_is_refused() {
        let mut ds = read("t\nPART/1, GROUND\nPART/2, QG = 1, 2, 3\nEND\n");
        ds.text = "t\nPART/1, GROUND\nPART/2, QG = 7, 2, 3\nEND\n".to_string();
        let p = pose(&ds, 2, [0.0; 3], [0.0; 3]);
        assert!(write_part_poses(&ds, &[p]).is_err());
    }

    #[test]
    fn write_atomically_replaces_the_file_and_fails_cleanly() {
        let dir = std::env::temp_dir().join(format!("linkage-writer-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("{e}"));
        let path = dir.join("model.adm");
        write_atomically(&path, "first\r\n").unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(fs::read(&path).ok(), Some(b"first\r\n".to_vec()));
        write_atomically(&path, "second\n").unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(fs::read_to_string(&path).ok().as_deref(), Some("second\n"));
        let names: Vec<_> = fs::read_dir(&dir)
            .unwrap_or_else(|e| panic!("{e}"))
            .filter_map(|e| e.ok().map(|e| e.file_name()))
            .collect();
        assert_eq!(names, vec![std::ffi::OsString::from("model.adm")]);

        let missing = dir.join("no-such-directory").join("model.adm");
        assert!(write_atomically(&missing, "x").is_err());
        assert!(!missing.exists());
        assert!(
            write_atomically(&dir, "x").is_err(),
            "a directory is not replaced"
        );
        let _ = fs::remove_dir_all(&dir);
    }
}
