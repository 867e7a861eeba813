//! `linkage compare A B`: two time histories compared signal by signal.
//!
//! **Inputs.** Each file is an Adams or linkage request file (`.req`, read by
//! [`linkage_adm::reqfile`]) or a linkage CSV (`simulate --out`: a header `time,<name>,…`,
//! then one row per output; a column's unit suffix, `PART_2.x [mm]`, is not part of its
//! name). A file ending in `.csv` is a CSV, one ending in `.req` a request
//! file; any other is a CSV when its first line holds a comma.
//!
//! **Signals.** A request file gives six signals per request, named `REQUEST_<id>.<component>`
//! with the reader's component names (`x y z psi theta phi`, `vx … wz`, `ax … wdz`,
//! `fx … tz`, `f2 f3 f4 f6 f7 f8`); a CSV gives one per column after `time`. Two files of the
//! same kind are matched by name. A request file against a CSV: the CSV columns
//! `<name>.<component>` whose name (or its last `.`-separated part, for Adams View names such
//! as `.model.REQUEST_1`) is `REQUEST_<id>` (any case) are request `id`'s — which is how
//! `simulate` names the columns of REQUESTs without an Adams View name. Two columns claiming
//! the same request and component are an input error, and so are files with no signal in
//! common.
//!
//! **Times.** Signals are compared at B's output times within A's (a B time outside A's
//! span by more than [`TIME_SLACK`] of it is not compared); A is interpolated linearly in
//! time between its outputs, and taken as it is at equal times. Where a file repeats a time
//! (the initial-conditions output and the first step, both at t = 0), the last output of that
//! time is used. Times must not decrease.
//!
//! **Figures.** Per signal: the largest `|B − A|` over the compared times and where it
//! occurs; the range of A (max − min over all of A's outputs) with a floor, `--floor`
//! (default 1, in the signal's units): a signal whose range is below the floor, a constant
//! one in particular, is compared absolutely; and the ratio `max |B − A| / max(range, floor)`,
//! which `--tol` bounds (default 10⁻³). Angles — the `psi`, `theta`, `phi` components, in
//! degrees — differ modulo 360: differences are wrapped into (−180, 180], A is interpolated
//! along the shorter arc, and the range is that of A unwrapped (continued across ±180).
//! A NaN or infinite value at a compared time fails its signal.
//!
//! **Exit codes.** 0 when every signal is within the tolerance, 1 when some are not (they are
//! listed first, worst first), 2 for bad input (unreadable or malformed files, with
//! `file:line:column`, or nothing in common).

use crate::common::{input_error, print_json, Format};
use linkage_adm::reqfile::{read_request_file, RequestFile};
use linkage_adm::{Diagnostic, Diagnostics, Span};
use serde::Serialize;
use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;
use std::process::ExitCode;
use std::sync::Arc;

/// Default bound on `max |B − A| / max(range, floor)`.
pub const DEFAULT_TOLERANCE: f64 = 1e-3;
/// Default floor of a signal's range (in the signal's units).
pub const DEFAULT_RANGE_FLOOR: f64 = 1.0;
/// How far (relative to the larger of A's time span and its last time) a B time may lie
/// outside A's span and still be compared, at A's end value: Adams writes times with six
/// digits, so its last time may fall short of the exact one by 5·10⁻⁶ of it.
pub const TIME_SLACK: f64 = 1e-5;

/// Options of `linkage compare`.
pub struct CompareArgs<'a> {
    pub a: &'a Path,
    pub b: &'a Path,
    pub tol: f64,
    pub floor: f64,
    pub format: Format,
}

/// What a file is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
enum Source {
    RequestFile,
    Csv,
}

/// One signal of a file.
pub(crate) struct Signal {
    pub(crate) name: String,
    /// The request id and component it belongs to, when known.
    request: Option<(u64, String)>,
    /// Degrees, compared modulo 360.
    angle: bool,
    /// The unit its CSV header states (`crank.x [m]`), when it states one.
    pub(crate) unit: Option<String>,
    pub(crate) values: Vec<f64>,
}

