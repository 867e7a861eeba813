mod common;

use common::{assert_close, eval_str, MockEnv, TIME_VAR};
use linkage_expr::{
    evaluate, evaluate_time_series, evaluate_with_gradient, parse, ElementForce, ElementForceArgs,
    EvalErrorKind, ForceComponent, MarkerArgs, MeasureKind, SplineData, StateRef, TimeEnv,
};
use std::f64::consts::{E, PI};

fn t(time: f64) -> TimeEnv {
    TimeEnv { time, mode: 0 }
}

fn check(text: &str, want: f64) {
    assert_close(eval_str(text, &MockEnv::new()), want, 1e-12, text);
}

#[test]
fn intrinsics() {
    check("ABS(-3)", 3.0);
    check("ABS(2.5)", 2.5);
    check("ACOS(0.5)", PI / 3.0);
    check("AINT(-2.7)", -2.0);
    check("AINT(2.7)", 2.0);
    check("ANINT(2.5)", 3.0);
    check("ANINT(-2.5)", -3.0);
    check("ANINT(2.4)", 2.0);
    check("ASIN(0.5)", PI / 6.0);
    check("ATAN(1)", PI / 4.0);
    check("ATAN2(1, -1)", 3.0 * PI / 4.0);
    check("ATAN2(-2, 0)", -PI / 2.0);
    check("ATAN2(0, -1)", PI);
    check("COS(PI)", -1.0);
    check("COSH(0)", 1.0);
    check("COSH(1)", (E + 1.0 / E) / 2.0);
    check("DIM(5, 3)", 2.0);
    check("DIM(3, 5)", 0.0);
    check("EXP(1)", E);
    check("LOG(EXP(2))", 2.0);
    check("LOG10(1000)", 3.0);
    check("MAX(1, 5, 3)", 5.0);
    check("MAX(-1, -5)", -1.0);
    check("MIN(4, -2, 7)", -2.0);
    check("MOD(7, 3)", 1.0);
    check("MOD(-7, 3)", -1.0);
    check("MOD(7, -3)", 1.0);
    check("MOD(7.5, 2)", 1.5);
    check("SIGN(3, -2)", -3.0);
    check("SIGN(-3, 2)", 3.0);
    check("SIGN(-3, 0)", 3.0);
    check("SIN(PI/2)", 1.0);
    check("SINH(1)", (E - 1.0 / E) / 2.0);
    check("SQRT(16)", 4.0);
    check("TAN(PI/4)", 1.0);
    check("TANH(0.5)", (E - 1.0) / (E + 1.0));
}

#[test]
fn steps_match_reference_vectors() {
    check("STEP(0.25, 0, 0, 1, 1)", 0.15625);
    check("STEP5(0.25, 0, 0, 1, 1)", 0.103515625);
    assert_close(
        eval_str("HAVSIN(0.25, 0, 0, 1, 1)", &t(0.0)),
        0.1464466,
        1e-7,
        "HAVSIN",
    );
    for f in ["STEP", "STEP5", "HAVSIN"] {
        check(&format!("{f}(0.5, 0, 0, 1, 1)"), 0.5);
        check(&format!("{f}(-1, 0, 2, 1, 5)"), 2.0);
        check(&format!("{f}(0, 0, 2, 1, 5)"), 2.0);
        check(&format!("{f}(1, 0, 2, 1, 5)"), 5.0);
        check(&format!("{f}(7, 0, 2, 1, 5)"), 5.0);
        // general h0/h1 and interval: STEP(x, 1, 2, 3, -2) at x = 2 is the midpoint 0
        check(&format!("{f}(2, 1, 2, 3, -2)"), 0.0);
    }
    // STEP(1.5, 1, 10, 3, 30): Δ = 0.25 → 10 + 20·0.15625
    check("STEP(1.5, 1, 10, 3, 30)", 13.125);
    check("STEP5(1.5, 1, 10, 3, 30)", 10.0 + 20.0 * 0.103515625);
    // reversed interval runs backwards: Δ = (x - 1)/(0 - 1)
    check("STEP(0.75, 1, 0, 0, 1)", 0.15625);
}

