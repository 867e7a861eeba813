//! The fault harness of issue 34: every analysis command of the binary (`verify`, `ic`,
//! `static`, `linear`, `simulate`, `run`) on mutated datasets and command files, with mutated
//! option values, in a fresh folder per input. (The in-process mutation fuzzing of reading,
//! building and verify is `crates/solve/tests/fuzz.rs`; this one runs the whole binary, so
//! it sees exit codes, aborts and the files a command writes.)
//!
//! Inputs: the bundled mechanisms and small corpus datasets with their command files; each
//! run mutates numbers of the dataset (one to three of them) and of the command file, and
//! the command's option values (`--end`, `--steps`, `--time-limit`), to values that broke
//! commands before (0, negative, 1E23, 1.797E308, NaN, 4000000000, …), and sometimes names
//! an input as the output (`--out in.adm`, `--save in.adm`, `--html in.adm`).
//!
//! Properties of every run: it ends (a watchdog kills it after [`WATCHDOG`]); exit code 0, 1
//! or 2 (never a panic's 101, an abort or a signal), no `panicked` in its messages; the input
//! files are byte for byte what they were.
//!
//! CI runs it as its own step (`.ci/run`: `cargo test --release -p linkage-cli --test
//! fault_harness -- --ignored --nocapture`).
//!
//! Deterministic (64-bit LCG, fixed seed; `LINKAGE_HARNESS_SEED` changes it) and bounded:
//! `LINKAGE_HARNESS_RUNS` runs (default 1500), stopping after `LINKAGE_HARNESS_SECONDS`
//! (default 120) of wall-clock time; the count of runs and of exit codes is printed.

mod common;
use common::root;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// The longest a run may take (every analysis also gets `--time-limit` of at most 5 s).
const WATCHDOG: Duration = Duration::from_secs(60);

/// Values that broke commands before, and ordinary ones.
const NUMBERS: [&str; 16] = [
    "0",
    "-1",
    "-0",
    "1E23",
    "1.797E308",
    "1e-300",
    "NaN",
    "INF",
    "4000000000",
    "1E200",
    "0.5",
    "2",
    "1e300",
    "-1e300",
    "1E12",
    "3",
];

struct Lcg(u64);

impl Lcg {
    fn below(&mut self, n: usize) -> usize {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((self.0 >> 33) as usize) % n.max(1)
    }
    fn number(&mut self) -> &'static str {
        NUMBERS[self.below(NUMBERS.len())]
    }
}

