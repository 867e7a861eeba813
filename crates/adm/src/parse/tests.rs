//! Unit tests of the parser: statement form, ids, numbers, values, expressions, diagnostics.

use super::values::parse_number;
use super::*;
use crate::diagnostic::Severity;
use crate::statement::ExprText;

fn run(text: &str) -> Parsed {
    parse(Arc::from("t.adm"), text, 1, Language::Dataset, false)
}

/// Parses `body` as the statements after a title line; panics on errors.
fn ok(body: &str) -> Vec<Statement> {
    let p = run(&format!("title\n{body}"));
    let errors: Vec<String> = p
        .diagnostics
        .iter()
        .filter(|d| d.is_error())
        .map(|d| d.to_string())
        .collect();
    assert!(errors.is_empty(), "{errors:#?}");
    p.statements
}

fn one(body: &str) -> Statement {
    let mut v = ok(body);
    assert_eq!(v.len(), 1, "{v:#?}");
    v.remove(0)
}

/// The errors of `body` (after a title line) as `(line, col, message)`.
fn errors(body: &str) -> Vec<(u32, u32, String)> {
    run(&format!("title\n{body}"))
        .diagnostics
        .into_iter()
        .filter(|d| d.is_error())
        .map(|d| {
            let s = d.span.unwrap_or_default();
            (s.line, s.col, d.message)
        })
        .collect()
}

fn numbers(st: &Statement, key: &str) -> Vec<f64> {
    st.arg(key)
        .map(|a| {
            a.values
                .iter()
                .filter_map(|v| match v {
                    Value::Number { value, .. } => Some(*value),
                    _ => None,
                })
                .collect()
        })
        .unwrap_or_default()
}

fn expr<'s>(st: &'s Statement, key: &str) -> &'s ExprText {
    match st.arg(key).map(|a| a.values.as_slice()) {
        Some([Value::Expr(e)]) => e,
        other => panic!("{key}: {other:?}"),
    }
}

fn words(st: &Statement, key: &str) -> Vec<String> {
    st.arg(key)
        .map(|a| {
            a.values
                .iter()
                .map(|v| match v {
                    Value::Word { text, .. } | Value::Str { text, .. } => text.clone(),
                    Value::Number { value, .. } => value.to_string(),
                    Value::Expr(e) => format!("<{}>", e.text),
                })
                .collect()
        })
        .unwrap_or_default()
}

// ---- numbers ---------------------------------------------------------------------------------

#[test]
fn fortran_reals_and_degree_suffix() {
    for (t, v) in [
        ("1", 1.0),
        (".4", 0.4),
        ("-0.28", -0.28),
        ("+10", 10.0),
        ("1.0E-04", 1.0e-4),
        ("5.0E-002", 0.05),
        ("4.32E+09", 4.32e9),
        ("1.", 1.0),
        ("0102", 102.0),
    ] {
        assert_eq!(parse_number(t), Some((v, false)), "{t}");
    }
    for (t, deg) in [("90D", 90.0), ("1D", 1.0), ("30.0d", 30.0), ("-45D", -45.0)] {
        let (v, d) = parse_number(t).unwrap_or_else(|| panic!("{t}"));
        assert!(d);
        assert!((v - f64::to_radians(deg)).abs() < 1e-15, "{t}");
    }
    for t in [
        "", "-", ".", "1.0D0", "1E", "1e+", "inf", "NaN", "2x", "1..2", "D", "1DD",
    ] {
        assert_eq!(parse_number(t), None, "{t}");
    }
}

