//! Fuzzing of the expression language: random expressions from the grammar (every function
//! name, with right and wrong argument counts, every operator, the numbers that break
//! arithmetic), the same texts mutated character by character, and deep nesting of every
//! kind. Deterministic (fixed seed, a fixed number of inputs), as `linkage-solve`'s
//! `tests/fuzz.rs`, whose header says why this is not `cargo fuzz`.
//!
//! Properties: parsing and every evaluation (value, gradient, time series) never panic and
//! never overflow the stack; a value that evaluates is finite; the value with and without
//! the gradient agree; what `Display` prints parses back to the same tree.
//!
//! `LINKAGE_FUZZ_ITERATIONS` and `LINKAGE_FUZZ_SEED` change the run (long local runs).

mod common;

use common::MockEnv;
use linkage_expr::{
    evaluate, evaluate_path_series, evaluate_time_series, evaluate_with_gradient, parse,
    ElementForce, Intrinsic, MeasureKind, Special, TimeEnv,
};
use std::panic::{catch_unwind, AssertUnwindSafe};

/// Small deterministic generator (64-bit LCG with the high bits taken).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> usize {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 33) as usize
    }
    fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            self.next() % n
        }
    }
    fn pick<'a>(&mut self, items: &'a [&'a str]) -> &'a str {
        items[self.below(items.len())]
    }
}

fn env_or<T: std::str::FromStr>(name: &str, default: T) -> T {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

const NUMBERS: &[&str] = &[
    "0", "1", "2", "0.5", ".5", "1.", "3", "1E308", "1E-320", "1E-300", "1E400", "90D", "360D",
    "1.0E-04", "5.0E-002", "4.32E+09", "1E3", "1000000", "0.0", "7",
];
const ATOMS: &[&str] = &["TIME", "PI", "DTOR", "RTOD", "MODE", "time"];
const BINARY: &[&str] = &["+", "-", "*", "/", "%", "**"];

/// Every callable name with how many arguments it might take (0 to 6, some right, most wrong).
fn names() -> Vec<&'static str> {
    let mut n: Vec<&'static str> = Vec::new();
    n.extend(Intrinsic::ALL.iter().map(|f| f.name()));
    n.extend(Special::ALL.iter().map(|f| f.name()));
    n.extend(MeasureKind::ALL.iter().map(|f| f.name()));
    n.extend(ElementForce::ALL.iter().map(|f| f.name()));
    n.extend([
        "VARVAL", "DIF", "DIF1", "ARYVAL", "ORIENT", "USER", "IF", "NOSUCH",
    ]);
    n
}