/// A file's time histories, one value per signal and output time.
pub(crate) struct Series {
    pub(crate) file: Arc<str>,
    source: Source,
    pub(crate) times: Vec<f64>,
    /// The unit of the times, when the file states it (`time [s]`).
    pub(crate) time_unit: Option<String>,
    /// The line of each output time (CSV only), for messages.
    lines: Vec<u32>,
    pub(crate) signals: Vec<Signal>,
}

fn error(file: &Arc<str>, span: Option<Span>, msg: impl Into<String>) -> Diagnostics {
    Diagnostics(vec![Diagnostic::error(file.clone(), span, msg)])
}

fn is_angle(component: &str) -> bool {
    matches!(component, "psi" | "theta" | "phi")
}

/// Reads a request file or a CSV (see the module doc for which).
pub(crate) fn load(path: &Path) -> Result<Series, Diagnostics> {
    let file: Arc<str> = Arc::from(path.display().to_string());
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    if ext.as_deref() == Some("req") {
        return read_request_file(path).map(from_request_file);
    }
    let text = match std::fs::read(path) {
        Ok(bytes) => String::from_utf8_lossy(&bytes).into_owned(),
        Err(e) => return Err(error(&file, None, format!("cannot read file: {e}"))),
    };
    if ext.as_deref() == Some("csv") || text.lines().next().is_some_and(|l| l.contains(',')) {
        parse_csv(file, &text)
    } else {
        linkage_adm::reqfile::parse_request_file(file, &text).map(from_request_file)
    }
}

fn from_request_file(f: RequestFile) -> Series {
    let mut signals = Vec::new();
    for r in &f.requests {
        for (c, comp) in r.component_names().iter().enumerate() {
            signals.push(Signal {
                name: format!("REQUEST_{}.{comp}", r.id),
                request: Some((r.id, comp.to_string())),
                angle: r.type_code == 1 && is_angle(comp),
                unit: None,
                values: r.component(c),
            });
        }
    }
    Series {
        file: f.file,
        source: Source::RequestFile,
        times: f.times,
        time_unit: None,
        lines: Vec::new(),
        signals,
    }
}

/// The request a CSV column belongs to: `REQUEST_<id>.<component>`, or with a longer name
/// whose last `.`-separated part is `REQUEST_<id>`.
fn column_request(name: &str) -> Option<(u64, String)> {
    let (prefix, component) = name.rsplit_once('.')?;
    let last = prefix.rsplit('.').next()?;
    let digits = last
        .get(..8)
        .filter(|p| p.eq_ignore_ascii_case("REQUEST_"))
        .and(last.get(8..))?;
    let id = digits.parse().ok()?;
    Some((id, component.to_ascii_lowercase()))
}

/// The 1-based character column where field `k` of a comma-separated line starts.
fn field_column(line: &str, k: usize) -> u32 {
    let before: usize = line.split(',').take(k).map(|f| f.chars().count() + 1).sum();
    u32::try_from(before + 1).unwrap_or(u32::MAX)
}

/// The unit suffix of a CSV header field (`crank.x [m]` → `m`), if it has one.
fn column_unit(field: &str) -> Option<String> {
    let field = field.trim();
    let name = linkage_report::units::column_name(field);
    field
        .get(name.len()..)
        .map(|rest| rest.trim().trim_start_matches('[').trim_end_matches(']'))
        .filter(|u| !u.is_empty())
        .map(str::to_string)
}

