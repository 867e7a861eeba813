//! The `linkage ic` text report: every section read back and checked against values known
//! independently (mechanisms/README.md, the least-change assembly of crates/solve/tests/ic.rs,
//! closed-form statics of the door and the pendulum), with signs.

mod common;

use common::{root, run};

fn ic_text(mechanism: &str) -> (i32, String, String) {
    let src = root().join("mechanisms").join(mechanism);
    run(&["ic", src.to_str().unwrap()])
}

/// Numbers of a report line (what follows the name), `(a, b, c)` vectors included.
fn numbers(line: &str) -> Vec<f64> {
    line.split(|c: char| c.is_whitespace() || c == '(' || c == ')' || c == ',')
        .filter_map(|w| w.parse::<f64>().ok())
        .collect()
}

/// The one line starting (after indentation) with `prefix`.
fn line<'a>(text: &'a str, prefix: &str) -> &'a str {
    let found: Vec<&str> = text
        .lines()
        .filter(|l| l.trim_start().starts_with(prefix))
        .collect();
    assert_eq!(found.len(), 1, "{prefix:?} in\n{text}");
    found[0]
}

fn close(got: f64, want: f64, tol: f64, what: &str) {
    assert!((got - want).abs() <= tol, "{what}: {got} vs {want}");
}

#[test]
fn exploded_fourbar_report_states_the_least_change_repair_and_the_redundancy() {
    let (code, out, err) = ic_text("exploded_fourbar.adm");
    assert_eq!(code, 0, "{out}\n{err}");
    assert!(out.starts_with("INITIAL CONDITIONS: Adams View model name: exploded_fourbar"));
    assert!(out.contains(
        "units: NEWTON KILOGRAM METER SECOND (UCF 1); torque newton·meter, angles in degrees"
    ));
    let d = line(&out, "Displacement: converged in ");
    let n = numbers(d);
    assert!(n[0] >= 1.0 && n[1] < 1e-10, "{d}");

    // Moved parts: the least-change assembly (crates/solve/tests/ic.rs computes it
    // independently; here to the report's 6 decimals and 4 in degrees).
    for (name, t, deg) in [
        ("crank ", [0.002386, -0.001386, 0.0], 0.3162),
        ("coupler ", [-0.196434, 0.098883, -0.050000], 5.0004),
        ("rocker ", [0.001180, 0.000270, 0.0], 0.0462),
    ] {
        let l = line(&out, name);
        let v = numbers(l);
        assert_eq!(v.len(), 4, "{l}");
        for c in 0..3 {
            close(v[c], t[c], 1.5e-6, l);
        }
        close(v[3], deg, 1.5e-4, l);
    }

    let repaired: String = out
        .lines()
        .filter(|l| l.contains('→'))
        .map(|l| format!("{l}\n"))
        .collect();
    // Repaired joints: the residuals at input of mechanisms/README.md (lengths, and the
    // rotational rows' dot products as angles, asin in degrees), all repaired to rounding.
    let asin_deg = |x: f64| x.asin().to_degrees();
    for (joint, before) in [
        (
            "crank_coupler (Revolute Joint)",
            [
                0.2053859166,
                -0.0960836381,
                0.2025225498,
                asin_deg(0.0796347858),
                asin_deg(-0.0354178541),
            ],
        ),
        (
            "coupler_rocker (Revolute Joint)",
            [
                0.1946140834,
                -0.1039163619,
                -0.1025225498,
                asin_deg(0.0342397561),
                asin_deg(-0.0801483786),
            ],
        ),
    ] {
        for (k, equation) in [
            "Translation of I Marker Along Xg",
            "Translation of I Marker Along Yg",
            "Translation of I Marker Along Zg",
            "Rotation Between Zi & Xj",
            "Rotation Between Zi & Yj",
        ]
        .iter()
        .enumerate()
        {
            // The repaired line (the redundant list may name the same equation).
            let l = line(&repaired, &format!("{joint}  {equation}  "));
            let v = numbers(l);
            assert_eq!(v.len(), 2, "{l}");
            // Printed to 5 significant digits.
            close(v[0], before[k], 1e-4 * before[k].abs(), l);
            assert!(v[1].abs() < 1e-10, "{l}");
            assert_eq!(l.ends_with("deg"), k >= 3, "{l}");
        }
    }

    // Once assembled the four-bar is planar: 1 DOF, 3 consistent redundant equations.
    assert!(out.contains("\n1 Degrees of Freedom at the assembled configuration\n"));
    let redundant: Vec<&str> = out
        .lines()
        .skip_while(|l| !l.starts_with("Redundant constraint equations"))
        .skip(1)
        .take_while(|l| !l.trim().is_empty())
        .collect();
    assert_eq!(redundant.len(), 3, "{redundant:?}");
    assert!(redundant.iter().all(|l| l.ends_with("consistent")));
    assert!(line(&out, "Velocity: converged").contains("largest error"));
    let a = line(&out, "Acceleration and force: largest error");
    assert!(numbers(a)[0] < 1e-9, "{a}");
    // Every joint has its reaction row.
    for joint in [
        "crank_pivot",
        "crank_coupler",
        "coupler_rocker",
        "rocker_pivot",
    ] {
        // The table pads the name: the other lines follow it with " (Revolute Joint)".
        let l = line(&out, &format!("{joint}    "));
        assert_eq!(numbers(l).len(), 6, "{l}");
    }
    assert!(!out.contains("error:") && !err.contains("error:"), "{err}");
}

