//! Mutation fuzzing of the whole input path a user's file takes: dataset reader
//! (`linkage_adm::parse_dataset`), model building (`linkage_model::build_model`), motion
//! functions (`ExpressionDrivers::new`), `verify` and `explain`.
//!
//! Why not `cargo fuzz`: it needs a nightly toolchain, and CI runs on stable only. Why not
//! proptest: its strength is shrinking structured values, but our inputs are texts mutated
//! at random, and the harness needs no dependency. So this is a plain test with a
//! deterministic generator (64-bit LCG, fixed seed): every CI run tries the same inputs, a
//! failure reproduces from its iteration number, and the run is bounded (a fixed number of
//! inputs, and a wall-clock cap so a slow machine cannot stall CI).
//!
//! Inputs are mutations of the bundled datasets (`mechanisms/*.adm`, `examples/*.adm`): byte
//! flips, line deletions, duplications and swaps, token swaps between lines, numbers replaced
//! by 0, negative, huge, tiny, `NaN`/`INF` text or overflowing literals, splices of two
//! datasets, pieces of the language inserted anywhere, and random token soup.
//!
//! Properties: nothing panics; every input error carries a line and column; a verification
//! that succeeds reports finite numbers.
//!
//! Long local runs (several minutes, other seeds):
//!
//! ```sh
//! LINKAGE_FUZZ_ITERATIONS=200000 LINKAGE_FUZZ_SEED=7 LINKAGE_FUZZ_SECONDS=600 LINKAGE_FUZZ_CORPUS=1 \
//!     cargo test --release -p linkage-solve --test fuzz -- --nocapture
//! ```
//!
//! A failing input is written to `target/fuzz-failures/` (name = what failed); every crash
//! found becomes a file under `tests/data/fuzz/`, named after what it found, which
//! [`fuzz_regressions_are_handled`] runs every time.

use linkage_solve::constraints::drivers::ExpressionDrivers;
use linkage_solve::pipeline::verify::verify;
use linkage_solve::stages::explain::explain;
use linkage_solve::tolerances::Tolerances;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Once};

/// How far the inputs got: rejected by the reader, by model building, by the motion
/// functions, verified (printed at the end of a run, to see that mutations reach verify).
static REACHED: [AtomicUsize; 4] = [const { AtomicUsize::new(0) }; 4];
use std::time::{Duration, Instant};

/// Small deterministic generator (64-bit LCG with the high bits taken), so failures reproduce.
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

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The bundled datasets, sorted by name (the order the mutations index); with
/// `LINKAGE_FUZZ_CORPUS=1` (long local runs) the shared corpus's datasets too.
fn seeds() -> Vec<String> {
    let mut paths = Vec::new();
    let mut dirs = vec![repo().join("mechanisms"), repo().join("examples")];
    if std::env::var_os("LINKAGE_FUZZ_CORPUS").is_some() {
        dirs.push(repo().join("../shared/corpus"));
    }
    for dir in dirs {
        let Ok(entries) = std::fs::read_dir(dir) else {
            continue;
        };
        for e in entries.flatten() {
            let p = e.path();
            if p.extension().is_some_and(|x| x == "adm") {
                paths.push(p);
            }
        }
    }
    paths.sort();
    let texts: Vec<String> = paths
        .iter()
        .filter_map(|p| std::fs::read_to_string(p).ok())
        .collect();
    assert!(!texts.is_empty(), "no seed datasets under mechanisms/");
    texts
}

/// Replacements for numbers: the values that break arithmetic.
const NUMBERS: &[&str] = &[
    "0",
    "-0",
    "0.0",
    "-1",
    "1",
    "2",
    "-2.5",
    "1E308",
    "-1E308",
    "1E-320",
    "1E400",
    "-1E400",
    "NaN",
    "nan",
    "INF",
    "-INF",
    "1.0D0",
    "1E",
    ".",
    "-",
    "99999999999999999999",
    "4294967296",
    "2147483648",
    "-2147483649",
    "1e-300",
    "360D",
    "1D",
    "1E+",
    "0x10",
];