#[test]
fn shf_poly_cheby_fourier() {
    check("SHF(1, 0.5, 2, PI, 0, 1)", 3.0);
    check("SHF(0.25, 0, 3, 2, 0.5, -1)", -1.0);
    // 2·sin(3·(1 − 0.5) − 0.2) + 0.7
    check("SHF(1, 0.5, 2, 3, 0.2, 0.7)", 2.0 * (1.3f64).sin() + 0.7);
    check("POLY(2, 1, 1, 2, 3)", 6.0);
    check("POLY(3, 1, 1, 2, 3)", 17.0);
    check("POLY(5, 2, 7)", 7.0);
    check("POLY(0.5, 0, 1, -1, 0, 8)", 1.0 - 0.5 + 1.0);
    // u = 0.5: T0..T3 = 1, 0.5, -0.5, -1
    check("CHEBY(1.5, 1, 1, 2, 3, 4)", -3.5);
    check("CHEBY(3, 1, 0, 0, 1)", 7.0); // T2(2) = 2·4 − 1
    check("CHEBY(0.2, 0.2, 5, 9, 9)", 5.0 - 9.0); // u = 0: T2 = −1
    check("FORCOS(1, 0, PI/2, 1, 2, 3)", -2.0);
    check("FORSIN(1, 0, PI/2, 1, 2, 3)", 3.0);
    check("FORCOS(0.3, 0.1, 2, 0.5, 1)", 0.5 + (0.4f64).cos());
    check(
        "FORSIN(0.3, 0.1, 2, 0.5, 1, -1)",
        0.5 + (0.4f64).sin() - (0.8f64).sin(),
    );
}

#[test]
fn impact_and_bistop() {
    // §12 vector: 100·0.1^1.5 + 10·1
    check(
        "IMPACT(0.9, -1, 1, 100, 1.5, 10, 0.1)",
        100.0 * 0.1f64.powf(1.5) + 10.0,
    );
    assert_close(
        eval_str("IMPACT(0.9, -1, 1, 100, 1.5, 10, 0.1)", &t(0.0)),
        13.16228,
        1e-6,
        "IMPACT",
    );
    // inside the damping ramp: STEP(0.95, 0.9, 10, 1, 0) = 5
    check(
        "IMPACT(0.95, -1, 1, 100, 1.5, 10, 0.1)",
        100.0 * 0.05f64.powf(1.5) + 5.0,
    );
    check("IMPACT(1, -1, 1, 100, 1.5, 10, 0.1)", 0.0);
    check("IMPACT(1.2, -1, 1, 100, 1.5, 10, 0.1)", 0.0);
    // separating fast: force would be negative → 0
    check("IMPACT(0.95, 10, 1, 100, 1.5, 10, 0.1)", 0.0);

    // left of x1: 100·0.1² + 10·1
    check("BISTOP(-0.1, -1, 0, 1, 100, 2, 10, 0.05)", 11.0);
    // right of x2: −100·0.1² − 10·1
    check("BISTOP(1.1, 1, 0, 1, 100, 2, 10, 0.05)", -11.0);
    // inside the gap
    check("BISTOP(0.5, 3, 0, 1, 100, 2, 10, 0.05)", 0.0);
    check("BISTOP(0, 3, 0, 1, 100, 2, 10, 0.05)", 0.0);
    check("BISTOP(1, 3, 0, 1, 100, 2, 10, 0.05)", 0.0);
    // right, within the damping ramp: STEP(1.025, 1, 0, 1.05, 10) = 5
    check(
        "BISTOP(1.025, 2, 0, 1, 100, 2, 10, 0.05)",
        -100.0 * 0.025f64.powi(2) - 5.0 * 2.0,
    );
    // right side moving back into the gap fast: min(·, 0) = 0
    check("BISTOP(1.1, -5, 0, 1, 100, 2, 10, 0.05)", 0.0);
    // left side separating fast: max(·, 0) = 0
    check("BISTOP(-0.1, 5, 0, 1, 100, 2, 10, 0.05)", 0.0);
}

#[test]
fn arithmetic_if_evaluates_only_the_chosen_branch() {
    let env = MockEnv::new();
    assert_eq!(eval_str("IF(1: 1/0, 0, 5)", &env), 5.0);
    assert_eq!(eval_str("IF(-1: 2, 1/0, SQRT(-1))", &env), 2.0);
    assert_eq!(eval_str("IF(0: LOG(0), 3, 1/0)", &env), 3.0);
    assert_eq!(eval_str("IF(TIME - 0.37: 1, 2, 3)", &env), 2.0);
    let mut m5 = MockEnv::new();
    m5.mode = 5;
    assert_eq!(eval_str("IF(MODE-5: 0, 1, 0)", &m5), 1.0);
    assert_eq!(eval_str("IF(MODE-5: 0, 1, 0)", &env), 0.0);
    assert!(evaluate(&parse("IF(1: 0, 0, 1/0)").unwrap(), &env).is_err());
}