/// The door (20 kg, CM 0.4 m out along +x, hinges 1.6 m apart on the y axis, gravity −y):
/// the bottom hinge carries the weight, +196.133 N along y, and pushes the door out,
/// +49.03325 N along x; the top hinge pulls it in, −49.03325 N (W·0.4/1.6); the top hinge's
/// removed rows carry nothing. A pendulum hanging from its hinge: +2 g along y.
#[test]
fn reactions_are_printed_with_their_signs() {
    let (code, out, err) = ic_text("door_two_hinges.adm");
    assert_eq!(code, 0, "{out}\n{err}");
    assert!(line(&out, "Displacement: converged in 0 iterations").contains("largest residual"));
    assert!(!out.contains("Moved parts"), "{out}");
    let w = 20.0 * 9.80665;
    let bottom = numbers(line(&out, "hinge_bottom    "));
    let top = numbers(line(&out, "hinge_top    "));
    let expected_bottom = [w / 4.0, w, 0.0, 0.0, 0.0, 0.0];
    let expected_top = [-w / 4.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    for c in 0..6 {
        // Seven significant digits printed.
        close(bottom[c], expected_bottom[c], 1e-6 * w, "hinge_bottom");
        close(top[c], expected_top[c], 1e-6 * w, "hinge_top");
    }

    let (code, out, _) = ic_text("pendulum.adm");
    assert_eq!(code, 0);
    let hinge = numbers(line(&out, "hinge    "));
    let expected = [0.0, 2.0 * 9.80665, 0.0, 0.0, 0.0, 0.0];
    for c in 0..6 {
        close(hinge[c], expected[c], 1e-6 * 19.6133, "hinge");
    }
}

/// A door hung on two hinges whose axes are 2° apart cannot be assembled: the report marks
/// the top hinge's rotation INCONSISTENT with its 2° residual and ends in an `error:` line
/// naming it; exit 1.
#[test]
fn an_inconsistent_redundancy_is_reported_with_its_residual_and_exit_1() {
    let (code, out, err) = ic_text("door_tilted_hinge.adm");
    assert_eq!(code, 1, "{out}\n{err}");
    let l = line(
        &out,
        "hinge_top (Revolute Joint)  Rotation Between Zi & Yj  INCONSISTENT",
    );
    assert!(l.ends_with("residual 2.0000E+00 degrees"), "{l}");
    // The report ends with the one error line (standard error repeats it).
    let errors: Vec<&str> = out.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(errors.len(), 1, "{out}");
    assert_eq!(out.lines().last(), Some(errors[0]));
    assert!(err.contains(errors[0]), "{err}");
    assert!(
        errors[0].contains("Rotation Between Zi & Yj of hinge_top (residual 2.0000E+00 deg)"),
        "{}",
        errors[0]
    );
}
