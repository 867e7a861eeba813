//! linkage against Adams' own time histories: the Chrono Adams test models
//! (`projectchrono__chrono__data__adams__test_*.adm` of the shared corpus, third-party files
//! that are not part of this repository) with the request files Adams Solver wrote for them
//! (`*_ADAMS.req`). Skipped, with a notice, when the corpus folder is absent.
//!
//! Each case: read the `.acf` for `SIMULATE/…, END=, DTOUT=|STEPS=`, simulate with linkage,
//! evaluate the dataset's REQUESTs at every output ([`RequestSet`]) and compare with the
//! `.req` history at every output time (the times must agree).
//!
//! What is compared, per request (the models all have the same five):
//! - REQUEST/1 DISPLACEMENT of the part's CM marker from ground: x, y, z, and the orientation
//!   given by ψ, θ, φ, compared as the angle of the rotation between Adams' and linkage's
//!   orientation (the 3-1-3 angles themselves are ill-conditioned near θ = 0, where the
//!   Spherical case starts, and wrap at ±180°);
//! - REQUEST/2 VELOCITY and REQUEST/3 ACCELERATION (linear and angular);
//! - REQUEST/5: the joint reaction `JOINT(1, 0, comp, 0)` (force on the I marker and torque
//!   about it, ground axes), or the FORCE request / `FX(…)…TZ(…)` measures of the models
//!   without a joint;
//! - REQUEST/4 (Euler parameters through `ORIENT(27, …)`) is not compared: ORIENT is not in
//!   linkage's expression language, so the request is dropped before [`RequestSet::new`]
//!   (which would refuse it) and the drop is printed.
//!
//! Error measure: for every group of three components (x y z, vx vy vz, wx wy wz, fx fy fz,
//! tx ty tz, …) the worst absolute difference over all output times, divided by the range the
//! Adams signal covers (largest range of the three components over the run). The .req values
//! are printed with 6 significant digits, so agreement better than about 1e-5 of the range
//! cannot be expected; Adams integrated these models with GSTIFF at ERROR = 1e-4 and
//! HMAX = 1e-5 (the .acf), linkage with its HHT-α integrator, so the two differ by the error of
//! both integrators. Tolerances (relative to the range):
//! - positions, orientation (degrees relative to the angle swept), velocities:
//!   [`TOL_KINEMATICS`] = 1e-3;
//! - accelerations and reactions: [`TOL_DYNAMICS`] = 2e-3: they are algebraic functions of the
//!   positions and velocities, but Adams' GSTIFF (a BDF method) reports accelerations with
//!   an error one order of its step larger than the positions (visible right after t = 0,
//!   where Adams' own tangential acceleration is off by several percent of its small value).
//!
//! linkage is run with INTEGRATOR ERROR = [`LINKAGE_ERROR`] (1e-6) instead of the .acf's
//! 1e-4: linkage's error estimate is the HHT local truncation error of the positions, and at
//! 1e-4 the pendulum's phase drifts by a few 1e-3 of its range after five seconds of
//! swinging; HMAX = 1e-5 of the .acf is not used (it only serves GSTIFF's accuracy and would
//! mean half a million steps).
//!
//! A case whose elements linkage does not model (a statement linkage refuses in force
//! analyses, an element the model or the force set rejects) is skipped with a notice; a case
//! that runs and does not match fails.

use glam::DMat3;
use linkage_adm::reqfile::{read_request_file, RequestFile, RequestHistory};
use linkage_adm::{parse_commands, read_dataset, Dataset, Value};
use linkage_model::frames::euler313_to_matrix;
use linkage_solve::applied::{AppliedForces, NoForces};
use linkage_solve::drivers::ExpressionDrivers;
use linkage_solve::dynamics::{run, IntegratorSettings, Output};
use linkage_solve::forces::ForceSet;
use linkage_solve::requests::RequestSet;
use linkage_solve::tolerances::Tolerances;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Positions, orientation and velocities: worst error / range.
const TOL_KINEMATICS: f64 = 1e-3;
/// Accelerations and reactions: worst error / range.
const TOL_DYNAMICS: f64 = 2e-3;
/// linkage's INTEGRATOR ERROR in these runs (see the module docs).
const LINKAGE_ERROR: f64 = 1e-6;

