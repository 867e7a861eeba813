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
    }
}