/// Pieces of the dataset language inserted anywhere.
const PIECES: &[&str] = &[
    "PART/",
    "MARKER/",
    "JOINT/",
    "JPRIM/",
    "MOTION/",
    "COUPLER/",
    "GEAR/",
    "GCON/",
    "SFORCE/",
    "VARIABLE/",
    "REQUEST/",
    "SPRINGDAMPER/",
    "BUSHING/",
    "VFORCE/",
    "GFORCE/",
    "SPLINE/",
    "ARRAY/",
    "UNITS/",
    "ACCGRAV/",
    "EQUILIBRIUM/",
    "IC/",
    "INTEGRATOR/",
    "END",
    ", ",
    ",",
    "=",
    " = ",
    "/",
    "\n",
    "\n, ",
    "&\n",
    "!",
    "! adams_view_name='x'\n",
    ":",
    "(",
    ")",
    "[",
    "]",
    "\\",
    "1",
    "-1",
    "0",
    "90D",
    "1E9",
    "NaN",
    "GROUND",
    "REVOLUTE",
    "SPHERICAL",
    "TRANSLATIONAL",
    "FIXED",
    "UNIVERSAL",
    "CYLINDRICAL",
    "PLANAR",
    "INPLANE",
    "INLINE",
    "ORIENTATION",
    "PARALLEL_AXES",
    "PERPENDICULAR",
    "ATPOINT",
    "HOOKE",
    "CONVEL",
    "RACKPIN",
    "SCREW",
    "I = ",
    "J = ",
    "PART = ",
    "QP = ",
    "QG = ",
    "REULER = ",
    "ZP = ",
    "XP = ",
    "MASS = ",
    "CM = ",
    "IP = ",
    "FUNCTION = ",
    "JOINT = ",
    "JOINTS = ",
    "TYPE = ",
    "SCALES = ",
    "FUNCTION = DX(1,2)/0",
    "FUNCTION = VARVAL(1)",
    "FUNCTION = TIME**1E9",
    "IC = 1",
    "ICTRAN = ",
    "ICROT = ",
    "TRANSLATION",
    "ROTATION",
    "DISPLACEMENT",
    "VELOCITY",
    "ACCELERATION",
    "B1",
    "B2",
    "B3",
    "X",
    "Y",
    "Z",
    "EXACT = X:Y:Z:PSI",
    "FLOATING",
    "é",
    "\u{0}",
    "\t",
    "\r\n",
];

/// One mutation of `text` (`others`: the seeds, for splices).
fn mutate(rng: &mut Lcg, text: &str, others: &[String]) -> String {
    let lines: Vec<&str> = text.lines().collect();
    match rng.below(10) {
        // Byte flips (kept valid UTF-8: the reader takes `&str`; files are read lossily).
        0 => {
            let mut bytes = text.as_bytes().to_vec();
            for _ in 0..1 + rng.below(4) {
                if bytes.is_empty() {
                    break;
                }
                let k = rng.below(bytes.len());
                bytes[k] ^= 1 << rng.below(7);
            }
            String::from_utf8_lossy(&bytes).into_owned()
        }
        // Line deletion.
        1 => {
            let mut l = lines.clone();
            if !l.is_empty() {
                let k = 1 + rng.below(l.len());
                l.remove(k.min(l.len() - 1));
            }
            l.join("\n")
        }
        // Line duplication (duplicate ids, repeated statements).
        2 => {
            let mut l = lines.clone();
            if !l.is_empty() {
                let k = rng.below(l.len());
                let at = rng.below(l.len() + 1);
                l.insert(at, lines[k]);
            }
            l.join("\n")
        }
        // Two lines swapped (continuations move to other statements).
        3 => {
            let mut l = lines.clone();
            if l.len() > 1 {
                let (a, b) = (rng.below(l.len()), rng.below(l.len()));
                l.swap(a, b);
            }
            l.join("\n")
        }
        // Numbers replaced by the values that break arithmetic.
        4 | 5 => replace_numbers(rng, text),
        // Tokens swapped between places.
        6 => swap_tokens(rng, text),
        // A piece of the language inserted anywhere.
        7 => {
            let mut t = text.to_string();
            for _ in 0..1 + rng.below(3) {
                let mut at = rng.below(t.len() + 1);
                while !t.is_char_boundary(at) {
                    at -= 1;
                }
                t.insert_str(at, rng.pick(PIECES));
            }
            t
        }
        // Splice: the head of this dataset, the tail of another (ids collide and dangle).
        8 => {
            let other: Vec<&str> = others[rng.below(others.len())].lines().collect();
            let a = rng.below(lines.len() + 1);
            let b = rng.below(other.len() + 1);
            let mut l: Vec<&str> = lines[..a].to_vec();
            l.extend_from_slice(&other[b..]);
            l.join("\n")
        }
        // Truncation anywhere.
        _ => {
            let mut at = rng.below(text.len() + 1);
            while !text.is_char_boundary(at) {
                at -= 1;
            }
            text[..at].to_string()
        }
    }
}

