//! FRICTION end to end: the friction each report gives for a block on a 20° ramp (μs = 0.5
//! holds it): none at the start of the IC (at rest, no deformation yet), `m g sin θ` up the
//! ramp at static equilibrium and at the end of a run, with the normal load `m g cos θ`.

mod common;
use common::json;

const G: f64 = 9.80665;

fn ramp(tag: &str) -> std::path::PathBuf {
    let (s, c) = 20f64.to_radians().sin_cos();
    let text = format!(
        "block on a ramp\nUNITS/, FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
PART/1, GROUND\nMARKER/11, PART = 1\n\
PART/2, MASS = 2, CM = 20, IP = 0.1, 0.1, 0.1\nMARKER/20, PART = 2\nMARKER/21, PART = 2\n\
JOINT/1, TRANSLATIONAL, I = 21, J = 11\n\
FRICTION/1, JOINT = 1, MU_STATIC = 0.5, MU_DYNAMIC = 0.3, INPUTS = REACTION_FORCE\n\
ACCGRAV/, JGRAV = {}, KGRAV = {}\nEND\n",
        -G * c,
        -G * s
    );
    let f = std::env::temp_dir().join(format!("linkage-friction-{}-{tag}.adm", std::process::id()));
    std::fs::write(&f, text).unwrap();
    f
}

#[test]
fn reports_give_the_friction_that_holds_a_block_on_a_ramp() {
    let f = ramp("reports");
    let path = f.to_str().unwrap();
    let normal = 2.0 * G * 20f64.to_radians().cos();
    let along = 2.0 * G * 20f64.to_radians().sin();
    let check = |v: &serde_json::Value, force: f64| {
        let fr = &v["frictions"][0];
        assert_eq!(fr["element"], "FRICTION/1", "{v}");
        assert_eq!(fr["joint"], "JOINT_1");
        assert_eq!(fr["regime"], "stiction");
        let n = fr["normal_load"].as_f64().unwrap();
        assert!((n - normal).abs() < 1e-6 * normal, "{n}");
        let fz = fr["force"][2].as_f64().unwrap();
        assert!((fz - force).abs() < 1e-5 * along, "{fz} vs {force}");
    };
    let (code, ic) = json(&["ic", path, "--format", "json"]);
    assert_eq!(code, 0, "{ic}");
    check(&ic, 0.0);
    let (code, st) = json(&["static", path, "--format", "json"]);
    assert_eq!(code, 0, "{st}");
    check(&st, along);
    let (code, sim) = json(&[
        "simulate", path, "--end", "3", "--steps", "30", "--format", "json",
    ]);
    assert_eq!(code, 0, "{sim}");
    check(&sim, along);
    let _ = std::fs::remove_file(&f);
}

#[test]
fn simulate_csv_has_the_friction_columns_named_after_the_element() {
    // The block held on the ramp: at every output (after the stiction spring has taken the
    // load, t ≥ 1 s) FRICTION_1.fz = m g sin θ up the ramp, .normal = m g cos θ, with
    // their units in the header.
    let f = ramp("csv");
    let csv = f.with_extension("csv");
    let (code, sim) = json(&[
        "simulate",
        f.to_str().unwrap(),
        "--end",
        "3",
        "--steps",
        "3",
        "--format",
        "json",
        "--out",
        csv.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{sim}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    for c in [
        "FRICTION_1.fx [N]",
        "FRICTION_1.tz [N·m]",
        "FRICTION_1.normal [N]",
        "FRICTION_1.slip [m/s]",
    ] {
        assert!(header.contains(&c), "{c} in {header:?}");
    }
    let col = |name: &str| header.iter().position(|h| h.starts_with(name)).unwrap();
    let (fz, normal) = (col("FRICTION_1.fz "), col("FRICTION_1.normal "));
    let last: Vec<f64> = text
        .lines()
        .last()
        .unwrap()
        .split(',')
        .map(|x| x.parse().unwrap())
        .collect();
    let n = 2.0 * G * 20f64.to_radians().cos();
    let along = 2.0 * G * 20f64.to_radians().sin();
    assert!((last[normal] - n).abs() < 1e-6 * n, "{}", last[normal]);
    assert!((last[fz] - along).abs() < 1e-5 * along, "{}", last[fz]);
    let _ = std::fs::remove_file(&f);
    let _ = std::fs::remove_file(&csv);
}
