//! Command files end to end: several analyses in a row on one model, against closed forms;
//! errors that name the command; files that stay whole when a run stops.

use linkage_run::{run_command_file, RunError, RunOptions};
use std::path::{Path, PathBuf};

/// A slider on a translational joint along ground x, held by a zero-length spring (k = 100
/// N/m) against gravity along −x (m = 2 kg, g = 9.81), and a rotor on a revolute joint about
/// ground z driven by MOTION/5 (its CM 0.5 m along its x).
const MODEL: &str = "slider and rotor\n\
UNITS/, FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
PART/1, GROUND\n\
MARKER/10, PART = 1\n\
MARKER/11, PART = 1, REULER = 90D, 90D, 0\n\
MARKER/12, PART = 1\n\
PART/2, MASS = 2, CM = 20, IP = 1, 1, 1, QG = -0.1, 0, 0\n\
MARKER/20, PART = 2\n\
MARKER/21, PART = 2, REULER = 90D, 90D, 0\n\
JOINT/1, TRANSLATIONAL, I = 21, J = 11\n\
SPRINGDAMPER/7, TRANSLATIONAL, I = 20, J = 10, K = 100, C = 0, LENGTH = 0\n\
PART/3, MASS = 1, CM = 31, IP = 0.1, 0.1, 0.1\n\
MARKER/30, PART = 3\n\
MARKER/31, PART = 3, QP = 0.5, 0, 0\n\
JOINT/2, REVOLUTE, I = 30, J = 12\n\
MOTION/5, JOINT = 2, ROTATION, FUNCTION = 0*TIME\n\
ACCGRAV/, IGRAV = -9.81\n\
END\n";

const G: f64 = 9.81;
const X_EQ: f64 = -2.0 * G / 100.0;

/// A fresh folder for one test.
fn folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("linkage-run-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp folder");
    dir
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).expect("writes");
    p
}

/// The CSV as (column names without their units, rows of numbers).
fn csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).expect("csv exists");
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .expect("header")
        .split(',')
        .map(|f| linkage_report::units::column_name(f).to_string())
        .collect();
    let rows = lines
        .map(|l| {
            l.split(',')
                .map(|x| x.parse::<f64>().expect("a number"))
                .collect::<Vec<f64>>()
        })
        .collect();
    (header, rows)
}

fn column(header: &[String], name: &str) -> usize {
    header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name} in {header:?}"))
}