/// A linkage CSV: a header whose first column is `time`, then rows of numbers.
fn parse_csv(file: Arc<str>, text: &str) -> Result<Series, Diagnostics> {
    let mut lines = text.lines().enumerate().map(|(k, l)| {
        (
            u32::try_from(k + 1).unwrap_or(u32::MAX),
            l.trim_end_matches('\r'),
        )
    });
    let Some((_, header)) = lines.next() else {
        return Err(error(
            &file,
            None,
            "the file is empty (expected a CSV header)",
        ));
    };
    // Columns by name: a unit suffix (`PART_2.x [mm]`) is not part of it.
    let names: Vec<&str> = header
        .split(',')
        .map(linkage_report::units::column_name)
        .collect();
    let units: Vec<Option<String>> = header.split(',').map(column_unit).collect();
    if names.first() != Some(&"time") {
        return Err(error(
            &file,
            Some(Span::new(1, 1)),
            "the first column of a linkage CSV must be 'time'",
        ));
    }
    let mut seen = HashMap::new();
    for (k, n) in names.iter().enumerate() {
        if n.is_empty() {
            return Err(error(
                &file,
                Some(Span::new(1, field_column(header, k))),
                format!("column {} has no name", k + 1),
            ));
        }
        if let Some(first) = seen.insert(*n, k) {
            return Err(error(
                &file,
                Some(Span::new(1, field_column(header, k))),
                format!(
                    "column '{n}' appears twice (columns {} and {})",
                    first + 1,
                    k + 1
                ),
            ));
        }
    }
    let mut signals: Vec<Signal> = names[1..]
        .iter()
        .zip(&units[1..])
        .map(|(n, unit)| Signal {
            name: n.to_string(),
            request: column_request(n),
            angle: n.rsplit('.').next().is_some_and(is_angle),
            unit: unit.clone(),
            values: Vec::new(),
        })
        .collect();
    let (mut times, mut rows) = (Vec::new(), Vec::new());
    for (line_no, line) in lines {
        if line.trim().is_empty() {
            continue;
        }
        let fields: Vec<&str> = line.split(',').collect();
        if fields.len() != names.len() {
            return Err(error(
                &file,
                Some(Span::new(line_no, 1)),
                format!("{} fields, the header has {}", fields.len(), names.len()),
            ));
        }
        for (k, f) in fields.iter().enumerate() {
            let v: f64 = f.trim().parse().map_err(|_| {
                error(
                    &file,
                    Some(Span::new(line_no, field_column(line, k))),
                    format!("'{}' is not a number", f.trim()),
                )
            })?;
            match k {
                0 if !v.is_finite() => {
                    return Err(error(
                        &file,
                        Some(Span::new(line_no, 1)),
                        format!("the time '{}' is not a finite number", f.trim()),
                    ))
                }
                0 => times.push(v),
                _ => signals[k - 1].values.push(v),
            }
        }
        rows.push(line_no);
    }
    Ok(Series {
        file,
        source: Source::Csv,
        times,
        time_unit: units[0].clone(),
        lines: rows,
        signals,
    })
}

impl Series {
    /// Keeps the last output of each repeated time; an error where times decrease.
    fn last_of_repeats(mut self) -> Result<Series, Diagnostics> {
        let n = self.times.len();
        let mut keep = Vec::with_capacity(n);
        for k in 0..n {
            match self.times.get(k + 1) {
                Some(&next) if next < self.times[k] => {
                    let span = self.lines.get(k + 1).map(|&l| Span::new(l, 1));
                    return Err(error(
                        &self.file,
                        span,
                        format!(
                            "output time {next} follows {}: times must not decrease",
                            self.times[k]
                        ),
                    ));
                }
                Some(&next) if next == self.times[k] => {}
                _ => keep.push(k),
            }
        }
        if keep.len() < n {
            self.times = keep.iter().map(|&k| self.times[k]).collect();
            for s in &mut self.signals {
                s.values = keep.iter().map(|&k| s.values[k]).collect();
            }
        }
        Ok(self)
    }

    fn describe(&self) -> String {
        match self.source {
            Source::RequestFile => format!(
                "request file: {} requests, {} output times",
                self.signals.len() / 6,
                self.times.len()
            ),
            Source::Csv => format!(
                "CSV: {} columns, {} output times",
                self.signals.len(),
                self.times.len()
            ),
        }
    }
}

/// Signals of A and B matched (indices into each file's signals), and the unmatched names.
struct Matching {
    pairs: Vec<(usize, usize)>,
    only_a: Vec<String>,
    only_b: Vec<String>,
}

