//! Every command file of the corpus (`../shared/corpus/*.acf`) runs to its end or stops with a
//! message that names the place and the reason; the Chrono validation cases, run through their
//! own command files (GSTIFF, ERROR = 1e-4, HMAX = 1e-5), match Adams' request files.
//!
//! The corpus is read by relative path; without it the test fails when `CI` is set and skips
//! with a notice elsewhere.

use linkage_adm::reqfile::{read_request_file, RequestFile};
use linkage_run::{run_command_file, RunOptions};
use std::path::{Path, PathBuf};

fn corpus() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/corpus");
    if dir.is_dir() {
        return Some(dir);
    }
    assert!(
        std::env::var_os("CI").is_none(),
        "the corpus folder {} is missing",
        dir.display()
    );
    eprintln!("notice: {} is missing; corpus test skipped", dir.display());
    None
}

/// Largest difference of each signal relative to max(range of Adams' signal, 1), at the
/// output times both files have, with Adams' conventions where they are not unique: Euler
/// parameters (REQUEST/4 of the Chrono models) are compared up to their common sign, and ψ, φ
/// only through ψ + φ where θ is within 0.1° of 0 or 180° (the 3-1-3 angles cannot separate
/// them there); angles modulo 360°.
fn worst_ratio(adams: &RequestFile, ours: &RequestFile, until: f64) -> (f64, String) {
    let mut worst = (0.0f64, String::new());
    for ra in &adams.requests {
        let Some(rb) = ours.request(ra.id) else {
            continue;
        };
        let pairs: Vec<(usize, usize)> = adams
            .times
            .iter()
            .enumerate()
            .filter(|(_, t)| **t <= until)
            .filter_map(|(ka, t)| {
                ours.times
                    .iter()
                    .rposition(|u| (u - t).abs() <= 1e-9)
                    .map(|kb| (ka, kb))
            })
            .collect();
        let angles = ra.type_code == 1;
        let quaternion = ra.type_code == 5 && ra.comment.contains("EULER");
        for c in 0..6 {
            let series: Vec<f64> = ra.values.iter().map(|v| v[c]).collect();
            let range = series.iter().cloned().fold(f64::MIN, f64::max)
                - series.iter().cloned().fold(f64::MAX, f64::min);
            let scale = range.max(1.0);
            for &(ka, kb) in &pairs {
                let (a, b) = (ra.values[ka], rb.values[kb]);
                let diff = if quaternion {
                    let sign = if (0..6).map(|k| a[k] * b[k]).sum::<f64>() < 0.0 {
                        -1.0
                    } else {
                        1.0
                    };
                    (a[c] - sign * b[c]).abs()
                } else if angles && c >= 3 {
                    let singular = a[4].to_radians().sin().abs() < 0.1f64.to_radians().sin();
                    let wrap = |x: f64| (x + 180.0).rem_euclid(360.0) - 180.0;
                    if singular && c != 4 {
                        wrap((a[3] + a[5]) - (b[3] + b[5])).abs()
                    } else {
                        wrap(a[c] - b[c]).abs()
                    }
                } else {
                    (a[c] - b[c]).abs()
                };
                let ratio = diff / scale;
                if ratio > worst.0 {
                    worst = (
                        ratio,
                        format!(
                            "REQUEST/{} value {} at t = {}",
                            ra.id,
                            c + 1,
                            adams.times[ka]
                        ),
                    );
                }
            }
        }
    }
    worst
}

