//! Nothing is dropped silently: every statement linkage does not model or run (a FLEX_BODY
//! whose modal data are in a missing MNF file,
//! NFORCE, CURVE, UCON, a USER subroutine, GSE) is named by verify with its file:line,
//! every analysis that cannot run without it refuses with the whole list at once, and
//! `--deactivate` runs the rest of the model with the report saying what was left out.

mod common;
use common::*;
use std::path::PathBuf;

/// A pendulum (one revolute joint, gravity) and, after it, every kind of statement linkage
/// does not model or run. Lines: FLEX_BODY 10, NFORCE 12, CURVE 13, MATRIX 14 (the curve's data,
/// read), UCON 15,
/// SFORCE 16, GSE 17.
const EXTRAS: &str = "pendulum with extras
UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND
ACCGRAV/JGRAV = -9.81
PART/1, GROUND
MARKER/10, PART = 1
PART/2, MASS = 1, CM = 20, IP = 1, 1, 1
MARKER/20, PART = 2, QP = 1, 0, 0
MARKER/21, PART = 2
JOINT/1, REVOLUTE, I = 21, J = 10
FLEX_BODY/5, MNF_FILE = 'wing.mnf'
MARKER/50, FLEX_BODY = 5
NFORCE/3
CURVE/7, OPEN, MATRIX = 8
MATRIX/8, FULL = RORDER, ROWS = 2, COLUMNS = 3, VALUES = 0, 0, 0, 1, 1, 1
UCON/9, FUNCTION = 0
SFORCE/4, ROTATIONAL, I = 21, J = 10, FUNCTION = USER(1, 2)
GSE/6, NS = 1, FUNCTION = USER(1)
GRAPHICS/1, CYLINDER, CM = 20
RESULTS/FORMATTED
END
";

/// Every statement the analyses refuse.
const REFUSED: [(&str, u32); 5] = [
    ("FLEX_BODY/5", 10),
    ("NFORCE/3", 12),
    ("UCON/9", 15),
    ("SFORCE/4", 16),
    ("GSE/6", 17),
];

