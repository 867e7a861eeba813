//! Outputs that cannot destroy inputs, inputs that cannot exhaust memory, standard output as a
//! file, and a closed pipe that ends the program quietly.

mod common;
use common::{root, run};
use std::io::{BufRead, BufReader};
use std::path::PathBuf;
use std::process::{Command, Stdio};

/// A copy of `mechanisms/pendulum.adm` in a fresh folder.
fn pendulum(tag: &str) -> (PathBuf, String) {
    let dir = std::env::temp_dir().join(format!("linkage-out-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(root().join("mechanisms/pendulum.adm")).unwrap();
    let f = dir.join("in.adm");
    std::fs::write(&f, &text).unwrap();
    (f, text)
}

#[test]
fn an_output_that_is_the_input_is_refused_and_the_input_kept() {
    let (f, text) = pendulum("same");
    let dir = f.parent().unwrap().to_path_buf();
    let link = dir.join("link.adm");
    std::os::unix::fs::symlink(&f, &link).unwrap();
    let dotted = format!("{}/./in.adm", dir.display());
    let input = f.to_str().unwrap();
    for args in [
        vec![
            "simulate", input, "--end", "0.1", "--steps", "2", "--out", input,
        ],
        vec![
            "simulate", input, "--end", "0.1", "--steps", "2", "--out", &dotted,
        ],
        vec!["ic", input, "--save", link.to_str().unwrap()],
        vec!["static", link.to_str().unwrap(), "--save", input],
    ] {
        let (code, _, err) = run(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains("refusing to write"), "{args:?}: {err}");
        assert!(err.contains("it is the input"), "{args:?}: {err}");
        assert_eq!(std::fs::read_to_string(&f).unwrap(), text, "{args:?}");
    }
}

#[test]
fn devices_and_directories_are_refused_as_inputs() {
    for path in ["/dev/zero", "/tmp"] {
        let (code, _, err) = run(&["verify", path]);
        assert_eq!(code, 2, "{path}: {err}");
        assert!(err.contains("not a regular file"), "{path}: {err}");
    }
}

#[test]
fn a_dash_sends_the_time_histories_to_standard_output() {
    let (f, _) = pendulum("dash");
    let (code, out, err) = run(&[
        "simulate",
        f.to_str().unwrap(),
        "--end",
        "0.1",
        "--steps",
        "2",
        "--out",
        "-",
    ]);
    assert_eq!(code, 0, "{err}");
    let lines: Vec<&str> = out.lines().collect();
    assert!(lines[0].starts_with("time [s],rod.x [m],"), "{out}");
    assert_eq!(lines.len(), 4, "header and three outputs: {out}");
    // The summary went to stderr, and no file named `-` was written.
    assert!(err.contains("rod"), "{err}");
    assert!(!f.parent().unwrap().join("-").exists());
}

#[test]
fn a_closed_pipe_ends_the_program_quietly() {
    let dir = std::env::temp_dir().join(format!("linkage-pipe-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // A long report: 300 parallelogram loops, each with redundant equations to list.
    let f = dir.join("chain.adm");
    std::fs::write(&f, linkage_solve::generate::parallelogram_chain(300, 30.0)).unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_linkage"))
        .args(["verify", f.to_str().unwrap()])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut first)
        .unwrap();
    // The reader goes away after one line, as `| head -1` does.
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(first.starts_with("VERIFY MODEL"), "{first}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(!err.contains("Broken pipe"), "{err}");
}

#[test]
fn time_histories_are_streamed_with_memory_that_does_not_grow_with_the_outputs() {
    let (f, _) = pendulum("stream");
    let csv = f.with_extension("csv");
    // 400,000 outputs (about 80 MB of CSV): kept in memory, they would take hundreds of MB.
    // Reaped by wait4 below, which also gives its peak memory.
    #[allow(clippy::zombie_processes)]
    let child = Command::new(env!("CARGO_BIN_EXE_linkage"))
        .args([
            "simulate",
            f.to_str().unwrap(),
            "--end",
            "40",
            "--steps",
            "400000",
            "--out",
            csv.to_str().unwrap(),
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    // This child's own peak (other tests of this binary run children at the same time, so
    // RUSAGE_CHILDREN would mix theirs in).
    let (code, peak) = wait_with_peak_kb(child.id());
    assert_eq!(code, 0);
    let rows = std::fs::read_to_string(&csv).unwrap().lines().count();
    assert_eq!(rows, 400_002, "header and every output");
    assert!(peak < 60_000, "peak resident memory {peak} kB");
    std::fs::remove_file(&csv).unwrap();
}

/// Waits for the child `pid`: its exit code and its peak resident memory (kB).
fn wait_with_peak_kb(pid: u32) -> (i32, i64) {
    // SAFETY: wait4 only writes the status and the struct it is given.
    unsafe {
        let mut status = 0;
        let mut usage: libc::rusage = std::mem::zeroed();
        let r = libc::wait4(pid as libc::pid_t, &mut status, 0, &mut usage);
        assert_eq!(r, pid as libc::pid_t, "wait4");
        (libc::WEXITSTATUS(status), usage.ru_maxrss)
    }
}

/// A slider on a spring (k = 100 N/m, m = 1 kg) driven by a sinusoidal force at 30 rad/s: the
/// steps stay near the forcing period for as long as the run lasts.
const FORCED: &str = "forced slider
UNITS/, FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND
PART/1, GROUND
MARKER/10, PART = 1, REULER = 90D, 90D, 0
MARKER/12, PART = 1, QP = -1, 0, 0
PART/2, MASS = 1, CM = 20, IP = 1, 1, 1
MARKER/20, PART = 2
MARKER/21, PART = 2, REULER = 90D, 90D, 0
JOINT/1, TRANSLATIONAL, I = 21, J = 10
SPRINGDAMPER/2, TRANSLATIONAL, I = 20, J = 12, K = 100, C = 0, LENGTH = 1
SFORCE/3, TRANSLATIONAL, I = 20, J = 12, FUNCTION = 5*SIN(30*TIME)
END
";

#[test]
fn a_time_limit_stops_a_run_between_two_outputs() {
    let (f, _) = pendulum("limit");
    std::fs::write(&f, FORCED).unwrap();
    let csv = f.with_extension("csv");
    // A million seconds of forced vibration with two outputs: hours between outputs.
    let started = std::time::Instant::now();
    let (code, _, err) = run(&[
        "simulate",
        f.to_str().unwrap(),
        "--end",
        "1e6",
        "--steps",
        "2",
        "--time-limit",
        "0.5",
        "--out",
        csv.to_str().unwrap(),
    ]);
    let elapsed = started.elapsed().as_secs_f64();
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("the time limit of 0.5 s was reached"), "{err}");
    assert!(elapsed < 10.0, "stopped after {elapsed} s");
    // The output at the start is written, whole.
    let text = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(text.lines().count(), 2, "{text}");
}

#[test]
fn a_missing_ground_and_an_impossible_hmax_name_their_place() {
    let (f, _) = pendulum("places");
    let dir = f.parent().unwrap();
    let no_ground = dir.join("no_ground.adm");
    std::fs::write(
        &no_ground,
        "m\nPART/2, MASS = 1, CM = 3\nMARKER/3, PART = 2\nEND\n",
    )
    .unwrap();
    let (code, _, err) = run(&["verify", no_ground.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("no_ground.adm:2:1: error: the dataset has no GROUND part"),
        "{err}"
    );
    let hmax = dir.join("hmax.adm");
    std::fs::write(
        &hmax,
        "m\nPART/1, GROUND\nPART/2, MASS = 1, CM = 3, IP = 1, 1, 1\nMARKER/3, PART = 2\n\
         INTEGRATOR/HMAX = 1e-12\nEND\n",
    )
    .unwrap();
    let (code, _, err) = run(&[
        "simulate",
        hmax.to_str().unwrap(),
        "--end",
        "100",
        "--steps",
        "2",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("hmax.adm:5:12: error: INTEGRATOR HMAX = 1E-12"),
        "{err}"
    );
}

#[test]
fn a_time_limit_stops_damped_settling() {
    let (f, _) = pendulum("settle-limit");
    // An undamped spring-mass, released 0.3 m from its rest length and given 1e8 time units
    // to settle: it never does.
    let text = FORCED
        .replace(
            "PART/2, MASS = 1, CM = 20, IP = 1, 1, 1\n",
            "PART/2, MASS = 1, CM = 20, IP = 1, 1, 1, QG = 0.3, 0, 0\n",
        )
        .replace(
            "SFORCE/3, TRANSLATIONAL, I = 20, J = 12, FUNCTION = 5*SIN(30*TIME)\n",
            "",
        )
        .replace(
            "END\n",
            // A positive damping is the dataset's (0 would be chosen from the model, and settle).
            "EQUILIBRIUM/, DYNAMIC, SETTLING_TIME = 1e8, GLOBAL_DAMPING = 1e-12\nEND\n",
        );
    std::fs::write(&f, text).unwrap();
    let started = std::time::Instant::now();
    let (code, _, err) = run(&[
        "static",
        f.to_str().unwrap(),
        "--settle",
        "--time-limit",
        "0.5",
    ]);
    let elapsed = started.elapsed().as_secs_f64();
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("the time limit of 0.5 s was reached while settling"),
        "{err}"
    );
    assert!(elapsed < 10.0, "stopped after {elapsed} s");
}
