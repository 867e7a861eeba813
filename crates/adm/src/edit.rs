//! Structural edits of a dataset: change a joint's or a primitive's type, turn a JOINT into a
//! JPRIM, point a joint at another marker, add markers and primitives.
//!
//! Contract:
//! - [`apply_edits`] returns the original text with only the listed changes made; every other
//!   byte (comments, blank lines, line endings, spacing, argument order, everything after
//!   `END`) is kept.
//! - A type keyword is replaced as a whole word at the position the reader found it (an
//!   abbreviation such as `REV` is replaced by the full new keyword). `JOINT/7` becomes
//!   `JPRIM/<new id>` in place, so the statement keeps its place and its `adams_view_name`
//!   comment. A marker reference (`I = 303`) is replaced as a whole number token, which must
//!   read as the id the reader saw.
//! - New statements are written, one argument per continuation line, just before the line of
//!   the first `END` (at the end of the text when there is none), with the file's first line
//!   ending, each preceded by an `adams_view_name` comment when a name is given. New markers
//!   are placed explicitly (`PART =`, `QP =`, `REULER =` in the part's BCS, angles in degrees
//!   with the `D` suffix, numbers in shortest round-trip form).
//! - The result is re-read; every edit must read back as requested, otherwise nothing is
//!   returned (an error, never a silently wrong file). Errors are also returned for a statement
//!   index that is not of the expected kind, an id already used by another statement of the
//!   same kind, or a token that cannot be found at its position.
//!
//! Write the text with [`crate::writer::write_atomically`].

use crate::diagnostic::{Diagnostic, Diagnostics, Span};
use crate::statement::{Statement, Value};
use crate::typed::{Dataset, JointType, JprimType, MarkerCarrier};

/// The I or the J marker of a joint or primitive.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MarkerKey {
    I,
    J,
}

impl MarkerKey {
    fn key(self) -> &'static str {
        match self {
            MarkerKey::I => "I",
            MarkerKey::J => "J",
        }
    }
}

/// One change of the dataset. `statement` is an index into [`Dataset::statements`].
#[derive(Clone, Debug, PartialEq)]
pub enum Edit {
    /// A JOINT gets another type keyword.
    JointType { statement: usize, kind: JointType },
    /// A JPRIM gets another type keyword.
    JprimType { statement: usize, kind: JprimType },
    /// A JOINT is rewritten in place as `JPRIM/id` of type `kind` (same I and J). The joint
    /// must have no joint-only arguments (IC, ICTRAN, ICROT, PD, PITCH).
    JointToJprim {
        statement: usize,
        id: u64,
        kind: JprimType,
    },
    /// The `I =` or `J =` marker id of a JOINT or JPRIM is replaced.
    SetMarker {
        statement: usize,
        key: MarkerKey,
        marker: u64,
    },
    /// A new marker on the part that carries marker `like`: origin `qp` and body 3-1-3 angles
    /// `reuler` (radians) in that part's BCS.
    AddMarker {
        id: u64,
        like: u64,
        qp: [f64; 3],
        reuler: [f64; 3],
        name: Option<String>,
    },
    /// A new joint primitive between markers `i` and `j`.
    AddJprim {
        id: u64,
        kind: JprimType,
        i: u64,
        j: u64,
        name: Option<String>,
    },
}

/// The dataset text with `edits` made (see the module contract).
pub fn apply_edits(ds: &Dataset, edits: &[Edit]) -> Result<String, Diagnostics> {
    if edits.is_empty() {
        return Ok(ds.text.clone());
    }
    let lines = Lines::new(&ds.text);
    let mut plan = Plan {
        ds,
        lines: &lines,
        replacements: Vec::new(),
        appended: Vec::new(),
        errors: Vec::new(),
    };
    for e in edits {
        plan.edit(e);
    }
    plan.check_new_ids(edits);
    if !plan.errors.is_empty() {
        return Err(Diagnostics(plan.errors));
    }
    let Plan {
        mut replacements,
        appended,
        ..
    } = plan;
    if !appended.is_empty() {
        let ending = lines.first_ending(&ds.text);
        let (at, lead) = match ds.end_line.and_then(|l| lines.line(l)) {
            Some(line) => (line.start, ""),
            None if ds.text.is_empty() || ds.text.ends_with(['\n', '\r']) => (ds.text.len(), ""),
            None => (ds.text.len(), ending),
        };
        let mut text = String::from(lead);
        for block in &appended {
            for l in block {
                text.push_str(l);
                text.push_str(ending);
            }
        }
        replacements.push(Replacement {
            start: at,
            end: at,
            text,
            span: Span::default(),
        });
    }
    let text = splice(ds, replacements)?;
    check(ds, &text, edits)?;
    Ok(text)
}