fn match_signals(a: &Series, b: &Series) -> Result<Matching, Diagnostics> {
    let mut pairs = Vec::new();
    if a.source == b.source {
        let by_name: HashMap<&str, usize> = b
            .signals
            .iter()
            .enumerate()
            .map(|(k, s)| (s.name.as_str(), k))
            .collect();
        for (ka, s) in a.signals.iter().enumerate() {
            if let Some(&kb) = by_name.get(s.name.as_str()) {
                pairs.push((ka, kb));
            }
        }
    } else {
        let (req, csv, req_is_a) = match a.source {
            Source::RequestFile => (a, b, true),
            Source::Csv => (b, a, false),
        };
        let mut by_request: HashMap<&(u64, String), Vec<usize>> = HashMap::new();
        for (k, s) in csv.signals.iter().enumerate() {
            if let Some(r) = &s.request {
                by_request.entry(r).or_default().push(k);
            }
        }
        for (kr, s) in req.signals.iter().enumerate() {
            let Some(key) = &s.request else { continue };
            match by_request.get(key).map(Vec::as_slice) {
                Some([kc]) => pairs.push(if req_is_a { (kr, *kc) } else { (*kc, kr) }),
                Some(several) if several.len() > 1 => {
                    let names: Vec<&str> = several
                        .iter()
                        .map(|&k| csv.signals[k].name.as_str())
                        .collect();
                    return Err(error(
                        &csv.file,
                        Some(Span::new(1, 1)),
                        format!(
                            "columns {} all name request {} component {}: which one {} of {} \
                             is cannot be told",
                            names.join(", "),
                            key.0,
                            key.1,
                            s.name,
                            req.file
                        ),
                    ));
                }
                _ => {}
            }
        }
    }
    let mut in_a = vec![false; a.signals.len()];
    let mut in_b = vec![false; b.signals.len()];
    for &(ka, kb) in &pairs {
        in_a[ka] = true;
        in_b[kb] = true;
    }
    let unmatched = |s: &Series, used: &[bool]| -> Vec<String> {
        s.signals
            .iter()
            .zip(used)
            .filter(|(_, u)| !**u)
            .map(|(s, _)| s.name.clone())
            .collect()
    };
    let only_a = unmatched(a, &in_a);
    let only_b = unmatched(b, &in_b);
    if pairs.is_empty() {
        let hint = if a.source != b.source {
            " (a CSV's request columns are matched by their names REQUEST_<id>.<component>; \
             requests with other Adams View names cannot be matched to a request file's ids)"
        } else {
            ""
        };
        return Err(error(
            &b.file,
            None,
            format!("no signal in common with {}{hint}", a.file),
        ));
    }
    Ok(Matching {
        pairs,
        only_a,
        only_b,
    })
}

/// Where B's time `k` falls in A: A's output index and the weight of the next one.
struct Position {
    b: usize,
    a: usize,
    weight: f64,
}

/// B's output times within A's span (see [`TIME_SLACK`]) located in A (both strictly
/// increasing).
fn locate(a: &[f64], b: &[f64]) -> Vec<Position> {
    let (Some(&first), Some(&last)) = (a.first(), a.last()) else {
        return Vec::new();
    };
    let slack = TIME_SLACK * (last - first).max(last.abs()).max(f64::MIN_POSITIVE);
    let mut out = Vec::new();
    let mut ka = 0;
    for (kb, &t) in b.iter().enumerate() {
        if t < first - slack || t > last + slack {
            continue;
        }
        let t = t.clamp(first, last);
        while ka + 1 < a.len() && a[ka + 1] <= t {
            ka += 1;
        }
        let weight = if a[ka] == t || ka + 1 == a.len() {
            0.0
        } else {
            (t - a[ka]) / (a[ka + 1] - a[ka])
        };
        out.push(Position {
            b: kb,
            a: ka,
            weight,
        });
    }
    out
}

/// An angle difference in degrees, wrapped into (−180, 180].
fn wrap_degrees(d: f64) -> f64 {
    let r = d.rem_euclid(360.0);
    if r > 180.0 {
        r - 360.0
    } else {
        r
    }
}

/// How one signal compares.
#[derive(Clone, Debug, Serialize)]
struct SignalComparison {
    name: String,
    angle: bool,
    /// Largest |B − A| (angles wrapped); null when a value is NaN or infinite.
    max_difference: f64,
    /// max − min of A (angles unwrapped).
    range: f64,
    /// `max_difference / max(range, floor)`; null when not finite.
    ratio: f64,
    /// B's time of the largest difference (of the first non-finite value when there is one).
    time: f64,
    /// A (interpolated) and B at that time.
    a: f64,
    b: f64,
    within: bool,
}

