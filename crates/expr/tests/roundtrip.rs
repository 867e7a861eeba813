//! Property-style tests: random trees print to re-parseable text; random text never panics.
mod common;

use common::MockEnv;
use linkage_expr::{
    evaluate, evaluate_time_series, evaluate_with_gradient, parse, BinOp, Constant, ElementForce,
    Expr, Function, Intrinsic, MeasureKind, Special, StateKind,
};

/// xorshift64* pseudo-random generator (deterministic, dependency-free).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
    fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn number(r: &mut Rng) -> f64 {
    match r.below(6) {
        0 => r.below(1000) as f64,
        1 => (r.unit() * 1000.0 * 1000.0).round() / 1000.0,
        2 => r.unit(),
        3 => r.unit() * 1e-300,
        4 => r.unit() * 1e300,
        _ => {
            // arbitrary finite positive bit pattern
            let bits = r.next() & 0x7FEF_FFFF_FFFF_FFFF;
            f64::from_bits(bits)
        }
    }
}

fn all_functions() -> Vec<Function> {
    Intrinsic::ALL
        .iter()
        .map(|&f| Function::Intrinsic(f))
        .chain(Special::ALL.iter().map(|&f| Function::Special(f)))
        .chain(MeasureKind::ALL.iter().map(|&f| Function::Measure(f)))
        .chain(ElementForce::ALL.iter().map(|&f| Function::ElementForce(f)))
        .chain(StateKind::ALL.iter().map(|&f| Function::State(f)))
        .chain([Function::Orient])
        .collect()
}

fn leaf(r: &mut Rng) -> Expr {
    match r.below(3) {
        0 => Expr::Number(number(r)),
        1 => Expr::Degrees(number(r)),
        _ => Expr::Constant(*r.pick(Constant::ALL)),
    }
}

fn bin(op: BinOp, lhs: Expr, rhs: Expr) -> Expr {
    Expr::Binary {
        op,
        lhs: Box::new(lhs),
        rhs: Box::new(rhs),
    }
}

fn vector(r: &mut Rng, depth: usize, fns: &[Function]) -> Expr {
    if depth == 0 || r.below(3) == 0 {
        return Expr::Vector(Box::new([
            scalar(r, depth.saturating_sub(1), fns),
            scalar(r, depth.saturating_sub(1), fns),
            scalar(r, depth.saturating_sub(1), fns),
        ]));
    }
    let d = depth - 1;
    match r.below(6) {
        0 => Expr::Neg(Box::new(vector(r, d, fns))),
        1 => bin(
            *r.pick(&[BinOp::Add, BinOp::Sub]),
            vector(r, d, fns),
            vector(r, d, fns),
        ),
        2 => bin(BinOp::Mul, scalar(r, d, fns), vector(r, d, fns)),
        3 => bin(BinOp::Mul, vector(r, d, fns), scalar(r, d, fns)),
        4 => bin(BinOp::Div, vector(r, d, fns), scalar(r, d, fns)),
        _ => bin(BinOp::Cross, vector(r, d, fns), vector(r, d, fns)),
    }
}

fn scalar(r: &mut Rng, depth: usize, fns: &[Function]) -> Expr {
    if depth == 0 || r.below(5) == 0 {
        return leaf(r);
    }
    let d = depth - 1;
    match r.below(9) {
        0 => Expr::Neg(Box::new(scalar(r, d, fns))),
        1..=3 => {
            let op = *r.pick(&[BinOp::Add, BinOp::Sub, BinOp::Mul, BinOp::Div, BinOp::Pow]);
            bin(op, scalar(r, d, fns), scalar(r, d, fns))
        }
        4 => bin(BinOp::Mul, vector(r, d, fns), vector(r, d, fns)),
        5 => Expr::If {
            test: Box::new(scalar(r, d, fns)),
            lt: Box::new(scalar(r, d, fns)),
            eq: Box::new(scalar(r, d, fns)),
            gt: Box::new(scalar(r, d, fns)),
        },
        6 => {
            let n = r.below(4);
            Expr::User((0..n).map(|_| scalar(r, d, fns)).collect())
        }
        _ => {
            let func = *r.pick(fns);
            let (min, max) = func.arity();
            let max = max.min(min + 3);
            let n = min + r.below(max - min + 1);
            Expr::Call {
                func,
                args: (0..n).map(|_| scalar(r, d, fns)).collect(),
            }
        }
    }
}

#[test]
fn random_trees_print_to_reparseable_text() {
    let fns = all_functions();
    let mut r = Rng(0x9E37_79B9_7F4A_7C15);
    let env = MockEnv::new();
    for i in 0..3000 {
        let depth = 1 + i % 7;
        let e = scalar(&mut r, depth, &fns);
        let text = e.to_string();
        let back = parse(&text).unwrap_or_else(|err| panic!("{text:?}: {err}"));
        assert_eq!(back, e, "{text}");
        // evaluation never panics (errors are fine)
        let _ = evaluate(&e, &env);
        let _ = evaluate_with_gradient(&e, &env);
        let _ = evaluate_time_series(&e, &env);
    }
}

const PIECES: &[&str] = &[
    "1", "2.5", ".5", "1E3", "1.0E-04", "30D", "0", "(", ")", "[", "]", ",", ":", "+", "-", "*",
    "/", "**", "%", " ", "\n", "TIME", "PI", "MODE", "IF(", "USER(", "SIN(", "STEP(", "DX(",
    "MAX(", "AKISPL(", "JOINT(", "VARVAL(", "POLY(", "x", "é", "\\", "1.0D0", "E", "D", "..",
];

#[test]
fn random_text_never_panics() {
    let env = MockEnv::new();
    let mut r = Rng(12345);
    let mut parsed = 0;
    for _ in 0..20_000 {
        let n = 1 + r.below(16);
        let text: String = (0..n).map(|_| *r.pick(PIECES)).collect();
        match parse(&text) {
            Ok(e) => {
                parsed += 1;
                let _ = evaluate(&e, &env);
                let _ = evaluate_with_gradient(&e, &env);
                let _ = evaluate_time_series(&e, &env);
                assert_eq!(parse(&e.to_string()).as_ref(), Ok(&e), "{text:?}");
            }
            Err(err) => assert!(err.offset <= text.len(), "{text:?}: {err}"),
        }
    }
    assert!(parsed > 100, "only {parsed} random strings parsed");
    // raw bytes, including invalid UTF-8 boundaries avoided by lossy conversion
    for _ in 0..5_000 {
        let bytes: Vec<u8> = (0..r.below(24)).map(|_| r.next() as u8).collect();
        let text = String::from_utf8_lossy(&bytes);
        if let Err(err) = parse(&text) {
            assert!(err.offset <= text.len());
            assert!(text.is_char_boundary(err.offset));
        }
    }
}
