mod common;

use common::{eval_str, MockEnv, TIME_VAR};
use linkage_expr::{
    evaluate, parse, BinOp, Constant, Expr, Function, Intrinsic, MeasureKind, Special, TimeEnv,
    MAX_DEPTH, MAX_NESTING,
};

fn num(v: f64) -> Box<Expr> {
    Box::new(Expr::Number(v))
}

fn env() -> TimeEnv {
    TimeEnv { time: 2.0, mode: 5 }
}

#[test]
fn precedence() {
    let e = env();
    assert_eq!(eval_str("2**3**2", &e), 512.0);
    assert_eq!(eval_str("-2**2", &e), -4.0);
    assert_eq!(eval_str("(-2)**2", &e), 4.0);
    assert_eq!(eval_str("2*-3", &e), -6.0);
    assert_eq!(eval_str("2**-1", &e), 0.5);
    assert_eq!(eval_str("-2**-1", &e), -0.5);
    assert_eq!(eval_str("2**-1**2", &e), 0.5);
    assert_eq!(eval_str("2-3-4", &e), -5.0);
    assert_eq!(eval_str("2/4/2", &e), 0.25);
    assert_eq!(eval_str("2*3+4*5", &e), 26.0);
    assert_eq!(eval_str("2+3*4**2", &e), 50.0);
    assert_eq!(eval_str("- -3", &e), 3.0);
    assert_eq!(eval_str("+3 - +2", &e), 1.0);
    assert_eq!(eval_str("-3*-2", &e), 6.0);
    assert_eq!(eval_str("2*3**2", &e), 18.0);
    assert_eq!(eval_str("-(2+3)*2", &e), -10.0);
    assert_eq!(eval_str("1 - 2 + 3", &e), 2.0);
}

#[test]
fn minus_a_pow_minus_b_structure() {
    // -A**-B = -(A**(-B))
    let e = parse("-2**-3").unwrap();
    assert_eq!(
        e,
        Expr::Neg(Box::new(Expr::Binary {
            op: BinOp::Pow,
            lhs: num(2.0),
            rhs: Box::new(Expr::Neg(num(3.0))),
        }))
    );
    assert_eq!(evaluate(&e, &env()).unwrap(), -0.125);
    // right associativity
    assert_eq!(
        parse("1**2**3").unwrap(),
        Expr::Binary {
            op: BinOp::Pow,
            lhs: num(1.0),
            rhs: Box::new(Expr::Binary {
                op: BinOp::Pow,
                lhs: num(2.0),
                rhs: num(3.0),
            }),
        }
    );
}

#[test]
fn numbers_constants_and_case() {
    let e = env();
    assert_eq!(eval_str("1.0E-04", &e), 1.0e-4);
    assert_eq!(eval_str("5.0E-002", &e), 0.05);
    assert_eq!(eval_str("4.32E+09", &e), 4.32e9);
    assert_eq!(eval_str(".4", &e), 0.4);
    assert_eq!(eval_str("180D", &e), std::f64::consts::PI);
    assert_eq!(
        eval_str("30.0d * time", &e),
        60.0 * std::f64::consts::PI / 180.0
    );
    assert_eq!(eval_str("pi", &e), std::f64::consts::PI);
    assert_eq!(eval_str("DTOR*RTOD", &e), 1.0);
    assert_eq!(eval_str("Time", &e), 2.0);
    assert_eq!(eval_str("mode", &e), 5.0);
    assert_eq!(eval_str("sin(Pi/2)", &e), 1.0);
    assert_eq!(parse("30d").unwrap(), Expr::Degrees(30.0));
    assert_eq!(parse("time").unwrap(), Expr::Constant(Constant::Time));
}

#[test]
fn multi_line_real_expressions() {
    let env = MockEnv::new();
    // Continuation lines join into the expression written on one line: the same value.
    let texts = [
        " - 1.0*RTOD*(az(207,208)-0.0*DTOR)\n - 5.0E-002*RTOD*wz(207,208,208)\n + 0.0",
        "IF(MODE-5: 0,-DIF(101)-1E7*(VARVAL(3)-1),0 )",
        "-1E5*DZ(9000005,9000001,9000001)\n-1E4*VZ(9000005,9000001,9000001)",
        "STEP(TIME, 0, 0, 1, 30D)*AKISPL(DX(1,2), 0, 1, 1)",
        "JOINT(1,0,2,0)",
    ];
    for text in texts {
        let multi = evaluate(&parse(text).unwrap(), &env).unwrap();
        let single = evaluate(&parse(&text.replace('\n', " ")).unwrap(), &env).unwrap();
        assert!(multi.is_finite(), "{text}: {multi}");
        assert_eq!(multi, single, "{text}");
    }
    // The first one term by term: −RTOD·AZ − 0.05·RTOD·WZ.
    let first = evaluate(&parse(texts[0]).unwrap(), &env).unwrap();
    let terms = eval_str("-RTOD*AZ(207,208) - 5.0E-002*RTOD*WZ(207,208,208)", &env);
    assert!(
        (first - terms).abs() <= 1e-12 * terms.abs().max(1.0),
        "{first} vs {terms}"
    );
    // MODE is 4 in the mock: the IF takes its first branch, 0.
    assert_eq!(eval_str(texts[1], &env), 0.0);
}

