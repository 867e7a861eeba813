//! Every marker a function expression names by a literal id exists: checked when the model
//! is read (every object, elements and data elements too, in a REQUEST's F1…F8), so that `verify` refuses `FUNCTION = DX(999)` (no MARKER/999) at its place in the
//! file instead of a simulation failing at time 0.
//!
//! The references checked, in every expression argument of every statement (FUNCTION, F1…F8,
//! EVALUATE, …): markers of the measures (`DX(i, j, k)`, `VX(i, j, k, l)`, …), of `ORIENT`
//! and of the `rm` argument of the element force functions; the element of an element force
//! function (`JOINT(7, …)` names JOINT/7, `BUSH(3, …)` BUSHING/3); VARIABLE (`VARVAL`), DIFF
//! (`DIF`, `DIF1`), ARRAY (`ARYVAL`), PINPUT (`PINVAL`), POUTPUT (`POUVAL`), SENSOR
//! (`SENVAL`) and SPLINE (`AKISPL`, `CUBSPL`). An id computed by the expression is left to the
//! evaluation; an expression that does not parse or calls USER is reported elsewhere.

use super::context::Ctx;
use linkage_adm::{keyword_id, Dataset, ExprText, Span, Value};
use linkage_expr::{Expr, Function, MeasureKind, Special, StateKind};
use std::collections::{HashMap, HashSet};

/// One object an expression names: the call (`DX`) and how many calls of that name come
/// before it, the statement keyword, the id.
struct Named {
    call: &'static str,
    rank: usize,
    statement: &'static str,
    id: u64,
}

/// The id an argument gives when it is a literal whole number.
fn literal(e: Option<&Expr>) -> Option<u64> {
    match e {
        Some(Expr::Number(v)) if v.fract() == 0.0 && (0.0..=f64::from(u32::MAX)).contains(v) => {
            // Exact: an integral value in u32 range.
            Some(*v as u64)
        }
        _ => None,
    }
}

/// Every object `e` names with a literal id, in the order of the calls (pre-order).
fn named(e: &Expr) -> Vec<Named> {
    let mut out = Vec::new();
    let mut calls: HashMap<&'static str, usize> = HashMap::new();
    e.walk(&mut |node| {
        let Expr::Call { func, args } = node else {
            return;
        };
        let call = func.name();
        let count = calls.entry(call).or_insert(0);
        let rank = *count;
        *count += 1;
        let mut push = |statement: &'static str, pos: usize| {
            if let Some(id) = literal(args.get(pos)) {
                out.push(Named {
                    call,
                    rank,
                    statement,
                    id,
                });
            }
        };
        match *func {
            Function::Measure(kind) => {
                let roles = MeasureKind::marker_roles(kind).len();
                (0..roles.min(args.len())).for_each(|pos| push("MARKER", pos));
            }
            Function::Orient => [2, 3].into_iter().for_each(|pos| push("MARKER", pos)),
            Function::ElementForce(kind) => {
                push(kind.statement(), 0);
                push("MARKER", 3);
            }
            Function::State(kind) => push(
                match kind {
                    StateKind::Varval => "VARIABLE",
                    StateKind::Dif | StateKind::Dif1 => "DIFF",
                    StateKind::Aryval => "ARRAY",
                    StateKind::Pinval => "PINPUT",
                    StateKind::Pouval => "POUTPUT",
                    StateKind::Senval => "SENSOR",
                },
                0,
            ),
            Function::Special(Special::Akispl | Special::Cubspl) => push("SPLINE", 2),
            Function::Special(_) | Function::Intrinsic(_) => {}
        }
    });
    out
}