#[test]
fn every_corpus_command_file_runs_or_stops_naming_the_place_and_the_reason() {
    let Some(dir) = corpus() else { return };
    let out = std::env::temp_dir().join(format!("linkage-run-corpus-{}", std::process::id()));
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("lists")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "acf"))
        .collect();
    files.sort();
    assert_eq!(files.len(), 43, "corpus command files");
    let mut ran = Vec::new();
    let mut figures = Vec::new();
    for acf in &files {
        let name = acf.file_stem().unwrap().to_string_lossy().into_owned();
        let options = RunOptions {
            out_dir: Some(out.join(&name)),
            model: None,
            interrupt: None,
            deactivate: Vec::new(),
            allow_unstable: false,
            read: Default::default(),
            ..Default::default()
        };
        match run_command_file(acf, &options) {
            Ok(summary) => {
                assert!(summary.commands > 0, "{name}");
                ran.push(name.clone());
                // Adams' own request file, when the corpus has it.
                let adams = dir.join(format!("{name}_ADAMS.req"));
                if let (Some(req), true) = (summary.req, adams.exists()) {
                    let a = read_request_file(&adams).expect("Adams' file reads");
                    let b = read_request_file(&req).expect("ours reads");
                    assert_eq!(a.times.len(), b.times.len(), "{name}: output count");
                    // Distance_Case02 (a rod hanging on a distance constraint, free to spin)
                    // is chaotic: the difference between two runs doubles every 0.25 s; two
                    // linkage runs with ERROR = 1e-8 and 1e-9 differ in θ by 0.85° at 1.75 s,
                    // 1.3° at 2 s and 0.8 of a signal's range at 4 s, so past 1.5 s no
                    // solution is a reference, Adams' own (ERROR = 1e-4) included.
                    let until = if name.ends_with("Distance_Case02") {
                        1.5
                    } else {
                        f64::INFINITY
                    };
                    figures.push((name, worst_ratio(&a, &b, until)));
                }
            }
            Err(stopped) => {
                let text = stopped.error.to_string();
                // Every stop names a file position (the command, or the dataset element).
                assert!(
                    text.contains(".acf:") || text.contains(".adm:"),
                    "{name}: {text}"
                );
                assert!(!text.is_empty(), "{name}");
            }
        }
    }
    let _ = std::fs::remove_dir_all(&out);
    for (name, (ratio, at)) in &figures {
        eprintln!("{name}: worst {ratio:.2e} of range ({at})");
    }
    // 23 run to their end: the Chrono cases (all but RotSpring, whose REQUEST/5 asks a
    // rotational SFORCE for forces — Adams refuses it too) and five small test models. The
    // others stop on elements linkage does not model yet (CONTACT, GSE, DIFF, USER
    // subroutines) or, for the three templates without a dataset, ask for --model.
    assert_eq!(ran.len(), 23, "{ran:?}");
    let bound = |case: &str| -> f64 {
        figures
            .iter()
            .find(|(n, _)| n.ends_with(case))
            .map(|(_, (r, _))| *r)
            .unwrap_or_else(|| panic!("{case} has no comparison"))
    };
    // Within 1e-3 of each signal's range (measured: Revolute_Case01 6.1e-5, Revolute_Case02
    // 1.2e-4, Spherical_Case01 4.5e-4, Universal_Case01 4.5e-4, Universal_Case02 4.5e-4,
    // Distance_Case01 2.0e-5, Distance_Case02 to 1.5 s 1.3e-5, TransSpring_Case01 4.4e-7).
    for case in [
        "Revolute_Case01",
        "Revolute_Case02",
        "Spherical_Case01",
        "Universal_Case01",
        "Universal_Case02",
        "Distance_Case01",
        "Distance_Case02",
        "TransSpring_Case01",
    ] {
        assert!(bound(case) < 1e-3, "{case}: {:?}", bound(case));
    }
}

/// Distance_Case03: a body hanging on a distance constraint from the ground origin, its CM
/// marker at REULER = −90°, 0°, 0° (θ = 0: only ψ + φ = −90° is fixed by the pose). It
/// starts to turn about x only after the constraint tilts, so for the first outputs θ is at
/// rounding level; Adams' run (the figures, held out of the corpus) writes ψ = −90°,
/// φ = 0° at t = 0.01 s, the split of its first output continued. Our request file and CSV
/// must do the same — and the Euler parameters with them (P0 = cos 45° > 0, P3 = −sin 45°),
/// and the CSV's part angles: no jump of ψ, φ or the parameters' sign between outputs while
/// θ stays at ≈ 0.
#[test]
fn distance_case03_keeps_adams_split_of_psi_and_phi_near_theta_zero() {
    let Some(dir) = corpus() else { return };
    let acf = dir.join("projectchrono__chrono__data__adams__test_Distance_Case03.acf");
    let out = std::env::temp_dir().join(format!("linkage-run-dist03-{}", std::process::id()));
    let options = RunOptions {
        out_dir: Some(out.clone()),
        model: None,
        interrupt: None,
        deactivate: Vec::new(),
        allow_unstable: false,
        read: Default::default(),
        ..Default::default()
    };
    let summary = run_command_file(&acf, &options).unwrap_or_else(|e| panic!("{}", e.error));
    let req = read_request_file(&summary.req.expect("a request file")).expect("reads");
    let csv = std::fs::read_to_string(summary.csv.expect("a CSV file")).expect("reads");
    let _ = std::fs::remove_dir_all(&out);
    let k = req
        .times
        .iter()
        .position(|t| (t - 0.01).abs() < 1e-9)
        .expect("an output at t = 0.01");
    // The .req (E13.5): REQUEST/1 is DISPLACEMENT of the CM marker relative to ground.
    let d = req.request(1).expect("REQUEST/1").values[k];
    assert!(d[4].abs() < 1e-4, "θ at t = 0.01 is ≈ 0: {d:?}");
    assert!((d[3] + 90.0).abs() < 1e-4, "ψ = −90° at t = 0.01: {d:?}");
    assert!(d[5].abs() < 1e-4, "φ = 0° at t = 0.01: {d:?}");
    // REQUEST/4: ORIENT(27, 1..4) stored as F2, F3, F4, F6.
    let p = req.request(4).expect("REQUEST/4").values[k];
    let h = std::f64::consts::FRAC_1_SQRT_2;
    assert!((p[0] - h).abs() < 1e-4 && (p[3] + h).abs() < 1e-4, "{p:?}");
    // Every output while θ < 1e-4°: the same split, and P0 of the same sign.
    let psi_phi_p0 = |k: usize| {
        let d = req.request(1).unwrap().values[k];
        (d[3], d[4], d[5], req.request(4).unwrap().values[k][0])
    };
    let small: Vec<usize> = (0..req.times.len())
        .take_while(|&k| psi_phi_p0(k).1.abs() < 1e-4)
        .collect();
    assert!(small.len() >= 2, "{} outputs at θ ≈ 0", small.len());
    for &k in &small {
        let (psi, _, phi, p0) = psi_phi_p0(k);
        assert!(
            (psi + 90.0).abs() < 1e-4 && phi.abs() < 1e-4 && p0 > 0.0,
            "t = {}: ψ = {psi}, φ = {phi}, P0 = {p0}",
            req.times[k]
        );
    }
    // The CSV: the REQUEST_1 columns and the part's own angles at t = 0.01.
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().expect("a header").split(',').collect();
    let row: Vec<f64> = lines
        .map(|l| {
            l.split(',')
                .map(|x| x.parse::<f64>().unwrap())
                .collect::<Vec<_>>()
        })
        .find(|r| (r[0] - 0.01).abs() < 1e-9)
        .expect("a row at t = 0.01");
    let column = |name: &str| {
        let c = header
            .iter()
            .position(|h| h.starts_with(name))
            .unwrap_or_else(|| panic!("no column {name} in {header:?}"));
        row[c]
    };
    // The part's own axes start as ground's (ψ = φ = 0), its CM marker's at ψ = −90°.
    for (name, psi0) in [("REQUEST_1", -90.0), ("PART_2", 0.0)] {
        let (psi, phi) = (
            column(&format!("{name}.psi")),
            column(&format!("{name}.phi")),
        );
        assert!((psi - psi0).abs() < 1e-4, "{name}.psi = {psi}");
        assert!(phi.abs() < 1e-4, "{name}.phi = {phi}");
    }
}

