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
    // Distance_Case01 2.0e-5, Distance_Case02 to 1.5 s 5.4e-4, TransSpring_Case01 4.4e-7).
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