fn compare_signal(
    name: &str,
    sa: &Signal,
    sb: &Signal,
    at: &[Position],
    b_times: &[f64],
    floor: f64,
    tol: f64,
) -> SignalComparison {
    let angle = sa.angle || sb.angle;
    let a = &sa.values;
    let (mut lo, mut hi, mut unwrapped) = (f64::INFINITY, f64::NEG_INFINITY, f64::NAN);
    for (k, &v) in a.iter().enumerate() {
        unwrapped = if angle && k > 0 && unwrapped.is_finite() && a[k - 1].is_finite() {
            unwrapped + wrap_degrees(v - a[k - 1])
        } else {
            v
        };
        if unwrapped.is_finite() {
            lo = lo.min(unwrapped);
            hi = hi.max(unwrapped);
        }
    }
    let range = if hi >= lo { hi - lo } else { 0.0 };
    let mut worst = (0.0_f64, f64::NAN, f64::NAN, f64::NAN);
    let mut bad = false;
    for p in at {
        let a0 = a[p.a];
        let va = if p.weight == 0.0 {
            a0
        } else {
            let step = a[p.a + 1] - a0;
            a0 + p.weight * if angle { wrap_degrees(step) } else { step }
        };
        let vb = sb.values[p.b];
        let d = if angle {
            wrap_degrees(vb - va)
        } else {
            vb - va
        };
        if !d.is_finite() {
            if !bad {
                worst = (f64::NAN, b_times[p.b], va, vb);
            }
            bad = true;
        } else if !bad && (d.abs() > worst.0 || worst.1.is_nan()) {
            worst = (d.abs(), b_times[p.b], va, vb);
        }
    }
    let ratio = worst.0 / range.max(floor);
    SignalComparison {
        name: name.to_string(),
        angle,
        max_difference: worst.0,
        range,
        ratio,
        time: worst.1,
        a: worst.2,
        b: worst.3,
        within: ratio.is_finite() && ratio <= tol,
    }
}

/// Where a file came from.
#[derive(Serialize)]
struct FileJson {
    file: String,
    kind: Source,
    signals: usize,
    times: usize,
}

/// The whole comparison.
#[derive(Serialize)]
struct CompareJson {
    a: FileJson,
    b: FileJson,
    tolerance: f64,
    range_floor: f64,
    /// B's output times compared (repeats counted once).
    times_compared: usize,
    first_time: f64,
    last_time: f64,
    /// Signals over the tolerance.
    exceeding: usize,
    /// Signals over the tolerance first (worst first), then the others in A's order.
    signals: Vec<SignalComparison>,
    only_in_a: Vec<String>,
    only_in_b: Vec<String>,
}

fn file_json(s: &Series) -> FileJson {
    FileJson {
        file: s.file.to_string(),
        kind: s.source,
        signals: s.signals.len(),
        times: s.times.len(),
    }
}

fn compare(a: &Series, b: &Series, tol: f64, floor: f64) -> Result<CompareJson, Diagnostics> {
    let matching = match_signals(a, b)?;
    let at = locate(&a.times, &b.times);
    let (Some(first), Some(last)) = (at.first(), at.last()) else {
        return Err(error(
            &b.file,
            None,
            format!(
                "no output time within {}'s span ({} to {})",
                a.file,
                a.times.first().copied().unwrap_or(f64::NAN),
                a.times.last().copied().unwrap_or(f64::NAN)
            ),
        ));
    };
    let mut signals: Vec<SignalComparison> = matching
        .pairs
        .iter()
        .map(|&(ka, kb)| {
            let (sa, sb) = (&a.signals[ka], &b.signals[kb]);
            // A CSV's column name is the more specific one.
            let name = if a.source == Source::Csv {
                &sa.name
            } else {
                &sb.name
            };
            compare_signal(name, sa, sb, &at, &b.times, floor, tol)
        })
        .collect();
    // Failing first, worst first (non-finite ratios before all); the rest keep their order.
    let key = |s: &SignalComparison| {
        if s.ratio.is_nan() {
            f64::INFINITY
        } else {
            s.ratio
        }
    };
    signals.sort_by(|x, y| match (x.within, y.within) {
        (false, false) => key(y).total_cmp(&key(x)),
        (a, b) => a.cmp(&b),
    });
    Ok(CompareJson {
        a: file_json(a),
        b: file_json(b),
        tolerance: tol,
        range_floor: floor,
        times_compared: at.len(),
        first_time: b.times[first.b],
        last_time: b.times[last.b],
        exceeding: signals.iter().filter(|s| !s.within).count(),
        signals,
        only_in_a: matching.only_a,
        only_in_b: matching.only_b,
    })
}

