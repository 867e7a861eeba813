//! Adams user subroutines written in Fortran and C, compiled at test time (gfortran, gcc) and
//! run through the binary with `--user-lib`: each against the same model written with
//! built-in functions, in IC, statics, linear and dynamics, within 1e-6 relative; ERRMES with
//! STOP; a library or symbol that is missing; the trust rule.
//!
//! The model: a 2 kg block on a vertical TRANSLATIONAL joint (global z), its CM 1 m above the
//! ground marker, gravity −z, held by a force element between them.

mod common;
use common::*;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Results of the two runs agree to this, relative to the largest magnitude of the quantity.
const SAME: f64 = 1e-6;

/// A fresh folder for one test.
fn folder(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("linkage-usersub-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Compiles the test source `source` (in tests/user_subroutines) with `compiler` into the
/// shared library `dir/lib{name}.so`.
fn compile(compiler: &str, source: &str, dir: &Path, name: &str) -> PathBuf {
    let src = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/user_subroutines")
        .join(source);
    let lib = dir.join(format!("lib{name}.so"));
    let out = Command::new(compiler)
        .args(["-shared", "-fPIC", "-O2", "-o"])
        .arg(&lib)
        .arg(&src)
        .output()
        .unwrap_or_else(|e| panic!("{compiler} runs (.ci/run installs gcc and gfortran): {e}"));
    assert!(
        out.status.success(),
        "{compiler} compiles {source}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    lib
}

/// The block model with `force` (its force statement(s)) and `extra` statements.
fn block(dir: &Path, name: &str, force: &str) -> PathBuf {
    let text = format!(
        "block with a force element\n\
         UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
         PART/1, GROUND\n\
         MARKER/1, PART = 1\n\
         MARKER/2, PART = 1\n\
         PART/2, MASS = 2, CM = 3, IP = 1, 1, 1\n\
         MARKER/3, PART = 2, QP = 0, 0, 1\n\
         MARKER/4, PART = 2, QP = 0, 0, 1\n\
         JOINT/1, TRANSLATIONAL, I = 4, J = 2\n\
         {force}\n\
         ACCGRAV/KGRAV = -9.80665\n\
         END\n"
    );
    let path = dir.join(format!("{name}.adm"));
    std::fs::write(&path, text).unwrap();
    path
}

/// Every number of two JSON documents, side by side (strings, file names and timings left
/// out), with the path to each.
fn numbers(
    a: &serde_json::Value,
    b: &serde_json::Value,
    at: &str,
    out: &mut Vec<(String, f64, f64)>,
) {
    use serde_json::Value::*;
    match (a, b) {
        (Number(x), Number(y)) => {
            out.push((at.to_string(), x.as_f64().unwrap(), y.as_f64().unwrap()))
        }
        (Array(x), Array(y)) => {
            assert_eq!(x.len(), y.len(), "{at}: lengths differ");
            for (k, (x, y)) in x.iter().zip(y).enumerate() {
                numbers(x, y, &format!("{at}[{k}]"), out);
            }
        }
        (Object(x), Object(y)) => {
            for (k, v) in x {
                // Timings, and the findings and notes that name the subroutine and its library.
                let skip = [
                    "time_s",
                    "elapsed",
                    "seconds",
                    "runs_without",
                    "warnings",
                    "notes",
                ];
                if skip.iter().any(|s| k.contains(s)) {
                    continue;
                }
                if let Some(w) = y.get(k) {
                    numbers(v, w, &format!("{at}.{k}"), out);
                }
            }
        }
        _ => {}
    }
}

/// Asserts that every number agrees within [`SAME`] relative to the largest magnitude of its
/// kind (at least 1e-9 absolute); returns how many numbers were compared.
fn assert_same(what: &str, a: &serde_json::Value, b: &serde_json::Value) -> usize {
    let mut pairs = Vec::new();
    numbers(a, b, "", &mut pairs);
    let scale = pairs
        .iter()
        .fold(0f64, |m, (_, x, y)| m.max(x.abs()).max(y.abs()));
    for (at, x, y) in &pairs {
        let tol = SAME * x.abs().max(y.abs()).max(scale * 1e-3).max(1e-9);
        assert!(
            (x - y).abs() <= tol,
            "{what}{at}: built-in {x} vs subroutine {y}"
        );
    }
    pairs.len()
}

/// `linkage <command> <model> --format json [--user-lib lib]`: the document (exit 0).
fn analysis(command: &str, model: &Path, lib: Option<&Path>, extra: &[&str]) -> serde_json::Value {
    let mut args = vec![command, model.to_str().unwrap(), "--format", "json"];
    if let Some(l) = lib {
        args.extend(["--user-lib", l.to_str().unwrap()]);
    }
    args.extend(extra);
    let (code, out, err) = run(&args);
    assert_eq!(code, 0, "{command} {}: {out}\n{err}", model.display());
    serde_json::from_str(&out).unwrap_or_else(|e| panic!("JSON ({e}): {out}"))
}

/// A CSV path of its own for each simulation (tests run in parallel; a corpus model's folder
/// is never written to).
fn scratch_csv() -> PathBuf {
    static NEXT: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let n = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    std::env::temp_dir().join(format!("linkage-usersub-{}-{n}.csv", std::process::id()))
}

/// The CSV of a simulation: rows of numbers.
fn simulate(model: &Path, lib: Option<&Path>, end: &str) -> Vec<Vec<f64>> {
    let out = scratch_csv();
    let mut args = vec![
        "simulate",
        model.to_str().unwrap(),
        "--end",
        end,
        "--steps",
        "50",
    ];
    args.extend(["--out", out.to_str().unwrap()]);
    if let Some(l) = lib {
        args.extend(["--user-lib", l.to_str().unwrap()]);
    }
    let (code, stdout, err) = run(&args);
    assert_eq!(code, 0, "simulate {}: {stdout}\n{err}", model.display());
    std::fs::read_to_string(&out)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect()
}

/// IC, statics, linear and dynamics of `builtin` and `user` agree within [`SAME`].
fn same_in_every_analysis(builtin: &Path, user: &Path, lib: &Path) {
    for command in ["ic", "static", "linear"] {
        let a = analysis(command, builtin, None, &[]);
        let b = analysis(command, user, Some(lib), &[]);
        let n = assert_same(command, &a, &b);
        assert!(n > 3, "{command}: only {n} numbers compared");
    }
    let a = simulate(builtin, None, "2");
    let b = simulate(user, Some(lib), "2");
    assert_eq!(a.len(), b.len());
    let scale = a.iter().flatten().fold(0f64, |m, x| m.max(x.abs()));
    for (ra, rb) in a.iter().zip(&b) {
        for (x, y) in ra.iter().zip(rb) {
            assert!(
                (x - y).abs() <= SAME * scale,
                "simulate at t = {}: built-in {x} vs subroutine {y}",
                ra[0]
            );
        }
    }
}

#[test]
fn fortran_sfosub_spring_damper_matches_the_builtin_spring_in_every_analysis() {
    let dir = folder("sfosub");
    let lib = compile("gfortran", "spring.f90", &dir, "springs");
    let builtin = block(
        &dir,
        "builtin",
        "SFORCE/1, TRANSLATIONAL, I = 3, J = 1, FUNCTION = -100*(DM(3,1)-1.2) - 2*VR(3,1)",
    );
    let user = block(
        &dir,
        "user",
        "SFORCE/1, TRANSLATIONAL, I = 3, J = 1, FUNCTION = USER(100, 2, 1.2, 3, 1)\n\
         , ROUTINE = springs::sfosub",
    );
    same_in_every_analysis(&builtin, &user, &lib);
    // Statics: the spring carries the weight, DM = 1.2 − m·g/k.
    let s = analysis("static", &user, Some(&lib), &[]);
    let z = s["parts"][0]["position"][2].as_f64().unwrap();
    let expected = 1.2 - 2.0 * 9.80665 / 100.0;
    assert!(
        (z - expected).abs() < 1e-9,
        "static height {z} vs {expected}"
    );
    // Linear: the partials by differences give the spring's stiffness.
    let k = s["lowest_stiffness"].as_f64().unwrap();
    assert!((k - 100.0).abs() < 1e-6 * 100.0, "stiffness {k}");
}

#[test]
fn fortran_varsub_control_law_matches_the_builtin_variable_in_every_analysis() {
    let dir = folder("varsub");
    let lib = compile("gfortran", "spring.f90", &dir, "control");
    // A PD law holding the block at 0.9 m: u = −400·(DZ − 0.9) − 30·VZ, applied as a force.
    let law = |function: &str| {
        format!(
            "VARIABLE/1, FUNCTION = {function}\n\
             SFORCE/1, TRANSLATIONAL, I = 3, J = 1, FUNCTION = VARVAL(1)"
        )
    };
    let builtin = block(&dir, "builtin", &law("-400*(DZ(3,1)-0.9) - 30*VZ(3,1)"));
    let user = block(
        &dir,
        "user",
        &law("USER(400, 30, 3, 1, 0.9)\n, ROUTINE = control::"),
    );
    same_in_every_analysis(&builtin, &user, &lib);
}

#[test]
fn c_style_impact_force_with_its_struct_matches_the_builtin_impact() {
    let dir = folder("impact");
    let lib = compile("gcc", "impact.c", &dir, "contact");
    // The block on a stiff contact whose surface is 1.004 m above the ground marker: it starts
    // 4 mm into it (25 N against a 19.6 N weight) and settles.
    let builtin = block(
        &dir,
        "builtin",
        "SFORCE/1, TRANSLATIONAL, I = 3, J = 1, \
         FUNCTION = IMPACT(DM(3,1), VR(3,1), 1.004, 1e5, 1.5, 50, 0.01)",
    );
    let user = block(
        &dir,
        "user",
        "SFORCE/1, TRANSLATIONAL, I = 3, J = 1, FUNCTION = USER(1.004, 1e5, 1.5, 50, 0.01, 3, 1)",
    );
    same_in_every_analysis(&builtin, &user, &lib);
}

#[test]
fn errmes_with_stop_ends_the_simulation_with_the_message_and_the_time() {
    let dir = folder("errmes");
    let lib = compile("gfortran", "spring.f90", &dir, "springs");
    let model = block(
        &dir,
        "brittle",
        "SFORCE/1, TRANSLATIONAL, I = 3, J = 1, FUNCTION = USER(0.25)\n\
         , ROUTINE = springs::brittle",
    );
    let csv = dir.join("brittle.csv");
    let (code, out, err) = run(&[
        "simulate",
        model.to_str().unwrap(),
        "--end",
        "1",
        "--steps",
        "10",
        "--out",
        csv.to_str().unwrap(),
        "--user-lib",
        lib.to_str().unwrap(),
    ]);
    let all = format!("{out}{err}");
    assert_ne!(code, 0, "{all}");
    assert!(all.contains("the spring broke"), "{all}");
    // The last accepted output, and the (trial) time the subroutine stopped at, past 0.25.
    assert!(all.contains("simulation stopped at time 0.2:"), "{all}");
    let at = all
        .split("ERRMES with STOP at time ")
        .nth(1)
        .expect("the stop's time");
    let t: f64 = at.split(':').next().unwrap().parse().unwrap();
    assert!(t > 0.25 && t <= 0.3 + 1e-9, "stopped at {t}: {all}");
    // At once, not after the integrator shrank its step to the minimum retrying.
    assert!(!all.contains("at its minimum"), "{all}");
    // The outputs before the stop stay whole: rows 0, 0.1 and 0.2.
    let rows = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(rows.lines().count(), 4, "{rows}");
    assert!(rows.ends_with('\n'), "whole rows: {rows}");
}

#[test]
fn a_missing_library_is_an_input_error_at_the_statement() {
    let dir = folder("nolib");
    let lib = compile("gfortran", "spring.f90", &dir, "springs");
    let model = block(
        &dir,
        "nolib",
        "SFORCE/1, TRANSLATIONAL, I = 3, J = 1, FUNCTION = USER(100, 2, 1.2, 3, 1)\n\
         , ROUTINE = nowhere::sfosub",
    );
    let (code, out, err) = run(&[
        "static",
        model.to_str().unwrap(),
        "--user-lib",
        lib.to_str().unwrap(),
    ]);
    let all = format!("{out}{err}");
    assert_eq!(code, 2, "{all}");
    assert!(
        all.contains("nolib.adm:10:"),
        "file:line:column of the FUNCTION: {all}"
    );
    assert!(
        all.contains("SFORCE/1") && all.contains("library 'nowhere'"),
        "{all}"
    );
}

#[test]
fn a_missing_symbol_is_an_input_error_naming_what_was_looked_for() {
    let dir = folder("nosym");
    let lib = compile("gfortran", "spring.f90", &dir, "springs");
    let model = block(
        &dir,
        "nosym",
        "SFORCE/1, TRANSLATIONAL, I = 3, J = 1, FUNCTION = USER(1)\n, ROUTINE = springs::absent",
    );
    let (code, out, err) = run(&[
        "static",
        model.to_str().unwrap(),
        "--user-lib",
        lib.to_str().unwrap(),
    ]);
    let all = format!("{out}{err}");
    assert_eq!(code, 2, "{all}");
    assert!(all.contains("no symbol absent_"), "{all}");
    assert!(
        all.contains(&lib.canonicalize().unwrap().display().to_string()),
        "{all}"
    );
}

#[test]
fn without_user_lib_a_user_call_is_refused_and_a_path_in_the_dataset_is_not_loaded() {
    let dir = folder("trust");
    let lib = compile("gfortran", "spring.f90", &dir, "springs");
    let spelled = format!(
        "SFORCE/1, TRANSLATIONAL, I = 3, J = 1, FUNCTION = USER(100, 2, 1.2, 3, 1)\n\
         , ROUTINE = {}::sfosub",
        lib.display()
    );
    let model = block(&dir, "spelled", &spelled);
    let (code, out, err) = run(&["static", model.to_str().unwrap()]);
    assert_ne!(code, 0, "refused without --user-lib: {out}{err}");
    // The library's folder is given, but not the file the dataset spells: not loaded.
    let other = folder("trust-other");
    let (code, out, err) = run(&[
        "static",
        model.to_str().unwrap(),
        "--user-lib",
        other.to_str().unwrap(),
    ]);
    let all = format!("{out}{err}");
    assert_eq!(code, 2, "{all}");
    assert!(all.contains("loads only when you give that file"), "{all}");
    // Given that very file, it runs.
    let (code, out, err) = run(&[
        "static",
        model.to_str().unwrap(),
        "--user-lib",
        lib.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{out}{err}");
    assert!(
        format!("{out}{err}").contains(&format!(
            "user subroutines loaded from {}",
            lib.canonicalize().unwrap().display()
        )),
        "the report names the library: {out}{err}"
    );
}

#[test]
fn verify_lists_the_subroutine_each_statement_calls() {
    let dir = folder("verify");
    let lib = compile("gfortran", "spring.f90", &dir, "springs");
    let model = block(
        &dir,
        "verify",
        "SFORCE/1, TRANSLATIONAL, I = 3, J = 1, FUNCTION = USER(100, 2, 1.2, 3, 1)\n\
         , ROUTINE = springs::sfosub",
    );
    let (code, out, err) = run(&[
        "verify",
        model.to_str().unwrap(),
        "--user-lib",
        lib.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{out}{err}");
    assert!(
        out.contains(
            "User subroutines the analyses call:\n   SFORCE_1 (SFORCE/1, line 10): its FUNCTION \
             calls the user subroutine SFOSUB as ROUTINE = springs::sfosub"
        ),
        "verify names the subroutine: {out}"
    );
    assert!(
        !out.contains("runs without") && !out.contains("refused by"),
        "{out}"
    );
}

/// The OMTLMSimulator shaft (corpus), whose GFORCE calls `tlmadams::` GFOSUB, with the
/// co-simulation force replaced by a C GFOSUB stiffness `libtlmadams.so` the test builds.
const SHAFT: &str = "OpenModelica__OMTLMSimulator__CompositeModels__ADAMSBEAST__Shaft";

#[test]
fn corpus_shaft_command_file_refused_for_its_gfosub_runs_with_a_c_stiffness_library() {
    let Some(corpus) = corpus() else { return };
    let dir = folder("shaft");
    // `ROUTINE = tlmadams::` finds libtlmadams.so in the folder given with --user-lib.
    compile("gcc", "tlm_stiffness.c", &dir, "tlmadams");
    let acf = corpus.join(format!("{SHAFT}.acf"));
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    let (code, stdout, err) = run(&[
        "run",
        acf.to_str().unwrap(),
        "--out-dir",
        out.to_str().unwrap(),
    ]);
    assert_ne!(code, 0, "refused without the library: {stdout}{err}");
    let (code, stdout, err) = run(&[
        "run",
        acf.to_str().unwrap(),
        "--out-dir",
        out.to_str().unwrap(),
        "--user-lib",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "runs with the library: {stdout}{err}");
    assert!(
        stdout.contains("51 output(s)") || stdout.contains("output(s)"),
        "{stdout}"
    );
    // The same dataset with the stiffness written as GFORCE components: the same motion.
    let adm = std::fs::read_to_string(corpus.join(format!("{SHAFT}.adm")))
        .unwrap()
        .replace("\r\n", "\n");
    let builtin_text = adm.replace(
        "FUNCTION = USER(5, 6, 6)\\\n, ROUTINE = tlmadams::",
        "FX = -DX(5,6,6)\\FY = -DY(5,6,6)\\FZ = -DZ(5,6,6)",
    );
    assert_ne!(
        builtin_text, adm,
        "the GFORCE statement is where the test expects it"
    );
    let builtin = dir.join("shaft_builtin.adm");
    std::fs::write(&builtin, builtin_text).unwrap();
    let a = simulate(&builtin, None, "1");
    let b = simulate(&corpus.join(format!("{SHAFT}.adm")), Some(&dir), "1");
    assert_eq!(a.len(), b.len());
    let scale = a.iter().flatten().fold(0f64, |m, x| m.max(x.abs()));
    for (ra, rb) in a.iter().zip(&b) {
        for (x, y) in ra.iter().zip(rb) {
            assert!((x - y).abs() <= SAME * scale, "t = {}: {x} vs {y}", ra[0]);
        }
    }
}

#[test]
fn fortran_difsub_first_order_lag_matches_the_builtin_diff_in_every_analysis() {
    let dir = folder("difsub");
    let lib = compile("gfortran", "spring.f90", &dir, "lags");
    // The spring pulls with 5·y besides, y the lag (τ = 0.5 s) of the block's height.
    let with = |function: &str| {
        format!(
            "DIFF/1, IC = 1, FUNCTION = {function}\n\
             SFORCE/1, TRANSLATIONAL, I = 3, J = 1, \
             FUNCTION = -100*(DM(3,1)-1.2) - 2*VR(3,1) + 5*DIF(1)"
        )
    };
    let builtin = block(&dir, "builtin", &with("(DZ(3,1) - DIF(1))/0.5"));
    let user = block(&dir, "user", &with("USER(0.5, 3, 1)\n, ROUTINE = lags::"));
    same_in_every_analysis(&builtin, &user, &lib);
}

#[test]
fn fortran_motsub_drive_matches_the_builtin_motion() {
    let dir = folder("motsub");
    let lib = compile("gfortran", "spring.f90", &dir, "drives");
    let with = |function: &str| {
        format!(
            "MOTION/1, JOINT = 1, TRANSLATION, FUNCTION = {function}\n\
             SFORCE/1, TRANSLATIONAL, I = 3, J = 1, FUNCTION = -100*(DM(3,1)-1.2) - 2*VR(3,1)"
        )
    };
    let builtin = block(&dir, "builtin", &with("1 + 0.1*SIN(2*TIME)"));
    let user = block(&dir, "user", &with("USER(0.1, 2, 1)\n, ROUTINE = drives::"));
    for command in ["ic", "static"] {
        let a = analysis(command, &builtin, None, &[]);
        let b = analysis(command, &user, Some(&lib), &[]);
        assert!(assert_same(command, &a, &b) > 3);
    }
    let a = simulate(&builtin, None, "2");
    let b = simulate(&user, Some(&lib), "2");
    assert_eq!(a.len(), b.len());
    let scale = a.iter().flatten().fold(0f64, |m, x| m.max(x.abs()));
    for (ra, rb) in a.iter().zip(&b) {
        for (x, y) in ra.iter().zip(rb) {
            assert!((x - y).abs() <= SAME * scale, "t = {}: {x} vs {y}", ra[0]);
        }
    }
}

/// The header of a simulate CSV written for `model` with `lib`.
fn simulate_header(model: &Path, lib: &Path) -> Vec<String> {
    let out = scratch_csv();
    let (code, stdout, err) = run(&[
        "simulate",
        model.to_str().unwrap(),
        "--end",
        "0.1",
        "--steps",
        "2",
        "--out",
        out.to_str().unwrap(),
        "--user-lib",
        lib.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "simulate {}: {stdout}\n{err}", model.display());
    let text = std::fs::read_to_string(&out).unwrap();
    text.lines()
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect()
}

/// The block with its spring and a REQUEST whose eight values are `request`.
fn block_with_request(dir: &Path, name: &str, request: &str) -> PathBuf {
    block(
        dir,
        name,
        &format!(
            "SFORCE/1, TRANSLATIONAL, I = 3, J = 1, FUNCTION = -100*(DM(3,1)-1.2) - 2*VR(3,1)\n\
             REQUEST/1, {request}"
        ),
    )
}

#[test]
fn reqsub_in_fortran_and_c_writes_the_eight_values_of_the_builtin_request() {
    let dir = folder("reqsub");
    let fortran = compile("gfortran", "spring.f90", &dir, "reqf");
    let c = compile("gcc", "reqsub.c", &dir, "reqc");
    let builtin = block_with_request(
        &dir,
        "builtin",
        "F1 = TIME\\F2 = DZ(3,1)\\F3 = VZ(3,1,1)\\F4 = ACCZ(3,1,1)\\F5 = DM(3,1)\\\
         F6 = VR(3,1)\\F7 = 2.5*DZ(3,1)\\F8 = SFORCE(1,0,4,0)",
    );
    let a = simulate(&builtin, None, "2");
    for (tag, lib) in [("fortran", &fortran), ("c", &c)] {
        let user = block_with_request(&dir, tag, "FUNCTION = USER(3, 1, 2.5, 1)");
        let header = simulate_header(&user, lib);
        let requests = header.iter().filter(|h| h.starts_with("REQUEST_1")).count();
        assert_eq!(requests, 8, "{tag}: eight REQUEST columns in {header:?}");
        let b = simulate(&user, Some(lib), "2");
        assert_eq!(a.len(), b.len());
        let scale = a.iter().flatten().fold(0f64, |m, x| m.max(x.abs()));
        for (ra, rb) in a.iter().zip(&b) {
            assert_eq!(ra.len(), rb.len(), "{tag}: columns");
            for (x, y) in ra.iter().zip(rb) {
                assert!(
                    (x - y).abs() <= SAME * scale,
                    "{tag} at t = {}: built-in {x} vs REQSUB {y}",
                    ra[0]
                );
            }
            // RESULT(1) is TIME, RESULT(7) is 2.5·RESULT(2): the columns are the subroutine's.
            let n = rb.len();
            assert!((rb[n - 8] - rb[0]).abs() <= 1e-12, "{tag}: F1 = TIME");
            assert!((rb[n - 2] - 2.5 * rb[n - 7]).abs() <= 1e-9 * scale.max(1.0));
        }
    }
}

/// The bushing's preloads, stiffnesses, dampings (FX, FY, FZ, TX, TY, TZ) and its free
/// length along z.
const BUSHING: [[f64; 6]; 3] = [
    [4.0, -3.0, 0.0, 0.5, -0.7, 0.2],
    [10.0, 20.0, 100.0, 5.0, 6.0, 7.0],
    [1.0, 1.5, 2.0, 0.1, 0.2, 0.3],
];

#[test]
fn fortran_gfosub_six_component_bushing_matches_the_builtin_gforce_in_every_analysis() {
    let dir = folder("gfosub");
    let lib = compile("gfortran", "spring.f90", &dir, "bush");
    let [pre, stiff, damp] = BUSHING;
    let measures = [
        ("FX", "DX(3,1,1)", "VX(3,1,1,1)"),
        ("FY", "DY(3,1,1)", "VY(3,1,1,1)"),
        ("FZ", "(DZ(3,1,1)-1.2)", "VZ(3,1,1,1)"),
        ("TX", "AX(3,1)", "WX(3,1,1)"),
        ("TY", "AY(3,1)", "WY(3,1,1)"),
        ("TZ", "AZ(3,1)", "WZ(3,1,1)"),
    ];
    let components: Vec<String> = measures
        .iter()
        .enumerate()
        .map(|(k, (c, d, v))| format!("{c} = {} - {}*{d} - {}*{v}", pre[k], stiff[k], damp[k]))
        .collect();
    let gforce = |functions: &str| {
        format!("MARKER/5, PART = 1, FLOATING\nGFORCE/1, I = 3, JFLOAT = 5, RM = 1, {functions}")
    };
    let builtin = block(&dir, "builtin", &gforce(&components.join("\\\n, ")));
    let params: Vec<String> = [3.0, 1.0]
        .iter()
        .chain(pre.iter())
        .chain(stiff.iter())
        .chain(damp.iter())
        .chain([1.2].iter())
        .map(|p| p.to_string())
        .collect();
    let user = block(
        &dir,
        "user",
        &gforce(&format!(
            "FUNCTION = USER({})\n, ROUTINE = bush::",
            params.join(", ")
        )),
    );
    same_in_every_analysis(&builtin, &user, &lib);
    // Statics: FZ carries the weight, DZ = 1.2 − m·g/k_z.
    let s = analysis("static", &user, Some(&lib), &[]);
    let z = s["parts"][0]["position"][2].as_f64().unwrap();
    let expected = 1.2 - 2.0 * 9.80665 / stiff[2];
    assert!(
        (z - expected).abs() < 1e-9,
        "static height {z} vs {expected}"
    );
    // The joint holds the bushing's preloads in x, y and every torque: its reaction is their
    // opposite, component by component (RM is the ground's axes).
    let r = &s["reactions"][0];
    for (k, preload) in pre.iter().enumerate() {
        let (what, n) = if k < 3 {
            ("force", k)
        } else {
            ("torque", k - 3)
        };
        let got = r[what][n].as_f64().unwrap();
        let want = if k == 2 { 0.0 } else { -preload };
        assert!(
            (got - want).abs() < 1e-9,
            "reaction {what}[{n}] {got} vs {want}"
        );
    }
}

#[test]
fn fortran_sensub_halts_where_the_builtin_sensor_does() {
    let dir = folder("sensub");
    let lib = compile("gfortran", "spring.f90", &dir, "sense");
    // The block starts at 1 m, below its rest height 1.2 − m·g/k ≈ 1.0039 m, and rises through
    // 1.003 m, where the sensor halts the run.
    let with = |function: &str| {
        format!(
            "SFORCE/1, TRANSLATIONAL, I = 3, J = 1, FUNCTION = -100*(DM(3,1)-1.2) - 2*VR(3,1)\n\
             SENSOR/1, VALUE = 0, GE, ERROR = 1E-9, HALT, FUNCTION = {function}"
        )
    };
    let builtin = block(&dir, "builtin", &with("DZ(3,1) - 1.003"));
    let user = block(
        &dir,
        "user",
        &with("USER(3, 1, 1.003)\n, ROUTINE = sense::"),
    );
    let halt = |model: &Path, lib: Option<&Path>| {
        let v = analysis("simulate", model, lib, &["--end", "2", "--steps", "50"]);
        assert_eq!(v["ended_by_sensor"], "SENSOR_1 (HALT)", "{v}");
        v["end_time"].as_f64().unwrap()
    };
    let a = halt(&builtin, None);
    let b = halt(&user, Some(&lib));
    assert!(
        a > 0.0 && a < 2.0,
        "the built-in sensor fires within the run: {a}"
    );
    assert!(
        (a - b).abs() <= SAME * a,
        "built-in halts at {a}, SENSUB at {b}"
    );
    let x = simulate(&builtin, None, "2");
    let y = simulate(&user, Some(&lib), "2");
    assert_eq!(x.len(), y.len(), "the same outputs up to the halt");
}

#[test]
fn fortran_subroutine_calling_impact_step_poly_and_bistop_matches_the_builtin_functions() {
    let dir = folder("utilities");
    let lib = compile("gfortran", "spring.f90", &dir, "util");
    // The contact of the C impact test, a force ramp in time, a polynomial in the height and
    // a BISTOP whose gap the block stays inside.
    let builtin = block(
        &dir,
        "builtin",
        "SFORCE/1, TRANSLATIONAL, I = 3, J = 1, \
         FUNCTION = IMPACT(DM(3,1), VR(3,1), 1.004, 1e5, 1.5, 50, 0.01) + STEP(TIME, 0, 0, 1, 2) \
         + POLY(DM(3,1), 1, 0, 3, 5) + BISTOP(DM(3,1), VR(3,1), 0.5, 1.5, 1e4, 1.5, 10, 0.01)",
    );
    let user = block(
        &dir,
        "user",
        "SFORCE/1, TRANSLATIONAL, I = 3, J = 1, \
         FUNCTION = USER(1.004, 1e5, 1.5, 50, 0.01, 0, 3, 5, 3, 1)\n, ROUTINE = util::utilforce",
    );
    same_in_every_analysis(&builtin, &user, &lib);
}

#[test]
fn fortran_sfosub_reading_its_constants_with_gtaray_matches_the_builtin_spring() {
    let dir = folder("gtaray");
    let lib = compile("gfortran", "spring.f90", &dir, "arrays");
    let builtin = block(
        &dir,
        "builtin",
        "SFORCE/1, TRANSLATIONAL, I = 3, J = 1, FUNCTION = -100*(DM(3,1)-1.2) - 2*VR(3,1)",
    );
    let user = block(
        &dir,
        "user",
        "ARRAY/7, IC, NUMBERS = 100, 2, 1.2, 3, 1\n\
         SFORCE/1, TRANSLATIONAL, I = 3, J = 1, FUNCTION = USER(7)\n, ROUTINE = arrays::arrayspring",
    );
    same_in_every_analysis(&builtin, &user, &lib);
}

/// The numbers of the `.req` file a command file writes for `model` (run in its folder,
/// output `{stem}_out`), with `lib` given or not.
fn req_numbers(model: &Path, lib: Option<&Path>) -> Vec<f64> {
    let dir = model.parent().unwrap();
    let stem = model.file_stem().unwrap().to_string_lossy().into_owned();
    let acf = dir.join(format!("{stem}.acf"));
    std::fs::write(
        &acf,
        format!("{stem}\n{stem}_out\nSIMULATE/DYNAMIC, END = 1, STEPS = 20\nSTOP\n"),
    )
    .unwrap();
    let mut args = vec![
        "run",
        acf.to_str().unwrap(),
        "--out-dir",
        dir.to_str().unwrap(),
    ];
    if let Some(l) = lib {
        args.extend(["--user-lib", l.to_str().unwrap()]);
    }
    let (code, out, err) = run(&args);
    assert_eq!(code, 0, "run {}: {out}\n{err}", acf.display());
    let req = std::fs::read_to_string(dir.join(format!("{stem}_out.req")))
        .unwrap_or_else(|e| panic!("{stem}_out.req: {e}\n{out}"));
    req.split_whitespace()
        .filter_map(|t| t.parse::<f64>().ok())
        .collect()
}

#[test]
fn reqsub_writes_the_req_file_of_the_builtin_request() {
    let dir = folder("reqsub-req");
    let lib = compile("gfortran", "spring.f90", &dir, "reqf");
    let builtin = block_with_request(
        &dir,
        "builtin",
        "F1 = TIME\\F2 = DZ(3,1)\\F3 = VZ(3,1,1)\\F4 = ACCZ(3,1,1)\\F5 = DM(3,1)\\\
         F6 = VR(3,1)\\F7 = 2.5*DZ(3,1)\\F8 = SFORCE(1,0,4,0)",
    );
    let user = block_with_request(&dir, "user", "FUNCTION = USER(3, 1, 2.5, 1)");
    let a = req_numbers(&builtin, None);
    let b = req_numbers(&user, Some(&lib));
    // 21 outputs of the six values the R3 format keeps (F2–F4, F6–F8; F1 and F5 are
    // magnitudes in Adams' convention), with 6 significant digits.
    assert!(a.len() >= 21 * 7, "{} numbers", a.len());
    assert_eq!(a.len(), b.len(), "the same layout");
    let scale = a.iter().fold(0f64, |m, x| m.max(x.abs()));
    for (k, (x, y)) in a.iter().zip(&b).enumerate() {
        assert!(
            (x - y).abs() <= 1e-5 * x.abs().max(y.abs()) + SAME * scale,
            ".req number {k}: built-in {x} vs REQSUB {y}"
        );
    }
}

#[test]
fn a_reqsub_is_called_once_with_iflag_for_its_eight_values() {
    let dir = folder("iflag");
    let lib = compile("gcc", "reqsub.c", &dir, "reqc");
    let user = block_with_request(&dir, "user", "FUNCTION = USER(0)\n, ROUTINE = reqc::Iflags");
    let rows = simulate(&user, Some(&lib), "0.5");
    assert!(rows.len() > 2);
    for r in &rows {
        let n = r.len();
        assert_eq!(&r[n - 8..], &[1.0; 8], "one IFLAG call: {r:?}");
    }
}