/// Column offset of the `nth` (0-based) call `NAME(` in `text` (case-insensitive, not part of
/// a longer name), or 0 when it cannot be found.
fn call_offset(text: &str, name: &str, nth: usize) -> usize {
    let upper = text.to_ascii_uppercase();
    let bytes = upper.as_bytes();
    let mut seen = 0;
    let mut from = 0;
    while let Some(k) = upper[from..].find(name).map(|k| k + from) {
        from = k + name.len();
        let before_ok = k == 0 || !(bytes[k - 1].is_ascii_alphanumeric() || bytes[k - 1] == b'_');
        let after = upper[from..].trim_start();
        if before_ok && after.starts_with('(') {
            if seen == nth {
                return k;
            }
            seen += 1;
        }
    }
    0
}

/// The ids each statement keyword has in `ds`, and the marker ids `markers` (MARKER
/// statements and the markers FE_PARTs and FLEX_BODYs make).
pub(crate) struct Known<'a> {
    ids: HashMap<&'a str, HashSet<u64>>,
    markers: &'a HashMap<u64, usize>,
}

impl<'a> Known<'a> {
    pub(crate) fn new(ds: &'a Dataset, markers: &'a HashMap<u64, usize>) -> Self {
        let mut ids: HashMap<&str, HashSet<u64>> = HashMap::new();
        for s in &ds.statements {
            if let Some(id) = s.id {
                ids.entry(s.keyword.as_str()).or_default().insert(id);
            }
        }
        // The kinds a large model's loader keeps only typed ([`super::TYPED_ONLY`]).
        let typed = [
            (
                "JOINT",
                ds.joints.iter().map(|j| j.header.id).collect::<Vec<_>>(),
            ),
            ("JPRIM", ds.jprims.iter().map(|j| j.header.id).collect()),
            ("MOTION", ds.motions.iter().map(|m| m.header.id).collect()),
        ];
        for (keyword, list) in typed {
            ids.entry(keyword).or_default().extend(list);
        }
        Known { ids, markers }
    }

    fn exists(&self, statement: &str, id: u64) -> bool {
        if statement == "MARKER" {
            // Marker 0 is the ground frame.
            return id == 0 || self.markers.contains_key(&id);
        }
        self.ids.get(statement).is_some_and(|s| s.contains(&id))
    }
}

/// Errors (at the call, `file:line:column`) for every reference to an object that does not
/// exist in every expression of `ds` (the raw statements, and the MOTIONs, which a large
/// model's loader keeps only typed).
pub(crate) fn check(ds: &Dataset, known: &Known, cx: &mut Ctx) {
    for s in &ds.statements {
        // A REQUEST's problems are reported by the analyses that write REQUESTs
        // ([`crate::requests::resolve_requests`] checks its references with [`missing`]).
        if s.keyword == "REQUEST" {
            continue;
        }
        for a in &s.args {
            for v in &a.values {
                if let Value::Expr(text) = v {
                    let element = || match s.id {
                        Some(id) => label(
                            s.view_name
                                .clone()
                                .unwrap_or_else(|| keyword_id(&s.keyword, '_', id)),
                            &s.keyword,
                            id,
                            s.span.line,
                        ),
                        None => format!("{} (line {})", s.keyword, s.span.line),
                    };
                    check_expression(&element, &a.key, text, known, cx);
                }
            }
        }
    }
    if ds.statements.iter().any(|s| s.keyword == "MOTION") {
        return;
    }
    for m in &ds.motions {
        if let Some(f) = &m.function {
            let h = &m.header;
            let element = || label(h.name.clone(), "MOTION", h.id, h.span.line);
            check_expression(&element, "FUNCTION", &f.value.expr, known, cx);
        }
    }
}

/// `NAME (KEYWORD/id, line N)`, as elements are named in messages.
fn label(name: String, keyword: &str, id: u64, line: u32) -> String {
    format!("{name} ({}, line {line})", keyword_id(keyword, '/', id))
}