struct Replacement {
    start: usize,
    end: usize,
    text: String,
    span: Span,
}

struct Plan<'a> {
    ds: &'a Dataset,
    lines: &'a Lines,
    replacements: Vec<Replacement>,
    /// New statements, as lines without line endings.
    appended: Vec<Vec<String>>,
    errors: Vec<Diagnostic>,
}

impl<'a> Plan<'a> {
    fn error(&mut self, span: Option<Span>, msg: impl Into<String>) {
        self.errors
            .push(Diagnostic::error(self.ds.file.clone(), span, msg));
    }

    fn statement(&mut self, index: usize, keyword: &str) -> Option<&'a Statement> {
        let ds = self.ds;
        match ds.statements.get(index) {
            Some(st) if st.keyword == keyword => Some(st),
            Some(st) => {
                self.error(
                    Some(st.span),
                    format!(
                        "statement {index} is {}, not a {keyword}; it cannot be edited as one",
                        st.keyword
                    ),
                );
                None
            }
            None => {
                self.error(
                    None,
                    format!(
                        "statement index {index} is out of range ({} statements)",
                        ds.statements.len()
                    ),
                );
                None
            }
        }
    }

    fn edit(&mut self, e: &Edit) {
        match e {
            Edit::JointType { statement, kind } => {
                if let Some(st) = self.statement(*statement, "JOINT") {
                    self.retype(st, JOINT_WORDS, kind.keyword());
                }
            }
            Edit::JprimType { statement, kind } => {
                if let Some(st) = self.statement(*statement, "JPRIM") {
                    self.retype(st, JPRIM_WORDS, kind.keyword());
                }
            }
            Edit::JointToJprim {
                statement,
                id,
                kind,
            } => {
                let Some(st) = self.statement(*statement, "JOINT") else {
                    return;
                };
                if let Some(a) = st
                    .args
                    .iter()
                    .find(|a| ["IC", "ICTRAN", "ICROT", "PD", "PITCH"].contains(&a.key.as_str()))
                {
                    let msg = format!(
                        "{} has '{}', which a JPRIM does not take; it cannot become a primitive",
                        label(st),
                        a.key
                    );
                    self.error(Some(a.span), msg);
                    return;
                }
                self.retype(st, JOINT_WORDS, kind.keyword());
                self.rename_statement(st, &format!("JPRIM/{id}"));
            }
            Edit::SetMarker {
                statement,
                key,
                marker,
            } => {
                let ds = self.ds;
                let Some(st) = ds.statements.get(*statement) else {
                    self.error(None, format!("statement index {statement} is out of range"));
                    return;
                };
                if st.keyword != "JOINT" && st.keyword != "JPRIM" {
                    let msg = format!("{} is not a JOINT or JPRIM", label(st));
                    self.error(Some(st.span), msg);
                    return;
                }
                self.set_number(st, key.key(), *marker);
            }
            Edit::AddMarker {
                id,
                like,
                qp,
                reuler,
                name,
            } => self.add_marker(*id, *like, qp, reuler, name.as_deref()),
            Edit::AddJprim {
                id,
                kind,
                i,
                j,
                name,
            } => {
                let mut lines = name_comment(name.as_deref());
                lines.push(format!("JPRIM/{id}"));
                lines.push(format!(", {}", kind.keyword()));
                lines.push(format!(", I = {i}"));
                lines.push(format!(", J = {j}"));
                self.appended.push(lines);
            }
        }
    }

    /// Replaces the statement's type word (one of `words`) by `new`.
    fn retype(&mut self, st: &Statement, words: &[&str], new: &str) {
        let Some(arg) = st
            .args
            .iter()
            .find(|a| a.values.is_empty() && words.contains(&a.key.as_str()))
        else {
            let msg = format!("{} has no type keyword to replace", label(st));
            self.error(Some(st.span), msg);
            return;
        };
        match self.lines.word_at(&self.ds.text, arg.span) {
            Some((start, end)) => self.replacements.push(Replacement {
                start,
                end,
                text: new.to_string(),
                span: arg.span,
            }),
            None => {
                let msg = format!(
                    "the type keyword of {} is not found at its position",
                    label(st)
                );
                self.error(Some(arg.span), msg);
            }
        }
    }

    /// Replaces `KEYWORD/id` at the start of the statement.
    fn rename_statement(&mut self, st: &Statement, new: &str) {
        let text = &self.ds.text;
        let found = self.lines.word_at(text, st.span).and_then(|(start, end)| {
            let rest = text.get(end..)?.as_bytes();
            let mut k = 0;
            while matches!(rest.get(k), Some(b' ' | b'\t')) {
                k += 1;
            }
            if rest.get(k) != Some(&b'/') {
                return None;
            }
            k += 1;
            while matches!(rest.get(k), Some(b' ' | b'\t')) {
                k += 1;
            }
            let digits = rest
                .iter()
                .skip(k)
                .take_while(|b| b.is_ascii_digit())
                .count();
            let id: u64 = std::str::from_utf8(rest.get(k..k + digits)?)
                .ok()?
                .parse()
                .ok()?;
            (Some(id) == st.id).then_some((start, end + k + digits))
        });
        match found {
            Some((start, end)) => self.replacements.push(Replacement {
                start,
                end,
                text: new.to_string(),
                span: st.span,
            }),
            None => {
                let msg = format!("the keyword and id of {} are not found", label(st));
                self.error(Some(st.span), msg);
            }
        }
    }

    /// Replaces the (single, integer) value of argument `key` by `value`.
    fn set_number(&mut self, st: &Statement, key: &str, value: u64) {
        let Some(arg) = st.args.iter().find(|a| a.key == key) else {
            let msg = format!("{} has no '{key}' argument", label(st));
            self.error(Some(st.span), msg);
            return;
        };
        let Some(Value::Number {
            value: old, span, ..
        }) = arg.values.first()
        else {
            let msg = format!("'{key}' of {} is not a number", label(st));
            self.error(Some(arg.span), msg);
            return;
        };
        let text = &self.ds.text;
        let found = self.lines.byte_of(text, *span).and_then(|start| {
            let rest = text.get(start..)?.as_bytes();
            let len = rest
                .iter()
                .take_while(|b| b.is_ascii_digit() || matches!(b, b'+' | b'.'))
                .count();
            let read: f64 = std::str::from_utf8(rest.get(..len)?).ok()?.parse().ok()?;
            let ends = !rest
                .get(len)
                .is_some_and(|b| b.is_ascii_alphanumeric() || *b == b'_');
            (ends && read == *old).then_some((start, start + len))
        });
        match found {
            Some((start, end)) => self.replacements.push(Replacement {
                start,
                end,
                text: value.to_string(),
                span: *span,
            }),
            None => {
                let msg = format!(
                    "the value of '{key}' of {} is not found at its position",
                    label(st)
                );
                self.error(Some(*span), msg);
            }
        }
    }

    fn add_marker(
        &mut self,
        id: u64,
        like: u64,
        qp: &[f64; 3],
        reuler: &[f64; 3],
        name: Option<&str>,
    ) {
        let ds = self.ds;
        let Some(m) = ds.markers.iter().find(|m| m.header.id == like) else {
            self.error(None, format!("MARKER/{like} does not exist"));
            return;
        };
        let part = match m.carrier {
            Some(MarkerCarrier::Part(r)) => r.id,
            _ => {
                let msg = format!(
                    "{} is not on a PART; a marker like it cannot be added",
                    m.header.name
                );
                self.error(Some(m.header.span), msg);
                return;
            }
        };
        if qp.iter().chain(reuler).any(|v| !v.is_finite()) {
            self.error(None, format!("MARKER/{id}: a value is not finite"));
            return;
        }
        let mut lines = name_comment(name);
        lines.push(format!("MARKER/{id}"));
        lines.push(format!(", PART = {part}"));
        lines.push(format!(
            ", QP = {}, {}, {}",
            real(qp[0]),
            real(qp[1]),
            real(qp[2])
        ));
        lines.push(format!(
            ", REULER = {}D, {}D, {}D",
            real(reuler[0].to_degrees()),
            real(reuler[1].to_degrees()),
            real(reuler[2].to_degrees())
        ));
        self.appended.push(lines);
    }

    /// New MARKER and JPRIM ids must not be used already (nor twice by the edits).
    fn check_new_ids(&mut self, edits: &[Edit]) {
        let ds = self.ds;
        let mut markers: Vec<u64> = Vec::new();
        let mut jprims: Vec<u64> = Vec::new();
        for e in edits {
            match e {
                Edit::AddMarker { id, .. } => {
                    if markers.contains(id) || ds.markers.iter().any(|m| m.header.id == *id) {
                        self.error(None, format!("MARKER id {id} is already used"));
                    }
                    markers.push(*id);
                }
                Edit::AddJprim { id, .. } | Edit::JointToJprim { id, .. } => {
                    if jprims.contains(id) || ds.jprims.iter().any(|j| j.header.id == *id) {
                        self.error(None, format!("JPRIM id {id} is already used"));
                    }
                    jprims.push(*id);
                }
                _ => {}
            }
        }
    }
}