fn spline_env() -> MockEnv {
    let mut env = MockEnv::new();
    env.splines.insert(
        2,
        SplineData::new(
            (0..6).map(f64::from).collect(),
            vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
            false,
        )
        .unwrap(),
    );
    env.splines.insert(
        3,
        SplineData::new(
            (0..5).map(f64::from).collect(),
            (0..5).map(|i| f64::from(i * i)).collect(),
            false,
        )
        .unwrap(),
    );
    env.splines.insert(
        4,
        SplineData::new(vec![0.0, 1.0, 2.0], vec![0.0, 1.0, 0.0], false).unwrap(),
    );
    env.splines.insert(
        5,
        SplineData::new(vec![0.0, 1.0, 2.0], vec![0.0, 1.0, 0.0], true).unwrap(),
    );
    env
}

#[test]
fn splines() {
    let env = spline_env();
    let c = |text: &str, want: f64| assert_close(eval_str(text, &env), want, 1e-12, text);
    // through the data points
    let data = env.splines.get(&1).unwrap().clone();
    for (x, y) in data.x().iter().zip(data.y()) {
        c(&format!("AKISPL({x}, 0, 1)"), *y);
        c(&format!("CUBSPL({x}, 0, 1)"), *y);
    }
    // Akima on a step-shaped data set: flat parts stay flat, the rise is the smooth Hermite
    // 3u² − 2u³ (both node slopes are 0).
    c("AKISPL(1.5, 0, 2)", 0.0);
    c("AKISPL(4.5, 0, 2)", 1.0);
    c("AKISPL(2.5, 0, 2)", 0.5);
    c("AKISPL(2.25, 0, 2)", 0.15625);
    c("AKISPL(2.5, 0, 2, 1)", 1.5);
    c("AKISPL(2.25, 0, 2, 2)", 3.0);
    // Akima reproduces x² on equally spaced data (node slopes 2x).
    c("AKISPL(2.5, 0, 3)", 6.25);
    c("AKISPL(0.3, 0, 3)", 0.09);
    c("AKISPL(3.7, 0, 3, 1)", 7.4);
    c("AKISPL(1.2, 0, 3, 2)", 2.0);
    // Natural cubic spline of (0,0),(1,1),(2,0) is 1.5x − 0.5x³ on [0,1].
    c("CUBSPL(0.5, 0, 4)", 0.6875);
    c("CUBSPL(0.5, 0, 4, 1)", 1.5 - 1.5 * 0.25);
    c("CUBSPL(0.5, 0, 4, 2)", -1.5);
    c("CUBSPL(1.5, 0, 4)", 0.6875);
    c("CUBSPL(1.5, 0, 4, 1)", -(1.5 - 1.5 * 0.25));
    // extrapolation: the end cubic continues, or the end tangent with LINEAR_EXTRAPOLATE
    c("CUBSPL(3, 0, 4)", -1.0);
    c("CUBSPL(3, 0, 5)", -1.5);
    c("CUBSPL(3, 0, 5, 1)", -1.5);
    c("CUBSPL(3, 0, 5, 2)", 0.0);
    c("CUBSPL(-1, 0, 5)", -1.5);
    // x may be any expression; z is ignored for 1-D splines
    c("AKISPL(TIME + 1.88, 7, 2)", 0.15625);
}

#[test]
fn spline_errors() {
    let env = spline_env();
    let e = evaluate(&parse("AKISPL(1, 0, 42)").unwrap(), &env).unwrap_err();
    assert_eq!(e.kind, EvalErrorKind::UnknownReference);
    assert_eq!(e.message, "AKISPL: SPLINE/42 does not exist");
    let e = evaluate(&parse("CUBSPL(1, 0, 1, 3)").unwrap(), &env).unwrap_err();
    assert_eq!(e.kind, EvalErrorKind::InvalidArgument);
    let e = evaluate(&parse("CUBSPL(1, 0, 1.5)").unwrap(), &env).unwrap_err();
    assert_eq!(e.kind, EvalErrorKind::InvalidArgument);
}