fn check_expression(
    element: &dyn Fn() -> String,
    key: &str,
    text: &ExprText,
    known: &Known,
    cx: &mut Ctx,
) {
    let Ok(e) = linkage_expr::parse(&text.text) else {
        return;
    };
    if e.contains_user() {
        return;
    }
    // Markers only: an element or data element a function names may be left out on
    // request (a DIFF reading a deactivated CONTACT, a VARIABLE no force uses reading a
    // SENSOR), which the force builder reports for the expressions an analysis evaluates.
    for (span, why) in missing(&e, text, known) {
        if why.contains(": MARKER/") {
            cx.error(span, format!("{}: {key}: {why}", element()));
        }
    }
}

/// Every object the parsed expression `e` (of `text`) names that does not exist: the place
/// of its call and `DX(…): MARKER/999 does not exist`.
pub(crate) fn missing(e: &Expr, text: &ExprText, known: &Known) -> Vec<(Span, String)> {
    named(e)
        .into_iter()
        .filter(|r| !known.exists(r.statement, r.id))
        .map(|r| {
            (
                text.span_at(call_offset(&text.text, r.call, r.rank)),
                format!(
                    "{}(…): {} does not exist",
                    r.call,
                    keyword_id(r.statement, '/', r.id)
                ),
            )
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn statements(e: &str) -> Vec<(&'static str, &'static str, u64)> {
        named(&linkage_expr::parse(e).unwrap())
            .into_iter()
            .map(|n| (n.call, n.statement, n.id))
            .collect()
    }

    #[test]
    fn every_kind_of_literal_reference_is_named_with_its_statement() {
        assert_eq!(
            statements("DX(999, 3) + ORIENT(1, 1, 5, 6) + BUSH(4, 0, 2, 7)"),
            vec![
                ("DX", "MARKER", 999),
                ("DX", "MARKER", 3),
                ("ORIENT", "MARKER", 5),
                ("ORIENT", "MARKER", 6),
                ("BUSH", "BUSHING", 4),
                ("BUSH", "MARKER", 7),
            ]
        );
        assert_eq!(
            statements("VARVAL(2)*DIF(3)+ARYVAL(4,1)+SENVAL(5)+AKISPL(TIME,0,6)+VARVAL(1+1)"),
            vec![
                ("VARVAL", "VARIABLE", 2),
                ("DIF", "DIFF", 3),
                ("ARYVAL", "ARRAY", 4),
                ("SENVAL", "SENSOR", 5),
                ("AKISPL", "SPLINE", 6),
            ]
        );
    }

    #[test]
    fn a_call_is_found_by_its_name_and_rank_in_the_text() {
        assert_eq!(call_offset("2*dx(1) + DX (999)", "DX", 1), 10);
        assert_eq!(call_offset("IDX(1)+DX(2)", "DX", 0), 7);
        assert_eq!(call_offset("TIME", "DX", 0), 0);
    }
}

#[cfg(test)]
mod dataset_tests {
    use crate::build::test_support::{build, errors};

    #[test]
    fn an_element_force_function_of_an_existing_element_is_accepted() {
        let extra = "JOINT/5, REVOLUTE, I = 20, J = 1\nREQUEST/6, F2 = JOINT(5, 0, 2, 0)";
        if let Err(e) = build(extra) {
            panic!("{e}");
        }
        // Also when the loader has dropped the raw statements of the typed-only kinds.
        let text = format!("{}{extra}\nEND\n", crate::build::test_support::BASE);
        let mut ds = linkage_adm::parse_dataset(std::sync::Arc::from("m.adm"), &text).unwrap();
        ds.statements
            .retain(|s| !crate::TYPED_ONLY.contains(&s.keyword.as_str()));
        if let Err(e) = crate::build_model(&ds) {
            panic!("{e}");
        }
    }

    #[test]
    fn a_measure_of_a_missing_marker_is_an_error_at_the_call() {
        let e = errors("SFORCE/7, ROTATION, I = 20, J = 1, FUNCTION = 2*DX(20, 999)");
        assert_eq!(e.len(), 1, "{e:?}");
        assert_eq!((e[0].0, e[0].1), (12, 49), "{e:?}");
        assert!(e[0].2.contains("DX(…): MARKER/999 does not exist"), "{e:?}");
    }
}
