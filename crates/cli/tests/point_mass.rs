//! POINT_MASS end to end (ADM-ELEMENTS §13): three translational degrees of freedom in every
//! analysis — verify's counts, initial conditions, statics, linearization and simulation —
//! against closed forms, and the elements that would turn or constrain the rotation of a point
//! mass refused by name.

mod common;
use common::{json, run};
use std::path::PathBuf;

const G: f64 = 9.81;

const HEADER: &str = "\
UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND
PART/1, GROUND
MARKER/1, PART = 1, QP = 0, 0, 0
MARKER/3, PART = 1, QP = 0, 0, 0
";

/// A dataset `title` + [`HEADER`] + `body`, written to a temp file named after `tag`.
fn dataset(tag: &str, body: &str) -> PathBuf {
    let text = format!("point mass {tag}\n{HEADER}{body}\nEND\n");
    let f = std::env::temp_dir().join(format!("linkage-pm-{tag}-{}.adm", std::process::id()));
    std::fs::write(&f, text).unwrap();
    f
}

/// The CSV written by `simulate FILE --end END --steps N --out …`: header and rows.
fn simulate_csv(f: &std::path::Path, end: f64, steps: usize) -> (Vec<String>, Vec<Vec<f64>>) {
    let csv = f.with_extension("csv");
    let (code, out, err) = run(&[
        "simulate",
        f.to_str().unwrap(),
        "--end",
        &end.to_string(),
        "--steps",
        &steps.to_string(),
        "--out",
        csv.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{out}\n{err}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    let header = lines
        .next()
        .unwrap()
        .split(',')
        .map(|h| h.split(' ').next().unwrap_or(h).to_string())
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    (header, rows)
}

fn column(header: &[String], name: &str) -> usize {
    header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name} in {header:?}"))
}

const FALL: &str = "\
POINT_MASS/4, MASS = 2, QG = 0, 0, 10, VX = 1
MARKER/40, POINT_MASS = 4
ACCGRAV/KGRAV = -9.81
INTEGRATOR/GSTIFF, ERROR = 1E-8";

#[test]
fn point_mass_has_three_degrees_of_freedom() {
    let f = dataset("free", FALL);
    let (code, v) = json(&["verify", f.to_str().unwrap(), "--format", "json"]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(v["point_masses"], 1);
    assert_eq!(v["moving_parts"], 0);
    assert_eq!(v["constraint_equations"], 0);
    assert_eq!(v["gruebler"], 3);
    assert_eq!(v["dof"], 3);
    // INPLANE leaves 2, INLINE 1, ATPOINT none; a spherical pendulum (distance GCON) 2.
    for (prim, dof) in [("INPLANE", 2), ("INLINE", 1), ("ATPOINT", 0)] {
        let f = dataset(
            &format!("prim-{prim}"),
            &format!("{FALL}\nJPRIM/1, {prim}, I = 40, J = 3"),
        );
        let (code, v) = json(&["verify", f.to_str().unwrap(), "--format", "json"]);
        assert_eq!(code, 0, "{v}");
        assert_eq!(
            (v["gruebler"].as_i64(), v["dof"].as_i64()),
            (Some(dof), Some(dof))
        );
    }
    let (_, out, _) = run(&["verify", f.to_str().unwrap()]);
    assert!(
        out.contains("    1 Point Masses (3 degrees of freedom each)"),
        "{out}"
    );
}

#[test]
fn point_mass_falls_freely() {
    // z = z0 − ½ g t², x = vx t (no rotation, no inertia needed).
    let f = dataset("fall", FALL);
    let (h, rows) = simulate_csv(&f, 1.0, 4);
    let (x, z, vz) = (
        column(&h, "POINT_MASS_4.x"),
        column(&h, "POINT_MASS_4.z"),
        column(&h, "POINT_MASS_4.vz"),
    );
    assert_eq!(rows.len(), 5);
    for r in &rows {
        let t = r[0];
        assert!((r[x] - t).abs() < 1e-9, "{r:?}");
        assert!((r[z] - (10.0 - 0.5 * G * t * t)).abs() < 1e-6, "{r:?}");
        assert!((r[vz] + G * t).abs() < 1e-6, "{r:?}");
    }
}

/// A point mass m = 4 on a spring k = 100 along an INLINE primitive (ground x axis), free
/// length 1, started at 1.1: ω = √(k/m) = 5 rad/s.
const SPRING: &str = "\
POINT_MASS/4, MASS = 4, QG = 1.1, 0, 0, CM = 40
MARKER/40, POINT_MASS = 4
MARKER/41, POINT_MASS = 4, REULER = 90D, 90D, 0
MARKER/5, PART = 1, REULER = 90D, 90D, 0
JPRIM/1, INLINE, I = 41, J = 5
SPRINGDAMPER/1, TRANSLATIONAL, I = 40, J = 3, K = 100, C = 0, LENGTH = 1
INTEGRATOR/GSTIFF, ERROR = 1E-8";

#[test]
fn point_mass_on_a_spring_oscillates_at_root_k_over_m() {
    let f = dataset("spring", SPRING);
    let (code, v) = json(&["linear", f.to_str().unwrap(), "--format", "json"]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(v["dof"], 1);
    let eig = &v["eigenvalues"][0];
    let hz = 5.0 / std::f64::consts::TAU;
    assert!(
        (eig["imag"].as_f64().unwrap() - hz).abs() < 1e-9 * hz,
        "{eig}"
    );
    assert!(eig["real"].as_f64().unwrap().abs() < 1e-9, "{eig}");
    // x(t) = 1 + 0.1 cos 5t over one period.
    let (h, rows) = simulate_csv(&f, std::f64::consts::TAU / 5.0, 8);
    let x = column(&h, "POINT_MASS_4.x");
    for r in &rows {
        let expected = 1.0 + 0.1 * (5.0 * r[0]).cos();
        assert!((r[x] - expected).abs() < 1e-5, "{r:?} vs {expected}");
    }
}

#[test]
fn point_mass_hangs_on_a_spring_at_mg_over_k() {
    // Static deflection m g / k = 2·9.81/100 below the free length 1.
    let f = dataset(
        "hang",
        "POINT_MASS/4, MASS = 2, QG = 0, 0, -1\n\
         MARKER/40, POINT_MASS = 4\n\
         JPRIM/1, INLINE, I = 40, J = 3\n\
         SPRINGDAMPER/1, TRANSLATIONAL, I = 40, J = 1, K = 100, C = 0, LENGTH = 1\n\
         ACCGRAV/KGRAV = -9.81",
    );
    let (code, v) = json(&["static", f.to_str().unwrap(), "--format", "json"]);
    assert_eq!(code, 0, "{v}");
    let z = v["parts"][0]["position"][2].as_f64().unwrap();
    assert!((z - (-1.0 - 2.0 * G / 100.0)).abs() < 1e-9, "{v}");
    assert_eq!(v["stable"], true);
    // The rotation hold carries nothing and is not reported as a reaction.
    let reactions = v["reactions"].as_array().unwrap();
    assert!(
        reactions.iter().all(|r| r["element"] != "POINT_MASS/4"),
        "{reactions:?}"
    );
}

#[test]
fn spherical_pendulum_of_a_point_mass_swings_at_root_g_over_l() {
    // A point mass held at distance L = 2 from a ground point by a GCON: two small-swing
    // modes at √(g/L).
    let f = dataset(
        "spherical",
        "POINT_MASS/4, MASS = 3, QG = 0, 0, -2\n\
         MARKER/40, POINT_MASS = 4\n\
         GCON/1, I = 40, FUNCTION = DM(40, 1) - 2\n\
         ACCGRAV/KGRAV = -9.81",
    );
    let (code, v) = json(&["verify", f.to_str().unwrap(), "--format", "json"]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(
        (v["gruebler"].as_i64(), v["dof"].as_i64()),
        (Some(2), Some(2))
    );
    let (code, v) = json(&["linear", f.to_str().unwrap(), "--format", "json"]);
    assert_eq!(code, 0, "{v}");
    let hz = (G / 2.0f64).sqrt() / std::f64::consts::TAU;
    let eig = v["eigenvalues"].as_array().unwrap();
    assert_eq!(eig.len(), 2, "{eig:?}");
    for e in eig {
        assert!((e["imag"].as_f64().unwrap() - hz).abs() < 1e-9 * hz, "{e}");
    }
}

#[test]
fn elements_that_turn_or_lock_a_point_mass_are_refused_by_name() {
    let f = dataset(
        "refused",
        "POINT_MASS/4, MASS = 2\n\
         MARKER/40, POINT_MASS = 4\n\
         MARKER/5, PART = 1, FLOATING\n\
         JOINT/7, REVOLUTE, I = 40, J = 3\n\
         JPRIM/8, PERPENDICULAR, I = 40, J = 3\n\
         VTORQUE/2, I = 40, JFLOAT = 5, RM = 1, TZ = 1\n\
         SFORCE/3, ROTATIONAL, I = 40, J = 3, FUNCTION = 1",
    );
    for args in [&["verify"][..], &["simulate", "--end", "1"]] {
        let cmd = args[0];
        let mut all = args.to_vec();
        all.insert(1, f.to_str().unwrap());
        let (code, _, err) = run(&all);
        assert_eq!(code, 2, "{err}");
        for (line, name) in [
            (9, "JOINT_7"),
            (10, "JPRIM_8"),
            (11, "VTORQUE_2"),
            (12, "SFORCE_3"),
        ] {
            let at = format!("{}:{line}:1: error: {name}: ", f.display());
            assert!(err.contains(&at), "{cmd}: {at} missing in {err}");
        }
        assert!(err.contains("POINT_MASS_4 is a POINT_MASS"), "{err}");
    }
}