/// A random expression of depth at most `depth`.
fn expr(rng: &mut Lcg, names: &[&'static str], depth: usize) -> String {
    if depth == 0 || rng.below(4) == 0 {
        return match rng.below(3) {
            0 => rng.pick(ATOMS).to_string(),
            _ => rng.pick(NUMBERS).to_string(),
        };
    }
    match rng.below(9) {
        0..=2 => format!(
            "{} {} {}",
            expr(rng, names, depth - 1),
            rng.pick(BINARY),
            expr(rng, names, depth - 1)
        ),
        3 => format!("-{}", expr(rng, names, depth - 1)),
        4 => format!("({})", expr(rng, names, depth - 1)),
        5 => format!(
            "IF({}: {}, {}, {})",
            expr(rng, names, depth - 1),
            expr(rng, names, depth - 1),
            expr(rng, names, depth - 1),
            expr(rng, names, depth - 1)
        ),
        6 => {
            let v: Vec<String> = (0..3).map(|_| expr(rng, names, depth - 1)).collect();
            let w: Vec<String> = (0..3).map(|_| expr(rng, names, depth - 1)).collect();
            let op = rng.pick(&["*", "%", "+", "-"]);
            format!("[{}] {op} [{}]", v.join(", "), w.join(", "))
        }
        _ => {
            let name = names[rng.below(names.len())];
            // Mostly small ids (markers, elements, splines) so that measures evaluate.
            let n = rng.below(7);
            let args: Vec<String> = (0..n)
                .map(|_| {
                    if rng.below(2) == 0 {
                        rng.below(4).to_string()
                    } else {
                        expr(rng, names, depth - 1)
                    }
                })
                .collect();
            format!("{name}({})", args.join(", "))
        }
    }
}

/// Character-level mutations of `text`.
fn mutate(rng: &mut Lcg, text: &str) -> String {
    let mut chars: Vec<char> = text.chars().collect();
    for _ in 0..1 + rng.below(3) {
        let k = rng.below(chars.len() + 1);
        match rng.below(4) {
            0 if k < chars.len() => {
                chars.remove(k);
            }
            1 => {
                let c = rng.pick(&[
                    "(", ")", ",", ":", "*", "-", "[", "]", "E", "D", ".", "1", " ", "é",
                ]);
                chars.insert(k, c.chars().next().unwrap_or(' '));
            }
            2 if chars.len() > 1 => {
                let j = rng.below(chars.len());
                let i = k.min(chars.len() - 1);
                chars.swap(i, j);
            }
            _ => {
                for (at, c) in rng.pick(NUMBERS).chars().enumerate() {
                    chars.insert((k + at).min(chars.len()), c);
                }
            }
        }
    }
    chars.into_iter().collect()
}

/// Parses and evaluates `text` every way; `Err` says which property failed.
fn check(text: &str) -> Result<(), String> {
    let Ok(e) = parse(text) else {
        return Ok(());
    };
    let printed = e.to_string();
    match parse(&printed) {
        Ok(again) if again == e => {}
        Ok(again) => {
            return Err(format!(
                "{text:?} prints as {printed:?}, which reads as {again:?}"
            ))
        }
        Err(err) => {
            return Err(format!(
                "{text:?} prints as {printed:?}, which fails: {err}"
            ))
        }
    }
    let env = MockEnv::new();
    let value = evaluate(&e, &env);
    if let Ok(v) = value {
        if !v.is_finite() {
            return Err(format!("{text:?} evaluates to {v}"));
        }
    }
    if let (Ok(v), Ok(d)) = (&value, evaluate_with_gradient(&e, &env)) {
        let same = v == &d.value() || (v - d.value()).abs() <= 1e-12 * v.abs().max(1.0);
        if !same {
            return Err(format!("{text:?}: value {v}, with gradient {}", d.value()));
        }
    }
    for t in [0.0, 1.0, -1.0] {
        if let Ok(s) = evaluate_time_series(&e, &TimeEnv { time: t, mode: 1 }) {
            if s.iter().any(|x| !x.is_finite()) {
                return Err(format!("{text:?}: time series {s:?} at {t}"));
            }
        }
    }
    let _ = evaluate_path_series(&e, &env);
    Ok(())
}

fn run_one(text: &str) -> Result<(), String> {
    catch_unwind(AssertUnwindSafe(|| check(text)))
        .unwrap_or_else(|_| Err(format!("{text:?} panicked")))
}

#[test]
fn random_expressions_never_panic() {
    let iterations: u64 = env_or("LINKAGE_FUZZ_ITERATIONS", 20_000);
    let seed: u64 = env_or("LINKAGE_FUZZ_SEED", 0xe_c4e);
    let names = names();
    let mut rng = Lcg(seed);
    let mut failures = Vec::new();
    for k in 0..iterations {
        let depth = 1 + rng.below(6);
        let mut text = expr(&mut rng, &names, depth);
        if rng.below(3) == 0 {
            text = mutate(&mut rng, &text);
        }
        if let Err(why) = run_one(&text) {
            eprintln!("iteration {k}: {why}");
            failures.push(why);
        }
    }
    assert!(
        failures.is_empty(),
        "{} failures; the first: {}",
        failures.len(),
        failures[0]
    );
}

/// Nesting far beyond the parser's limits, of every kind, is an error, not a stack overflow
/// (the test thread has the default 2 MiB stack).
#[test]
fn deep_nesting_of_every_kind_is_an_error() {
    let n = 100_000;
    let texts = [
        format!("{}1{}", "(".repeat(n), ")".repeat(n)),
        format!("{}1", "-".repeat(n)),
        format!("{}1", "+-".repeat(n)),
        format!("2{}", "**2".repeat(n)),
        format!("1{}", "+1".repeat(n)),
        format!("1{}", "/0".repeat(n)),
        format!("{}TIME{}", "SIN(".repeat(n), ")".repeat(n)),
        format!("{}1{}", "IF(1:".repeat(n), ",2,3)".repeat(n)),
        format!("{}1{}", "[".repeat(n), ",0,0]".repeat(n)),
        format!("{}1", "-(".repeat(n)),
        "(".repeat(n),
        ")".repeat(n),
    ];
    for t in &texts {
        if let Err(why) = run_one(t) {
            panic!("{}…: {why}", &t[..40.min(t.len())]);
        }
    }
}

/// Division by zero, overflow, domain errors: errors (or finite values), never panics.
#[test]
fn arithmetic_edges_evaluate_or_fail_cleanly() {
    for t in [
        "1/0",
        "0/0",
        "1%0",
        "MOD(1, 0)",
        "0**-1",
        "(-8)**(1/3)",
        "1E308*10",
        "EXP(1E3)",
        "LOG(0)",
        "SQRT(-1)",
        "ACOS(2)",
        "ATAN2(0, 0)",
        "10**400",
        "1E400",
        "1E-320/1E-320",
        "SINH(1E3)",
        "TAN(PI/2)",
        "AINT(1E300)",
        "ANINT(-1E300)",
        "DIM(1E308, -1E308)",
        "STEP(TIME, 1, 0, 1, 1)",
        "HAVSIN(TIME, 0, 0, 0, 1)",
        "POLY(TIME, 0)",
        "CHEBY(TIME, 0)",
        "FORCOS(TIME, 0, 0)",
        "IMPACT(TIME, 0, 0, 1, 1, 1, 1)",
        "BISTOP(TIME, 0, 1, 0, 1, 1, 1, 1)",
        "AKISPL(TIME, 0, 1E10)",
        "CUBSPL(TIME, 0, -1)",
        "SHF(TIME, 0, 1, 1E308, 0, 0)",
        "DX(4294967296)",
        "VARVAL(-1)",
        "ARYVAL(1, 1E10)",
        "JOINT(1, 2, 9)",
        "ORIENT(99, 1, 1)",
        "MODE**MODE**MODE**MODE",
        "STEP5(TIME, 0, 0, 0, 1)",
        // Found by the fuzzer: f''/2 finite, f'' = inf, returned as a time series.
        "1E308 / TIME",
    ] {
        if let Err(why) = run_one(t) {
            panic!("{why}");
        }
    }
}
