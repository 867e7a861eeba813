//! Issue 34: no input harmed, no run without end, no number silently wrong. Each test runs
//! the built binary on the exact case the issue lists.

mod common;
use common::{root, run};
use std::path::{Path, PathBuf};

/// A fresh folder holding a copy of `mechanisms/pendulum.adm` as `in.adm`.
fn folder(tag: &str) -> (PathBuf, String) {
    let dir = std::env::temp_dir().join(format!("linkage-holes-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(root().join("mechanisms/pendulum.adm")).unwrap();
    std::fs::write(dir.join("in.adm"), &text).unwrap();
    (dir, text)
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Runs `linkage run file.acf` in `dir` (outputs there): exit code, stdout, stderr.
fn run_in(dir: &Path, args: &[&str]) -> (i32, String, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_linkage"))
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn outputs_that_are_inputs_by_hard_link_or_by_name_are_refused_and_the_inputs_kept() {
    let (dir, text) = folder("identity");
    let input = dir.join("in.adm");
    let hard = dir.join("hard.adm");
    std::fs::hard_link(&input, &hard).unwrap();
    // A hard link is the same file whatever its path: simulate --out and ic --save.
    for args in [
        vec![
            "simulate",
            s(&input),
            "--end",
            "0.1",
            "--steps",
            "2",
            "--out",
            s(&hard),
        ],
        vec!["ic", s(&input), "--save", s(&hard)],
    ] {
        let (code, _, err) = run(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains("refusing to write"), "{args:?}: {err}");
        assert_eq!(std::fs::read_to_string(&input).unwrap(), text, "{args:?}");
    }
    // run --html naming the dataset the command file names.
    std::fs::write(
        dir.join("h.acf"),
        "in\nq\nSIMULATE/DYNAMIC, END=0.1, STEPS=2\n",
    )
    .unwrap();
    let (code, _, err) = run_in(&dir, &["run", "h.acf", "--html", "in.adm"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("refusing to write in.adm"), "{err}");
    assert!(!err.contains("no html page"), "{err}");
    assert_eq!(std::fs::read_to_string(&input).unwrap(), text);
    // A command file named x.msg, whose output name is x: its message file would be itself.
    let acf = "in\nx\nSIMULATE/DYNAMIC, END=0.1, STEPS=2\n";
    std::fs::write(dir.join("x.msg"), acf).unwrap();
    let (code, _, err) = run_in(&dir, &["run", "x.msg"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("refusing to write x.msg"), "{err}");
    assert_eq!(std::fs::read_to_string(dir.join("x.msg")).unwrap(), acf);
    // A dataset named y.req, whose request file would be itself.
    std::fs::write(dir.join("y.req"), &text).unwrap();
    std::fs::write(
        dir.join("r.acf"),
        "y.req\ny\nSIMULATE/DYNAMIC, END=0.1, STEPS=2\n",
    )
    .unwrap();
    let (code, _, err) = run_in(&dir, &["run", "r.acf"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("refusing to write y.req"), "{err}");
    assert_eq!(std::fs::read_to_string(dir.join("y.req")).unwrap(), text);
}

#[test]
fn output_counts_beyond_the_cap_and_impossible_time_limits_are_input_errors_not_panics() {
    let (dir, _) = folder("counts");
    for (k, sim) in [
        "END = 1E23, DTOUT = 0.01",
        "STEPS = 4000000000, END = 1",
        "END = 1E12, DTOUT = 0.01",
    ]
    .iter()
    .enumerate()
    {
        let name = format!("c{k}.acf");
        std::fs::write(
            dir.join(&name),
            format!("in\nc{k}\nSIMULATE/DYNAMIC, {sim}\n"),
        )
        .unwrap();
        let (code, _, err) = run_in(&dir, &["run", &name]);
        assert_eq!(code, 2, "{sim}: {err}");
        assert!(
            err.contains("at most 1000000") || err.contains("more than the 1000000"),
            "{sim}: {err}"
        );
        assert!(!err.contains("panicked"), "{sim}: {err}");
    }
    let input = dir.join("in.adm");
    for limit in ["nan", "inf", "1e20"] {
        for args in [
            vec![
                "simulate",
                s(&input),
                "--end",
                "0.1",
                "--steps",
                "2",
                "--time-limit",
                limit,
            ],
            vec!["static", s(&input), "--settle", "--time-limit", limit],
        ] {
            let (code, _, err) = run(&args);
            assert_eq!(code, 2, "{args:?}: {err}");
            assert!(
                err.contains("--time-limit must be a positive number"),
                "{args:?}: {err}"
            );
            assert!(!err.contains("panicked"), "{args:?}: {err}");
        }
    }
}

#[test]
fn an_end_near_the_largest_double_ends_at_the_time_limit() {
    let (dir, _) = folder("end");
    // END = 1.797E308 in ten steps: output times that do not overflow, and a run that the
    // wall-clock limit ends (exit 1, saying so) within seconds.
    std::fs::write(
        dir.join("e.acf"),
        "in\ne\nSIMULATE/DYNAMIC, END = 1.797E308, STEPS = 10\n",
    )
    .unwrap();
    let started = std::time::Instant::now();
    let (code, _, err) = run_in(&dir, &["run", "e.acf", "--time-limit", "1"]);
    let elapsed = started.elapsed().as_secs_f64();
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("time limit"), "{err}");
    assert!(elapsed < 20.0, "ended after {elapsed} s");
    let input = dir.join("in.adm");
    let started = std::time::Instant::now();
    let (code, _, err) = run(&["simulate", s(&input), "--end", "1e200", "--time-limit", "1"]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("the time limit of 1 s was reached"), "{err}");
    assert!(started.elapsed().as_secs_f64() < 20.0);
}

#[test]
fn linear_reports_of_huge_gravity_or_inertia_hold_only_finite_numbers_or_fail() {
    let (dir, text) = folder("finite");
    let cases = [
        (
            "g.adm",
            text.replace("ACCGRAV/", "ACCGRAV/, JGRAV = 1e200 !"),
        ),
        ("ip.adm", {
            let mut t = String::new();
            for l in text.lines() {
                if l.contains("IP =") {
                    t.push_str(&l[..l.find("IP =").unwrap()]);
                    t.push_str("IP = 1e300, 1e300, 1e300");
                } else {
                    t.push_str(l);
                }
                t.push('\n');
            }
            t
        }),
    ];
    for (name, dataset) in cases {
        let path = dir.join(name);
        std::fs::write(&path, dataset).unwrap();
        let (code, out, err) = run(&["linear", s(&path), "--format", "json"]);
        let v: serde_json::Value =
            serde_json::from_str(&out).unwrap_or_else(|e| panic!("{name}: {e}: {out} {err}"));
        let errors = v["errors"].as_array().unwrap();
        // serde_json writes NaN and infinities as null: a report without errors has none.
        if errors.is_empty() {
            assert_eq!(code, 0, "{name}");
            assert!(!out.contains("null"), "{name}: {out}");
        } else {
            assert_eq!(code, 1, "{name}: {out}");
        }
    }
}

#[test]
fn command_files_empty_cut_short_without_analysis_or_dataset_are_refused_with_their_place() {
    let (dir, _) = folder("acf");
    let cases = [
        ("empty.acf", "", "names no dataset"),
        (
            "cut.acf",
            "in\nout\nSIMULATE/DYNAMIC, END=1,\n",
            "cut.acf:3:24: error: the command file ends inside a command",
        ),
        ("none.acf", "in\nout\n", "has no analysis"),
        (
            "missing.acf",
            "missing\nout\nSIMULATE/DYNAMIC, END=1, STEPS=2\n",
            "missing.acf:1:1: the dataset of line 1: missing.adm",
        ),
    ];
    for (name, acf, says) in cases {
        std::fs::write(dir.join(name), acf).unwrap();
        let (code, _, err) = run_in(&dir, &["run", name]);
        assert_eq!(code, 2, "{name}: {err}");
        assert!(err.contains(says), "{name}: {err}");
    }
    assert!(!dir.join("out.csv").exists(), "no empty CSV is written");
}

#[test]
fn a_request_left_out_of_a_command_file_run_leaves_the_others_in_its_files() {
    let (dir, text) = folder("deactivate");
    let dataset = text.replacen(
        "ACCGRAV/",
        "REQUEST/4, DISPLACEMENT, I = 203, J = 101\nREQUEST/5, VELOCITY, I = 203, J = 101\nACCGRAV/",
        1,
    );
    std::fs::write(dir.join("rq.adm"), dataset).unwrap();
    std::fs::write(
        dir.join("d.acf"),
        "rq\nd\nSIMULATE/DYNAMIC, END=0.01, STEPS=2\n",
    )
    .unwrap();
    let (code, out, err) = run_in(&dir, &["run", "d.acf", "--deactivate", "REQUEST/5"]);
    assert_eq!(code, 0, "{out}{err}");
    assert!(out.contains("3 output(s)"), "{out}");
    let csv = std::fs::read_to_string(dir.join("d.csv")).unwrap();
    let header = csv.lines().next().unwrap();
    assert!(header.contains("REQUEST_4"), "{header}");
    assert!(!header.contains("REQUEST_5"), "{header}");
    assert_eq!(csv.lines().count(), 4, "{csv}");
}

#[test]
fn a_variable_left_out_is_named_as_left_out_at_the_element_that_uses_it() {
    let (dir, text) = folder("variable");
    let dataset = text.replacen(
        "ACCGRAV/",
        "VARIABLE/7, FUNCTION = 2*TIME\nSFORCE/8, ROTATION, I = 203, J = 101, \
         FUNCTION = VARVAL(7)\nACCGRAV/",
        1,
    );
    let path = dir.join("var.adm");
    std::fs::write(&path, dataset).unwrap();
    let (code, _, err) = run(&[
        "simulate",
        s(&path),
        "--end",
        "0.01",
        "--steps",
        "2",
        "--deactivate",
        "VARIABLE/7",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("SFORCE_8 (SFORCE/8"), "{err}");
    assert!(err.contains("VARIABLE/7 (VARIABLE_7, line"), "{err}");
    assert!(err.contains("is left out on request"), "{err}");
    // The same in a command file's DEACTIVATE.
    std::fs::write(
        dir.join("v.acf"),
        "var\nv\nDEACTIVATE/VARIABLE, ID=7\nSIMULATE/DYNAMIC, END=0.01, STEPS=2\n",
    )
    .unwrap();
    let (code, _, err) = run_in(&dir, &["run", "v.acf"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("v.acf:3:1: DEACTIVATE"), "{err}");
    assert!(err.contains("is left out on request"), "{err}");
}

/// `mechanisms/pendulum.adm` with `statement` added before its ACCGRAV, written as `name`.
fn with_statement(dir: &Path, text: &str, name: &str, statement: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(
        &path,
        text.replacen("ACCGRAV/", &format!("{statement}\nACCGRAV/"), 1),
    )
    .unwrap();
    path
}

#[test]
fn a_function_naming_a_missing_marker_or_element_fails_verify_at_its_place() {
    let (dir, text) = folder("references");
    // The SFORCE is line 75 of the file; its FUNCTION starts at column 50.
    let head = "SFORCE/8, ROTATION, I = 203, J = 101, FUNCTION = ";
    for (k, (function, call, missing)) in [
        ("DX(999)", "DX", "MARKER/999"),
        ("DX(203, 101, 998)", "DX", "MARKER/998"),
        ("ORIENT(1, 1, 203, 997)", "ORIENT", "MARKER/997"),
    ]
    .into_iter()
    .enumerate()
    {
        let name = format!("r{k}.adm");
        let path = with_statement(&dir, &text, &name, &format!("{head}{function}"));
        let (code, out, err) = run(&["verify", s(&path)]);
        assert_eq!(code, 2, "{function}: {out}{err}");
        assert!(!out.contains("verified successfully"), "{function}: {out}");
        let column = head.len() + 1 + function.find(call).unwrap();
        let place = format!("{name}:75:{column}: ");
        let says =
            format!("SFORCE_8 (SFORCE/8, line 75): FUNCTION: {call}(…): {missing} does not exist");
        assert!(
            err.contains(&place) && err.contains(&says),
            "{function}: {err}"
        );
    }
    // Data elements a force uses: refused by every analysis before it runs, at the force.
    for (k, (function, missing)) in [
        ("VARVAL(99)", "VARIABLE/99 does not exist"),
        ("DIF(5)", "DIFF/5 does not exist"),
        ("ARYVAL(6, 1)", "ARRAY/6 does not exist"),
        ("SENVAL(7)", "SENSOR/7 does not exist"),
        ("AKISPL(TIME, 0, 8)", "SPLINE/8 does not exist"),
        ("PINVAL(9, 1)", "PINPUT/9 does not exist"),
    ]
    .into_iter()
    .enumerate()
    {
        let name = format!("d{k}.adm");
        let path = with_statement(&dir, &text, &name, &format!("{head}{function}"));
        let (code, _, err) = run(&["simulate", s(&path), "--end", "0.1", "--steps", "2"]);
        assert_eq!(code, 2, "{function}: {err}");
        assert!(
            err.contains(&format!("{name}:75:50: ")) && err.contains(missing),
            "{function}: {err}"
        );
    }
    // A VARIABLE no force uses is checked too; a REQUEST's F2 by every analysis that
    // writes REQUESTs (here simulate --out), before it runs.
    let path = with_statement(&dir, &text, "v.adm", "VARIABLE/3, FUNCTION = VX(203, 996)");
    let (code, _, err) = run(&["verify", s(&path)]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("v.adm:75:24: ") && err.contains("VX(…): MARKER/996 does not exist"),
        "{err}"
    );
    let path = with_statement(&dir, &text, "q.adm", "REQUEST/4, F2 = DM(995)");
    let csv = dir.join("q.csv");
    let (code, _, err) = run(&[
        "simulate",
        s(&path),
        "--end",
        "0.1",
        "--steps",
        "2",
        "--out",
        s(&csv),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("q.adm:75:17: ") && err.contains("DM(…): MARKER/995 does not exist"),
        "{err}"
    );
    assert!(!csv.exists());
    // Existing references, ground (marker 0) and a computed id are accepted.
    let path = with_statement(
        &dir,
        &text,
        "ok.adm",
        &format!("{head}DX(203, 0) + DY(200 + 3)"),
    );
    let (code, out, err) = run(&["verify", s(&path)]);
    assert_eq!(code, 0, "{out}{err}");
}

#[test]
fn a_kinematic_run_to_1e200_fails_with_a_short_time_and_writes_no_row_there() {
    let dir = std::env::temp_dir().join(format!("linkage-holes-horizon-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(
        root().join("mechanisms/fourbar_motion.adm"),
        dir.join("fm.adm"),
    )
    .unwrap();
    std::fs::write(
        dir.join("fm.acf"),
        "fm\nfm\nSIMULATE/KINEMATIC, END = 1E200, STEPS = 2\n",
    )
    .unwrap();
    let (code, _, err) = run_in(&dir, &["run", "fm.acf"]);
    // The crank's motion (30 deg/s) at 5E+199 s is an angle no double resolves: the
    // positions cannot be found and the run says so at that time, in a few characters.
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("at time 5E+199"), "{err}");
    assert!(!err.contains("0000000000"), "{err}");
    let csv = std::fs::read_to_string(dir.join("fm.csv")).unwrap();
    let times: Vec<&str> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap())
        .collect();
    assert_eq!(times, ["0"], "only the start is a result: {times:?}");
}

/// Starts `linkage args…` in `dir`, waits until `csv` has more than `rows` lines, sends
/// SIGINT, and returns the exit code and the CSV (the command's standard output, written to
/// `csv`, when `on_stdout`).
fn interrupted(
    dir: &Path,
    args: &[&str],
    (csv, on_stdout): (&str, bool),
    rows: usize,
) -> (i32, String) {
    let stdout = if on_stdout {
        std::fs::File::create(dir.join(csv)).unwrap().into()
    } else {
        std::process::Stdio::null()
    };
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_linkage"))
        .args(args)
        .current_dir(dir)
        .stdout(stdout)
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let started = std::time::Instant::now();
    loop {
        let lines = std::fs::read_to_string(dir.join(csv)).map_or(0, |t| t.lines().count());
        if lines > rows {
            break;
        }
        assert!(
            started.elapsed().as_secs() < 60,
            "{args:?}: {lines} CSV lines after 60 s: outputs are not streamed"
        );
        assert!(child.try_wait().unwrap().is_none(), "{args:?} ended early");
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    // SAFETY: kill sends a signal to the child this test started; no memory is involved.
    unsafe {
        libc::kill(child.id() as libc::pid_t, libc::SIGINT);
    }
    let status = child.wait().unwrap();
    let text = std::fs::read_to_string(dir.join(csv)).unwrap();
    (status.code().unwrap_or(-1), text)
}

#[test]
fn a_zero_dof_run_and_quasi_static_series_stream_rows_and_stop_on_sigint_with_whole_rows() {
    let dir = std::env::temp_dir().join(format!("linkage-holes-stream-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(
        root().join("mechanisms/fourbar_motion.adm"),
        dir.join("fm.adm"),
    )
    .unwrap();
    std::fs::write(
        dir.join("k.acf"),
        "fm\nk\nSIMULATE/KINEMATIC, END = 1000, STEPS = 999999\n",
    )
    .unwrap();
    for (args, csv) in [
        (
            vec![
                "simulate", "fm.adm", "--end", "1000", "--steps", "999999", "--out", "s.csv",
            ],
            ("s.csv", false),
        ),
        (vec!["run", "k.acf"], ("k.csv", false)),
        // The quasi-static series on standard output.
        (
            vec![
                "static", "fm.adm", "--end", "1000", "--steps", "999999", "--format", "csv",
            ],
            ("q.csv", true),
        ),
    ] {
        let (code, text) = interrupted(&dir, &args, csv, 200);
        // Interrupted: exit 1 for both commands, as a run that did not finish.
        assert_eq!(code, 1, "{args:?}");
        let mut lines = text.lines();
        let fields = lines.next().unwrap().split(',').count();
        let rows: Vec<&str> = lines.collect();
        assert!(
            rows.len() > 200 && rows.len() < 1_000_000,
            "{args:?}: {}",
            rows.len()
        );
        assert!(text.ends_with('\n'), "{args:?}: the last row is whole");
        for row in &rows {
            assert_eq!(row.split(',').count(), fields, "{args:?}: {row}");
        }
    }
}

#[test]
fn a_run_html_whose_dataset_fails_says_why_and_keeps_the_input_error_exit_code() {
    let (dir, text) = folder("html-reason");
    with_statement(
        &dir,
        &text,
        "bad.adm",
        "SFORCE/8, ROTATION, I = 203, J = 101, FUNCTION = DX(999)",
    );
    std::fs::write(
        dir.join("b.acf"),
        "bad\nb\nSIMULATE/DYNAMIC, END=0.1, STEPS=2\n",
    )
    .unwrap();
    let (code, _, err) = run_in(&dir, &["run", "b.acf", "--html", "b.html"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("bad.adm:75:50: error: SFORCE_8"), "{err}");
    assert!(
        err.contains("no html page: the dataset of the command file could not be opened"),
        "{err}"
    );
    assert!(!err.contains("opened no dataset"), "{err}");
    assert!(!dir.join("b.html").exists());
}

#[test]
fn a_command_file_lists_every_refused_statement_at_once_as_simulate_does() {
    let (dir, text) = folder("at-once");
    let path = with_statement(
        &dir,
        &text,
        "u.adm",
        "REQUEST/5, FUNCTION = USER(1)\nSFORCE/8, ROTATION, I = 203, J = 101, FUNCTION = USER(2)",
    );
    let (code, _, simulate) = run(&["simulate", s(&path), "--end", "0.1", "--steps", "2"]);
    assert_eq!(code, 2, "{simulate}");
    std::fs::write(
        dir.join("u.acf"),
        "u\nu\nSIMULATE/DYNAMIC, END=0.1, STEPS=2\n",
    )
    .unwrap();
    let (code, _, err) = run_in(&dir, &["run", "u.acf"]);
    assert_eq!(code, 2, "{err}");
    // simulate (which writes no REQUEST) names the SFORCE (line 76); run, which writes the
    // REQUESTs, names the REQUEST (line 75) and the SFORCE in one go.
    assert!(simulate.contains("u.adm:76:50: "), "{simulate}");
    for place in ["u.adm:75:", "u.adm:76:50: "] {
        assert!(err.contains(place), "run: {place}: {err}");
    }
}