const JOINT_WORDS: &[&str] = &[
    "CONVEL",
    "CYLINDRICAL",
    "FIXED",
    "HOOKE",
    "PLANAR",
    "RACKPIN",
    "REVOLUTE",
    "SCREW",
    "SPHERICAL",
    "TRANSLATIONAL",
    "UNIVERSAL",
];

const JPRIM_WORDS: &[&str] = &[
    "ATPOINT",
    "INLINE",
    "INPLANE",
    "ORIENTATION",
    "PARALLEL_AXES",
    "PERPENDICULAR",
];

fn name_comment(name: Option<&str>) -> Vec<String> {
    match name {
        Some(n) if !n.contains(['\'', '\n', '\r']) => {
            vec!["!".into(), format!("!   adams_view_name='{n}'")]
        }
        _ => vec!["!".into()],
    }
}

fn label(st: &Statement) -> String {
    match st.id {
        Some(id) => format!("{}/{id}", st.keyword),
        None => format!("{}/", st.keyword),
    }
}

/// A real the reader turns back into the same `f64` (shortest round-trip digits, always with
/// a point or an exponent).
fn real(v: f64) -> String {
    if v == 0.0 {
        return "0.0".into();
    }
    let a = v.abs();
    if (1e-4..1e15).contains(&a) {
        let s = format!("{v}");
        if s.contains('.') {
            s
        } else {
            s + ".0"
        }
    } else {
        let s = format!("{v:E}");
        match s.split_once('E') {
            Some((m, e)) if !m.contains('.') => format!("{m}.0E{e}"),
            _ => s,
        }
    }
}