/// Byte ranges of the numbers in `text` (digits with an optional sign, point and exponent).
fn number_ranges(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut k = 0;
    while k < b.len() {
        let start_ok = k == 0 || !(b[k - 1].is_ascii_alphanumeric() || b[k - 1] == b'_');
        if start_ok
            && (b[k].is_ascii_digit()
                || (b[k] == b'.' && b.get(k + 1).is_some_and(u8::is_ascii_digit)))
        {
            let s = if k > 0 && b[k - 1] == b'-' { k - 1 } else { k };
            let mut e = k;
            while e < b.len() && (b[e].is_ascii_digit() || b[e] == b'.') {
                e += 1;
            }
            if e < b.len() && (b[e] == b'E' || b[e] == b'e') {
                let mut f = e + 1;
                if f < b.len() && (b[f] == b'+' || b[f] == b'-') {
                    f += 1;
                }
                if f < b.len() && b[f].is_ascii_digit() {
                    e = f;
                    while e < b.len() && b[e].is_ascii_digit() {
                        e += 1;
                    }
                }
            }
            out.push((s, e));
            k = e;
        } else {
            k += 1;
        }
    }
    out
}

fn replace_numbers(rng: &mut Lcg, text: &str) -> String {
    let ranges = number_ranges(text);
    if ranges.is_empty() {
        return text.to_string();
    }
    let mut chosen: Vec<usize> = (0..1 + rng.below(3))
        .map(|_| rng.below(ranges.len()))
        .collect();
    chosen.sort_unstable();
    chosen.dedup();
    let mut out = String::with_capacity(text.len() + 16);
    let mut last = 0;
    for k in chosen {
        let (s, e) = ranges[k];
        out.push_str(&text[last..s]);
        out.push_str(rng.pick(NUMBERS));
        last = e;
    }
    out.push_str(&text[last..]);
    out
}

/// Byte ranges of the words and numbers of `text` (split at spaces, commas, `=`, `/`, newlines).
fn token_ranges(text: &str) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut start = None;
    for (k, c) in text.char_indices() {
        let sep = c.is_whitespace() || matches!(c, ',' | '=' | '/' | '(' | ')');
        match (start, sep) {
            (None, false) => start = Some(k),
            (Some(s), true) => {
                out.push((s, k));
                start = None;
            }
            _ => {}
        }
    }
    if let Some(s) = start {
        out.push((s, text.len()));
    }
    out
}

fn swap_tokens(rng: &mut Lcg, text: &str) -> String {
    let t = token_ranges(text);
    if t.len() < 2 {
        return text.to_string();
    }
    let (mut a, mut b) = (rng.below(t.len()), rng.below(t.len()));
    if a == b {
        return text.to_string();
    }
    if a > b {
        std::mem::swap(&mut a, &mut b);
    }
    let (ra, rb) = (t[a], t[b]);
    format!(
        "{}{}{}{}{}",
        &text[..ra.0],
        &text[rb.0..rb.1],
        &text[ra.1..rb.0],
        &text[ra.0..ra.1],
        &text[rb.1..]
    )
}

/// Random token soup: a title line, then pieces of the language and numbers.
fn soup(rng: &mut Lcg) -> String {
    let mut t = String::from("fuzz\n");
    for _ in 0..rng.below(120) {
        if rng.below(3) == 0 {
            t.push_str(rng.pick(NUMBERS));
        } else {
            t.push_str(rng.pick(PIECES));
        }
    }
    t
}