#[test]
fn call_structure() {
    assert_eq!(
        parse("dx(1, 2)").unwrap(),
        Expr::Call {
            func: Function::Measure(MeasureKind::Dx),
            args: vec![Expr::Number(1.0), Expr::Number(2.0)],
        }
    );
    assert_eq!(
        parse("MAX(1,2,3)").unwrap(),
        Expr::Call {
            func: Function::Intrinsic(Intrinsic::Max),
            args: vec![Expr::Number(1.0), Expr::Number(2.0), Expr::Number(3.0)],
        }
    );
    let user = parse("1 + USER(1.05, 80,\n 20, 0.5)").unwrap();
    assert!(user.contains_user());
    assert!(!parse("STEP(TIME,0,0,1,1)").unwrap().contains_user());
    assert!(parse("USER()").unwrap().contains_user());
    assert!(parse("STEP(TIME,0,0,1,1)").unwrap().uses_time());
    assert!(parse("2*VARVAL(1)").unwrap().uses_state());
    assert!(!parse("SIN(TIME)").unwrap().uses_state());
    match parse("POLY(1, 0, 1)").unwrap() {
        Expr::Call { func, .. } => assert_eq!(func, Function::Special(Special::Poly)),
        other => panic!("{other:?}"),
    }
}

fn err(text: &str) -> (usize, String) {
    let e = parse(text).expect_err(text);
    (e.offset, e.message)
}

#[test]
fn error_offsets_and_messages() {
    let (o, m) = err("1 + * 2");
    assert_eq!(o, 4, "{m}");
    assert!(
        m.contains("expected an operand") && m.contains("'*'"),
        "{m}"
    );

    let (o, m) = err("SIN(1");
    assert_eq!(o, 5);
    assert_eq!(
        m,
        "expected ')' to close '(' opened at offset 3, found end of expression"
    );

    let (o, m) = err("FOO(1)");
    assert_eq!((o, m.as_str()), (0, "unknown function 'FOO'"));
    let (o, m) = err("2 * foo");
    assert_eq!((o, m.as_str()), (4, "unknown name 'FOO'"));

    let (o, m) = err("3 + (1 + 2");
    assert_eq!(o, 10);
    assert!(m.contains("opened at offset 4"), "{m}");

    assert_eq!(err("").0, 0);
    assert!(err("   ").1.contains("empty"));
    assert_eq!(err("1 2").0, 2);
    let (o, m) = err("1)");
    assert_eq!(o, 1);
    assert!(m.contains("unmatched"), "{m}");
    assert_eq!(err("1 + 2 +").0, 7);
    assert_eq!(err("SIN 1").0, 4);
    assert_eq!(err("PI(2)"), (0, "PI is a constant, not a function".into()));
    assert_eq!(
        err("1 + STEP(1,2)"),
        (4, "STEP expects 5 arguments, got 2".into())
    );
    assert_eq!(err("SIN()"), (0, "SIN expects 1 argument, got 0".into()));
    assert_eq!(
        err("MAX(1)"),
        (0, "MAX expects at least 2 arguments, got 1".into())
    );
    assert_eq!(
        err("DX(1,2,3,4)"),
        (0, "DX expects 1 to 3 arguments, got 4".into())
    );
    let (o, m) = err("IF(1, 2, 3, 4)");
    assert_eq!(o, 4);
    assert!(m.contains("expected ':'"), "{m}");
    assert_eq!(err("IF(1: 2, 3)").0, 10);
    assert_eq!(err("SIN(1,)").0, 6);
    assert_eq!(err("1.0D0").0, 3);
    assert_eq!(err("1 # 2").0, 2);
}

#[test]
fn vectors() {
    let e = env();
    assert_eq!(eval_str("[1,2,3]*[4,5,6]", &e), 32.0);
    assert_eq!(eval_str("([1,0,0]%[0,1,0])*[0,0,1]", &e), 1.0);
    assert_eq!(eval_str("[1,0,0]%[0,1,0]*[0,0,1]", &e), 1.0);
    assert_eq!(eval_str("(2*[1,2,3] - [1,1,1]/2)*[1,1,1]", &e), 10.5);
    assert_eq!(eval_str("-[1,2,3]*[1,1,1]", &e), -6.0);
    assert_eq!(
        err("[1,2,3]"),
        (0, "the expression is a vector; a scalar is required".into())
    );
    assert_eq!(err("1 % 2").0, 2);
    assert_eq!(err("[1,2,3] + 1").0, 8);
    assert_eq!(err("1 / [1,2,3]").0, 2);
    assert_eq!(err("[1,2,3]**2").0, 7);
    assert_eq!(err("SIN([1,2,3])").0, 4);
    assert_eq!(err("[1,2]").0, 4);
    assert_eq!(err("[1,2,3,4]*[1,1,1]").0, 6);
    assert_eq!(err("[[1,2,3],1,1]*[1,1,1]").0, 1);
    assert_eq!(err("IF([1,2,3]: 1, 2, 3)").0, 3);
}

