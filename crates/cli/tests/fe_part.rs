//! FE_PART through the binary: the corpus dataset's six-node 3DBEAM counted in `verify` as
//! Adams' chapter counts a nonlinear FE body (markers use nodes 1, 4 and 6: 18 constraint
//! modes; 18 interior DOF, so 18 of the 20 normal modes; 6 rigid-body modes), the count
//! following `MSC_NLFE_MNFSWAP_EIGENVALUES` (set on the child process only), and the nodes'
//! columns in the simulate CSV.

mod common;
use common::*;
use std::process::Command;

const DATASET: &str = "bthornton191__adams_vscode__test__files__test.adm";

fn verify_json(path: &str, modes: Option<&str>) -> serde_json::Value {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_linkage"));
    cmd.args(["verify", path, "--format", "json"]);
    match modes {
        Some(m) => cmd.env("MSC_NLFE_MNFSWAP_EIGENVALUES", m),
        None => cmd.env_remove("MSC_NLFE_MNFSWAP_EIGENVALUES"),
    };
    let out = cmd.output().unwrap_or_else(|e| panic!("binary runs: {e}"));
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("not JSON: {e}"))
}

#[test]
fn corpus_fe_part_is_counted_as_an_equivalent_flexible_body() {
    let Some(dir) = corpus() else { return };
    let path = dir.join(DATASET);
    let path = path.to_string_lossy();
    let v = verify_json(&path, None);
    let fe = &v["fe_parts"][0];
    assert_eq!(fe["name"], "Fe_Part_1");
    assert_eq!(fe["marker_nodes"], serde_json::json!([1, 4, 6]));
    assert_eq!(fe["normal_modes_requested"], 20);
    assert_eq!(fe["normal_modes"], 18);
    assert_eq!(fe["constraint_modes"], 18);
    assert_eq!(fe["rigid_body_modes"], 6);
    assert_eq!(fe["gruebler_dof"], 42);
    assert_eq!(fe["nodal_dof"], 36);
    // PART_3 (6) + the FE part (42); no constraints. DOF by rank: 6 + 36 nodal.
    assert_eq!(v["gruebler"], 48);
    assert_eq!(v["dof"], 42);
    assert_eq!(v["moving_parts"], 1);
    assert_eq!(
        v["unconstrained_parts"],
        serde_json::json!(["PART_3", "Fe_Part_1"])
    );
    // Ten normal modes asked for: 10 + 18 + 6.
    let v = verify_json(&path, Some("10"));
    assert_eq!(v["fe_parts"][0]["gruebler_dof"], 34);
    assert_eq!(v["gruebler"], 40);
    let (code, text, _) = run(&["verify", &path]);
    assert_eq!(code, 0);
    assert!(
        text.contains("Fe_Part_1: 6 nodes; 18 normal modes (20 requested) + 18 constraint modes"),
        "{text}"
    );
}

#[test]
fn corpus_fe_part_nodes_have_csv_columns() {
    let Some(dir) = corpus() else { return };
    let path = dir.join(DATASET);
    let (code, csv, err) = run(&[
        "simulate",
        &path.to_string_lossy(),
        "--deactivate",
        "CONTACT",
        "--end",
        "0.01",
        "--steps",
        "2",
        "--out",
        "-",
    ]);
    assert_eq!(code, 0, "{err}");
    let header = csv.lines().next().unwrap_or_default();
    for n in 1..=6 {
        assert!(
            header.contains(&format!("Fe_Part_1.node_{n}.x [mm]")),
            "{header}"
        );
    }
    // Free fall from rest: node 4 drops g·t²/2 = 0.4903 mm in 0.01 s.
    let cols: Vec<&str> = header.split(',').collect();
    let k = cols
        .iter()
        .position(|c| *c == "Fe_Part_1.node_4.y [mm]")
        .unwrap();
    let last: Vec<f64> = csv
        .lines()
        .last()
        .unwrap()
        .split(',')
        .map(|x| x.parse().unwrap())
        .collect();
    let drop = 47.02729423 - last[k];
    assert!((drop / (0.5 * 9806.65 * 1e-4) - 1.0).abs() < 1e-3, "{drop}");
}

/// A six-node cantilever along x (steel, L = 1 m, 10 mm square), clamped at node 1, a tip
/// load of fixed direction (PL²/EI ≈ 1.7) and a marker on node 4 given by points.
fn bent_cantilever() -> String {
    cantilever("-300", "")
}

/// The cantilever of [`bent_cantilever`] with the tip load `FY = fy` (newtons) and the
/// statements `extra`.
fn cantilever(fy: &str, extra: &str) -> String {
    let (a, i, j) = (1e-4, 1e-8 / 12.0, 0.1406e-8);
    let coords: Vec<String> = (0..6)
        .map(|k| format!("{}, {}, 0, 0, 0, 0, 0", k + 1, 0.2 * k as f64))
        .collect();
    let sections: Vec<String> = (0..6)
        .map(|k| format!("{}, {a}, {i}, {i}, 0, {j}", k + 1))
        .collect();
    format!(
        "beam\nUNITS/, FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
         PART/1, GROUND\nMARKER/1, PART = 1\nMARKER/12, PART = 1, FLOATING\n\
         FE_PART/3, TYPE = 3DBEAM, NODE_LABELS = 1, 2, 3, 4, 5, 6\n, COORDINATES = {}\n\
         , SECTION = {}\n, MATERIAL = 1\n\
         MATERIAL/1, DENSITY = 7800, YOUNGS_MODULUS = 2.1E11, POISSONS_RATIO = 0.3\n\
         MARKER/10, FE_PART = 3, NODE_LABEL = 1\n\
         MARKER/11, FE_PART = 3, NODE_LABEL = 6, QP = 1, 0, 0\n\
         MARKER/13, FE_PART = 3, NODE_LABEL = 4, QP = 0.6, 0.01, 0, XP = 0.7, 0.01, 0, ZP = 0.6, 0.01, 1\n\
         JOINT/1, FIXED, I = 10, J = 1\n\
         VFORCE/1, I = 11, JFLOAT = 12, RM = 1, FX = 0, FY = {fy}, FZ = 0\n\
         {extra}EQUILIBRIUM/MAXIT = 100\nEND\n",
        coords.join("\n, "),
        sections.join("\n, "),
    )
}