fn splice(ds: &Dataset, mut reps: Vec<Replacement>) -> Result<String, Diagnostics> {
    reps.sort_by_key(|r| (r.start, r.end));
    let text = &ds.text;
    let mut out = String::with_capacity(text.len() + 256);
    let mut at = 0;
    for r in &reps {
        let Some(keep) = text.get(at..r.start) else {
            return Err(Diagnostics(vec![Diagnostic::error(
                ds.file.clone(),
                Some(r.span),
                "two edits of the dataset overlap",
            )]));
        };
        out.push_str(keep);
        out.push_str(&r.text);
        at = r.end;
    }
    out.push_str(text.get(at..).unwrap_or(""));
    Ok(out)
}

/// Re-reads the edited text and checks every edit.
fn check(ds: &Dataset, text: &str, edits: &[Edit]) -> Result<(), Diagnostics> {
    let internal = |msg: String| Diagnostic::error(ds.file.clone(), None, msg);
    let new = crate::parse_dataset(ds.file.clone(), text).map_err(|d| {
        let mut all = vec![internal(
            "internal error: the edited dataset does not read back".into(),
        )];
        all.extend(d.0);
        Diagnostics(all)
    })?;
    let mut errors = Vec::new();
    for e in edits {
        let ok = match e {
            Edit::JointType { statement, kind } => new
                .joints
                .iter()
                .any(|j| j.header.statement == *statement && j.kind == *kind),
            Edit::JprimType { statement, kind } => new
                .jprims
                .iter()
                .any(|j| j.header.statement == *statement && j.kind == *kind),
            Edit::JointToJprim {
                statement,
                id,
                kind,
            } => new
                .jprims
                .iter()
                .any(|j| j.header.statement == *statement && j.header.id == *id && j.kind == *kind),
            Edit::SetMarker {
                statement,
                key,
                marker,
            } => {
                let pick = |i: u64, j: u64| match key {
                    MarkerKey::I => i,
                    MarkerKey::J => j,
                };
                new.joints
                    .iter()
                    .filter(|j| j.header.statement == *statement)
                    .map(|j| pick(j.i.id, j.j.id))
                    .chain(
                        new.jprims
                            .iter()
                            .filter(|j| j.header.statement == *statement)
                            .map(|j| pick(j.i.id, j.j.id)),
                    )
                    .any(|m| m == *marker)
            }
            Edit::AddMarker { id, qp, .. } => new.markers.iter().any(|m| {
                m.header.id == *id
                    && m.qp.as_ref().is_some_and(|q| {
                        q.value
                            .iter()
                            .zip(qp)
                            .all(|(a, b)| (a - b).abs() <= 1e-12 * b.abs().max(1.0))
                    })
            }),
            Edit::AddJprim { id, kind, i, j, .. } => new
                .jprims
                .iter()
                .any(|p| p.header.id == *id && p.kind == *kind && p.i.id == *i && p.j.id == *j),
        };
        if !ok {
            errors.push(internal(format!(
                "internal error: the edit {e:?} does not read back"
            )));
        }
    }
    if errors.is_empty() {
        Ok(())
    } else {
        Err(Diagnostics(errors))
    }
}

