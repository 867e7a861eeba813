//! The corpus datasets with control elements: every DIFF, LSE, TFSISO, MATRIX, PINPUT and
//! POUTPUT is modelled (no finding names one), a GSE is named as the USER subroutines it is,
//! and the Adams Controls plant with a PID DIFF (the wiper, Controls_Plant_5) runs, its DIFF
//! following its equation at every output.
//!
//! The corpus is read by relative path; without it the test fails when `CI` is set and skips
//! with a notice elsewhere.

mod common;
use common::corpus;
use linkage_model::settings::IntegratorMethod;
use linkage_solve::constraints::drivers::ExpressionDrivers;
use linkage_solve::coverage::{findings, Reason};
use linkage_solve::physics::forces::ForceSet;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::dynamics::{run, IntegratorSettings, Start};
use linkage_solve::tolerances::Tolerances;
use std::path::PathBuf;
const CONTROL_KEYWORDS: [&str; 6] = ["DIFF", "LSE", "TFSISO", "MATRIX", "PINPUT", "POUTPUT"];

#[test]
fn no_corpus_control_element_is_left_out_and_gses_are_named_user() {
    let Some(dir) = corpus() else { return };
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "adm"))
        .collect();
    files.sort();
    let (mut with_controls, mut gses) = (0, 0);
    for f in &files {
        let Ok(ds) = linkage_adm::read_dataset(f) else {
            continue;
        };
        let name = f.file_name().unwrap().to_string_lossy();
        let has = ds
            .statements
            .iter()
            .any(|s| CONTROL_KEYWORDS.contains(&s.keyword.as_str()));
        with_controls += usize::from(has);
        for found in findings(&ds) {
            let place = format!("{name}:{}: {}", found.span.line, found.element);
            if CONTROL_KEYWORDS.contains(&found.keyword.as_str()) {
                assert_eq!(
                    found.reason,
                    Reason::ExternalFileMissing,
                    "{place}: {found:?}"
                );
            }
            if found.keyword == "GSE" {
                gses += 1;
                assert_eq!(found.reason, Reason::UserSubroutine, "{place}");
            }
        }
    }
    assert!(
        with_controls >= 10,
        "{with_controls} datasets with control elements"
    );
    assert!(gses >= 6, "{gses} GSEs");
}

#[test]
fn the_wiper_plant_runs_with_its_pid_state() {
    let Some(dir) = corpus() else { return };
    let path =
        dir.join("Dinh-Hao-Nguyen__MSCAdams_Wiper_Project__ControlSimulink__Controls_Plant_5.adm");
    let ds = linkage_adm::read_dataset(&path).unwrap_or_else(|e| panic!("{e}"));
    assert!(findings(&ds).iter().all(|f| f.refused_by.is_empty()));
    let m = linkage_model::build_model(&ds)
        .unwrap_or_else(|e| panic!("{e}"))
        .model;
    assert_eq!(m.controls.count, 1);
    let d = ExpressionDrivers::new(&m).unwrap_or_else(|e| panic!("{e}"));
    let forces = ForceSet::new(&m).unwrap_or_else(|e| panic!("{e}"));
    let a = Assembled::new(&m, &d, &forces, &Tolerances::default());
    let times: Vec<f64> = (0..=10).map(|k| 0.002 * k as f64).collect();
    let settings = IntegratorSettings {
        method: IntegratorMethod::Bdf,
        ..m.integrator.settings.clone()
    };
    let r = run(&a, &times, &settings, Start::InitialConditions, |_| {});
    assert!(r.error.is_none(), "{:?}", r.error);
    let sim = r.simulation.expect("simulated");
    assert!(sim.failure.is_none(), "{:?}", sim.failure);
    assert_eq!(sim.outputs.len(), times.len());
    // DIFF/1 (PIDCON_sys): ẏ = VARVAL(29), the error the PID integrates. The rates satisfy
    // the equation at the integrator's velocities; the outputs' are projected onto the
    // constraints, which moves VARVAL(29) (a velocity error) within the integration error.
    for o in &sim.outputs {
        let f = forces
            .variable(29, &o.state, &o.velocities)
            .unwrap_or_else(|e| panic!("{e}"));
        let rate = o.state.controls.xdot[0];
        assert!(
            (rate - f).abs() <= 1e-4 * f.abs().max(1.0),
            "t = {}: DIF1 {rate} vs VARVAL(29) {f}",
            o.time
        );
    }
}
