//! SENSOR end to end (ADM-ELEMENTS §5): a HALT ends a fall at the closed-form time √(2h/g)
//! within the sensor's ERROR, with the outputs up to it and a report line naming the sensor;
//! PRINT writes an output at the event; RETURN in a command file goes on with the next
//! command, HALT ends the file.

mod common;
use common::{json, run};
use std::path::{Path, PathBuf};

const G: f64 = 9.81;

/// A point mass dropped from height 5 (DZ(40, 1) = 5 − ½ g t²), and `sensor`.
fn fall(tag: &str, sensor: &str) -> PathBuf {
    let text = format!(
        "falling point mass with a sensor\n\
         UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
         PART/1, GROUND\nMARKER/1, PART = 1\n\
         POINT_MASS/4, MASS = 2, QG = 0, 0, 5\nMARKER/40, POINT_MASS = 4\n\
         ACCGRAV/KGRAV = -9.81\nINTEGRATOR/GSTIFF, ERROR = 1E-7\n{sensor}\nEND\n"
    );
    let dir = std::env::temp_dir().join(format!("linkage-sensor-{}-{tag}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("fall.adm");
    std::fs::write(&f, text).unwrap();
    f
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// The `time` and `POINT_MASS_4.z` columns of a `simulate --out` CSV.
fn times_and_heights(csv: &Path) -> Vec<(f64, f64)> {
    let text = std::fs::read_to_string(csv).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let z = header
        .iter()
        .position(|h| h.starts_with("POINT_MASS_4.z "))
        .unwrap();
    lines
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            (v[0], v[z])
        })
        .collect()
}

#[test]
fn halt_ends_a_fall_at_root_two_h_over_g() {
    // DZ reaches 0 at t = √(2·5/g); the event is located to |DZ| ≤ ERROR = 1e-6, i.e. to
    // ERROR / |v| ≈ 1e-7 s, and the run is complete (exit 0), its last output the event.
    let f = fall(
        "halt",
        "SENSOR/1, VALUE = 0, LE, ERROR = 1E-6, HALT, FUNCTION = DZ(40, 1)",
    );
    let t_hit = (2.0 * 5.0 / G).sqrt();
    let csv = f.with_extension("csv");
    let (code, v) = json(&[
        "simulate",
        s(&f),
        "--end",
        "2",
        "--steps",
        "20",
        "--format",
        "json",
        "--out",
        s(&csv),
    ]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(v["completed"], true);
    assert_eq!(v["ended_by_sensor"], "SENSOR_1 (HALT)");
    let t = v["end_time"].as_f64().unwrap();
    assert!((t - t_hit).abs() < 1e-6, "{t} vs {t_hit}");
    let e = &v["sensors"][0];
    assert_eq!(e["element"], "SENSOR/1");
    assert!(e["function"].as_f64().unwrap().abs() <= 1e-6, "{e}");
    assert_eq!(e["actions"], serde_json::json!(["HALT"]));
    // The outputs up to the event: 0, 0.1, …, 1.0, then the event.
    let rows = times_and_heights(&csv);
    assert_eq!(rows.len(), 12, "{rows:?}");
    let (t_last, z_last) = rows[11];
    // The CSV keeps 12 significant digits.
    assert!((t_last - t).abs() < 1e-11, "{t_last} vs {t}");
    assert!(z_last.abs() <= 1e-6, "{z_last}");
    for &(t, z) in &rows[..11] {
        assert!((z - (5.0 - 0.5 * G * t * t)).abs() < 1e-6, "{t} {z}");
    }
    let (code, out, _) = run(&["simulate", s(&f), "--end", "2", "--steps", "20"]);
    assert_eq!(code, 0);
    assert!(
        out.contains("Sensor SENSOR_1 (SENSOR/1) fired at time 1.0096375"),
        "{out}"
    );
    assert!(
        out.contains("The run was ended at time 1.0096375") && out.contains("by SENSOR_1 (HALT)"),
        "{out}"
    );
}

#[test]
fn print_writes_an_output_at_the_event_and_the_run_goes_on() {
    // EQ at DZ = 2.5: t = √(2·2.5/g) = 0.7139; STEPSIZE sets the next trial step.
    let f = fall(
        "print",
        "SENSOR/2, VALUE = 2.5, ERROR = 1E-5, PRINT, STEPSIZE = 1E-3, YYDUMP, \
         FUNCTION = DZ(40, 1)",
    );
    let t_event = (2.0 * 2.5 / G).sqrt();
    let csv = f.with_extension("csv");
    let (code, v) = json(&[
        "simulate",
        s(&f),
        "--end",
        "1",
        "--steps",
        "4",
        "--format",
        "json",
        "--out",
        s(&csv),
    ]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(v["end_time"], 1.0);
    assert!(v["ended_by_sensor"].is_null());
    let e = &v["sensors"][0];
    assert_eq!(
        e["actions"],
        serde_json::json!(["PRINT", "YYDUMP", "STEPSIZE"])
    );
    let t = e["time"].as_f64().unwrap();
    // |DZ − 2.5| ≤ 1e-5 at speed g·t ≈ 7 m/s: within 1.5e-6 s.
    assert!((t - t_event).abs() < 2e-6, "{t} vs {t_event}");
    let dumped = e["dump"][0]["position"][2].as_f64().unwrap();
    assert!((dumped - 2.5).abs() <= 1e-5, "{e}");
    let rows = times_and_heights(&csv);
    let times: Vec<f64> = rows.iter().map(|r| r.0).collect();
    assert_eq!(times.len(), 6, "{times:?}");
    assert_eq!(&times[..3], &[0.0, 0.25, 0.5]);
    assert!((times[3] - t).abs() < 1e-11, "{times:?} vs {t}");
    assert_eq!(&times[4..], &[0.75, 1.0]);
    // The run after the event continues the same motion.
    let (t_end, z_end) = rows[5];
    assert!(
        (z_end - (5.0 - 0.5 * G * t_end * t_end)).abs() < 1e-6,
        "{z_end}"
    );
}

#[test]
fn return_goes_on_with_the_command_file_and_halt_ends_it() {
    for (action, commands, outputs) in [("RETURN", 3, 17), ("HALT", 1, 12)] {
        let f = fall(
            &format!("acf-{action}"),
            &format!("SENSOR/1, VALUE = 0, LE, ERROR = 1E-6, {action}, FUNCTION = DZ(40, 1)"),
        );
        let dir = f.parent().unwrap();
        let acf = dir.join("c.acf");
        std::fs::write(
            &acf,
            "fall\nout\nsim/dyn, end = 2, steps = 20\nsim/dyn, end = 3, steps = 5\nstop\n",
        )
        .unwrap();
        let (code, out, err) = run(&["run", s(&acf), "--out-dir", s(&dir.join("o"))]);
        assert_eq!(code, 0, "{out}\n{err}");
        assert!(
            out.contains(&format!(
                "{commands} command(s) carried out, {outputs} output(s)"
            )),
            "{action}: {out}"
        );
        let msg = std::fs::read_to_string(dir.join("o/out.msg")).unwrap();
        assert!(
            msg.contains(&format!(
                "SENSOR_1 ({action}) ended the simulation at time 1.0096375"
            )),
            "{msg}"
        );
        let halted = out.contains("ended by the HALT of SENSOR_1 at time 1.0096375");
        assert_eq!(halted, action == "HALT", "{out}");
        let last = *times(&dir.join("o/out.csv")).last().unwrap();
        let end = if action == "HALT" {
            (10.0 / G).sqrt()
        } else {
            3.0
        };
        assert!((last - end).abs() < 1e-6, "{action}: last output {last}");
    }
}

/// Runs `acf` (beside `f`, naming it) with `linkage run`: exit code, stdout, the message
/// file and the CSV's times.
fn run_acf(f: &Path, acf: &str) -> (i32, String, String, Vec<f64>) {
    let dir = f.parent().unwrap();
    let path = dir.join("c.acf");
    std::fs::write(&path, acf).unwrap();
    let (code, out, err) = run(&["run", s(&path), "--out-dir", s(&dir.join("o"))]);
    let msg = std::fs::read_to_string(dir.join("o/out.msg")).unwrap_or_else(|_| err.clone());
    let csv = times(&dir.join("o/out.csv"));
    (code, out, msg, csv)
}

#[test]
fn halt_of_a_quasi_static_series_ends_the_command_file() {
    // Two quasi-static series; the block's x = 1 + 0.1·t reaches 1.25 at t = 2.5 in the
    // first, whose HALT ends the file: exit 0 (a complete run), one command carried out, the
    // outputs 0.4, …, 2.4 and the event (7), none of the second series (to 6).
    let f = pushed_block(
        "acf-halt",
        "SENSOR/1, VALUE = 1.25, GE, ERROR = 1E-8, HALT, FUNCTION = DX(20, 1)",
    );
    let (code, out, msg, csv) = run_acf(
        &f,
        "block\nout\nsim/static, end = 4, steps = 10\nsim/static, end = 6, steps = 5\nstop\n",
    );
    assert_eq!(code, 0, "{out}\n{msg}");
    assert!(
        out.contains("1 command(s) carried out, 7 output(s)"),
        "{out}"
    );
    assert!(
        out.contains("ended by the HALT of SENSOR_1 at time 2.5"),
        "{out}"
    );
    assert_eq!(csv.len(), 7, "{csv:?}");
    assert!((csv[6] - 2.5).abs() < 1e-7, "{csv:?}");
    assert!(
        msg.contains("SENSOR_1 (HALT) ended the quasi-static series at time 2.5")
            && msg.contains("the command file ends here"),
        "{msg}"
    );
    assert!(
        msg.contains("Finished: ended by the HALT of SENSOR_1 at time 2.5")
            && !msg.contains("every command was carried out"),
        "{msg}"
    );
    // The second SIMULATE is never echoed: it was not run.
    assert!(!msg.contains("end = 6"), "{msg}");
}

#[test]
fn halt_of_a_kinematic_run_ends_the_command_file() {
    // The crank reaches 1 rad at t = √2 in the first kinematic run: the initial conditions,
    // 0.25, …, 1.25 and the event (7 outputs), and no output of the second run (to 4).
    let f = crank(
        "acf-halt",
        "SENSOR/1, VALUE = 1, GE, ERROR = 1E-7, HALT, FUNCTION = AZ(21, 1)",
    );
    let (code, out, msg, csv) = run_acf(
        &f,
        "crank\nout\nsim/kin, end = 3, steps = 12\nsim/kin, end = 4, steps = 4\nstop\n",
    );
    assert_eq!(code, 0, "{out}\n{msg}");
    assert!(
        out.contains("1 command(s) carried out, 7 output(s)"),
        "{out}"
    );
    assert_eq!(csv.len(), 7, "{csv:?}");
    assert!((csv[6] - 2f64.sqrt()).abs() < 1e-7, "{csv:?}");
    assert!(
        msg.contains("SENSOR_1 (HALT) ended the simulation at time 1.41421")
            && msg.contains("Finished: ended by the HALT of SENSOR_1"),
        "{msg}"
    );
}

#[test]
fn sensor_dt_sets_the_dynamic_output_interval_from_the_event_on() {
    // The fall reaches DZ = 2.5 at t* = √(2·2.5/g) = 0.713928 (inside the step to 0.9); from
    // then on outputs every 0.1: t* + 0.1, …, t* + 0.4 = 1.113928, then the end, 1.2. The
    // event itself is no output (no PRINT). Event located to |DZ − 2.5| ≤ 1e-6 at 7 m/s:
    // 1.5e-7 s.
    let f = fall(
        "dt",
        "SENSOR/1, VALUE = 2.5, LE, ERROR = 1E-6, DT = 0.1, FUNCTION = DZ(40, 1)",
    );
    let csv = f.with_extension("csv");
    let (code, v) = json(&[
        "simulate",
        s(&f),
        "--end",
        "1.2",
        "--steps",
        "4",
        "--format",
        "json",
        "--out",
        s(&csv),
    ]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(v["end_time"], 1.2);
    assert_eq!(v["sensors"][0]["actions"], serde_json::json!(["DT"]));
    let t_star = (2.0 * 2.5 / G).sqrt();
    let event = v["sensors"][0]["time"].as_f64().unwrap();
    assert!((event - t_star).abs() < 2e-7, "{event} vs {t_star}");
    let rows = times_and_heights(&csv);
    let times: Vec<f64> = rows.iter().map(|r| r.0).collect();
    assert_eq!(times.len(), 3 + 4 + 1, "{times:?}");
    assert_eq!(&times[..3], &[0.0, 0.3, 0.6]);
    for (k, t) in times[3..7].iter().enumerate() {
        let expected = t_star + 0.1 * (k + 1) as f64;
        assert!((t - expected).abs() < 2e-7, "{times:?}");
    }
    assert_eq!(times[7], 1.2);
    // The motion goes on unchanged through the new outputs.
    for &(t, z) in &rows {
        assert!((z - (5.0 - 0.5 * G * t * t)).abs() < 1e-6, "{t} {z}");
    }
}

#[test]
fn sensor_dt_at_an_output_time_keeps_that_output_and_spaces_the_rest() {
    // TIME ≥ 0.5 fires at the end of the step that lands on the output 0.5: that output is
    // written, then every 0.2 up to 1.5: 0.7, 0.9, 1.1, 1.3, 1.5.
    let f = fall(
        "dt-at-output",
        "SENSOR/1, VALUE = 0.5, GE, ERROR = 1E-9, DT = 0.2, FUNCTION = TIME",
    );
    let csv = f.with_extension("csv");
    let (code, v) = json(&[
        "simulate",
        s(&f),
        "--end",
        "1.5",
        "--steps",
        "6",
        "--format",
        "json",
        "--out",
        s(&csv),
    ]);
    assert_eq!(code, 0, "{v}");
    let got: Vec<f64> = times_and_heights(&csv).iter().map(|r| r.0).collect();
    let expected = [0.0, 0.25, 0.5, 0.7, 0.9, 1.1, 1.3, 1.5];
    assert_eq!(got.len(), expected.len(), "{got:?}");
    for (t, e) in got.iter().zip(expected) {
        assert!((t - e).abs() < 1e-9, "{got:?}");
    }
}

#[test]
fn senval_switches_a_force_on_when_its_sensor_fires() {
    // A 2 kg point mass at rest, no gravity; SENSOR/1 fires at t = 0.5 (TIME ≥ 0.5, to
    // ERROR = 1e-6) and stores EVALUATE = 4·TIME = 2. VFORCE FX = SENVAL(1) (0 before the
    // firing) and FY = VARVAL(1) with VARIABLE/1 = −SENVAL(1)/2: from t = 0.5 on the mass
    // accelerates at (1, −0.5) m/s², so at t = 1.5: x = ½·1·1² = 0.5, y = −0.25.
    let text = "senval\n\
         UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
         PART/1, GROUND\nMARKER/1, PART = 1\nMARKER/2, PART = 1, FLOATING\n\
         POINT_MASS/4, MASS = 2, QG = 0, 0, 0\nMARKER/40, POINT_MASS = 4\n\
         INTEGRATOR/GSTIFF, ERROR = 1E-7\n\
         SENSOR/1, VALUE = 0.5, GE, ERROR = 1E-6, FUNCTION = TIME\\, EVALUATE = 4*TIME\n\
         VARIABLE/1, FUNCTION = -SENVAL(1)/2\n\
         VFORCE/1, I = 40, JFLOAT = 2, RM = 1, FX = SENVAL(1)\\ FY = VARVAL(1)\\ FZ = 0\nEND\n";
    let dir = std::env::temp_dir().join(format!("linkage-senval-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("senval.adm");
    std::fs::write(&f, text).unwrap();
    let csv = dir.join("senval.csv");
    let (code, v) = json(&[
        "simulate",
        s(&f),
        "--end",
        "1.5",
        "--steps",
        "6",
        "--format",
        "json",
        "--out",
        s(&csv),
    ]);
    assert_eq!(code, 0, "{v}");
    let e = &v["sensors"][0];
    assert!((e["time"].as_f64().unwrap() - 0.5).abs() <= 1e-6, "{e}");
    assert!((e["stored"].as_f64().unwrap() - 2.0).abs() <= 4e-6, "{e}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| h.starts_with(name)).unwrap();
    let (x, y) = (col("POINT_MASS_4.x "), col("POINT_MASS_4.y "));
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 7, "{rows:?}");
    for r in &rows {
        let dt = (r[0] - 0.5).max(0.0);
        // Event time within 1e-6 and the stored value within 4e-6: 1e-5 on x.
        assert!(
            (r[x] - 0.5 * dt * dt).abs() < 1e-5,
            "t {}: x {}",
            r[0],
            r[x]
        );
        assert!(
            (r[y] + 0.25 * dt * dt).abs() < 1e-5,
            "t {}: y {}",
            r[0],
            r[y]
        );
    }
    assert!(
        (rows[6][x] - 0.5).abs() < 1e-5 && rows[2][x] == 0.0,
        "{rows:?}"
    );
}

/// A crank on a revolute joint at the ground origin, turned by the motion `½·t²` (zero
/// degrees of freedom: a kinematic run), and `sensor`.
fn crank(tag: &str, sensor: &str) -> PathBuf {
    let text = format!(
        "motion-driven crank with a sensor\n\
         UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
         PART/1, GROUND\nMARKER/1, PART = 1\n\
         PART/2, MASS = 1, CM = 20, IP = 1, 1, 1, QG = 0.5, 0, 0\nMARKER/20, PART = 2\n\
         MARKER/21, PART = 2, QP = -0.5, 0, 0\nJOINT/1, REVOLUTE, I = 21, J = 1\n\
         MOTION/1, JOINT = 1, ROTATION, FUNCTION = 0.5*TIME**2\n{sensor}\nEND\n"
    );
    let dir = std::env::temp_dir().join(format!("linkage-crank-{}-{tag}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("crank.adm");
    std::fs::write(&f, text).unwrap();
    f
}

/// The `time` column of a CSV.
fn times(csv: &Path) -> Vec<f64> {
    std::fs::read_to_string(csv)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap().parse().unwrap())
        .collect()
}

#[test]
fn halt_ends_a_kinematic_run_when_the_crank_reaches_its_angle() {
    // AZ = ½·t² reaches 1 rad at t = √2; located to |AZ − 1| ≤ 1e-7, i.e. to 1e-7/√2 s.
    let f = crank(
        "halt",
        "SENSOR/1, VALUE = 1, GE, ERROR = 1E-7, HALT, FUNCTION = AZ(21, 1)",
    );
    let csv = f.with_extension("csv");
    let (code, v) = json(&[
        "simulate",
        s(&f),
        "--end",
        "3",
        "--steps",
        "12",
        "--format",
        "json",
        "--out",
        s(&csv),
    ]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(v["ended_by_sensor"], "SENSOR_1 (HALT)");
    let t = v["end_time"].as_f64().unwrap();
    let t_hit = 2f64.sqrt();
    assert!((t - t_hit).abs() < 1e-7, "{t} vs {t_hit}");
    let e = &v["sensors"][0];
    assert!((e["function"].as_f64().unwrap() - 1.0).abs() <= 1e-7, "{e}");
    // Outputs 0, 0.25, …, 1.25, then the event.
    let got = times(&csv);
    assert_eq!(got.len(), 7, "{got:?}");
    assert_eq!(got[5], 1.25);
    assert!((got[6] - t).abs() < 1e-11, "{got:?}");
    let w = v["warnings"].to_string();
    assert!(!w.contains("not evaluated"), "{w}");
}

#[test]
fn sensor_dt_sets_the_output_interval_from_the_event_on() {
    // The crank reaches 1 rad at t* = √2 ≈ 1.41421; from then on outputs every 0.4 up to
    // the end: t* + 0.4, t* + 0.8, t* + 1.2 (2.61421), then the end, 3.
    let f = crank(
        "dt",
        "SENSOR/1, VALUE = 1, GE, ERROR = 1E-7, DT = 0.4, FUNCTION = AZ(21, 1)",
    );
    let csv = f.with_extension("csv");
    let (code, v) = json(&[
        "simulate",
        s(&f),
        "--end",
        "3",
        "--steps",
        "12",
        "--format",
        "json",
        "--out",
        s(&csv),
    ]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(v["end_time"], 3.0);
    assert_eq!(v["sensors"][0]["actions"], serde_json::json!(["DT"]));
    let got = times(&csv);
    let t_star = 2f64.sqrt();
    assert_eq!(got.len(), 6 + 4, "{got:?}");
    assert_eq!(&got[..6], &[0.0, 0.25, 0.5, 0.75, 1.0, 1.25]);
    for (k, t) in got[6..9].iter().enumerate() {
        let expected = t_star + 0.4 * (k + 1) as f64;
        assert!((t - expected).abs() < 1e-6, "{got:?}");
    }
    assert_eq!(got[9], 3.0);
}

/// A 1 kg block on a translational joint along x, held by a spring K = 100 N/m of free
/// length 1 to the origin and pushed by 10·TIME along x (RM = marker 1, whose z is ground x): in equilibrium x(t) = 1 + 0.1·t. And
/// `sensor`.
fn pushed_block(tag: &str, sensor: &str) -> PathBuf {
    let text = format!(
        "quasi-static block with a sensor\n\
         UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
         PART/1, GROUND\nMARKER/1, PART = 1, REULER = 90D, 90D, 0D\nMARKER/2, PART = 1, FLOATING\n\
         PART/2, MASS = 1, CM = 20, IP = 1, 1, 1, QG = 1, 0, 0\nMARKER/20, PART = 2\n\
         MARKER/21, PART = 2, REULER = 90D, 90D, 0D\nJOINT/1, TRANSLATIONAL, I = 21, J = 1\n\
         SPRINGDAMPER/1, I = 20, J = 1, K = 100, C = 0, LENGTH = 1\n\
         VFORCE/1, I = 20, JFLOAT = 2, RM = 1, FX = 0\\ FY = 0\\ FZ = 10*TIME\n{sensor}\nEND\n"
    );
    let dir = std::env::temp_dir().join(format!("linkage-qs-{}-{tag}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("block.adm");
    std::fs::write(&f, text).unwrap();
    f
}

#[test]
fn halt_ends_a_quasi_static_series_at_the_equilibrium_that_reaches_its_value() {
    // x = 1 + 0.1·t reaches 1.25 at t = 2.5 (between the outputs 2.4 and 2.8), located to
    // |x − 1.25| ≤ 1e-8, i.e. to 1e-7 s.
    let f = pushed_block(
        "halt",
        "SENSOR/1, VALUE = 1.25, GE, ERROR = 1E-8, HALT, FUNCTION = DX(20, 1)",
    );
    let (code, v) = json(&[
        "static",
        s(&f),
        "--end",
        "4",
        "--steps",
        "10",
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(v["ended_by_sensor"], "SENSOR_1 (HALT)");
    let e = &v["sensors"][0];
    assert!((e["time"].as_f64().unwrap() - 2.5).abs() < 1e-7, "{e}");
    let csv = csv_of(&f);
    let got = times(&csv);
    // 0, 0.4, …, 2.4, then the event.
    assert_eq!(got.len(), 8, "{got:?}");
    assert!((got[7] - 2.5).abs() < 1e-7, "{got:?}");
    let (code, out, _) = run(&["static", s(&f), "--end", "4", "--steps", "10"]);
    assert_eq!(code, 0);
    assert!(
        out.contains("The series was ended at time ") && out.contains("by SENSOR_1 (HALT)."),
        "{out}"
    );
    assert!(
        out.contains("Sensor SENSOR_1 (SENSOR/1) fired at time "),
        "{out}"
    );
}

#[test]
fn sensor_dt_sets_the_quasi_static_output_interval_from_the_event_on() {
    // The event at t* = 2.5, then equilibria every 0.5 up to the end: 3, 3.5, 4.
    let f = pushed_block(
        "dt",
        "SENSOR/1, VALUE = 1.25, GE, ERROR = 1E-8, DT = 0.5, FUNCTION = DX(20, 1)",
    );
    let (code, v) = json(&[
        "static",
        s(&f),
        "--end",
        "4",
        "--steps",
        "10",
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{v}");
    let csv = csv_of(&f);
    let got = times(&csv);
    assert_eq!(got.len(), 7 + 3, "{got:?}");
    for (k, t) in got[7..].iter().enumerate() {
        assert!((t - (3.0 + 0.5 * k as f64)).abs() < 1e-6, "{got:?}");
    }
    // The block follows x = 0.1·t at every output.
    let text = std::fs::read_to_string(&csv).unwrap();
    let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    let x = header
        .iter()
        .position(|h| h.starts_with("PART_2.x "))
        .unwrap();
    for l in text.lines().skip(1) {
        let r: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
        assert!((r[x] - 1.0 - 0.1 * r[0]).abs() < 1e-9, "{l}");
    }
}

/// `static --format csv` of the series to 4 in 10 steps, written beside `f`.
fn csv_of(f: &Path) -> PathBuf {
    let (code, out, err) = run(&[
        "static",
        s(f),
        "--end",
        "4",
        "--steps",
        "10",
        "--format",
        "csv",
    ]);
    assert_eq!(code, 0, "{err}");
    let csv = f.with_extension("csv");
    std::fs::write(&csv, out).unwrap();
    csv
}