#[test]
fn measure_arguments_map_to_roles() {
    let env = MockEnv::new();
    let markers = |text: &str| {
        evaluate(&parse(text).unwrap(), &env).unwrap();
        env.last_markers.borrow().unwrap()
    };
    let m = |i, j, k, l| MarkerArgs { i, j, k, l };
    assert_eq!(markers("DX(5)"), (MeasureKind::Dx, m(5, 0, 0, 0)));
    assert_eq!(markers("dz(1,2,3)"), (MeasureKind::Dz, m(1, 2, 3, 0)));
    assert_eq!(markers("VX(1,2,3,4)"), (MeasureKind::Vx, m(1, 2, 3, 4)));
    assert_eq!(markers("VM(1,2,3)"), (MeasureKind::Vm, m(1, 2, 0, 3)));
    assert_eq!(markers("VR(1,2,3)"), (MeasureKind::Vr, m(1, 2, 0, 3)));
    assert_eq!(markers("ACCM(1,2,3)"), (MeasureKind::Accm, m(1, 2, 0, 3)));
    assert_eq!(markers("WDTM(7,8,9)"), (MeasureKind::Wdtm, m(7, 8, 0, 9)));
    assert_eq!(
        markers("WZ(207,208,208)"),
        (MeasureKind::Wz, m(207, 208, 208, 0))
    );
    assert_eq!(
        markers("AZ(0207, 2*104)"),
        (MeasureKind::Az, m(207, 208, 0, 0))
    );
    assert_eq!(
        markers("DM(0202,0102)"),
        (MeasureKind::Dm, m(202, 102, 0, 0))
    );
    for kind in MeasureKind::ALL {
        let text = format!("{}(11)", kind.name());
        assert_eq!(markers(&text), (*kind, m(11, 0, 0, 0)), "{text}");
    }

    let force = |text: &str| {
        evaluate(&parse(text).unwrap(), &env).unwrap();
        env.last_force.borrow().unwrap()
    };
    assert_eq!(
        force("JOINT(7, 1, 4, 9)"),
        (
            ElementForce::Joint,
            ElementForceArgs {
                id: 7,
                on_j: true,
                component: ForceComponent::Fz,
                rm: 9
            }
        )
    );
    assert_eq!(
        force("SFORCE(3, 0, 1)"),
        (
            ElementForce::Sforce,
            ElementForceArgs {
                id: 3,
                on_j: false,
                component: ForceComponent::Fm,
                rm: 0
            }
        )
    );
    for kind in ElementForce::ALL {
        let text = format!("{}(2, 0, 8, 0)", kind.name());
        assert_eq!(force(&text).0, *kind);
    }

    let state = |text: &str| {
        evaluate(&parse(text).unwrap(), &env).unwrap();
        env.last_state.borrow().unwrap()
    };
    assert_eq!(state("VARVAL(3)"), StateRef::Varval(3));
    assert_eq!(state("DIF(4)"), StateRef::Dif(4));
    assert_eq!(state("DIF1(5)"), StateRef::Dif1(5));
    assert_eq!(state("ARYVAL(6, 2)"), StateRef::Aryval { id: 6, index: 2 });
}

fn eval_err(text: &str, env: &MockEnv) -> (EvalErrorKind, String) {
    let e = evaluate(&parse(text).unwrap(), env).expect_err(text);
    (e.kind, e.message)
}