fn env_or<T: std::str::FromStr>(name: &str, default: T) -> T {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// Byte ranges of the numbers in `text` after an `=` or a `,` (argument values).
fn numbers(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut k = 0;
    while k < b.len() {
        let starts = (b[k].is_ascii_digit() || b[k] == b'-' || b[k] == b'.')
            && text[..k].trim_end().ends_with(['=', ',']);
        if starts {
            let end = (k + 1..b.len())
                .find(|&e| !(b[e].is_ascii_alphanumeric() || b"+-.".contains(&b[e])))
                .unwrap_or(b.len());
            out.push((k, end));
            k = end;
        } else {
            k += 1;
        }
    }
    out
}

/// `text` with one to three of its argument numbers replaced.
fn mutate(rng: &mut Lcg, text: &str) -> String {
    let mut text = text.to_string();
    for _ in 0..1 + rng.below(3) {
        let spans = numbers(&text);
        if spans.is_empty() {
            break;
        }
        let (a, b) = spans[rng.below(spans.len())];
        text.replace_range(a..b, rng.number());
    }
    text
}

/// A dataset and a command file running it (named `in.adm` / `in.acf` in each run's folder).
struct Case {
    name: String,
    adm: String,
    acf: String,
}

fn cases() -> Vec<Case> {
    let mut out = Vec::new();
    for m in ["pendulum", "fourbar", "fourbar_motion", "slider_crank"] {
        let adm = std::fs::read_to_string(root().join(format!("mechanisms/{m}.adm"))).unwrap();
        out.push(Case {
            name: m.to_string(),
            adm,
            acf: "in\nout\nSIMULATE/DYNAMIC, END = 0.2, STEPS = 20\n".to_string(),
        });
    }
    if let Some(corpus) = common::corpus() {
        for c in [
            "projectchrono__chrono__data__adams__test_Prismatic_Case01",
            "projectchrono__chrono__data__adams__test_Spherical_Case01",
            "projectchrono__chrono__data__adams__test_Distance_Case01",
        ] {
            let adm = std::fs::read_to_string(corpus.join(format!("{c}.adm"))).unwrap();
            let acf = std::fs::read_to_string(corpus.join(format!("{c}.acf"))).unwrap();
            // Line 1 names the dataset, line 2 the outputs: both become this folder's.
            let rest: Vec<&str> = acf.lines().skip(2).collect();
            out.push(Case {
                name: c.to_string(),
                adm,
                acf: format!("in\nout\n{}\n", rest.join("\n")),
            });
        }
    }
    out
}

/// The command line of run `k`: a command, its options (some values mutated) and, one time
/// in ten, an input named as its output.
fn command(rng: &mut Lcg) -> Vec<String> {
    let o = |v: &str| v.to_string();
    let limit = ["1", "5", "0.5"][rng.below(3)];
    let clash = rng.below(10) == 0;
    let mut args: Vec<String> = match rng.below(6) {
        0 => vec![o("verify"), o("in.adm")],
        1 => {
            let save = if clash { "in.adm" } else { "saved.adm" };
            vec![o("ic"), o("in.adm"), o("--save"), o(save)]
        }
        2 => {
            let mut a = vec![o("static"), o("in.adm"), o("--time-limit"), o(limit)];
            if rng.below(2) == 0 {
                a.extend([o("--end"), o(rng.number()), o("--steps"), o("3")]);
            }
            a
        }
        3 => vec![o("linear"), o("in.adm"), o("--format"), o("json")],
        4 => {
            let out = if clash { "in.adm" } else { "out.csv" };
            let end = if rng.below(2) == 0 {
                "0.2"
            } else {
                rng.number()
            };
            let steps = ["10", "1", "4000000000", "0"][rng.below(4)];
            vec![
                o("simulate"),
                o("in.adm"),
                o("--end"),
                o(end),
                o("--steps"),
                o(steps),
                o("--time-limit"),
                o(limit),
                o("--out"),
                o(out),
            ]
        }
        _ => {
            let mut a = vec![o("run"), o("in.acf"), o("--time-limit"), o(limit)];
            if clash {
                a.extend([o("--html"), o("in.adm")]);
            }
            a
        }
    };
    if rng.below(20) == 0 {
        // An option value that is not a number at all.
        if let Some(v) = args.iter_mut().skip(2).find(|a| a.parse::<f64>().is_ok()) {
            *v = o("x");
        }
    }
    args
}

/// Runs `args` in `dir` under the watchdog: exit code (or why it has none) and stderr.
fn run_watched(dir: &Path, args: &[String]) -> Result<(i32, String), String> {
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_linkage"))
        .args(args)
        .current_dir(dir)
        .stdout(std::process::Stdio::null())
        .stderr(std::fs::File::create(dir.join("stderr.txt")).unwrap())
        .spawn()
        .unwrap();
    let started = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if started.elapsed() > WATCHDOG {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!("still running after {WATCHDOG:?}"));
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let err = std::fs::read_to_string(dir.join("stderr.txt")).unwrap_or_default();
    match status.code() {
        Some(code) => Ok((code, err)),
        None => Err(format!("ended by a signal ({status}): {err}")),
    }
}

#[test]
#[ignore = "its own step of .ci/run, which prints its count of runs: --ignored --nocapture"]
fn every_command_on_mutated_inputs_ends_with_a_valid_exit_code_and_leaves_its_inputs() {
    let cases = cases();
    let runs: u64 = env_or("LINKAGE_HARNESS_RUNS", 1500);
    let seed: u64 = env_or("LINKAGE_HARNESS_SEED", 0x34);
    let limit = Duration::from_secs_f64(env_or("LINKAGE_HARNESS_SECONDS", 120.0));
    let base: PathBuf =
        std::env::temp_dir().join(format!("linkage-harness-{}", std::process::id()));
    let start = Instant::now();
    let mut codes = [0usize; 3];
    let mut failures = Vec::new();
    let mut done = 0;
    for k in 0..runs {
        if start.elapsed() > limit {
            break;
        }
        let mut rng = Lcg(seed ^ k.wrapping_mul(0x9e37_79b9_7f4a_7c15));
        let case = &cases[rng.below(cases.len())];
        let adm = if rng.below(4) == 0 {
            case.adm.clone()
        } else {
            mutate(&mut rng, &case.adm)
        };
        let acf = if rng.below(2) == 0 {
            case.acf.clone()
        } else {
            mutate(&mut rng, &case.acf)
        };
        let args = command(&mut rng);
        let dir = base.join(format!("{k}"));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("in.adm"), &adm).unwrap();
        std::fs::write(dir.join("in.acf"), &acf).unwrap();
        let what = format!("run {k} ({}): linkage {}", case.name, args.join(" "));
        match run_watched(&dir, &args) {
            Err(why) => failures.push(format!("{what}: {why}")),
            Ok((code, err)) => {
                if !(0..=2).contains(&code) || err.contains("panicked") {
                    failures.push(format!("{what}: exit {code}: {err}"));
                } else {
                    codes[code as usize] += 1;
                }
            }
        }
        let kept = std::fs::read_to_string(dir.join("in.adm")).ok() == Some(adm.clone())
            && std::fs::read_to_string(dir.join("in.acf")).ok() == Some(acf.clone());
        if !kept {
            failures.push(format!("{what}: an input file was changed"));
        }
        if failures.is_empty() {
            let _ = std::fs::remove_dir_all(&dir);
        } else {
            // The folder of a failure stays, for its inputs.
            eprintln!("{}", failures.last().unwrap());
        }
        done = k + 1;
    }
    eprintln!(
        "fault harness: {done} of {runs} runs (seed {seed}) in {:.1} s: exit 0 {}, exit 1 {}, \
         exit 2 {}; {} failures",
        start.elapsed().as_secs_f64(),
        codes[0],
        codes[1],
        codes[2],
        failures.len()
    );
    assert!(done >= 50.min(runs), "only {done} runs in the time allowed");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    let _ = std::fs::remove_dir_all(&base);
}

#[test]
fn argument_numbers_are_found_and_replaced() {
    let text = "MARKER/3, QP = 1.5, -2E-3, 0\nSIMULATE/DYNAMIC, END=5.0, STEPS=10\n";
    let spans: Vec<&str> = numbers(text).iter().map(|&(a, b)| &text[a..b]).collect();
    assert_eq!(spans, ["1.5", "-2E-3", "0", "5.0", "10"]);
    let mut rng = Lcg(1);
    let changed = mutate(&mut rng, text);
    assert_ne!(changed, text);
    assert!(changed.starts_with("MARKER/3, QP = "), "{changed}");
}