/// Fkinev1 (a SOLIDWORKS-exported 3-RPR robot) run as Adams ran it (its message file in the
/// source repository: `simulate/initial_conditions`, then GSTIFF dynamics with outputs every
/// 5 ms). Its input is not assembled — its two MOTIONs ask the actuators for −150 and
/// −200 mm where the input has them 30.7 and 33.0 mm short, which `verify` reports — and
/// Adams' displacement IC assembles it, deactivating 28 redundant equations. Ours must too:
/// the assembly converges with both motions held, the same number of redundant equations,
/// all consistent, and the dynamics run from there.
#[test]
fn fkinev1_assembles_and_runs_as_adams_did() {
    let Some(dir) = corpus() else { return };
    let adm = dir.join("kiterunner347__3-RPR-parallel--robot__RPRAdams__fitestv1__Fkinev1.adm");
    let out = std::env::temp_dir().join(format!("linkage-run-fk-{}", std::process::id()));
    std::fs::create_dir_all(&out).unwrap();
    let acf = out.join("fk.acf");
    std::fs::write(
        &acf,
        format!(
            "{}\nfk\nsimulate/initial_conditions\nsimulate/dynamic, end = 0.05, dtout = 0.005\nstop\n",
            adm.display()
        ),
    )
    .unwrap();
    let options = RunOptions {
        out_dir: Some(out.clone()),
        model: None,
        interrupt: None,
        deactivate: Vec::new(),
        allow_unstable: false,
        read: Default::default(),
        ..Default::default()
    };
    let summary = run_command_file(&acf, &options).unwrap_or_else(|e| panic!("{}", e.error));
    let msg = std::fs::read_to_string(&summary.msg).unwrap();
    let _ = std::fs::remove_dir_all(&out);
    assert_eq!(summary.outputs, 11, "{msg}");
    assert!(msg.contains("Displacement: converged"), "{msg}");
    // Both motions held after the assembly (residual below 1e-10 mm).
    for motion in ["MOTION_1", "MOTION_2"] {
        let line = msg
            .lines()
            .find(|l| l.trim_start().starts_with(motion) && l.contains('→'))
            .unwrap_or_else(|| panic!("{motion} not repaired:\n{msg}"));
        let after: f64 = line.rsplit('→').next().unwrap().trim().parse().unwrap();
        assert!(after.abs() < 1e-10, "{line}");
    }
    assert!(
        msg.contains("There are 28 redundant constraint equations."),
        "{msg}"
    );
    let listed = msg
        .lines()
        .skip_while(|l| !l.starts_with("Redundant constraint equations (removed"))
        .skip(1)
        .take_while(|l| l.starts_with("   "))
        .collect::<Vec<_>>();
    assert_eq!(listed.len(), 28, "{listed:?}");
    assert!(
        listed.iter().all(|l| l.ends_with(" consistent")),
        "{listed:?}"
    );
}