/// Up to eight names, then how many more.
fn some_names(names: &[String]) -> String {
    let mut s = names.iter().take(8).cloned().collect::<Vec<_>>().join(", ");
    if names.len() > 8 {
        let _ = write!(s, ", … ({} more)", names.len() - 8);
    }
    s
}

fn to_text(j: &CompareJson, a: &Series, b: &Series) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "A: {} ({})", j.a.file, a.describe());
    let _ = writeln!(s, "B: {} ({})", j.b.file, b.describe());
    let _ = writeln!(
        s,
        "{} signals compared at {} times of B from {} to {} (A interpolated linearly in time)",
        j.signals.len(),
        j.times_compared,
        j.first_time,
        j.last_time
    );
    let _ = writeln!(
        s,
        "ratio = max |B - A| / max(range of A, {}); angles (psi, theta, phi, degrees) differ \
         modulo 360",
        j.range_floor
    );
    if j.exceeding > 0 {
        let _ = writeln!(
            s,
            "{} of {} signals exceed the tolerance {} (listed first)",
            j.exceeding,
            j.signals.len(),
            j.tolerance
        );
    } else {
        let _ = writeln!(
            s,
            "all {} signals are within the tolerance {}",
            j.signals.len(),
            j.tolerance
        );
    }
    s.push('\n');
    let width = j
        .signals
        .iter()
        .map(|x| x.name.chars().count())
        .max()
        .unwrap_or(0)
        .max(6);
    let _ = writeln!(
        s,
        "{:<width$}  {:>11}  {:>11}  {:>11}  {:>11}  {:>12}  {:>12}  status",
        "signal", "max |B-A|", "range", "ratio", "time", "A", "B"
    );
    for x in &j.signals {
        let _ = writeln!(
            s,
            "{:<width$}  {:>11.4e}  {:>11.4e}  {:>11.4e}  {:>11}  {:>12.5e}  {:>12.5e}  {}",
            x.name,
            x.max_difference,
            x.range,
            x.ratio,
            format!("{}", x.time),
            x.a,
            x.b,
            if x.within { "ok" } else { "EXCEEDS" }
        );
    }
    for (which, names) in [("A", &j.only_in_a), ("B", &j.only_in_b)] {
        if !names.is_empty() {
            let _ = writeln!(
                s,
                "\nnot compared: {} signals only in {which}: {}",
                names.len(),
                some_names(names)
            );
        }
    }
    s
}