/// Physical lines: byte offsets of start, end of content, end of line ending.
struct Lines {
    lines: Vec<(usize, usize, usize)>,
}

#[derive(Clone, Copy)]
struct Line {
    start: usize,
    content_end: usize,
}

impl Lines {
    fn new(text: &str) -> Lines {
        let b = text.as_bytes();
        let mut lines = Vec::new();
        let (mut start, mut k) = (0, 0);
        while k < b.len() {
            match b[k] {
                b'\n' => {
                    lines.push((start, k, k + 1));
                    k += 1;
                    start = k;
                }
                b'\r' => {
                    let n = if b.get(k + 1) == Some(&b'\n') { 2 } else { 1 };
                    lines.push((start, k, k + n));
                    k += n;
                    start = k;
                }
                _ => k += 1,
            }
        }
        if start < b.len() {
            lines.push((start, b.len(), b.len()));
        }
        Lines { lines }
    }

    /// Line `number` (1-based).
    fn line(&self, number: u32) -> Option<Line> {
        let k = usize::try_from(number).ok()?.checked_sub(1)?;
        self.lines
            .get(k)
            .map(|&(start, content_end, _)| Line { start, content_end })
    }

    fn first_ending<'t>(&self, text: &'t str) -> &'t str {
        self.lines
            .iter()
            .find(|l| l.2 > l.1)
            .and_then(|l| text.get(l.1..l.2))
            .unwrap_or("\n")
    }

    /// Byte offset of a span (1-based line, 1-based character column).
    fn byte_of(&self, text: &str, span: Span) -> Option<usize> {
        let line = self.line(span.line)?;
        let content = text.get(line.start..line.content_end)?;
        let col = usize::try_from(span.col).ok()?.checked_sub(1)?;
        content.char_indices().nth(col).map(|(k, _)| line.start + k)
    }

    /// Byte range of the word (letters, digits, `_`) starting at `span`.
    fn word_at(&self, text: &str, span: Span) -> Option<(usize, usize)> {
        let start = self.byte_of(text, span)?;
        let len = text
            .get(start..)?
            .bytes()
            .take_while(|b| b.is_ascii_alphanumeric() || *b == b'_')
            .count();
        (len > 0).then_some((start, start + len))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    const TEXT: &str = "model\r\n\
UNITS/\r\n, LENGTH = METER\r\n\
PART/1, GROUND\r\n\
MARKER/1, PART = 1\r\n\
MARKER/2, PART = 1, QP = 1, 0, 0\r\n\
PART/2, MASS = 1, CM = 3, IP = 1, 1, 1\r\n\
MARKER/3, PART = 2\r\n\
MARKER/4, QP = 1, 0, 0\r\n\
!  adams_view_name='hinge'\r\n\
JOINT/7\r\n, REV   ! the hinge\r\n, I = 3\r\n, J = 1\r\n\
JOINT/8, REVOLUTE, I = 4, J = 2\r\n\
JPRIM/1, ATPOINT, I = 4, J = 2\r\n\
END\r\n\
after end is kept\r\n";

    fn ds() -> Dataset {
        crate::parse_dataset(Arc::from("t.adm"), TEXT).unwrap()
    }

    fn stmt(ds: &Dataset, id: u64, kw: &str) -> usize {
        ds.statements
            .iter()
            .position(|s| s.keyword == kw && s.id == Some(id))
            .unwrap()
    }

    #[test]
    fn joint_type_is_replaced_in_place() {
        let d = ds();
        let s = stmt(&d, 7, "JOINT");
        let out = apply_edits(
            &d,
            &[Edit::JointType {
                statement: s,
                kind: JointType::Spherical,
            }],
        )
        .unwrap();
        assert_eq!(out, TEXT.replace(", REV   !", ", SPHERICAL   !"));
        let back = crate::parse_dataset(Arc::from("t.adm"), &out).unwrap();
        assert_eq!(back.joints[0].kind, JointType::Spherical);
        assert_eq!(back.joints[0].header.name, "hinge");
    }

    #[test]
    fn joint_becomes_a_primitive_and_statements_are_added_before_end() {
        let d = ds();
        let s = stmt(&d, 8, "JOINT");
        let edits = [
            Edit::JointToJprim {
                statement: s,
                id: 2,
                kind: JprimType::Inline,
            },
            Edit::AddMarker {
                id: 5,
                like: 4,
                qp: [1.0, 0.0, 0.0],
                reuler: [0.0, 90f64.to_radians(), 0.0],
                name: Some("pin".into()),
            },
            Edit::SetMarker {
                statement: s,
                key: MarkerKey::I,
                marker: 5,
            },
            Edit::AddJprim {
                id: 3,
                kind: JprimType::Perpendicular,
                i: 5,
                j: 2,
                name: Some("hinge_perp".into()),
            },
        ];
        let out = apply_edits(&d, &edits).unwrap();
        let expected = TEXT
            .replace(
                "JOINT/8, REVOLUTE, I = 4,",
                "JPRIM/2, INLINE, I = 5,",
            )
            .replace(
                "END\r\n",
                "!\r\n!   adams_view_name='pin'\r\nMARKER/5\r\n, PART = 2\r\n, QP = 1.0, 0.0, 0.0\r\n, REULER = 0.0D, 90.0D, 0.0D\r\n\
                 !\r\n!   adams_view_name='hinge_perp'\r\nJPRIM/3\r\n, PERPENDICULAR\r\n, I = 5\r\n, J = 2\r\nEND\r\n",
            );
        assert_eq!(out, expected);
        let back = crate::parse_dataset(Arc::from("t.adm"), &out).unwrap();
        assert_eq!(back.jprims.len(), 3);
        assert_eq!(back.joints.len(), 1);
        let pin = back.markers.iter().find(|m| m.header.id == 5).unwrap();
        assert_eq!(pin.header.name, "pin");
        assert!(matches!(pin.carrier, Some(MarkerCarrier::Part(r)) if r.id == 2));
    }

    #[test]
    fn used_ids_and_joint_only_arguments_are_refused() {
        let d = ds();
        let err = apply_edits(
            &d,
            &[Edit::AddJprim {
                id: 1,
                kind: JprimType::Inline,
                i: 3,
                j: 1,
                name: None,
            }],
        )
        .unwrap_err();
        assert!(
            err.to_string().contains("JPRIM id 1 is already used"),
            "{err}"
        );
        let text = TEXT.replace(", J = 1\r\n", ", J = 1\r\n, IC = 5D\r\n");
        let d = crate::parse_dataset(Arc::from("t.adm"), &text).unwrap();
        let s = stmt(&d, 7, "JOINT");
        let err = apply_edits(
            &d,
            &[Edit::JointToJprim {
                statement: s,
                id: 9,
                kind: JprimType::Inline,
            }],
        )
        .unwrap_err();
        assert!(err.to_string().contains("'IC'"), "{err}");
        // A statement of another kind.
        let err = apply_edits(
            &d,
            &[Edit::JointType {
                statement: stmt(&d, 1, "JPRIM"),
                kind: JointType::Fixed,
            }],
        )
        .unwrap_err();
        assert!(err.to_string().contains("not a JOINT"), "{err}");
    }

    #[test]
    fn without_end_statements_are_appended() {
        let text = "m\nPART/1, GROUND\nMARKER/1, PART = 1\nPART/2, MASS = 1\nMARKER/2, PART = 2";
        let d = crate::parse_dataset(Arc::from("t.adm"), text).unwrap();
        let out = apply_edits(
            &d,
            &[Edit::AddJprim {
                id: 4,
                kind: JprimType::Atpoint,
                i: 2,
                j: 1,
                name: None,
            }],
        )
        .unwrap();
        assert_eq!(
            out,
            format!("{text}\n!\nJPRIM/4\n, ATPOINT\n, I = 2\n, J = 1\n")
        );
    }

    #[test]
    fn reals_round_trip() {
        for v in [0.1, -2.5e-7, 1e20, 3.0, 1.0 / 3.0] {
            assert_eq!(real(v).parse::<f64>().unwrap(), v);
        }
        assert_eq!(real(3.0), "3.0");
        assert_eq!(real(1e20), "1.0E20");
    }
}