#[test]
fn numbers_in_lists_keep_their_spans_and_degrees() {
    let st = one("MARKER/0102, PART = 01, QP = 0, -.4, 0, REULER = 180D, 90D, 180D");
    assert_eq!(st.id, Some(102));
    assert_eq!(numbers(&st, "PART"), [1.0]);
    assert_eq!(numbers(&st, "QP"), [0.0, -0.4, 0.0]);
    let reuler = st
        .arg("REULER")
        .map(|a| a.values.clone())
        .unwrap_or_default();
    match reuler.first() {
        Some(Value::Number {
            value,
            degrees,
            span,
        }) => {
            assert!(*degrees);
            assert!((value - std::f64::consts::PI).abs() < 1e-15);
            assert_eq!(*span, Span::new(2, 50));
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn bad_number_is_an_error_at_its_column() {
    assert_eq!(
        errors("PART/2, MASS = 1.0D0"),
        [(2, 16, "invalid number '1.0D0'".to_string())]
    );
    let p = run("t\nPART/2, MASS = 2.5d-3\n");
    assert!(p.diagnostics[0]
        .hint
        .as_deref()
        .is_some_and(|h| h.contains("'E'")));
    let p = run("t\nMARKER/1, QP = 1, 2x, 3\n");
    assert_eq!(p.diagnostics[0].hint, None);
    assert_eq!(
        errors("MARKER/1, QP = 1, 2x, 3"),
        [(2, 19, "invalid number '2x'".to_string())]
    );
    assert_eq!(
        errors("PART/2, MASS = heavy"),
        [(2, 16, "expected a number, found 'heavy'".to_string())]
    );
    assert_eq!(errors("PART/2, MASS = 2*3")[0].1, 16);
}

#[test]
fn detached_degree_suffix_is_accepted_with_a_warning() {
    let p = run("t\nPOINT_MASS/422, REULER=20 D,40, 30D\n");
    let st = &p.statements[0];
    let values = numbers(st, "REULER");
    assert!((values[0] - 20f64.to_radians()).abs() < 1e-15);
    assert_eq!(values[1], 40.0);
    assert!(p
        .diagnostics
        .iter()
        .any(|d| d.severity == Severity::Warning && d.span == Some(Span::new(2, 24))));
}

// ---- statements and ids ----------------------------------------------------------------------

#[test]
fn statement_names_are_matched_by_prefix_and_case_insensitive() {
    let v = ok("part/1, ground\nSPRING/20, I=3, J=4, TRANSLATION, C=1\njp/3, inl, i=1, j=2");
    assert_eq!(v[0].keyword, "PART");
    assert!(v[0].arg("GROUND").is_some());
    assert_eq!(v[1].keyword, "SPRINGDAMPER");
    assert!(
        v[1].arg("TRANSLATIONAL").is_some(),
        "partial table canonicalises"
    );
    assert_eq!(v[2].keyword, "JPRIM");
    assert!(v[2].arg("INLINE").is_some());
    assert!(v.iter().all(|s| s.known));
}

#[test]
fn ambiguous_statement_name_is_an_error_naming_candidates() {
    let e = errors("S/1, I=1");
    assert_eq!(e.len(), 1);
    assert_eq!((e[0].0, e[0].1), (2, 1));
    assert!(
        e[0].2.contains("SFORCE") && e[0].2.contains("SPLINE"),
        "{}",
        e[0].2
    );
}

#[test]
fn unknown_statement_is_a_warning_and_kept_generic() {
    let p = run("t\nLEONARDO/50,PEPPINO=125\nPART/1\n");
    assert!(p.diagnostics.iter().all(|d| !d.is_error()));
    let w: Vec<_> = p
        .diagnostics
        .iter()
        .map(|d| (d.span, d.message.clone()))
        .collect();
    assert_eq!(
        w,
        [(
            Some(Span::new(2, 1)),
            "unknown statement 'LEONARDO' ignored".to_string()
        )]
    );
    let st = &p.statements[0];
    assert!(!st.known);
    assert_eq!(st.keyword, "LEONARDO");
    assert_eq!(st.id, Some(50));
    assert_eq!(numbers(st, "PEPPINO"), [125.0]);
    // Garbage inside an unknown statement is not an error either.
    let p = run("t\nADAMS/View model name: x\nLEOSILVA,1,10,I=11\nPIRLA\n");
    assert_eq!(p.diagnostics.len(), 3);
    assert!(p
        .diagnostics
        .iter()
        .all(|d| d.severity == Severity::Warning));
    assert_eq!(p.statements.len(), 3);
}

#[test]
fn ids_positive_with_leading_zeros_or_absent() {
    let v = ok("PART/01, GROUND\nUNITS/FORCE = NEWTON\nACCGRAV/\n, KGRAV = -9.80665\nOUTPUT/REQSAVE, GRSAVE\nMARKER/17172491, PART = 1");
    assert_eq!(v[0].id, Some(1));
    assert_eq!(v[1].id, None);
    assert_eq!(words(&v[1], "FORCE"), ["NEWTON"]);
    assert_eq!(v[2].id, None);
    assert_eq!(numbers(&v[2], "KGRAV"), [-9.80665]);
    assert!(v[3].arg("REQSAVE").is_some() && v[3].arg("GRSAVE").is_some());
    assert_eq!(v[4].id, Some(17172491));
}

#[test]
fn bad_ids_are_errors_at_the_id() {
    assert_eq!(
        errors("PART/abc"),
        [(
            2,
            6,
            "invalid id 'abc' of PART: expected a positive integer".to_string()
        )]
    );
    assert_eq!(errors("PART/0")[0].1, 6);
    assert_eq!(errors("PART/1.5")[0].1, 6);
    assert_eq!(errors("PART/, MASS=1")[0].1, 6);
    assert_eq!(errors("PART/99999999999999999999999")[0].1, 6);
    assert_eq!(
        errors("PART 1"),
        [(2, 6, "expected '/' after 'PART', found '1'".to_string())]
    );
    assert_eq!(
        errors("PART/1 GROUND"),
        [(2, 8, "expected ',' before 'G'".to_string())]
    );
    assert_eq!(errors("%&(MASS=2,)")[0].1, 1);
    assert_eq!(errors("PART/2930, %&(MASS=2,) CM=3")[0].1, 12);
}

#[test]
fn statements_keep_lines_span_and_view_name() {
    let v = ok("!  adams_view_name='crank'\nPART/2\n, MASS = 1\n\n, CM = 3\nMARKER/1");
    assert_eq!(v[0].lines, (3, 6));
    assert_eq!(v[0].span, Span::new(3, 1));
    assert_eq!(v[0].view_name.as_deref(), Some("crank"));
    assert_eq!(v[1].view_name, None);
}

#[test]
fn reading_stops_at_end() {
    let p = run("t\nPART/1\nEND\nPART/abc\n,,,garbage\"\n");
    assert_eq!(p.statements.len(), 1);
    assert_eq!(p.stop_line, Some(3));
    assert!(p.diagnostics.is_empty());
    let p = run("t\nPART/1\nend ! done\n");
    assert_eq!(p.stop_line, Some(3));
    let p = run("t\nPART/1\nEND, junk = (\nPART/2\n");
    assert_eq!((p.stop_line, p.statements.len()), (Some(3), 1));
    assert!(p.diagnostics.is_empty());
}

#[test]
fn semicolon_terminated_statements() {
    let v = ok("PART/1,MASS=40,CM=1;\nMARKER/1,PART=1;\nPART/2, MASS=1,\nIP=1,2,3, CM=4;");
    assert_eq!(v.len(), 3);
    assert_eq!(numbers(&v[2], "IP"), [1.0, 2.0, 3.0]);
    assert_eq!(numbers(&v[2], "CM"), [4.0]);
}

// ---- arguments -------------------------------------------------------------------------------

#[test]
fn argument_keys_are_canonicalised_in_typed_statements() {
    let st = one("MOTION/1, ROTATIONAL, JOINT = 1, FUN = 30.0d * time, VEL");
    let keys: Vec<&str> = st.args.iter().map(|a| a.key.as_str()).collect();
    assert_eq!(keys, ["ROTATION", "JOINT", "FUNCTION", "VELOCITY"]);
    let st = one("PART/1014, MASS=4, CM=1, X=10,20,30, Z=10,20,30, EXACT=X:Y:PHI");
    assert!(st.arg("XG").is_some() && st.arg("ZG").is_some());
    assert_eq!(words(&st, "EXACT"), ["X", "Y", "PHI"]);
}

#[test]
fn unknown_argument_of_typed_statement_is_an_error_with_position() {
    let e = errors("PART/90, GROUND, TUASORELLA;");
    assert_eq!(
        e,
        [(2, 18, "unknown argument 'TUASORELLA' of PART".to_string())]
    );
    // Leniently read: a warning, and the statement kept.
    let p = parse(
        Arc::from("t.adm"),
        "title\nPART/90, GROUND, TUASORELLA;",
        1,
        Language::Dataset,
        true,
    );
    assert_eq!(p.statements.len(), 1);
    assert_eq!(p.diagnostics.len(), 1);
    assert_eq!(p.diagnostics[0].severity, Severity::Warning);
    assert_eq!(
        p.diagnostics[0].message,
        "unknown argument 'TUASORELLA' of PART ignored"
    );
}

#[test]
fn a_misspelt_argument_is_an_error_that_suggests_the_argument_meant() {
    // MASSS for MASS: one letter too many. Every misspelling of the statement is reported,
    // and the statement is not read (its mass would silently be zero).
    let p = run("title\nPART/2, MASSS = 1, CM = 3, IPP = 1, 1, 1\n");
    assert!(p.statements.is_empty());
    let e: Vec<String> = p.diagnostics.iter().map(|d| d.message.clone()).collect();
    assert_eq!(
        e,
        [
            "unknown argument 'MASSS' of PART (did you mean MASS?)",
            "unknown argument 'IPP' of PART (did you mean IP?)",
        ]
    );
    assert!(p.diagnostics.iter().all(|d| d.is_error()));
    assert!(p.diagnostics[0]
        .hint
        .as_deref()
        .is_some_and(|h| h.contains("--lenient-arguments")));
    // Nothing close: no guess.
    let e = errors("PART/2, QUUXQUUX = 1");
    assert_eq!(e[0].2, "unknown argument 'QUUXQUUX' of PART");
}

#[test]
fn ambiguous_argument_of_typed_statement_is_an_error() {
    let e = errors("PART/3, V=1");
    assert_eq!(e.len(), 1);
    assert_eq!((e[0].0, e[0].1), (2, 9));
    assert!(e[0].2.contains("VM, VX, VY, VZ"), "{}", e[0].2);
}

#[test]
fn flag_with_value_and_value_without_equals_are_errors() {
    assert_eq!(
        errors("PART/1, GROUND = 1"),
        [(2, 16, "'GROUND' takes no value".to_string())]
    );
    assert_eq!(
        errors("PART/1, MASS"),
        [(2, 9, "'MASS' needs a value ('MASS = …')".to_string())]
    );
    assert_eq!(errors("MARKER/1, QP = ,")[0].1, 16);
}

#[test]
fn value_lists_continue_over_lines_until_the_next_keyword() {
    let st = one("PART/11, MASS = 502.03625, CM = 48, IP = 0.5086994843, 0.5118560751\r\n, 0.0552718941, VX = 44.75, VZ = 3.9");
    assert_eq!(
        numbers(&st, "IP"),
        [0.5086994843, 0.5118560751, 0.0552718941]
    );
    assert_eq!(numbers(&st, "VX"), [44.75]);
    let st = one("ARRAY/2, IC, SIZE = 6, NUMBERS = 0, 0.1, 1, 0, 0.7, 0.25");
    assert!(st.arg("IC").is_some_and(|a| a.values.is_empty()));
    assert_eq!(numbers(&st, "SIZE"), [6.0]);
    assert_eq!(numbers(&st, "NUMBERS").len(), 6);
    // Trailing comma and leading comma together separate two values.
    let v = ok("ARRAY/5\r\n, IC, SIZE = 3\r\n, NUMBERS = 2.0,\r\n, 1.0E+01,\r\n,21\r\nARRAY/6, NUMBERS =0,\n,0");
    assert_eq!(numbers(&v[0], "NUMBERS"), [2.0, 10.0, 21.0]);
    assert_eq!(numbers(&v[1], "NUMBERS"), [0.0, 0.0]);
}

#[test]
fn strings_colon_lists_and_free_text() {
    let st =
        one("REQUEST/1, F1 = DX(1)\\, CNAMES = \"top_disp\", \"\", \"a,b\", TITLE=IDEN1:IDEN2");
    assert_eq!(words(&st, "CNAMES"), ["top_disp", "", "a,b"]);
    assert!(matches!(
        st.arg("CNAMES").map(|a| &a.values[0]),
        Some(Value::Str { .. })
    ));
    assert_eq!(expr(&st, "TITLE").text, "IDEN1:IDEN2");
    let st =
        one("REQUEST/01, D,I=0201,J=0101,C=DISPLACEMENT: X Y Z PSI THETA PHI (body-fixed-3-1-3)");
    assert!(st.arg("DISPLACEMENT").is_some());
    assert_eq!(
        expr(&st, "COMMENT").text,
        "DISPLACEMENT: X Y Z PSI THETA PHI (body-fixed-3-1-3)"
    );
    let st = one("EQUILIBRIUM/MAXIT=20,PATTERN=T:F:T:T:F");
    assert_eq!(words(&st, "PATTERN"), ["T", "F", "T", "T", "F"]);
    let st = one("GFORCE/1, I=1, FUNCTION = USER(1)\\\n, ROUTINE = adrill_solver::BitForces");
    assert_eq!(expr(&st, "ROUTINE").text, "adrill_solver::BitForces");
    let st = one("SECTION/1\n, TYPE = Solid Rectangular\n, RECT_BASE = 100");
    assert_eq!(expr(&st, "TYPE").text, "Solid Rectangular");
    assert_eq!(numbers(&st, "RECT_BASE"), [100.0]);
}

// ---- expressions -----------------------------------------------------------------------------

#[test]
fn expression_spanning_lines_drops_continuation_commas() {
    let st = one("SFORCE/1\n, ROTATIONAL\n, I = 207\n, J = 208\n, FUNCTION =  - 1.0*RTOD*(az(207,208)-0.0*DTOR)\n, - 5.0E-002*RTOD*wz(207,208,208)\n, + 0.0\n");
    let e = expr(&st, "FUNCTION");
    assert_eq!(
        e.text,
        "- 1.0*RTOD*(az(207,208)-0.0*DTOR) - 5.0E-002*RTOD*wz(207,208,208) + 0.0"
    );
    // Every byte maps back to its source position.
    assert_eq!(e.span_at(0), Span::new(6, 15));
    let second = e.text.find("- 5.0").unwrap_or(0);
    assert_eq!(e.span_at(second), Span::new(7, 3));
    assert_eq!(e.span_at(second + 2), Span::new(7, 5));
    let last = e.text.len() - 1;
    assert_eq!(e.span_at(last), Span::new(8, 7));
    assert!(st.arg("ROTATIONAL").is_some());
}

#[test]
fn expression_continues_inside_parentheses() {
    let v = ok("VARIABLE/1, FUNCTION = USER(1.05, 2, 80,\n, 20, 0.5)\nDIFF/1, IC=0, FUNCTION = IF(MODE-5: 0,\n,-DIF(101)-1E7*(DIF(101)),\n,0 )");
    assert_eq!(expr(&v[0], "FUNCTION").text, "USER(1.05, 2, 80, 20, 0.5)");
    assert_eq!(
        expr(&v[1], "FUNCTION").text,
        "IF(MODE-5: 0,-DIF(101)-1E7*(DIF(101)),0 )"
    );
    assert_eq!(numbers(&v[1], "IC"), [0.0]);
}

#[test]
fn expression_ends_at_backslash_and_same_line_comma() {
    let st =
        one("REQUEST/05, F2=JOINT(1,0,2,0)\\F3=JOINT(1,0,3,0)\\F8=JOINT(1,0,8,0),C=RForce X Y Z");
    assert_eq!(expr(&st, "F2").text, "JOINT(1,0,2,0)");
    assert_eq!(expr(&st, "F3").text, "JOINT(1,0,3,0)");
    assert_eq!(expr(&st, "F8").text, "JOINT(1,0,8,0)");
    assert_eq!(expr(&st, "COMMENT").text, "RForce X Y Z");
    let st = one("VFORCE/9000020, I = 9000005, JFLOAT = 9000104, RM = 9000005\n, FX = 0\\\n, FY = 0\\\n, FZ = -1E5*DZ(9000005,9000001,9000001)\n,-1E4*VZ(9000005,9000001,9000001)");
    assert_eq!(expr(&st, "FX").text, "0");
    assert_eq!(expr(&st, "FY").text, "0");
    assert_eq!(
        expr(&st, "FZ").text,
        "-1E5*DZ(9000005,9000001,9000001)-1E4*VZ(9000005,9000001,9000001)"
    );
    let st = one("VFORCE/3,I=8,JFLOAT=2,RM=1,FX=18,FY=40,FZ=70");
    assert_eq!(expr(&st, "FY").text, "40");
}

#[test]
fn expression_ends_at_continuation_keyword_or_conditional() {
    let st = one("VARIABLE/5,FUNCTION=21E08+32E-06/(74.12E+01*441-18-57*VR(78,81)-65)^12+\n,2**78+2/(1+5),IC=18E05");
    assert_eq!(
        expr(&st, "FUNCTION").text,
        "21E08+32E-06/(74.12E+01*441-18-57*VR(78,81)-65)^12+2**78+2/(1+5)"
    );
    assert_eq!(numbers(&st, "IC"), [18e5]);
    let st = one("SFORCE/1, I = 1, J = 2\n, FUNCTION = 10*DM(1,2)\n, TRANSLATIONAL\n, ACTIONONLY");
    assert_eq!(expr(&st, "FUNCTION").text, "10*DM(1,2)");
    assert!(st.arg("TRANSLATIONAL").is_some() && st.arg("ACTIONONLY").is_some());
    let st = one("MOTION/1, JOINT = 1, FUNCTION = 2*time\n, VELOCITY");
    assert_eq!(expr(&st, "FUNCTION").text, "2*time");
    assert!(st.arg("VELOCITY").is_some());
    // After an operator the line must continue the expression.
    let st = one("SFORCE/1, I = 1, J = 2, FUNCTION = 10 *\n, ACTIONONLY");
    assert_eq!(expr(&st, "FUNCTION").text, "10 * ACTIONONLY");
}

#[test]
fn expression_keeps_strings_and_if_colons() {
    let st = one("GFORCE/1,I=1,RM=2,FX=18+(20*(40)-18)\\FY=22*DM(44,22)\\TZ=(IF(VR(78,81)\n,:0.18,0.42,0.32)),JFLOAT=2");
    assert_eq!(expr(&st, "TZ").text, "(IF(VR(78,81):0.18,0.42,0.32))");
    assert_eq!(numbers(&st, "JFLOAT"), [2.0]);
}

#[test]
fn unbalanced_parentheses_are_errors_at_the_position() {
    assert_eq!(
        errors("VARIABLE/1, FUNCTION = (1 + 2\n, + 3"),
        [(2, 24, "unclosed '(' in expression".to_string())]
    );
    assert_eq!(
        errors("VARIABLE/1, FUNCTION = 1 + 2)"),
        [(2, 29, "unbalanced ')' in expression".to_string())]
    );
    assert_eq!(errors("VARIABLE/1, FUNCTION = [1 + 2)")[0].1, 30);
    assert_eq!(
        errors("VARIABLE/1, FUNCTION = , IC = 1"),
        [(2, 22, "missing expression after 'FUNCTION ='".to_string())]
    );
}

#[test]
fn unterminated_string_is_an_error() {
    assert_eq!(errors("REQUEST/1, CNAMES = \"abc")[0].1, 21);
}

#[test]
fn continuation_without_statement_is_an_error() {
    assert_eq!(errors(", MASS = 1")[0].0, 2);
}

#[test]
fn never_panics_on_odd_input() {
    let samples = [
        "",
        "\n",
        "\n/",
        "\n/1",
        "\n,",
        "\n;",
        "\n;;;",
        "\nPART/",
        "\nPART/1,",
        "\nPART/1,,,",
        "\nPART/1, =",
        "\nPART/1, MASS==",
        "\nPART/1, IP=1:",
        "\nVARIABLE/1, FUNCTION=(",
        "\nVARIABLE/1, FUNCTION=)",
        "\nVARIABLE/1, FUNCTION=\\",
        "\nVARIABLE/1, FUNCTION=\"",
        "\nREQUEST/1, C=",
        "\nREQUEST/1, C=\"",
        "\nMARKER/1, QP=1 D",
        "\nMARKER/1, QP=1 D D",
        "\nMARKER/1, QP=-",
        "\nMARKER/1, QP=+.E",
        "\n\u{0}\u{0}",
        "\nPART/1 &",
        "\n&",
        "\n,&",
        "\nSTRING/1, STRING = \u{0}\u{0}\u{0}",
        "\n\u{feff}PART/1",
        "\nÄ/1, Ü=ö",
        "\nPART/1, X=10,20,30, Z=",
        "\nMOTION/1, X = ",
        "\nGRAPHICS/1, CYLINDER, CM=1\\\\\\",
    ];
    for s in samples {
        let _ = run(s);
        let _ = parse(Arc::from("t"), s, 0, Language::Commands, true);
    }
}

#[test]
fn value_may_start_on_the_continuation_line() {
    let st = one("FIELD/1101\r\n, I = 1101\r\n, CMATRIX = \r\n,  2.0210E+04,  0.0\r\n, -1.1128E+06\r\n, LENGTH = 1");
    assert_eq!(numbers(&st, "CMATRIX"), [2.021e4, 0.0, -1.1128e6]);
    assert_eq!(numbers(&st, "LENGTH"), [1.0]);
    let st = one("MARKER/1, QP =\n, 1, 2, 3\n, REULER = 0, 0, 0");
    assert_eq!(numbers(&st, "QP"), [1.0, 2.0, 3.0]);
    // The next argument is not taken as the value.
    let e = errors("MARKER/1, QP =\n, REULER = 0, 0, 0");
    assert_eq!(e, [(3, 1, "missing value after 'QP ='".to_string())]);
}

#[test]
fn text_list_continues_over_commas() {
    let st = one("GSE/990, NO = 1, FUNCTION = USER(0)\\\n, INTERFACE = adrill_solver::gse_deriv, adrill_solver::gse_output\n, adrill_solver::gse_update, adrill_solver::gse_samp\n, U = 991");
    assert_eq!(
        words(&st, "INTERFACE"),
        [
            "<adrill_solver::gse_deriv>",
            "<adrill_solver::gse_output>",
            "<adrill_solver::gse_update>",
            "<adrill_solver::gse_samp>"
        ]
    );
    assert_eq!(numbers(&st, "U"), [991.0]);
}
