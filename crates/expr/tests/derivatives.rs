//! Exact derivatives checked against central finite differences.
mod common;

use common::{MockEnv, TIME_VAR};
use linkage_expr::{
    evaluate, evaluate_time_series, evaluate_with_gradient, parse, ElementForce, MeasureKind,
    TimeEnv,
};

/// Checks every partial derivative of `text` (variables 0..6 and TIME) against central
/// differences at the mock environment's point.
fn check_gradient(text: &str) {
    let expr = parse(text).unwrap_or_else(|e| panic!("{text}: {e}"));
    let env = MockEnv::new();
    let d = evaluate_with_gradient(&expr, &env).unwrap_or_else(|e| panic!("{text}: {e}"));
    let v = evaluate(&expr, &env).unwrap();
    assert!(
        (d.value() - v).abs() <= 1e-12 * (1.0 + v.abs()),
        "{text}: value {} vs {v}",
        d.value()
    );
    let h = 1e-6;
    let perturbed = |k: u32, delta: f64| {
        let mut e = env.clone();
        if k == TIME_VAR {
            e.time += delta;
        } else {
            e.q[k as usize] += delta;
        }
        evaluate(&expr, &e).unwrap_or_else(|err| panic!("{text}: {err}"))
    };
    let vars = (0..env.q.len() as u32).chain([TIME_VAR]);
    let mut any_nonzero = false;
    for k in vars {
        let fd = (perturbed(k, h) - perturbed(k, -h)) / (2.0 * h);
        let exact = d.derivative(k);
        any_nonzero |= exact != 0.0;
        assert!(
            (fd - exact).abs() <= 1e-6 * (1.0 + exact.abs()),
            "{text}: d/dvar{k}: exact {exact}, finite difference {fd}"
        );
    }
    for &(k, _) in d.gradient() {
        assert!(
            k < env.q.len() as u32 || k == TIME_VAR,
            "{text}: stray index {k}"
        );
    }
    assert!(
        any_nonzero,
        "{text}: the gradient is identically zero (weak test case)"
    );
}

fn check_all(texts: &[&str]) {
    for t in texts {
        check_gradient(t);
    }
}

#[test]
fn operators() {
    check_all(&[
        "DX(1) + DY(2)",
        "DX(1) - DY(2)",
        "DX(1) * DY(2)",
        "DX(1) / DY(2)",
        "-DX(1)",
        "DX(1)**2",
        "DX(1)**3",
        "DX(1)**-2",
        "DY(2)**0 + DX(1)",
        "(ABS(DX(1)) + 0.5)**DY(2)",
        "2**DX(1)",
        "(ABS(DX(1)) + 0.5)**1.5",
        "30D*DX(1) + PI*DTOR*RTOD*DY(2)",
        "TIME*DX(1) + SIN(TIME)",
        "MODE*DX(1)",
        "[DX(1), DY(2), DZ(3)] * [VX(1), 2, TIME]",
        "([DX(1), 1, 2] % [DY(2), DZ(3), 3]) * [1, TIME, VM(1)]",
        "(2*[DX(1), 1, 1] - [1, DY(2), 1]/DZ(3))*[1, 1, 1]",
        "-[DX(1), 1, 1]*[DY(2), 1, 1]*DZ(3)",
        "([DX(1), 1, 1] + [DY(2), 1, 1])*([DX(1), 1, 1]*DY(2))",
    ]);
}

#[test]
fn intrinsics() {
    check_all(&[
        "ABS(DX(1))",
        "ABS(DY(2))",
        "ABS(-DX(1))",
        "ACOS(0.5*SIN(DX(1)))",
        "AINT(3*DX(1)) + DY(2)",
        "ANINT(3*DX(1)) + DY(2)",
        "ASIN(0.5*SIN(DX(1)))",
        "ATAN(DX(1))",
        "ATAN2(DX(1), DY(2))",
        "ATAN2(DX(1) + 3, DY(2))",
        "ATAN2(DX(1), DY(2) - 3)",
        "ATAN2(DX(1) - 3, -0.1*DY(2))",
        "ATAN2(DX(1), -3 + DY(2))",
        "COS(DX(1)*DY(2))",
        "COSH(DX(1))",
        "DIM(DX(1) + 5, DY(2))",
        "DIM(DX(1) - 5, DY(2)) + DX(1)",
        "EXP(DX(1))",
        "LOG(DX(1)**2 + 1)",
        "LOG10(DX(1)**2 + 1)",
        "MAX(DX(1), DY(2), VZ(3))",
        "MIN(DX(1), DY(2), VZ(3))",
        "MOD(5*DX(1), DY(2) + 3)",
        "MOD(-5*DX(1), DY(2) - 3)",
        "SIGN(DX(1), DY(2))",
        "SIGN(DX(1), -DY(2))",
        "SIN(DX(1))",
        "SINH(DX(1))",
        "SQRT(DX(1)**2 + 1)",
        "TAN(0.3*DX(1))",
        "TANH(DX(1))",
    ]);
}

