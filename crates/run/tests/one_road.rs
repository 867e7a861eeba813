//! One road: a model run from the command line and from a command file gets the same analysis
//! by the same code. For every bundled mechanism and every corpus dataset that runs, the CLI's
//! analyses (`linkage ic`, `linkage static`, `linkage simulate --out`: the API from the input,
//! as the CLI calls it) and a one-command `.acf` (`SIMULATE/INITIAL_CONDITIONS`,
//! `SIMULATE/STATIC`, `SIMULATE/DYNAMIC`) give the same numbers, value by value: the
//! simulation's CSV is the same text, and the `.msg` carries the CLI's whole text report
//! (every table: friction, curve contacts, sensors, controls).
//!
//! A command file that only changes an INTEGRATOR setting between two runs does not assemble
//! the model again; a DEACTIVATE does.
//!
//! The corpus is read by relative path; without it that part fails when `CI` is set and skips
//! with a notice elsewhere.

use linkage_api::simulate::{CsvTarget, SimulateArgs};
use linkage_api::statics::StaticArgs;
use linkage_run::{run_command_file, RunOptions, RunSummary};
use linkage_solve::coverage::Analysis;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// Wall-clock seconds an analysis of one road may take in this test before the dataset is
/// left out of the comparison (said in the output): a slow corpus model proves nothing more.
const BUDGET: f64 = 10.0;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .canonicalize()
        .expect("the repository")
}

fn corpus() -> Option<PathBuf> {
    let dir = root().join("../shared/corpus");
    if dir.is_dir() {
        return dir.canonicalize().ok();
    }
    assert!(
        std::env::var_os("CI").is_none(),
        "the corpus folder {} is missing",
        dir.display()
    );
    eprintln!("notice: {} is missing; corpus part skipped", dir.display());
    None
}

/// A fresh folder for one case's files.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("linkage_one_road_{}_{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp folder");
    dir
}