/// Runs `linkage compare`.
pub fn run(args: &CompareArgs) -> ExitCode {
    let bad_option = |msg: String| {
        eprintln!("error: {msg}");
        ExitCode::from(2)
    };
    if !(args.tol >= 0.0 && args.tol.is_finite()) {
        return bad_option(format!(
            "--tol must be a finite number ≥ 0, not {}",
            args.tol
        ));
    }
    if !(args.floor > 0.0 && args.floor.is_finite()) {
        return bad_option(format!(
            "--floor must be a positive number, not {}",
            args.floor
        ));
    }
    let loaded = load(args.a)
        .and_then(Series::last_of_repeats)
        .and_then(|a| Ok((a, load(args.b).and_then(Series::last_of_repeats)?)));
    let (a, b) = match loaded {
        Ok(ab) => ab,
        Err(d) => return input_error(&d, args.format),
    };
    let report = match compare(&a, &b, args.tol, args.floor) {
        Ok(r) => r,
        Err(d) => return input_error(&d, args.format),
    };
    match args.format {
        Format::Text => print!("{}", to_text(&report, &a, &b)),
        Format::Json => {
            if !print_json(&report) {
                return ExitCode::from(2);
            }
        }
    }
    if report.exceeding == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn csv(text: &str) -> Result<Series, Diagnostics> {
        parse_csv(Arc::from("t.csv"), text).and_then(Series::last_of_repeats)
    }

    fn first_error(r: Result<Series, Diagnostics>) -> String {
        match r {
            Ok(_) => panic!("no error"),
            Err(d) => d.0[0].to_string(),
        }
    }

    #[test]
    fn angle_differences_wrap_into_half_open_interval() {
        assert_eq!(wrap_degrees(359.0), -1.0);
        assert_eq!(wrap_degrees(-180.0), 180.0);
        assert_eq!(wrap_degrees(180.0), 180.0);
        assert_eq!(wrap_degrees(-181.0), 179.0);
        assert_eq!(wrap_degrees(720.5), 0.5);
    }

    #[test]
    fn request_columns_are_recognised_by_name() {
        assert_eq!(column_request("REQUEST_12.wdy"), Some((12, "wdy".into())));
        assert_eq!(
            column_request(".model.request_3.F2"),
            Some((3, "f2".into()))
        );
        assert_eq!(column_request("PART_2.x"), None);
        assert_eq!(column_request("REQUEST_.x"), None);
        assert_eq!(column_request("time"), None);
    }

    #[test]
    fn repeated_times_keep_the_last_output_and_csv_errors_are_located() {
        let s = csv("time,P.x,P.psi\n0,1,2\n0,3,4\n0.5,5,6\n").unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(s.times, [0.0, 0.5]);
        assert_eq!(s.signals[0].values, [3.0, 5.0]);
        assert!(s.signals[1].angle && !s.signals[0].angle);
        assert_eq!(
            first_error(csv("time,a\n0,1\n1,x\n")),
            "t.csv:3:3: error: 'x' is not a number"
        );
        assert_eq!(
            first_error(csv("time,a\n1,1\n0,2\n")),
            "t.csv:3:1: error: output time 0 follows 1: times must not decrease"
        );
        assert_eq!(
            first_error(csv("t,a\n")),
            "t.csv:1:1: error: the first column of a linkage CSV must be 'time'"
        );
        assert!(first_error(csv("time,a,a\n"))
            .starts_with("t.csv:1:8: error: column 'a' appears twice"));
        assert!(first_error(csv("time,a\n0,1,2\n")).starts_with("t.csv:2:1:"));
    }

    #[test]
    fn a_is_interpolated_at_b_times_and_angles_along_the_short_arc() {
        let a = csv("time,p.x,p.phi\n0,0,170\n1,10,-170\n2,20,-150\n")
            .unwrap_or_else(|e| panic!("{e}"));
        let b = csv("time,p.x,p.phi\n0.5,5,180\n1.5,15.5,-160\n3,0,0\n")
            .unwrap_or_else(|e| panic!("{e}"));
        let r = compare(&a, &b, 1e-3, 1.0).unwrap_or_else(|e| panic!("{e}"));
        // t = 3 is outside A.
        assert_eq!((r.times_compared, r.first_time, r.last_time), (2, 0.5, 1.5));
        let x = r
            .signals
            .iter()
            .find(|s| s.name == "p.x")
            .unwrap_or_else(|| panic!("p.x"));
        assert_eq!((x.max_difference, x.range, x.time), (0.5, 20.0, 1.5));
        assert_eq!(x.ratio, 0.025);
        let phi = r
            .signals
            .iter()
            .find(|s| s.name == "p.phi")
            .unwrap_or_else(|| panic!("phi"));
        // 180 against 180 at 0.5; −160 against −160 at 1.5; range 170 → 210 unwrapped.
        assert_eq!((phi.max_difference, phi.range), (0.0, 40.0));
        assert!(phi.within && !x.within);
        assert_eq!(r.signals[0].name, "p.x", "the failing signal comes first");
    }

    #[test]
    fn constant_signals_are_compared_absolutely_and_nan_fails() {
        let a = csv("time,c,n\n0,1e-16,1\n1,-1e-16,1\n").unwrap_or_else(|e| panic!("{e}"));
        let b = csv("time,c,n\n0,3e-16,NaN\n1,0,1\n").unwrap_or_else(|e| panic!("{e}"));
        let r = compare(&a, &b, 1e-3, 1.0).unwrap_or_else(|e| panic!("{e}"));
        let c = r
            .signals
            .iter()
            .find(|s| s.name == "c")
            .unwrap_or_else(|| panic!("c"));
        assert!(c.within && c.ratio < 1e-15);
        let n = &r.signals[0];
        assert_eq!(n.name, "n");
        assert!(!n.within && n.max_difference.is_nan() && n.time == 0.0);
    }
}