/// The input for iteration `k` of the run seeded by `seed`: one to three mutations of a seed
/// dataset, or (one time in twenty) token soup.
fn input(seed: u64, k: u64, seeds: &[String]) -> String {
    let mut rng = Lcg(seed ^ k.wrapping_mul(0x9e37_79b9_7f4a_7c15));
    rng.next();
    if rng.below(20) == 0 {
        return soup(&mut rng);
    }
    let mut text = seeds[rng.below(seeds.len())].clone();
    for _ in 0..1 + rng.below(3) {
        text = mutate(&mut rng, &text, seeds);
    }
    text
}

/// What one input must satisfy beside not panicking; `Err` says which property failed.
fn check(text: &str) -> Result<(), String> {
    let ds = match linkage_adm::parse_dataset(Arc::from("fuzz.adm"), text) {
        Ok(ds) => ds,
        Err(d) => {
            REACHED[0].fetch_add(1, Ordering::Relaxed);
            return located(&d, "reading");
        }
    };
    let built = match linkage_model::build_model(&ds) {
        Ok(b) => b,
        Err(d) => {
            REACHED[1].fetch_add(1, Ordering::Relaxed);
            return located(&d, "building");
        }
    };
    let drivers = match ExpressionDrivers::new(&built.model) {
        Ok(dr) => dr,
        Err(d) => {
            REACHED[2].fetch_add(1, Ordering::Relaxed);
            return located(&d, "motion functions");
        }
    };
    REACHED[3].fetch_add(1, Ordering::Relaxed);
    let v = verify(&built.model, &drivers, &Tolerances::default());
    if v.dof > 6 * v.moving_parts as i64 || v.rank > v.rows {
        return Err(format!(
            "verify: DOF {} rank {} of {} rows for {} parts",
            v.dof, v.rank, v.rows, v.moving_parts
        ));
    }
    // `verify --explain` on the models with redundant equations (every proposal is checked
    // by rank analysis of the changed model).
    if !v.redundant.is_empty() {
        let _ = explain(&built.model, &drivers, &Tolerances::default(), &v);
    }
    for r in &v.redundant {
        if r.residual.is_some_and(|x| !x.is_finite()) || !r.decision.is_finite() {
            return Err(format!("verify: non-finite residual of row {}", r.row));
        }
    }
    Ok(())
}

/// Every error of `d` has a line and column (and there is at least one error).
fn located(d: &linkage_adm::Diagnostics, stage: &str) -> Result<(), String> {
    if let Some(e) = d.0.iter().find(|e| e.is_error() && e.span.is_none()) {
        return Err(format!("{stage}: error without a location: {e}"));
    }
    if !d.0.iter().any(|e| e.is_error()) {
        return Err(format!("{stage}: failed without an error: {d}"));
    }
    Ok(())
}

static HOOK: Once = Once::new();

thread_local! {
    /// Whether this thread is inside [`run_one`], and the last panic caught there.
    static CATCHING: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
    static LAST_PANIC: std::cell::RefCell<String> = const { std::cell::RefCell::new(String::new()) };
}

/// Runs [`check`] on `text`, a panic being an `Err` that names it.
fn run_one(text: &str) -> Result<(), String> {
    catching(|| check(text))
}

/// Runs `f` catching panics; inside it, the panic's message and place are kept instead of
/// printed (other panics, such as a failed assertion of a test, print as usual).
fn catching(f: impl FnOnce() -> Result<(), String>) -> Result<(), String> {
    HOOK.call_once(|| {
        let default = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !CATCHING.with(|c| c.get()) {
                return default(info);
            }
            let place = info
                .location()
                .map(|l| format!("{}:{}", l.file(), l.line()))
                .unwrap_or_default();
            let msg = info
                .payload()
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| info.payload().downcast_ref::<String>().cloned())
                .unwrap_or_default();
            LAST_PANIC.with(|l| *l.borrow_mut() = format!("panic at {place}: {msg}"));
        }));
    });
    CATCHING.with(|c| c.set(true));
    let outcome = catch_unwind(AssertUnwindSafe(f));
    CATCHING.with(|c| c.set(false));
    match outcome {
        Ok(r) => r,
        Err(_) => Err(LAST_PANIC.with(|l| l.borrow().clone())),
    }
}