/// Statements whose forces linkage does not model; `linkage simulate` refuses them
/// (`crates/cli/src/common.rs`).
const UNMODELLED: [&str; 13] = [
    "CONTACT",
    "FRICTION",
    "NFORCE",
    "MFORCE",
    "GSE",
    "LSE",
    "TFSISO",
    "DIFF",
    "PTCV",
    "CVCV",
    "FE_LOAD",
    "UCON",
    "FLEX_BODY",
];

const PREFIX: &str = "projectchrono__chrono__data__adams__test_";

fn corpus_dir() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/corpus");
    if dir.is_dir() {
        Some(dir)
    } else {
        println!(
            "notice: corpus folder {} absent; Adams reference comparisons skipped",
            dir.display()
        );
        None
    }
}

/// The cases of the corpus: models with an Adams request file beside them.
fn discovered_cases(dir: &Path) -> Vec<String> {
    let mut cases: Vec<String> = std::fs::read_dir(dir)
        .map(|rd| {
            rd.filter_map(|e| e.ok())
                .filter_map(|e| e.file_name().to_str().map(str::to_string))
                .filter_map(|n| {
                    n.strip_prefix(PREFIX)
                        .and_then(|r| r.strip_suffix("_ADAMS.req"))
                        .map(str::to_string)
                })
                .filter(|case| dir.join(format!("{PREFIX}{case}.adm")).is_file())
                .collect()
        })
        .unwrap_or_default();
    cases.sort();
    cases
}

/// `KEY = number` of a command.
fn number(st: &linkage_adm::Statement, key: &str) -> Option<f64> {
    match st.arg(key)?.values.as_slice() {
        [Value::Number { value, .. }] => Some(*value),
        _ => None,
    }
}

/// Output times from the `.acf`'s SIMULATE command.
fn acf_times(path: &Path) -> Vec<f64> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let acf = parse_commands(Arc::from(path.display().to_string()), &text)
        .unwrap_or_else(|e| panic!("{e}"));
    let sim = acf
        .commands
        .iter()
        .find(|c| c.keyword == "SIMULATE")
        .unwrap_or_else(|| panic!("{}: no SIMULATE command", path.display()));
    let end = number(sim, "END").unwrap_or_else(|| panic!("SIMULATE without END"));
    let steps = match (number(sim, "DTOUT"), number(sim, "STEPS")) {
        (Some(dt), _) => (end / dt).round() as usize,
        (None, Some(n)) => n as usize,
        _ => panic!("SIMULATE without DTOUT or STEPS"),
    };
    (0..=steps).map(|k| end * k as f64 / steps as f64).collect()
}

/// Why linkage cannot run this model, if it cannot.
fn unsupported(ds: &Dataset) -> Option<String> {
    let names: Vec<String> = ds
        .statements
        .iter()
        .filter(|st| UNMODELLED.contains(&st.keyword.as_str()))
        .map(|st| format!("{}/{}", st.keyword, st.id.unwrap_or(0)))
        .collect();
    (!names.is_empty()).then(|| format!("linkage does not model {}", names.join(", ")))
}

/// Worst error of one signal group.
struct Group {
    /// `REQUEST_2.v` …
    name: String,
    /// Worst absolute difference and where (component, time).
    worst: f64,
    component: String,
    time: f64,
    /// Range of the Adams signal.
    range: f64,
    tol: f64,
}

impl Group {
    fn relative(&self) -> f64 {
        self.worst / self.range.max(f64::MIN_POSITIVE)
    }
}

/// Largest range (max − min over time) among the given components.
fn range(values: &[[f64; 6]], comps: &[usize]) -> f64 {
    comps
        .iter()
        .map(|&c| {
            let (lo, hi) = values
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                    (lo.min(v[c]), hi.max(v[c]))
                });
            hi - lo
        })
        .fold(0.0, f64::max)
}