#[test]
fn a_static_funnel_a_redefined_motion_and_a_deactivated_spring_follow_their_closed_forms() {
    let dir = folder("multi");
    write(&dir, "slider.adm", MODEL);
    let acf = write(
        &dir,
        "funnel.acf",
        "slider\nfunnel\n\
         ! loose first, then tight\n\
         EQUILIBRIUM/STABILITY = 1e-3, ERROR = 1e-2, IMBALANCE = 1e-2, MAXIT = 50\n\
         sim/stat, end = 0.2, steps = 2\n\
         equil/error = 1e-10, imbal = 1e-10\n\
         SIMULATE/STATIC\n\
         MOTION/5, FUNCTION = 2*TIME\n\
         INTEGRATOR/ERROR = 1e-7\n\
         SIMULATE/DYNAMIC, END = 1, STEPS = 8\n\
         DEACTIVATE/SPRINGDAMPER, ID = 7\n\
         SIMULATE/DYNAMIC, &\n   END = 1.5, STEPS = 5\n\
         STOP\n",
    );
    let summary = run_command_file(
        &acf,
        &RunOptions {
            out_dir: Some(dir.clone()),
            model: None,
            interrupt: None,
            deactivate: Vec::new(),
            allow_unstable: false,
            read: Default::default(),
            ..Default::default()
        },
    )
    .unwrap_or_else(|s| panic!("runs: {}", s.error));
    assert_eq!(summary.commands, 10);
    // 2 quasi-static outputs, 1 static, 8 + 5 dynamic.
    assert_eq!(summary.outputs, 16);
    let (header, rows) = csv(&dir.join("funnel.csv"));
    assert_eq!(rows.len(), 16);
    // The columns of `linkage simulate --out`, each with its unit.
    let raw = std::fs::read_to_string(dir.join("funnel.csv")).expect("csv exists");
    let first = raw.lines().next().unwrap_or_default();
    assert!(
        first.starts_with("time [") && first.contains(",PART_2.x ["),
        "{first}"
    );
    let (t, x) = (0, column(&header, "PART_2.x"));
    let (rx, ry) = (column(&header, "PART_3.x"), column(&header, "PART_3.y"));
    // Statics: the spring carries the weight, x = −m g / k, at 0.1, 0.2 and again at 0.2.
    for row in &rows[..3] {
        assert!((row[x] - X_EQ).abs() < 1e-9, "static x {}", row[x]);
    }
    assert_eq!(rows[2][t], 0.2);
    // Dynamics from the equilibrium at rest: the slider stays; the rotor turns by 2t.
    for row in &rows[3..11] {
        let time = row[t];
        assert!((row[x] - X_EQ).abs() < 1e-6, "t = {time}: x {}", row[x]);
        assert!(
            (row[rx] - 0.5 * (2.0 * time).cos()).abs() < 1e-9,
            "t = {time}"
        );
        assert!(
            (row[ry] - 0.5 * (2.0 * time).sin()).abs() < 1e-9,
            "t = {time}"
        );
    }
    assert!((rows[10][t] - 1.0).abs() < 1e-12);
    // Without the spring the slider falls from rest at t = 1: x = x_eq − g (t − 1)² / 2.
    for row in &rows[11..] {
        let dt = row[t] - 1.0;
        let want = X_EQ - 0.5 * G * dt * dt;
        assert!(
            (row[x] - want).abs() < 1e-5,
            "t = {}: x {} ≠ {want}",
            row[t],
            row[x]
        );
    }
    // The request file holds the same outputs; the message file tells what changed.
    let req = linkage_adm::reqfile::read_request_file(&dir.join("funnel.req")).expect("reads");
    assert_eq!(req.times.len(), 16);
    let msg = std::fs::read_to_string(dir.join("funnel.msg")).expect("msg");
    assert!(
        msg.contains(" command: DEACTIVATE/SPRINGDAMPER, ID = 7"),
        "{msg}"
    );
    assert!(
        msg.contains("The model changed: 1 → 1 degrees of freedom"),
        "{msg}"
    );
    assert!(msg.contains("Dynamics to t = 1.5"), "{msg}");
    assert!(msg.contains("every command was carried out"), "{msg}");
}

#[test]
fn a_command_that_cannot_apply_names_its_line_and_leaves_whole_files() {
    let dir = folder("stop");
    write(&dir, "slider.adm", MODEL);
    let acf = write(
        &dir,
        "stop.acf",
        "slider\nstop\nSIMULATE/STATIC, END = 0.1, STEPS = 2\nVARIABLE/99, FUNCTION = 1\n\
         SIMULATE/STATIC, END = 0.3, STEPS = 2\n",
    );
    let stopped = run_command_file(
        &acf,
        &RunOptions {
            out_dir: Some(dir.clone()),
            model: None,
            interrupt: None,
            deactivate: Vec::new(),
            allow_unstable: false,
            read: Default::default(),
            ..Default::default()
        },
    )
    .expect_err("VARIABLE/99 is not in the dataset");
    let text = stopped.error.to_string();
    assert!(text.contains("stop.acf:4:1"), "{text}");
    assert!(text.contains("the dataset has no VARIABLE/99"), "{text}");
    assert!(matches!(stopped.error, RunError::Refused { .. }));
    assert_eq!(stopped.error.exit_code(), 2);
    // What ran before is in the files, whole.
    let summary = stopped.summary.expect("files were written");
    assert_eq!(summary.outputs, 2);
    let (header, rows) = csv(&dir.join("stop.csv"));
    assert!(rows.iter().all(|r| r.len() == header.len()));
    assert_eq!(rows.len(), 2);
    let req = linkage_adm::reqfile::read_request_file(&dir.join("stop.req")).expect("reads");
    assert_eq!(req.times, vec![0.05, 0.1]);
    let msg = std::fs::read_to_string(dir.join("stop.msg")).expect("msg");
    assert!(msg.contains("ERROR"), "{msg}");
}