#[test]
fn domain_and_argument_errors() {
    use EvalErrorKind::*;
    let env = MockEnv::new();
    let e = |text: &str| eval_err(text, &env);
    assert_eq!(e("SQRT(-4)"), (Domain, "SQRT of negative number -4".into()));
    assert_eq!(e("1 + 1/(TIME - TIME)").0, Domain);
    assert!(e("1/0").1.contains("division by zero"));
    assert_eq!(e("LOG(0)"), (Domain, "LOG of non-positive number 0".into()));
    assert_eq!(
        e("LOG10(-1)"),
        (Domain, "LOG10 of non-positive number -1".into())
    );
    assert_eq!(e("ACOS(2)"), (Domain, "ACOS of 2, outside [-1, 1]".into()));
    assert!(e("ASIN(-1.5)").1.starts_with("ASIN"));
    assert!(e("MOD(1, 0)").1.starts_with("MOD"));
    assert!(e("ATAN2(0, 0)").1.starts_with("ATAN2"));
    assert!(e("(-8)**(1/3)").1.contains("non-integer power"));
    assert!(e("0**-1").1.contains("division by zero"));
    assert_eq!(eval_str("(-2)**3", &env), -8.0);
    assert_eq!(eval_str("0**0", &env), 1.0);
    assert!(e("EXP(1000)").1.contains("EXP"));
    assert!(e("1E300*1E300").1.contains("'*'"));
    assert!(e("[1,2,3]/0*[1,1,1]").1.contains("division"));
    assert_eq!(e("STEP(1, 2, 0, 2, 1)").0, InvalidArgument);
    assert!(e("IMPACT(0.5, 0, 1, 100, 1.5, 10, 0)")
        .1
        .contains("d must be positive"));
    assert!(e("IMPACT(0.5, 0, 1, -1, 1.5, 10, 0.1)")
        .1
        .contains("k must not be negative"));
    assert!(e("IMPACT(0.5, 0, 1, 1, 0, 10, 0.1)")
        .1
        .contains("e must be positive"));
    assert!(e("BISTOP(0.5, 0, 1, 1, 100, 2, 10, 0.1)")
        .1
        .contains("x1 must be less than x2"));
    assert_eq!(
        e("VARVAL(99)"),
        (UnknownReference, "VARIABLE/99 does not exist".into())
    );
    assert_eq!(e("DX(999)").0, UnknownReference);
    assert_eq!(
        e("DX(1.5)"),
        (
            InvalidArgument,
            "DX: argument 1 (marker id) must be a non-negative integer, got 1.5".into()
        )
    );
    assert_eq!(e("DX(1, -2)").0, InvalidArgument);
    assert!(e("JOINT(1, 2, 1, 0)").1.contains("jflag"));
    assert!(e("JOINT(1, 0, 9, 0)").1.contains("component must be 1..8"));
    assert!(e("ARYVAL(1, 0)").1.contains("1-based"));
    assert_eq!(
        e("2 + USER(1.05, 80, 20, 0.5)"),
        (UserSubroutine, "USER subroutine cannot be run".into())
    );
    // default environment methods report unavailability
    let plain = t(1.0);
    for text in ["DX(1)", "JOINT(1,0,1,0)", "VARVAL(1)", "AKISPL(1, 0, 1)"] {
        assert!(evaluate(&parse(text).unwrap(), &plain).is_err(), "{text}");
    }
    assert_eq!(
        evaluate(&parse("DX(1)").unwrap(), &plain).unwrap_err().kind,
        Unavailable
    );
}

#[test]
fn gradient_and_time_errors() {
    let env = MockEnv::new();
    // SQRT at 0 of a varying argument: infinite derivative
    let e = parse("SQRT(TIME - 0.37)").unwrap();
    assert_eq!(evaluate(&e, &env).unwrap(), 0.0);
    assert_eq!(
        evaluate_with_gradient(&e, &env).unwrap_err().kind,
        EvalErrorKind::Domain
    );
    assert!(evaluate_time_series(&e, &env).is_err());
    // ...but SQRT(0) of a constant is fine
    let c = parse("SQRT(0) + TIME").unwrap();
    assert_eq!(evaluate_time_series(&c, &env).unwrap()[1], 1.0);
    // SQRT(0) + TIME = TIME, d/dTIME = 1.
    let d = evaluate_with_gradient(&c, &env).unwrap();
    assert_eq!((d.value(), d.derivative(TIME_VAR)), (env.time, 1.0));
    // a MOTION function must depend on time only
    for text in [
        "DX(1) + TIME",
        "VARVAL(1)",
        "JOINT(1,0,1,0)",
        "STEP(TIME,0,0,1,DM(1,2))",
    ] {
        let err = evaluate_time_series(&parse(text).unwrap(), &env).unwrap_err();
        assert_eq!(err.kind, EvalErrorKind::NotTimeOnly, "{text}");
        assert!(err
            .message
            .contains("MOTION function must depend on time only"));
    }
    // but the ids inside are fine if they are constant and the measure is in an untaken branch
    let ok = parse("IF(TIME: DX(1), 2*TIME, 3)").unwrap();
    assert_eq!(
        evaluate_time_series(&ok, &TimeEnv { time: 0.0, mode: 0 }).unwrap(),
        [0.0, 2.0, 0.0]
    );
}
