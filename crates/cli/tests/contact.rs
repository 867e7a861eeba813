//! CONTACT through the command line: the `CONTACT(id, jflag, comp, rm)` function in REQUESTs
//! (the weight of a cube resting on a slab, on I and on J), and a contact on a Parasolid file
//! named by verify with the file, refused by simulate, and left out by `--deactivate`.

mod common;
use common::run;
use std::path::PathBuf;

const G: f64 = 9.81;

fn dataset(tag: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("linkage-contact-{}-{tag}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("m.adm");
    std::fs::write(&f, text).unwrap();
    f
}

/// A 10 kg cube of side 0.2 m dropped 5 mm onto a ground slab (top face z = 0); IMPACT
/// k = 1e6, e = 1.5; REQUEST/1 gives CONTACT(1, 0, 4, 0), CONTACT(1, 1, 4, 0) and
/// CONTACT(1, 0, 1, 0). `extra`: statements added.
fn cube(extra: &str) -> String {
    format!(
        "cube on a slab\n\
UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
PART/1, GROUND\n\
MARKER/1, PART = 1\n\
MARKER/2, PART = 1, QP = -1, -1, -0.1\n\
ACCGRAV/KGRAV = -9.81\n\
PART/2, MASS = 10, CM = 20, IP = 0.0667, 0.0667, 0.0667, QG = 0, 0, 0.105\n\
MARKER/20, PART = 2\n\
MARKER/22, PART = 2, QP = -0.1, -0.1, -0.1\n\
GRAPHICS/1, BOX, CORNER = 22, X = 0.2, Y = 0.2, Z = 0.2\n\
GRAPHICS/2, BOX, CORNER = 2, X = 2, Y = 2, Z = 0.1\n\
CONTACT/1, IGEOM = 1, JGEOM = 2, IMPACT, STIFFNESS = 1E6, DAMPING = 2E3, DMAX = 1E-4, \
EXPONENT = 1.5\n\
REQUEST/1, F2 = CONTACT(1, 0, 4, 0)\\F3 = CONTACT(1, 1, 4, 0)\\F4 = CONTACT(1, 0, 1, 0)\n\
{extra}END\n"
    )
}

#[test]
fn contact_function_gives_the_weight_on_i_and_its_reaction_on_j() {
    let f = dataset("request", &cube(""));
    let csv = f.with_extension("csv");
    let (code, out, err) = run(&[
        "simulate",
        f.to_str().unwrap(),
        "--end",
        "1",
        "--steps",
        "200",
        "--out",
        csv.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{out}\n{err}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let header: Vec<&str> = text
        .lines()
        .next()
        .unwrap()
        .split(',')
        .map(|h| h.split(' ').next().unwrap_or(h))
        .collect();
    let col = |n: &str| header.iter().position(|h| *h == n).unwrap();
    let last: Vec<f64> = text
        .lines()
        .last()
        .unwrap()
        .split(',')
        .map(|x| x.parse().unwrap())
        .collect();
    let w = 10.0 * G;
    // At rest the contact carries the weight: +m·g on the cube (I), −m·g on the slab (J).
    assert!((last[col("REQUEST_1.f2")] - w).abs() < 1e-3 * w, "{last:?}");
    assert!((last[col("REQUEST_1.f3")] + w).abs() < 1e-3 * w, "{last:?}");
    assert!((last[col("REQUEST_1.f4")] - w).abs() < 1e-3 * w, "{last:?}");
    // The first row: 5 mm above the slab, no force.
    let first: Vec<f64> = text
        .lines()
        .nth(1)
        .unwrap()
        .split(',')
        .map(|x| x.parse().unwrap())
        .collect();
    assert_eq!(first[col("REQUEST_1.f2")], 0.0);
}

#[test]
fn a_contact_on_a_parasolid_file_is_named_refused_and_deactivated() {
    let extra = "GRAPHICS/3, EXTERNAL, RM = 20, FILE = Wheel_Body.xmt_txt, ELEMENT = SOLID1\n\
CONTACT/2, IGEOM = 3, JGEOM = 2, IMPACT, STIFFNESS = 1E6, DAMPING = 2E3, DMAX = 1E-4, \
EXPONENT = 1.5\n";
    let f = dataset("parasolid", &cube(extra));
    let path = f.to_str().unwrap();
    let (code, out, err) = run(&["verify", path]);
    assert_eq!(code, 0, "{out}\n{err}");
    // Named with the file as written (case kept) and its place: CONTACT/2 is on line 15.
    assert!(out.contains("CONTACT_2 (CONTACT/2)"), "{out}");
    assert!(out.contains("'Wheel_Body.xmt_txt' does not exist"), "{out}");
    let (code, _, err) = run(&["simulate", path, "--end", "0.1", "--steps", "2"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains(&format!("{path}:15:")), "{err}");
    assert!(err.contains("Wheel_Body.xmt_txt"), "{err}");
    let (code, out, err) = run(&[
        "simulate",
        path,
        "--end",
        "0.1",
        "--steps",
        "2",
        "--deactivate",
        "CONTACT_2",
    ]);
    assert_eq!(code, 0, "{out}\n{err}");
    assert!(out.contains("left out on request (1): CONTACT_2"), "{out}");
}