/// Runs `commands` as a command file on `model` in `dir`, stopped after [`BUDGET`] seconds;
/// the summary (or the stop), the `.msg` text and the `.csv` text.
fn run_acf(
    dir: &Path,
    model: &Path,
    commands: &str,
) -> (Result<RunSummary, String>, String, String, bool) {
    let acf = dir.join("case.acf");
    std::fs::write(
        &acf,
        format!("{}\ncase\n{commands}\nSTOP\n", model.display()),
    )
    .expect("write acf");
    let interrupt = Arc::new(AtomicBool::new(false));
    let flag = Arc::clone(&interrupt);
    let done = Arc::new(AtomicBool::new(false));
    let finished = Arc::clone(&done);
    let timer = std::thread::spawn(move || {
        let start = Instant::now();
        while !finished.load(Ordering::Relaxed) {
            if start.elapsed() > Duration::from_secs_f64(BUDGET) {
                flag.store(true, Ordering::Relaxed);
                return;
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    });
    let options = RunOptions {
        out_dir: Some(dir.to_path_buf()),
        model: None,
        interrupt: Some(Arc::clone(&interrupt)),
        deactivate: Vec::new(),
        allow_unstable: false,
        read: Default::default(),
        ..Default::default()
    };
    let result = run_command_file(&acf, &options).map_err(|s| s.error.to_string());
    done.store(true, Ordering::Relaxed);
    let _ = timer.join();
    let msg = std::fs::read_to_string(dir.join("case.msg")).unwrap_or_default();
    let csv = std::fs::read_to_string(dir.join("case.csv")).unwrap_or_default();
    (result, msg, csv, interrupt.load(Ordering::Relaxed))
}

/// A `Write` into shared memory (the CLI road's CSV).
#[derive(Clone, Default)]
struct Shared(Arc<Mutex<Vec<u8>>>);

impl Write for Shared {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.0.lock().expect("lock").extend_from_slice(buf);
        Ok(buf.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// What one dataset showed.
#[derive(Default)]
struct Tally {
    compared: usize,
    skipped: Vec<String>,
    failures: Vec<String>,
}

/// `cli` (the CLI's text report, or `None` when the CLI road refused the model) must be in the
/// message file `msg` of the same analysis run by a command file.
fn check_report(tally: &mut Tally, case: &str, cli: &str, msg: &str) {
    tally.compared += 1;
    if !msg.contains(cli.trim_end()) {
        tally.failures.push(format!(
            "{case}: the .msg lacks the CLI's report\n--- CLI ---\n{cli}\n--- .msg ---\n{msg}"
        ));
    }
}

/// Both roads on `model` (one dataset).
fn compare(model: &Path, tally: &mut Tally) {
    let name = model
        .file_stem()
        .unwrap_or_default()
        .to_string_lossy()
        .to_string();
    let dir = scratch(&name);
    // A command file writes the request file of every analysis: a model whose REQUESTs do not
    // build is refused by it, as by `linkage simulate --out`; `ic` and `static` without
    // outputs do not read them, so they are not compared there.
    let requests_build = linkage_api::load(model, &[], None)
        .is_ok_and(|l| linkage_solve::physics::requests::RequestSet::new(&l.model).is_ok());
    if !requests_build {
        tally
            .skipped
            .push(format!("{name} ic and static (its REQUESTs do not build)"));
    }
    // IC.
    let ic_loaded = linkage_api::load(model, &[], Some(Analysis::Ic)).ok();
    if let Some(loaded) = ic_loaded.filter(|_| requests_build) {
        let clock = Instant::now();
        if let Ok(run) = linkage_api::ic::ic(&loaded) {
            let cli = linkage_report::ic::to_text(&run.report);
            let (result, msg, _, stopped) = run_acf(&dir, model, "SIMULATE/INITIAL_CONDITIONS");
            if stopped || clock.elapsed().as_secs_f64() > BUDGET {
                tally.skipped.push(format!("{name} ic (over {BUDGET} s)"));
            } else {
                check_report(tally, &format!("{name} ic"), &cli, &msg);
                if run.failed != result.is_err() {
                    tally.failures.push(format!(
                        "{name} ic: the CLI {} but the command file {}",
                        if run.failed { "failed" } else { "passed" },
                        match &result {
                            Ok(_) => "passed".to_string(),
                            Err(e) => format!("stopped: {e}"),
                        }
                    ));
                }
            }
        }
    }
    // Static equilibrium.
    let static_loaded = linkage_api::load(model, &[], Some(Analysis::Static)).ok();
    if let Some(loaded) = static_loaded.filter(|_| requests_build) {
        let args = StaticArgs {
            time_limit: Some(BUDGET),
            ..StaticArgs::default()
        };
        let clock = Instant::now();
        if let Ok(run) = linkage_api::statics::statics(&loaded, &args, &|_, _| {}) {
            let slow = clock.elapsed().as_secs_f64() > 0.5 * BUDGET;
            let cli = linkage_report::statics::to_text(&run.report);
            let (result, msg, _, stopped) = run_acf(&dir, model, "SIMULATE/STATIC");
            if slow || stopped {
                tally
                    .skipped
                    .push(format!("{name} static (over {BUDGET} s)"));
            } else {
                check_report(tally, &format!("{name} static"), &cli, &msg);
                if run.ok != result.is_ok() {
                    tally.failures.push(format!(
                        "{name} static: the CLI ok = {} but the command file gave {result:?}",
                        run.ok
                    ));
                }
            }
        }
    }
    // Dynamics: the same CSV, and the summary in the .msg.
    if let Ok(loaded) = linkage_api::load(model, &[], Some(Analysis::Simulate)) {
        let times = linkage_api::output_times(0.05, Some(5), None).expect("times");
        let csv = Shared::default();
        let target = csv.clone();
        let clock = Instant::now();
        let report = linkage_api::simulate::simulate(
            &loaded,
            SimulateArgs {
                times: &times,
                start: linkage_solve::stages::dynamics::Start::InitialConditions,
                allow_unstable: false,
                time_limit: Some(BUDGET),
                csv: Some(CsvTarget {
                    name: "cli.csv".into(),
                    open: Box::new(move || Ok(Box::new(target) as Box<dyn Write>)),
                }),
                progress: &mut |_| {},
                interrupted: &|| false,
                observe: None,
            },
        );
        if let Ok(report) = report {
            let slow = clock.elapsed().as_secs_f64() > 0.5 * BUDGET;
            let cli = linkage_report::simulate::to_text(&report);
            let cli_csv = String::from_utf8(csv.0.lock().expect("lock").clone()).expect("utf8");
            let (result, msg, acf_csv, stopped) =
                run_acf(&dir, model, "SIMULATE/DYNAMIC, END = 0.05, STEPS = 5");
            if slow || stopped {
                tally
                    .skipped
                    .push(format!("{name} simulate (over {BUDGET} s)"));
            } else {
                check_report(tally, &format!("{name} simulate"), &cli, &msg);
                tally.compared += 1;
                if cli_csv != acf_csv {
                    tally.failures.push(format!(
                        "{name} simulate: the CSVs differ\n--- CLI ---\n{cli_csv}\n--- .acf \
                         ---\n{acf_csv}"
                    ));
                }
                if report.errors.is_empty() != result.is_ok() {
                    tally.failures.push(format!(
                        "{name} simulate: the CLI's errors {:?} but the command file gave \
                         {result:?}",
                        report.errors
                    ));
                }
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

fn datasets(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("folder")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "adm"))
        .collect();
    v.sort();
    v
}

fn report(tally: &Tally, what: &str) {
    eprintln!(
        "{what}: {} comparisons, {} left out: {:?}",
        tally.compared,
        tally.skipped.len(),
        tally.skipped
    );
    assert!(
        tally.failures.is_empty(),
        "{} difference(s) between the CLI and the command file:\n{}",
        tally.failures.len(),
        tally.failures.join("\n\n")
    );
}

#[test]
fn every_bundled_mechanism_gives_the_same_numbers_from_the_cli_and_a_command_file() {
    let mut tally = Tally::default();
    for dir in ["mechanisms", "examples"] {
        for model in datasets(&root().join(dir)) {
            compare(&model, &mut tally);
        }
    }
    report(&tally, "bundled mechanisms");
    assert!(tally.compared >= 40, "only {} comparisons", tally.compared);
}

#[test]
fn every_corpus_dataset_that_runs_gives_the_same_numbers_from_the_cli_and_a_command_file() {
    let Some(dir) = corpus() else { return };
    let mut tally = Tally::default();
    for model in datasets(&dir) {
        compare(&model, &mut tally);
    }
    report(&tally, "corpus");
    assert!(tally.compared >= 100, "only {} comparisons", tally.compared);
}

/// The four-bar driven by a motion, run twice with only the integrator's ERROR changed between
/// the runs: the second run continues on the first one's assembly (one assembly in all), and
/// ends where a run without the change would, within the integrator's error.
#[test]
fn an_integrator_change_between_two_runs_does_not_assemble_the_model_again() {
    let model = root().join("examples/fourbar.adm");
    let dir = scratch("integrator_change");
    let (changed, changed_msg, changed_csv, _) = run_acf(
        &dir,
        &model,
        "SIMULATE/DYNAMIC, END = 0.5, STEPS = 10\nINTEGRATOR/ERROR = 1E-5\n\
         SIMULATE/DYNAMIC, END = 1.0, STEPS = 10",
    );
    let changed = changed.expect("the run ends");
    assert_eq!(changed.assemblies, 1, "{changed:?}");
    assert_eq!(changed.outputs, 21);
    // The second run says it continued; the first started from the initial conditions.
    assert_eq!(
        changed_msg
            .matches("Continued from the state the last analysis left")
            .count(),
        1,
        "{changed_msg}"
    );
    assert!(changed_msg.contains("Started from the initial conditions"));
    // A change of the model (a redefinition) assembles it again.
    let (redefined, _, _, _) = run_acf(
        &dir,
        &model,
        "SIMULATE/DYNAMIC, END = 0.5, STEPS = 10\nEQUILIBRIUM/STABILITY = 1E-4\n\
         SIMULATE/DYNAMIC, END = 1.0, STEPS = 10\nIC/ERROR = 1E-9\n\
         SIMULATE/DYNAMIC, END = 1.5, STEPS = 10",
    );
    let redefined = redefined.expect("the run ends");
    assert_eq!(redefined.assemblies, 2, "{redefined:?}");
    // One run to 1.0 at ERROR 1e-5 throughout ends where the two runs do, within their error.
    let (_, _, straight_csv, _) = run_acf(
        &dir,
        &model,
        "INTEGRATOR/ERROR = 1E-5\nSIMULATE/DYNAMIC, END = 1.0, STEPS = 20",
    );
    let last = |csv: &str| -> Vec<f64> {
        let line = csv.lines().last().expect("a row");
        line.split(',')
            .map(|x| x.trim().parse().unwrap_or(f64::NAN))
            .collect()
    };
    let (a, b) = (last(&changed_csv), last(&straight_csv));
    assert_eq!(a.len(), b.len());
    assert_eq!(a[0], 1.0);
    // Part positions (length units: the four-bar is in millimetres) within 1e-3 mm.
    for k in 1..4 {
        assert!(
            (a[k] - b[k]).abs() < 1e-3,
            "column {k}: {} vs {}",
            a[k],
            b[k]
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