/// Compares one request's columns (`ours`, six per output) with Adams' history.
fn compare(
    name: &str,
    adams: &RequestHistory,
    times: &[f64],
    ours: &[[f64; 6]],
    tol_first: f64,
    tol_second: f64,
) -> Vec<Group> {
    let labels = adams.component_names();
    let mut groups = Vec::new();
    let displacement = adams.type_code == 1;
    for (g, comps) in [[0usize, 1, 2], [3, 4, 5]].iter().enumerate() {
        let tol = if g == 0 { tol_first } else { tol_second };
        let mut group = Group {
            name: format!("{name}.{}", if g == 0 { "lin" } else { "ang" }),
            worst: 0.0,
            component: String::new(),
            time: 0.0,
            range: range(&adams.values, comps),
            tol,
        };
        if displacement && g == 1 {
            // Orientation: the angle between the two rotations, in degrees, against the
            // largest angle the part turns through from its initial orientation.
            let rot = |v: &[f64; 6]| euler313_to_matrix([v[3], v[4], v[5]].map(f64::to_radians));
            // Angle of the rotation aᵀb: cos = (trace − 1)/2.
            let angle = |a: &DMat3, b: &DMat3| {
                let m = a.transpose() * *b;
                let trace = m.x_axis.x + m.y_axis.y + m.z_axis.z;
                ((trace - 1.0) / 2.0).clamp(-1.0, 1.0).acos().to_degrees()
            };
            let r0 = rot(&adams.values[0]);
            group.range = adams
                .values
                .iter()
                .map(|v| angle(&r0, &rot(v)))
                .fold(0.0, f64::max);
            group.name = format!("{name}.orientation");
            for (k, (a, o)) in adams.values.iter().zip(ours).enumerate() {
                let e = angle(&rot(a), &rot(o));
                if e > group.worst {
                    (group.worst, group.component, group.time) = (e, "angle".into(), times[k]);
                }
            }
        } else {
            for (k, (a, o)) in adams.values.iter().zip(ours).enumerate() {
                for &c in comps {
                    let e = (a[c] - o[c]).abs();
                    if e > group.worst {
                        (group.worst, group.component, group.time) =
                            (e, labels[c].to_string(), times[k]);
                    }
                }
            }
        }
        groups.push(group);
    }
    groups
}

/// Our six values of a request in the .req's component order.
fn ours_for(
    columns: &[String],
    values: &[Vec<f64>],
    name: &str,
    adams: &RequestHistory,
) -> Vec<[f64; 6]> {
    let suffixes = match adams.type_code {
        1..=4 => adams.component_names().map(str::to_string),
        _ => ["f2", "f3", "f4", "f6", "f7", "f8"].map(str::to_string),
    };
    let index: Vec<usize> = suffixes
        .iter()
        .map(|s| {
            let col = format!("{name}.{s}");
            columns
                .iter()
                .position(|c| *c == col)
                .unwrap_or_else(|| panic!("no column {col} in {columns:?}"))
        })
        .collect();
    values
        .iter()
        .map(|row| {
            let mut six = [0.0; 6];
            for (dst, &k) in six.iter_mut().zip(&index) {
                *dst = row[k];
            }
            six
        })
        .collect()
}