#[test]
fn special_functions() {
    check_all(&[
        "STEP(DX(1), -5, DY(2), 5, VZ(3))",
        "STEP(DX(1), DY(2) - 3, 1, DY(2) + 3, 2)",
        "STEP(DX(1), 10, DY(2), 11, 2)",
        "STEP(DX(1), -10, DY(2), -9, VZ(3))",
        "STEP5(DX(1), -5, DY(2), 5, VZ(3))",
        "STEP5(DX(1), DY(2) - 3, 1, DY(2) + 3, 2)",
        "HAVSIN(DX(1), -5, DY(2), 5, VZ(3))",
        "HAVSIN(DX(1), DY(2) - 3, 1, DY(2) + 3, 2)",
        "SHF(DX(1), DY(2), VX(3), 1.3, WZ(4), 2)",
        "POLY(DX(1), 0.2, 1, DY(2), 3, -0.5)",
        "CHEBY(DX(1), 0.1, 1, 2, DY(2), 4, 5)",
        "FORCOS(DX(1), 0.1, 2, 1, DY(2), 3)",
        "FORSIN(DX(1), 0.1, DZ(3), 1, DY(2), 3)",
        "IMPACT(DX(1), -ABS(VZ(2)), DX(1) + 0.03, 100, 1.5, 10, 0.1)",
        "IMPACT(DX(1), -ABS(VZ(2)), DX(1) + 0.3, 100, 1.5, 10, 0.1)",
        "IMPACT(DX(1), -ABS(VZ(2)), DX(1) + 0.3 + 0.1*DY(2)**2, 1 + DZ(3)**2, 2.5, 10, 0.1)",
        "BISTOP(DX(1), -ABS(VZ(2)), DX(1) + 0.03, DX(1) + 1, 100, 2, 10, 0.1)",
        "BISTOP(DX(1), ABS(VZ(2)), DX(1) - 1, DX(1) - 0.02, 100, 2, 10, 0.1)",
        "BISTOP(DX(1), ABS(VZ(2)), DX(1) - 1, DX(1) - 0.5, 100, 2, 10, 0.1)",
        "AKISPL(DX(1), 0, 1)",
        "AKISPL(DX(1), 0, 1, 1) + DX(1)",
        "AKISPL(DX(1), 0, 1, 2) + AKISPL(DX(1) + 1.5, 0, 1, 2)",
        "AKISPL(DX(1) + 1.5, 0, 1)",
        "AKISPL(DX(1) + 1.5, 0, 1, 1)",
        "AKISPL(DX(1) + 4.5, 0, 1)",
        "AKISPL(DX(1) - 3.5, 0, 1)",
        "CUBSPL(DX(1) - 3.5, 0, 1, 1)",
        "CUBSPL(DX(1), 0, 1)",
        "CUBSPL(DX(1), 0, 1, 1)",
        "CUBSPL(DX(1), 0, 1, 2)",
        "CUBSPL(DX(1) + 10, 0, 1)",
        "IF(DX(1): DY(2)**2, 0, SIN(VZ(3)))",
        "IF(DX(1) - 10: DY(2)**2, 0, SIN(VZ(3)))",
        "IF(DX(1) + 10: DY(2)**2, 0, SIN(VZ(3)))",
    ]);
}

#[test]
fn measures_forces_and_states() {
    for kind in MeasureKind::ALL {
        check_gradient(&format!("{}(2, 3)*{}(1)", kind.name(), kind.name()));
    }
    for kind in ElementForce::ALL {
        check_gradient(&format!("{}(2, 1, 3, 4)**2", kind.name()));
    }
    check_all(&["VARVAL(1)*DIF(2) + DIF1(3)", "ARYVAL(4, 2)*SIN(VARVAL(1))"]);
}

/// Checks `[f, f', f'']` from Taylor arithmetic against finite differences in time.
fn check_time(text: &str, times: &[f64]) {
    let expr = parse(text).unwrap_or_else(|e| panic!("{text}: {e}"));
    let f = |t: f64| {
        evaluate(&expr, &TimeEnv { time: t, mode: 0 }).unwrap_or_else(|e| panic!("{text}: {e}"))
    };
    let mock = MockEnv::new();
    for &t in times {
        let [v, d1, d2] = evaluate_time_series(&expr, &TimeEnv { time: t, mode: 0 })
            .unwrap_or_else(|e| panic!("{text} at {t}: {e}"));
        assert!((v - f(t)).abs() <= 1e-12 * (1.0 + v.abs()), "{text}: value");
        let h1 = 1e-6;
        let fd1 = (f(t + h1) - f(t - h1)) / (2.0 * h1);
        let h2 = 1e-4;
        let fd2 = (f(t + h2) - 2.0 * f(t) + f(t - h2)) / (h2 * h2);
        assert!(
            (d1 - fd1).abs() <= 1e-6 * (1.0 + d1.abs()),
            "{text} at t={t}: f' exact {d1}, fd {fd1}"
        );
        assert!(
            (d2 - fd2).abs() <= 2e-5 * (1.0 + d2.abs()),
            "{text} at t={t}: f'' exact {d2}, fd {fd2}"
        );
        // the gradient path agrees on df/dt
        let mut env = mock.clone();
        env.time = t;
        let g = evaluate_with_gradient(&expr, &env).unwrap();
        assert!((g.derivative(common::TIME_VAR) - d1).abs() <= 1e-9 * (1.0 + d1.abs()));
    }
}