fn save_failure(name: &str, text: &str) -> PathBuf {
    let dir = repo().join("target/fuzz-failures");
    let _ = std::fs::create_dir_all(&dir);
    let path = dir.join(format!("{name}.adm"));
    let _ = std::fs::write(&path, text);
    path
}

/// The bounded CI run: `LINKAGE_FUZZ_ITERATIONS` inputs (default 3000) from
/// `LINKAGE_FUZZ_SEED` (default fixed), stopping early after `LINKAGE_FUZZ_SECONDS`
/// (default 40) of wall-clock time.
#[test]
fn mutated_datasets_never_panic() {
    let seeds = seeds();
    let iterations: u64 = env_or("LINKAGE_FUZZ_ITERATIONS", 3000);
    let seed: u64 = env_or("LINKAGE_FUZZ_SEED", 0x11_4ea9e);
    let limit = Duration::from_secs_f64(env_or("LINKAGE_FUZZ_SECONDS", 40.0));
    let start = Instant::now();
    let mut failures = Vec::new();
    let mut done = 0;
    for k in 0..iterations {
        if start.elapsed() > limit {
            break;
        }
        let text = input(seed, k, &seeds);
        if let Err(why) = run_one(&text) {
            let path = save_failure(&format!("seed{seed}_iter{k}"), &text);
            eprintln!("iteration {k}: {why}\n  input: {}", path.display());
            failures.push((k, why));
        }
        done = k + 1;
    }
    eprintln!(
        "fuzz: {done} of {iterations} inputs (seed {seed}) in {:.1} s: {:?} rejected by the \
         reader, by model building, by motion functions, verified; {} failures",
        start.elapsed().as_secs_f64(),
        REACHED.each_ref().map(|a| a.load(Ordering::Relaxed)),
        failures.len()
    );
    assert!(
        failures.is_empty(),
        "{} inputs failed; the first: iteration {}: {}",
        failures.len(),
        failures[0].0,
        failures[0].1
    );
}

/// Every crash the fuzzer found, kept as a dataset named after what it found.
#[test]
fn fuzz_regressions_are_handled() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/fuzz");
    let mut paths: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map(|r| r.flatten().map(|e| e.path()).collect())
        .unwrap_or_default();
    paths.sort();
    let mut failed = Vec::new();
    for p in &paths {
        let bytes = std::fs::read(p).expect("regression file reads");
        let text = String::from_utf8_lossy(&bytes);
        if let Err(why) = run_one(&text) {
            failed.push(format!("{}: {why}", p.display()));
        }
    }
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}

/// Coordinates so large that the analyses overflow are input errors at the coordinate.
#[test]
fn huge_coordinates_are_input_errors_at_the_coordinate() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/fuzz");
    for (name, line) in [
        ("part_qg_1e308_overflows_the_residuals.adm", 4),
        ("marker_qp_1e308_overflows_the_residuals.adm", 4),
    ] {
        let ds = linkage_adm::read_dataset(&dir.join(name)).expect("reads");
        let e = linkage_model::build_model(&ds).err().expect("rejected");
        let first = &e.0[0];
        assert!(first.message.contains("is beyond"), "{name}: {e}");
        assert_eq!(first.span.map(|s| s.line), Some(line), "{name}: {e}");
    }
}

/// The harness reports a panic with its place and message.
#[test]
fn a_panic_is_caught_and_named() {
    let e = catching(|| panic!("boom")).unwrap_err();
    assert!(e.contains("fuzz.rs") && e.contains("boom"), "{e}");
}

/// The mutations themselves: each gives a text (the harness is deterministic).
#[test]
fn the_same_seed_gives_the_same_inputs() {
    let seeds = seeds();
    for k in 0..50 {
        assert_eq!(input(3, k, &seeds), input(3, k, &seeds));
    }
    assert_eq!(
        number_ranges("QP = -1.5E-3, 2, x3"),
        vec![(5, 12), (14, 15)]
    );
}