fn run_case(case: &str) {
    let Some(dir) = corpus_dir() else { return };
    let adm = dir.join(format!("{PREFIX}{case}.adm"));
    let acf = dir.join(format!("{PREFIX}{case}.acf"));
    let req = dir.join(format!("{PREFIX}{case}_ADAMS.req"));
    let mut ds = read_dataset(&adm).unwrap_or_else(|e| panic!("{e}"));
    if let Some(why) = unsupported(&ds) {
        println!("notice: {case} skipped: {why}");
        return;
    }
    // ORIENT is not in linkage's expression language (module docs).
    ds.requests.retain(|r| {
        let orient = r
            .functions
            .iter()
            .flatten()
            .any(|f| f.value.expr.text.to_ascii_uppercase().contains("ORIENT("));
        if orient {
            println!(
                "notice: {case}: {} (ORIENT, Euler parameters) not compared: ORIENT is not in \
                 linkage's expression language",
                r.header.name
            );
        }
        !orient
    });
    let built = match linkage_model::build_model(&ds) {
        Ok(b) => b,
        Err(e) => {
            println!("notice: {case} skipped: the model is not supported:\n{e}");
            return;
        }
    };
    let model = built.model;
    let forces: Box<dyn AppliedForces> = if model.forces.is_empty() {
        Box::new(NoForces)
    } else {
        match ForceSet::new(&model) {
            Ok(f) => Box::new(f),
            Err(e) => {
                println!("notice: {case} skipped: force elements not supported:\n{e}");
                return;
            }
        }
    };
    let drivers = ExpressionDrivers::new(&model).unwrap_or_else(|e| panic!("{e}"));
    let requests = RequestSet::new(&model, &ds).unwrap_or_else(|e| panic!("{e}"));
    let times = acf_times(&acf);
    let settings = IntegratorSettings {
        error: LINKAGE_ERROR,
        ..Default::default()
    };
    let result = run(
        &model,
        &drivers,
        forces.as_ref(),
        &Tolerances::default(),
        &times,
        &settings,
        false,
        |_| {},
    );
    let sim = result
        .simulation
        .as_ref()
        .unwrap_or_else(|| panic!("{case}: no simulation: {:?}", result.error));
    assert!(sim.failure.is_none(), "{case}: {:?}", sim.failure);
    let outputs: &[Output] = &sim.outputs;
    let reference: RequestFile = read_request_file(&req).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(outputs.len(), reference.times.len(), "{case}: output count");
    for (o, t) in outputs.iter().zip(&reference.times) {
        assert!((o.time - t).abs() < 1e-9, "{case}: time {} vs {t}", o.time);
    }
    let columns = requests.columns();
    let values: Vec<Vec<f64>> = outputs
        .iter()
        .map(|o| {
            requests
                .evaluate(&model, o)
                .unwrap_or_else(|e| panic!("{e}"))
        })
        .collect();

    let mut groups = Vec::new();
    for r in &ds.requests {
        let Some(adams) = reference.request(r.header.id) else {
            panic!("{case}: REQUEST/{} is not in the .req file", r.header.id);
        };
        let ours = ours_for(&columns, &values, &r.header.name, adams);
        let (first, second) = match adams.type_code {
            1 | 2 => (TOL_KINEMATICS, TOL_KINEMATICS),
            _ => (TOL_DYNAMICS, TOL_DYNAMICS),
        };
        groups.extend(compare(
            &r.header.name,
            adams,
            &reference.times,
            &ours,
            first,
            second,
        ));
    }
    println!(
        "{case}: {} outputs, {} steps ({} rejected)",
        outputs.len(),
        sim.steps,
        sim.rejected
    );
    println!(
        "  {:<26} {:>12} {:>8} {:>8} {:>12} {:>10} {:>8}",
        "signal", "worst error", "at", "time", "Adams range", "relative", "tol"
    );
    let mut failed = Vec::new();
    for g in &groups {
        let rel = g.relative();
        // A group Adams holds at rounding level (|range| < 1e-9) only needs an absolute match.
        let ok = if g.range < 1e-9 {
            g.worst < 1e-9
        } else {
            rel <= g.tol
        };
        println!(
            "  {:<26} {:>12.4e} {:>8} {:>8.3} {:>12.4e} {:>10.2e} {:>8.0e}{}",
            g.name,
            g.worst,
            g.component,
            g.time,
            g.range,
            rel,
            g.tol,
            if ok { "" } else { "  MISMATCH" }
        );
        if !ok {
            failed.push(g.name.clone());
        }
    }
    assert!(
        failed.is_empty(),
        "{case}: {} do not match Adams",
        failed.join(", ")
    );
}

macro_rules! cases {
    ($($test:ident => $case:literal),* $(,)?) => {
        $(
            #[test]
            fn $test() {
                run_case($case);
            }
        )*

        /// Every case of the corpus has its test above.
        #[test]
        fn every_reference_case_has_a_test() {
            let Some(dir) = corpus_dir() else { return };
            let mut ours = vec![$($case.to_string()),*];
            ours.sort();
            assert_eq!(discovered_cases(&dir), ours);
        }
    };
}

cases! {
    distance_case01 => "Distance_Case01",
    distance_case02 => "Distance_Case02",
    revolute_case01 => "Revolute_Case01",
    revolute_case02 => "Revolute_Case02",
    spherical_case01 => "Spherical_Case01",
    trans_spring_case01 => "TransSpring_Case01",
    universal_case01 => "Universal_Case01",
    universal_case02 => "Universal_Case02",
}