#[test]
fn time_series() {
    let e = parse("30.0d*time").unwrap();
    let [f, d1, d2] = evaluate_time_series(&e, &TimeEnv { time: 2.0, mode: 0 }).unwrap();
    let rate = 30.0 * std::f64::consts::PI / 180.0;
    assert!((f - 2.0 * rate).abs() < 1e-15 && (d1 - rate).abs() < 1e-15 && d2 == 0.0);
    let e = parse("STEP(TIME, 0, 0, 1, 1)").unwrap();
    let at = |t: f64| evaluate_time_series(&e, &TimeEnv { time: t, mode: 0 }).unwrap();
    assert_eq!(at(1.5), [1.0, 0.0, 0.0]);
    assert_eq!(at(-0.5), [0.0, 0.0, 0.0]);
    // 3t² − 2t³ at 0.5: 0.5, 6t − 6t² = 1.5, 6 − 12t = 0
    assert_eq!(at(0.5), [0.5, 1.5, 0.0]);

    let times = [0.3, 0.8, 1.7];
    for text in [
        "30.0d*time",
        "STEP(TIME, 0, 0, 1, 1)",
        "STEP(TIME, 0.1, -2, 2.5, 3)",
        "STEP5(TIME, 0, 1, 2, 3)",
        "HAVSIN(TIME, 0, 0, 2, 1)",
        "SHF(TIME, 0.1, 2, 3, 0.5, 1)",
        "POLY(TIME, 0.5, 1, 2, 3, 4)",
        "CHEBY(TIME, 0, 1, 2, 3, 4)",
        "FORCOS(TIME, 0, 2, 1, 2, 3)",
        "FORSIN(TIME, 0.2, 2, 1, 2, 3)",
        "IMPACT(TIME, -1, 2, 100, 1.5, 10, 0.5)",
        "BISTOP(TIME, 1, 1, 1.5, 100, 2.5, 10, 0.5)",
        "ABS(TIME - 1)",
        "ACOS(TIME/2)",
        "ASIN(TIME/2)",
        "ATAN(TIME)",
        "ATAN2(TIME, 1 - TIME)",
        "ATAN2(1, TIME - 3)",
        "COS(TIME**2)",
        "COSH(TIME)",
        "DIM(TIME, 0.2)",
        "EXP(-TIME)",
        "LOG(TIME)",
        "LOG10(TIME + 1)",
        "MAX(TIME, 1 - TIME)",
        "MIN(TIME, 1 - TIME)",
        "MOD(3*TIME, 0.7)",
        "SIGN(TIME**2, TIME - 0.5)",
        "SIN(TIME)*COS(2*TIME)",
        "SINH(TIME)",
        "SQRT(TIME)",
        "TAN(TIME)",
        "TANH(TIME)",
        "TIME**TIME",
        "TIME**3",
        "1/TIME",
        "TIME**-0.5",
        "2**TIME",
        "(TIME - 1)**2",
        "AINT(TIME*3) + ANINT(TIME)",
        "AKISPL(TIME, 0, 1)",
        "AKISPL(TIME, 0, 1, 1)",
        "CUBSPL(TIME, 0, 1)",
        "CUBSPL(TIME, 0, 1, 1)",
        "IF(TIME - 0.5: TIME**2, 0, SIN(TIME))",
        "[TIME, 1, 2]*[TIME**2, TIME, 1]",
        "([TIME, 1, 0]%[0, TIME**2, 1])*[1, 1, TIME]",
    ] {
        if text.contains("SPL") {
            check_time_with_splines(text, &times);
        } else {
            check_time(text, &times);
        }
    }
}

/// Like [`check_time`] but in the mock environment, which provides SPLINE/1.
fn check_time_with_splines(text: &str, times: &[f64]) {
    let expr = parse(text).unwrap();
    let env_at = |t: f64| {
        let mut e = MockEnv::new();
        e.time = t;
        e
    };
    let f = |t: f64| evaluate(&expr, &env_at(t)).unwrap();
    for &t in times {
        let [v, d1, d2] = evaluate_time_series(&expr, &env_at(t)).unwrap();
        assert!((v - f(t)).abs() < 1e-12);
        let fd1 = (f(t + 1e-6) - f(t - 1e-6)) / 2e-6;
        let fd2 = (f(t + 1e-4) - 2.0 * f(t) + f(t - 1e-4)) / 1e-8;
        assert!((d1 - fd1).abs() <= 1e-6 * (1.0 + d1.abs()), "{text} at {t}");
        assert!((d2 - fd2).abs() <= 2e-5 * (1.0 + d2.abs()), "{text} at {t}");
    }
}