/// `text` written to a file of its own (named after `tag`) in the temporary folder.
fn dataset(tag: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("linkage-silent-{}-{tag}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("m.adm");
    std::fs::write(&f, text).unwrap();
    f
}

fn s(p: &std::path::Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn verify_names_every_statement_not_modelled_at_once_with_its_place() {
    let f = dataset("verify", EXTRAS);
    let (code, out, err) = run(&["verify", s(&f)]);
    assert_eq!(code, 0, "{out}\n{err}");
    for (element, line) in REFUSED {
        let place = format!("{}:{line} ", s(&f));
        assert!(
            out.lines()
                .any(|l| l.contains(&place) && l.contains(element)),
            "{element} at line {line} not listed:\n{out}"
        );
    }
    assert!(out.contains("USER subroutine"), "{out}");
    // The curve's MATRIX is read (modelled data), the CURVE is not used.
    assert!(
        out.contains("CURVE_7 (line 13)") && !out.contains("MATRIX_8"),
        "{out}"
    );
    assert!(!out.contains("Model verified successfully"), "{out}");
    let last = out.lines().rfind(|l| !l.trim().is_empty()).unwrap();
    assert!(
        last.contains("will refuse it") && last.contains("every other analysis"),
        "{last}"
    );

    let (code, v) = json(&["verify", s(&f), "--format", "json"]);
    assert_eq!(code, 0, "{v}");
    let not_run = v["not_run"].as_array().unwrap();
    let listed: Vec<(&str, u64, &str)> = not_run
        .iter()
        .map(|f| {
            (
                f["element"].as_str().unwrap(),
                f["line"].as_u64().unwrap(),
                f["reason"].as_str().unwrap(),
            )
        })
        .collect();
    assert_eq!(
        listed,
        [
            ("FLEX_BODY/5", 10, "external file missing"),
            ("NFORCE/3", 12, "not modelled"),
            ("CURVE/7", 13, "not used"),
            ("UCON/9", 15, "not modelled"),
            ("SFORCE/4", 16, "USER subroutine"),
            ("GSE/6", 17, "USER subroutine"),
        ]
    );
    assert_eq!(
        not_run[1]["refused_by"],
        serde_json::json!(["ic", "static", "static --end", "linear", "simulate"])
    );
    assert_eq!(
        v["later_refused_by"],
        serde_json::json!(["ic", "static", "static --end", "linear", "simulate"])
    );
    assert!(v["errors"].as_array().unwrap().is_empty());
}

#[test]
fn simulate_refuses_with_the_whole_list_and_deactivate_runs_the_rest() {
    let f = dataset("simulate", EXTRAS);
    let (code, out, err) = run(&["simulate", s(&f), "--end", "0.1", "--steps", "2"]);
    assert_eq!(code, 2, "{out}\n{err}");
    for (element, line) in REFUSED {
        let place = format!("{}:{line}:", s(&f));
        assert!(
            err.lines()
                .any(|l| l.starts_with(&place) && l.contains(element)),
            "{element} at line {line} not refused:\n{err}"
        );
    }
    assert!(err.contains("--deactivate NFORCE/3"), "{err}");
    assert!(
        !err.contains("CURVE"),
        "a curve nothing reads is not refused:\n{err}"
    );
    let (code, v) = json(&[
        "simulate",
        s(&f),
        "--end",
        "0.1",
        "--steps",
        "2",
        "--format",
        "json",
    ]);
    assert_eq!(code, 2);
    assert_eq!(v["errors"].as_array().unwrap().len(), REFUSED.len(), "{v}");

    // Left out by KEYWORD/id, by kind, by name, comma-separated or repeated.
    let (code, out, err) = run(&[
        "simulate",
        s(&f),
        "--end",
        "0.1",
        "--steps",
        "2",
        "--deactivate",
        "FLEX_BODY/5,NFORCE,UCON_9",
        "--deactivate",
        "sforce/4,GSE",
    ]);
    assert_eq!(code, 0, "{out}\n{err}");
    assert!(
        out.contains(
            "left out on request (5): FLEX_BODY_5 (FLEX_BODY/5, line 10), NFORCE_3 \
             (NFORCE/3, line 12), UCON_9 (UCON/9, line 15), SFORCE_4 (SFORCE/4, line \
             16), GSE_6 (GSE/6, line 17)"
        ),
        "{out}"
    );
    assert!(
        out.contains("runs without 1 CURVE (not used): CURVE_7 (line 13)"),
        "{out}"
    );
    let (code, v) = json(&[
        "simulate",
        s(&f),
        "--end",
        "0.1",
        "--steps",
        "2",
        "--format",
        "json",
        "--deactivate",
        "FLEX_BODY,NFORCE,UCON,SFORCE,GSE",
    ]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(v["left_out"].as_array().unwrap().len(), 5, "{v}");
    assert_eq!(v["left_out"][1]["element"], "NFORCE/3");
    assert_eq!(v["runs_without"].as_array().unwrap().len(), 1, "{v}");
}

#[test]
fn statics_refuse_with_the_whole_list_and_run_without_unused_data() {
    let f = dataset("static", EXTRAS);
    let (code, _, err) = run(&["static", s(&f)]);
    assert_eq!(code, 2);
    assert_eq!(err.matches(": error: ").count(), REFUSED.len(), "{err}");
    let (code, v) = json(&[
        "static",
        s(&f),
        "--format",
        "json",
        "--deactivate",
        "FLEX_BODY,NFORCE,UCON,SFORCE,GSE",
    ]);
    assert_eq!(code, 0, "{v}");
    let without: Vec<&str> = v["runs_without"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["element"].as_str().unwrap())
        .collect();
    assert_eq!(without, ["CURVE/7"]);
}

#[test]
fn ic_and_linear_refuse_a_flexible_body_nothing_is_attached_to() {
    let f = dataset("ic", EXTRAS);
    for command in ["ic", "linear"] {
        let (code, _, err) = run(&[command, s(&f)]);
        assert_eq!(code, 2, "{command}: {err}");
        assert!(
            err.contains(&format!("{}:10:1: error: FLEX_BODY_5", s(&f))),
            "{err}"
        );
        let (code, out, err) = run(&[
            command,
            s(&f),
            "--deactivate",
            "FLEX_BODY,NFORCE,UCON,SFORCE,GSE",
        ]);
        assert_eq!(code, 0, "{command}: {out}\n{err}");
        assert!(out.contains("left out on request (5)"), "{out}");
    }
}

#[test]
fn a_model_that_does_not_build_names_every_refused_statement_too() {
    // The joint uses a marker on the flexible body: a build error, reported with the rest.
    let text = EXTRAS.replace(
        "JOINT/1, REVOLUTE, I = 21, J = 10",
        "JOINT/1, REVOLUTE, I = 21, J = 50",
    );
    let f = dataset("build", &text);
    let (code, _, err) = run(&["simulate", s(&f), "--end", "1"]);
    assert_eq!(code, 2);
    assert!(err.contains("is on a FLEX_BODY"), "{err}");
    for (element, _) in REFUSED {
        assert!(err.contains(element), "{element} missing:\n{err}");
    }
    let (code, _, err) = run(&["verify", s(&f)]);
    assert_eq!(code, 2);
    assert!(err.contains("note: GSE_6 (GSE/6)"), "{err}");
}

#[test]
fn deactivate_names_that_choose_nothing_are_input_errors() {
    let f = dataset("names", EXTRAS);
    let (code, _, err) = run(&["verify", s(&f), "--deactivate", "SENSOR/99"]);
    assert_eq!(code, 2);
    assert!(err.contains("--deactivate SENSOR/99"), "{err}");
    let (code, out, _) = run(&["verify", s(&f), "--deactivate", "CURVE,MATRIX"]);
    assert_eq!(code, 0);
    assert!(out.contains("left out on request (2)"), "{out}");
    assert!(!out.contains("every analysis runs without"), "{out}");
}

#[test]
fn a_command_file_runs_what_its_deactivate_and_the_option_leave() {
    let f = dataset("run", EXTRAS);
    let dir = f.parent().unwrap();
    let acf = dir.join("c.acf");
    std::fs::write(&acf, "m\nout\nsim/dyn, end = 0.1, steps = 2\nstop\n").unwrap();
    let out_dir = dir.join("out");
    let (code, _, err) = run(&["run", s(&acf), "--out-dir", s(&out_dir)]);
    assert_eq!(code, 2, "{err}");
    for (element, line) in REFUSED {
        assert!(err.contains(&format!("m.adm:{line}:")), "{element}:\n{err}");
    }
    std::fs::write(
        &acf,
        "m\nout\nDEACTIVATE/NFORCE, ID = 3\nsim/dyn, end = 0.1, steps = 2\nstop\n",
    )
    .unwrap();
    let (code, _, err) = run(&[
        "run",
        s(&acf),
        "--out-dir",
        s(&out_dir),
        "--deactivate",
        "FLEX_BODY,UCON,SFORCE,GSE",
    ]);
    assert_eq!(code, 0, "{err}");
    let msg = std::fs::read_to_string(out_dir.join("out.msg")).unwrap();
    assert!(msg.contains("left out on request (5)"), "{msg}");
}