/// The rows of `static … --format csv` of `adm` (written as `name` in a folder of its own)
/// with `args`, and the index of the column whose header starts with `column`.
fn static_csv(name: &str, adm: &str, args: &[&str], column: &str) -> (Vec<Vec<f64>>, usize) {
    let dir = std::env::temp_dir().join(format!("linkage-fe-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let input = dir.join(format!("{name}.adm"));
    std::fs::write(&input, adm).unwrap();
    let input = input.to_string_lossy().into_owned();
    let mut all = vec!["static", input.as_str(), "--format", "csv"];
    all.extend_from_slice(args);
    let (code, csv, err) = run(&all);
    assert_eq!(code, 0, "{err}");
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    let k = header
        .iter()
        .position(|h| h.starts_with(column))
        .unwrap_or_else(|| panic!("no column {column} in {header:?}"));
    let rows = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    let _ = std::fs::remove_dir_all(&dir);
    (rows, k)
}

/// A small tip load's deflection `P·L³/(3·E·I)` of the cantilever: P = 1 N gives 1.905 mm
/// (δ/L ≈ 0.2 %: the large-deflection correction, ~(δ/L)², and the shear deflection
/// P·L/(κ·G·A) ≈ 8e-5 of it stay well inside 1e-3).
fn tip_deflection(p: f64) -> f64 {
    let (e, i) = (2.1e11, 1e-8 / 12.0);
    p / (3.0 * e * i)
}

/// A REQUEST on the tip node's marker against the ground origin (its y is the tip's
/// deflection: the marker is at x = L, y = 0 unloaded).
const TIP_REQUEST: &str = "REQUEST/1, DISPLACEMENT, I = 11, J = 1\n";

#[test]
fn static_csv_request_on_the_fe_tip_gives_pl3_over_3ei() {
    let (rows, k) = static_csv(
        "tip-request",
        &cantilever("-1", TIP_REQUEST),
        &[],
        "REQUEST_1.y",
    );
    assert_eq!(rows.len(), 1);
    let want = -tip_deflection(1.0);
    let got = rows[0][k];
    assert!((got / want - 1.0).abs() < 1e-3, "{got} vs PL³/3EI {want}");
}

#[test]
fn quasi_static_csv_request_on_the_fe_tip_follows_a_growing_load() {
    // FY = −2·TIME N: at t = 0, 0.5, 1 the tip deflects 0, δ(1 N), δ(2 N).
    let (rows, k) = static_csv(
        "tip-series",
        &cantilever("-2*TIME", TIP_REQUEST),
        &["--end", "1", "--steps", "2"],
        "REQUEST_1.y",
    );
    assert_eq!(rows.len(), 3);
    assert!(rows[0][k].abs() < 1e-9, "{:?}", rows[0]);
    for row in &rows[1..] {
        let want = -tip_deflection(2.0 * row[0]);
        assert!(
            (row[k] / want - 1.0).abs() < 1e-3,
            "t = {}: {} vs {want}",
            row[0],
            row[k]
        );
    }
}

#[test]
fn static_save_writes_the_deflected_nodes_and_ic_reads_them_back() {
    let dir = std::env::temp_dir().join(format!("linkage-fe-save-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let input = dir.join("beam.adm");
    let saved = dir.join("saved.adm");
    std::fs::write(&input, bent_cantilever()).unwrap();
    let (input, saved_s) = (input.to_string_lossy(), saved.to_string_lossy());
    let (code, eq) = json(&["static", &input, "--save", &saved_s, "--format", "json"]);
    assert_eq!(code, 0, "{eq}");
    let text = std::fs::read_to_string(&saved).unwrap();
    assert!(
        text.contains(", 6, 0.869521819"),
        "deflected tip node in COORDINATES:\n{text}"
    );
    let (code, ic) = json(&["ic", &saved_s, "--format", "json"]);
    assert_eq!(code, 0, "{ic}");
    let parts = |v: &serde_json::Value| -> Vec<(String, Vec<f64>)> {
        v["parts"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| {
                let mut x: Vec<f64> = p["position"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|v| v.as_f64().unwrap())
                    .collect();
                x.extend(
                    p["reuler"]
                        .as_array()
                        .unwrap()
                        .iter()
                        .map(|v| v.as_f64().unwrap()),
                );
                (p["name"].as_str().unwrap().to_string(), x)
            })
            .collect()
    };
    let (want, got) = (parts(&eq), parts(&ic));
    assert_eq!(want.len(), 6);
    assert_eq!(
        want.iter().map(|p| &p.0).collect::<Vec<_>>(),
        got.iter().map(|p| &p.0).collect::<Vec<_>>()
    );
    // Positions in m, angles in degrees: the saved numbers' resolution (1e-12) and the
    // assembly's tolerance.
    for ((name, a), (_, b)) in want.iter().zip(&got) {
        for (x, y) in a.iter().zip(b) {
            assert!((x - y).abs() < 1e-8, "{name}: {b:?} vs {a:?}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