#[test]
fn display_round_trips_examples() {
    for text in [
        "-2**-3",
        "2**3**2",
        "(2**3)**2",
        "(-2)**2",
        "-(1 + 2)*3",
        "1 - (2 - 3)",
        "1 - -2",
        "2*-3",
        "2/(3*4)",
        "2/3*4",
        "30.0d*TIME",
        "IF(TIME - 1: 0, 1, STEP(TIME, 1, 0, 2, 1))",
        "USER(1, 2, 3)",
        "USER()",
        "[1, 2, 3]*[4, 5, 6]",
        "-[1, 2, 3]%[1, 0, 0]*[0, 1, 0]",
        "0.1 + 1e-300 + 1.5e300",
        "JOINT(1, 0, 2, 0)",
    ] {
        let e = parse(text).unwrap();
        let printed = e.to_string();
        assert_eq!(parse(&printed).unwrap(), e, "{text} -> {printed}");
    }
    assert_eq!(parse("-2**-3").unwrap().to_string(), "-2**-3");
    assert_eq!(parse("(2**3)**2").unwrap().to_string(), "(2**3)**2");
    assert_eq!(parse("1-(2-3)").unwrap().to_string(), "1 - (2 - 3)");
    assert_eq!(
        parse("if(time:1,2,3)").unwrap().to_string(),
        "IF(TIME: 1, 2, 3)"
    );
    assert_eq!(parse("30d").unwrap().to_string(), "30D");
}

#[test]
fn depth_limits_do_not_overflow_the_stack() {
    let n = 100_000;
    let deep_parens = format!("{}1{}", "(".repeat(n), ")".repeat(n));
    assert!(parse(&deep_parens)
        .unwrap_err()
        .message
        .contains("too deeply"));
    let long_sum = vec!["1"; n].join("+");
    assert!(parse(&long_sum).unwrap_err().message.contains("too deeply"));
    let minus = format!("{}1", "-".repeat(n));
    assert!(parse(&minus).is_err());
    let powers = vec!["1"; n].join("**");
    assert!(parse(&powers).is_err());
    let calls = format!("{}1{}", "SIN(".repeat(n), ")".repeat(n));
    assert!(parse(&calls).is_err());

    // Just below the limit: parses, evaluates (with gradient), prints and re-parses.
    let k = MAX_DEPTH - 2;
    let sum = vec!["DX(1)"; k].join("+");
    let n = MAX_NESTING - 2;
    let nested = format!("{}TIME{}", "SIN(".repeat(n), ")".repeat(n));
    let parens = format!("{}TIME{}", "(1+".repeat(n), ")".repeat(n));
    let mixed = format!("{}{}{}", "(".repeat(n), sum, ")".repeat(n));
    let env = MockEnv::new();
    // The values and derivatives they must have, in closed form: k·DX(1) with k times its
    // gradient; SIN applied n times to TIME, d/dTIME = Π cos(sinᵏ(TIME)); n + TIME, d/dTIME = 1;
    // the sum again. Exact up to rounding of n terms (tolerance 1e-12 relative).
    let dx = linkage_expr::evaluate_with_gradient(&parse("DX(1)").unwrap(), &env).unwrap();
    let (mut sine, mut slope) = (env.time, 1.0);
    for _ in 0..n {
        slope *= sine.cos();
        sine = sine.sin();
    }
    let k_dx = |d: &linkage_expr::Dual| {
        assert!((d.value() - k as f64 * dx.value()).abs() < 1e-12 * k as f64);
        for &(var, g) in dx.gradient() {
            assert!((d.derivative(var) - k as f64 * g).abs() < 1e-12 * k as f64);
        }
    };
    for (which, text) in [sum, nested, parens, mixed].into_iter().enumerate() {
        let e = parse(&text).unwrap();
        let d = linkage_expr::evaluate_with_gradient(&e, &env)
            .unwrap_or_else(|err| panic!("case {which}: {err}"));
        match which {
            0 | 3 => k_dx(&d),
            1 => {
                assert!((d.value() - sine).abs() < 1e-12, "{}", d.value());
                assert!((d.derivative(TIME_VAR) - slope).abs() < 1e-12);
            }
            _ => {
                assert!((d.value() - (n as f64 + env.time)).abs() < 1e-12 * n as f64);
                assert_eq!(d.derivative(TIME_VAR), 1.0);
            }
        }
        assert_eq!(parse(&e.to_string()).unwrap(), e);
    }
}