#[test]
fn unknown_commands_and_kinematics_with_freedom_are_refused_by_name() {
    let dir = folder("refuse");
    write(&dir, "slider.adm", MODEL);
    let options = RunOptions {
        out_dir: Some(dir.clone()),
        model: None,
        interrupt: None,
        deactivate: Vec::new(),
        allow_unstable: false,
        read: Default::default(),
        ..Default::default()
    };
    let acf = write(&dir, "unknown.acf", "slider\nunknown\nFROBNICATE/NOW\n");
    let stopped = run_command_file(&acf, &options).expect_err("unknown command");
    let text = stopped.error.to_string();
    assert!(text.contains("unknown.acf:3:"), "{text}");
    assert!(text.contains("FROBNICATE"), "{text}");
    let acf = write(
        &dir,
        "kin.acf",
        "slider\nkin\nSIMULATE/KINEMATIC, END = 1, STEPS = 2\n",
    );
    let stopped = run_command_file(&acf, &options).expect_err("the slider is free");
    let text = stopped.error.to_string();
    assert!(text.contains("kin.acf:3:1: SIMULATE"), "{text}");
    assert!(
        text.contains("needs a model without degrees of freedom; this one has 1"),
        "{text}"
    );
}

#[test]
fn statemat_writes_the_state_matrix_of_the_free_motion() {
    let dir = folder("statemat");
    write(&dir, "slider.adm", MODEL);
    let acf = write(
        &dir,
        "plant.acf",
        "slider\nplant\nSIMULATE/STATIC\nLINEAR/STATEMAT, FILE = plant, FORMAT = MATLAB\n\
         LINEAR/EIGENSOL\nSTOP\n",
    );
    let options = RunOptions {
        out_dir: Some(dir.clone()),
        model: None,
        interrupt: None,
        deactivate: Vec::new(),
        allow_unstable: false,
        read: Default::default(),
        ..Default::default()
    };
    run_command_file(&acf, &options).unwrap_or_else(|s| panic!("runs: {}", s.error));
    // One free coordinate (the slider; the rotor is driven): A = [0 1; −k/m 0], k/m = 50.
    let a: Vec<Vec<f64>> = std::fs::read_to_string(dir.join("planta"))
        .expect("A written")
        .lines()
        .map(|l| l.split_whitespace().map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(a.len(), 2);
    let want = [[0.0, 1.0], [-50.0, 0.0]];
    for i in 0..2 {
        for j in 0..2 {
            assert!((a[i][j] - want[i][j]).abs() < 1e-9, "A = {a:?}");
        }
    }
    // The basis moves the slider along x only (a unit of z moves it by basis[0] metres).
    let st = std::fs::read_to_string(dir.join("plantst")).expect("basis written");
    let basis: Vec<f64> = st.lines().map(|l| l.trim().parse().unwrap()).collect();
    assert_eq!(basis.len(), 12);
    assert!(basis[0].abs() > 0.1, "{basis:?}");
    assert!(
        basis[1..].iter().all(|x| x.abs() < 1e-9 * basis[0].abs()),
        "{basis:?}"
    );
    assert_eq!(std::fs::read_to_string(dir.join("plantb")).unwrap(), "");
    // The eigen solution about the same point: √50 rad/s.
    let msg = std::fs::read_to_string(dir.join("plant.msg")).expect("msg");
    assert!(msg.contains("State matrices at time 0: 2 states"), "{msg}");
    let hz = 50f64.sqrt() / std::f64::consts::TAU;
    assert!(
        msg.contains(&format!("{:.5E}", hz).replace("E", "E+0")),
        "{hz} in {msg}"
    );
}

#[test]
fn statemat_with_plant_inputs_and_outputs_has_the_spring_s_static_gain() {
    let dir = folder("plant");
    // A force VARVAL(1) on the slider along the line from ground's origin (pushing it away,
    // towards −x) as the input; the slider's x as the output.
    let model = MODEL.replace(
        "ACCGRAV/",
        "VARIABLE/1, FUNCTION = 0\nVARIABLE/2, FUNCTION = DX(20, 10)\n\
         SFORCE/8, TRANSLATIONAL, I = 20, J = 10, FUNCTION = VARVAL(1)\n\
         PINPUT/1, VARIABLES = 1\nPOUTPUT/2, VARIABLES = 2\nACCGRAV/",
    );
    write(&dir, "slider.adm", &model);
    let acf = write(
        &dir,
        "plant.acf",
        "slider\nplant\nSIMULATE/STATIC\n\
         LINEAR/STATEMAT, PINPUT = 1, POUTPUT = 2, FILE = p, FORMAT = MATLAB\n",
    );
    let options = RunOptions {
        out_dir: Some(dir.clone()),
        model: None,
        interrupt: None,
        deactivate: Vec::new(),
        allow_unstable: false,
        read: Default::default(),
        ..Default::default()
    };
    run_command_file(&acf, &options).unwrap_or_else(|s| panic!("runs: {}", s.error));
    let read = |suffix: &str| -> Vec<Vec<f64>> {
        std::fs::read_to_string(dir.join(format!("p{suffix}")))
            .expect("written")
            .lines()
            .map(|l| l.split_whitespace().map(|x| x.parse().unwrap()).collect())
            .collect()
    };
    let (a, b, c, d) = (read("a"), read("b"), read("c"), read("d"));
    assert_eq!(
        (b.len(), b[0].len(), c.len(), c[0].len(), d.len()),
        (2, 1, 1, 2, 1)
    );
    assert!((a[1][0] + 50.0).abs() < 1e-9, "{a:?}");
    assert_eq!(b[0][0], 0.0);
    // The static gain −C A⁻¹ B + D is Δx/u = −1/k (the force pushes towards −x), whatever
    // the scale of the coordinate: with A = [0 1; −50 0], −C A⁻¹ B = c₁ b₂ / 50.
    let gain = c[0][0] * b[1][0] / 50.0 + d[0][0];
    assert!(
        (gain + 1.0 / 100.0).abs() < 1e-7,
        "gain {gain}: B {b:?} C {c:?}"
    );
    // The output does not depend on the velocity or directly on the input.
    assert!(
        c[0][1].abs() < 1e-9 && d[0][0].abs() < 1e-12,
        "C {c:?} D {d:?}"
    );
    // A plant naming a statement the dataset does not have is refused by name.
    let acf = write(
        &dir,
        "bad.acf",
        "slider\nbad\nLINEAR/STATEMAT, PINPUT = 9, FILE = q\n",
    );
    let stopped = run_command_file(&acf, &options).expect_err("no PINPUT/9");
    let text = stopped.error.to_string();
    assert!(
        text.contains("bad.acf:3:1: LINEAR: the dataset has no PINPUT/9"),
        "{text}"
    );
}

#[test]
fn a_nested_command_file_continues_the_same_run() {
    let dir = folder("nested");
    write(&dir, "slider.adm", MODEL);
    write(
        &dir,
        "second.acf",
        "\nSIMULATE/STATIC, END = 0.4, STEPS = 2\n",
    );
    let acf = write(
        &dir,
        "first.acf",
        "slider\nnested\nSIMULATE/STATIC, END = 0.2, STEPS = 2\nFILE/COMMAND = second\nSTOP\n",
    );
    let options = RunOptions {
        out_dir: Some(dir.clone()),
        model: None,
        interrupt: None,
        deactivate: Vec::new(),
        allow_unstable: false,
        read: Default::default(),
        ..Default::default()
    };
    let summary = run_command_file(&acf, &options).unwrap_or_else(|s| panic!("{}", s.error));
    assert_eq!(summary.outputs, 4);
    let req = linkage_adm::reqfile::read_request_file(&dir.join("nested.req")).expect("reads");
    assert_eq!(req.times, vec![0.1, 0.2, 0.3, 0.4]);
    // A command file that reads itself is stopped, not looped.
    let acf = write(&dir, "self.acf", "slider\nself\nFILE/COMMAND = self\n");
    let stopped = run_command_file(&acf, &options).expect_err("nesting bound");
    assert!(
        stopped.error.to_string().contains("nested more than"),
        "{}",
        stopped.error
    );
}

#[test]
fn file_model_switches_to_another_dataset_with_its_own_files() {
    let dir = folder("two");
    write(&dir, "slider.adm", MODEL);
    // The same slider with a stiffer spring: x = −m g / 400.
    write(&dir, "stiff.adm", &MODEL.replace("K = 100", "K = 400"));
    let acf = write(
        &dir,
        "two.acf",
        "slider\nsoft\nSIMULATE/STATIC\nFILE/MODEL = stiff, OUTPUT_PREFIX = hard\n\
         SIMULATE/STATIC\nSTOP\n",
    );
    let options = RunOptions {
        out_dir: Some(dir.clone()),
        model: None,
        interrupt: None,
        deactivate: Vec::new(),
        allow_unstable: false,
        read: Default::default(),
        ..Default::default()
    };
    run_command_file(&acf, &options).unwrap_or_else(|s| panic!("{}", s.error));
    for (name, k) in [("soft", 100.0), ("hard", 400.0)] {
        let (header, rows) = csv(&dir.join(format!("{name}.csv")));
        assert_eq!(rows.len(), 1, "{name}");
        let x = rows[0][column(&header, "PART_2.x")];
        assert!((x + 2.0 * G / k).abs() < 1e-9, "{name}: x = {x}");
    }
    let msg = std::fs::read_to_string(dir.join("soft.msg")).expect("one message file");
    assert!(msg.contains("FILE/MODEL = stiff"), "{msg}");
}

#[test]
fn an_interrupted_run_stops_after_its_step_and_leaves_whole_files() {
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::Arc;
    let dir = folder("interrupt");
    write(&dir, "slider.adm", MODEL);
    // Far more steps than the test waits for (HMAX = 1e-6 over 1000 s).
    let acf = write(
        &dir,
        "long.acf",
        "slider\nlong\nINTEGRATOR/ERROR = 1e-4, HMAX = 1e-6\n\
         SIMULATE/DYNAMIC, END = 1000, DTOUT = 1e-3\n",
    );
    let flag = Arc::new(AtomicBool::new(false));
    let options = RunOptions {
        out_dir: Some(dir.clone()),
        model: None,
        interrupt: Some(Arc::clone(&flag)),
        deactivate: Vec::new(),
        allow_unstable: false,
        read: Default::default(),
        ..Default::default()
    };
    // Interrupt once a few outputs are on disk (as Ctrl-C would, at any moment).
    let csv_path = dir.join("long.csv");
    let watcher = std::thread::spawn(move || {
        for _ in 0..6000 {
            let rows = std::fs::read_to_string(&csv_path).map_or(0, |t| t.lines().count());
            if rows > 5 {
                break;
            }
            std::thread::sleep(std::time::Duration::from_millis(10));
        }
        flag.store(true, Ordering::Relaxed);
    });
    let stopped = run_command_file(&acf, &options).expect_err("interrupted");
    watcher.join().expect("watcher");
    let linkage_run::RunError::Interrupted { time } = stopped.error else {
        panic!("{}", stopped.error);
    };
    assert!(time > 0.0 && time < 1000.0, "{time}");
    assert_eq!(linkage_run::RunError::Interrupted { time }.exit_code(), 1);
    // Every output up to the interruption, whole, in both files.
    let (header, rows) = csv(&dir.join("long.csv"));
    assert!(rows.iter().all(|r| r.len() == header.len()));
    // The run stops after the step it is in: the last output is the one before that time.
    let last = rows.last().map_or(f64::NAN, |r| r[0]);
    assert!(
        last <= time && time - last < 1e-3 + 1e-9,
        "last output {last}, stopped at {time}"
    );
    let req = linkage_adm::reqfile::read_request_file(&dir.join("long.req")).expect("reads");
    assert_eq!(req.times.len(), rows.len());
    let msg = std::fs::read_to_string(dir.join("long.msg")).expect("msg");
    assert!(
        msg.contains(&format!("interrupted at time {time}")),
        "{msg}"
    );
}

/// A row of a step table: time, step size, corrector iterations, cumulative steps, order.
type StepRow = (f64, f64, usize, usize, usize);

/// The rows of the step tables of a message file, one table per dynamic SIMULATE.
fn step_tables(msg: &str) -> Vec<Vec<StepRow>> {
    let mut tables = Vec::new();
    let mut lines = msg.lines();
    while let Some(line) = lines.next() {
        if !line.contains("Simulation      Step") {
            continue;
        }
        let rows = lines
            .by_ref()
            .skip(2)
            .map_while(|l| {
                let f: Vec<&str> = l.split_whitespace().collect();
                let number = |k: usize| f.get(k).and_then(|x| x.parse::<f64>().ok());
                let count = |k: usize| f.get(k).and_then(|x| x.parse::<usize>().ok());
                Some((number(0)?, number(1)?, count(2)?, count(3)?, count(4)?))
            })
            .collect();
        tables.push(rows);
    }
    tables
}

#[test]
fn the_message_file_has_adams_step_table_at_each_tenth_of_a_dynamic_run() {
    let dir = folder("steps");
    write(&dir, "slider.adm", MODEL);
    // The slider starts 0.1 m from its rest length and oscillates (ω = √(k/m) ≈ 7.1 rad/s);
    // HMAX = 0.01 caps the steps: at least 100 steps per second.
    let hmax = 0.01;
    let acf = write(
        &dir,
        "steps.acf",
        "slider\nsteps\n\
         INTEGRATOR/GSTIFF, ERROR = 1e-6, HMAX = 0.01\n\
         SIMULATE/DYNAMIC, END = 1, STEPS = 500\n\
         SIMULATE/DYNAMIC, END = 2, STEPS = 4\n\
         STOP\n",
    );
    let options = RunOptions {
        out_dir: Some(dir.clone()),
        ..Default::default()
    };
    run_command_file(&acf, &options).unwrap_or_else(|s| panic!("runs: {}", s.error));
    let msg = std::fs::read_to_string(dir.join("steps.msg")).expect("message file");
    let tables = step_tables(&msg);
    assert_eq!(tables.len(), 2, "{msg}");
    // 500 outputs: a row at the start and at each tenth of the span, not one per output.
    let first = &tables[0];
    let times: Vec<f64> = first.iter().map(|r| r.0).collect();
    assert_eq!(times.len(), 11, "{msg}");
    for (k, t) in times.iter().enumerate() {
        assert!((t - 0.1 * k as f64).abs() < 1e-9, "row {k} at {t}: {msg}");
    }
    // Before the first step: no step yet.
    assert_eq!(first[0].1, 0.0);
    assert_eq!(first[0].3, 0);
    for w in first.windows(2) {
        // Cumulative counts never decrease; corrector iterations at least one per step.
        assert!(w[1].3 > w[0].3 && w[1].2 >= w[0].2, "{msg}");
    }
    for &(t, h, iterations, steps, order) in &first[1..] {
        // Step sizes within HMAX (to the 6 digits printed), BDF orders 1…6.
        assert!(h > 0.0 && h <= hmax * (1.0 + 1e-5), "t = {t}: step {h}");
        assert!((1..=6).contains(&order), "t = {t}: order {order}");
        assert!(iterations >= steps, "t = {t}: {iterations} < {steps}");
        // At least one step per HMAX of the time covered.
        assert!(steps as f64 >= t / hmax - 1e-6, "t = {t}: {steps} steps");
    }
    // The second SIMULATE continues at t = 1 with its own counts; its 4 outputs (every 0.25,
    // coarser than a tenth) each get a row.
    let second: Vec<f64> = tables[1].iter().map(|r| r.0).collect();
    assert_eq!(second, vec![1.25, 1.5, 1.75, 2.0], "{msg}");
    assert!(
        tables[1][3].3 >= 100 && tables[1][3].3 < first[10].3 + 50,
        "{msg}"
    );
}
