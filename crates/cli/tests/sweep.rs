//! `linkage sweep` and `linkage sweep merge` end to end on `examples/spring_mass.adm` (m = 2 kg,
//! k = 800 N/m, spring 0.1 m longer than its span, no gravity).

mod common;
use common::{root, run};
use std::path::{Path, PathBuf};

/// A fresh folder for one test.
fn scratch(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("linkage-sweep-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Writes a spec over the example model with `body` (the [analysis] and [[vary]] tables).
fn spec(dir: &Path, body: &str) -> PathBuf {
    let model = root().join("examples/spring_mass.adm");
    let path = dir.join("sweep.toml");
    let text = format!("model = {:?}\n{body}", model.display().to_string());
    std::fs::write(&path, text).unwrap();
    path
}

fn sweep(args: &[&str]) -> (i32, String, String) {
    let mut all = vec!["sweep"];
    all.extend_from_slice(args);
    run(&all)
}

/// The summary's rows as maps from column name to field (no field holds a comma here).
fn summary(dir: &Path) -> Vec<std::collections::BTreeMap<String, String>> {
    let text = std::fs::read_to_string(dir.join("summary.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    lines
        .map(|l| {
            header
                .iter()
                .zip(l.split(','))
                .map(|(h, v)| (h.to_string(), v.to_string()))
                .collect()
        })
        .collect()
}

const LINEAR_OVER_K: &str = "[analysis]\nkind = \"linear\"\n[[vary]]\nstatement = \"SPRINGDAMPER/1\"\n\
                             argument = \"K\"\nrange = { start = 200.0, stop = 3200.0, count = 7 }\n";

#[test]
fn spring_mass_frequencies_follow_sqrt_k_over_m() {
    let dir = scratch("freq");
    let spec = spec(&dir, LINEAR_OVER_K);
    let out = dir.join("out");
    let out = out.to_str().unwrap();
    let (code, _, err) = sweep(&[spec.to_str().unwrap(), "--out", out, "--jobs", "2"]);
    assert_eq!(code, 0, "{err}");
    let (code, _, err) = sweep(&["merge", out]);
    assert_eq!(code, 0, "{err}");
    let rows = summary(Path::new(out));
    assert_eq!(rows.len(), 7);
    for (i, row) in rows.iter().enumerate() {
        let k: f64 = row["SPRINGDAMPER/1 K"].parse().unwrap();
        assert_eq!(k, 200.0 + 500.0 * i as f64, "range values in order");
        assert_eq!(row["status"], "ok");
        assert_eq!(row["dof"], "1");
        // f = sqrt(k/m)/(2π), m = 2 kg: the linearization of a linear spring is exact, so
        // only rounding separates them (1e-9 relative).
        let f: f64 = row["frequency_1"].parse().unwrap();
        let expected = (k / 2.0).sqrt() / std::f64::consts::TAU;
        assert!(
            (f - expected).abs() <= 1e-9 * expected,
            "k {k}: {f} vs {expected}"
        );
        // Results keep at most 12 significant digits (as every CSV of linkage); no field
        // is written as minus zero.
        let digits = row["frequency_1"]
            .chars()
            .filter(char::is_ascii_digit)
            .count();
        assert!(digits <= 13, "{}", row["frequency_1"]);
        for (column, value) in row {
            assert!(
                !value.starts_with("-0") || value.parse::<f64>().unwrap() != 0.0,
                "{column}: {value}"
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn two_shards_merged_equal_the_whole_sweep() {
    let dir = scratch("shards");
    let spec = spec(&dir, LINEAR_OVER_K);
    let spec = spec.to_str().unwrap();
    let whole = dir.join("whole");
    let split = dir.join("split");
    let (code, _, err) = sweep(&[spec, "--out", whole.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    // Shard 2 first: the order shards run in does not matter.
    for shard in ["2/2", "1/2"] {
        let (code, out, err) = sweep(&[spec, "--out", split.to_str().unwrap(), "--shard", shard]);
        assert_eq!(code, 0, "{err}");
        let runs = if shard == "1/2" {
            "4 run(s)"
        } else {
            "3 run(s)"
        };
        assert!(out.contains(runs), "{out}");
    }
    // Before the merge: shard 1 of 2 holds the even indices only.
    let first = split.join("shard-1-of-2/runs");
    assert!(first.join("000006.json").is_file() && !first.join("000001.json").exists());
    for d in [&whole, &split] {
        let (code, _, err) = sweep(&["merge", d.to_str().unwrap()]);
        assert_eq!(code, 0, "{err}");
    }
    let a = std::fs::read_to_string(whole.join("summary.csv")).unwrap();
    let b = std::fs::read_to_string(split.join("summary.csv")).unwrap();
    assert_eq!(a, b);
    assert_eq!(a.lines().count(), 8);
    // The per-run report is the CLI's JSON for the same model with K = 200 (but for the
    // file name it gives).
    let mut report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(first.join("000000.json")).unwrap()).unwrap();
    let changed = dir.join("k200.adm");
    let text = std::fs::read_to_string(root().join("examples/spring_mass.adm")).unwrap();
    std::fs::write(&changed, text.replace("K = 800", "K = 200")).unwrap();
    let (code, mut cli) = common::json(&["linear", changed.to_str().unwrap(), "--format", "json"]);
    assert_eq!(code, 0);
    for r in [&mut report, &mut cli] {
        r.as_object_mut().unwrap().remove("file");
    }
    assert_eq!(report, cli);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn merge_refuses_missing_and_doubly_recorded_runs() {
    let dir = scratch("refuse");
    let spec = spec(&dir, LINEAR_OVER_K);
    let spec = spec.to_str().unwrap();
    let out = dir.join("out");
    let o = out.to_str().unwrap();
    assert_eq!(sweep(&[spec, "--out", o, "--shard", "1/2"]).0, 0);
    let (code, _, err) = sweep(&["merge", o]);
    assert_eq!(code, 1);
    assert!(
        err.contains("3 of 7 runs have no record") && err.contains("1, 3, 5"),
        "{err}"
    );
    assert!(!out.join("summary.csv").exists());
    assert_eq!(sweep(&[spec, "--out", o, "--shard", "2/2"]).0, 0);
    let (code, _, err) = sweep(&["merge", o]);
    assert_eq!(code, 0, "{err}");
    assert!(out.join("summary.csv").exists());
    // A shard of another split of the same spec is refused when it starts, before any run.
    let (code, _, err) = sweep(&[spec, "--out", o, "--shard", "1/3"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("a split of this sweep into 2 shards") && err.contains("--shard K/2"),
        "{err}"
    );
    assert!(!out.join("shard-1-of-3").exists());
    // Records of another split put there by hand: the merge refuses them, and the summary
    // of the earlier merge, which no longer describes the folder, is removed.
    std::fs::create_dir_all(out.join("shard-1-of-3/runs")).unwrap();
    for name in ["000000.json", "000000.status.json"] {
        std::fs::copy(
            out.join("shard-1-of-2/runs").join(name),
            out.join("shard-1-of-3/runs").join(name),
        )
        .unwrap();
    }
    let (code, _, err) = sweep(&["merge", o]);
    assert_eq!(code, 1);
    assert!(
        err.contains("run 0 in shard-1-of-2 and shard-1-of-3"),
        "{err}"
    );
    assert!(
        !out.join("summary.csv").exists(),
        "a refused merge leaves no summary"
    );
    // Another spec into the same folder is refused before any run.
    let other = dir.join("other.toml");
    std::fs::write(
        &other,
        std::fs::read_to_string(spec)
            .unwrap()
            .replace("count = 7", "count = 3"),
    )
    .unwrap();
    let (code, _, err) = sweep(&[other.to_str().unwrap(), "--out", o]);
    assert_eq!(code, 2);
    assert!(err.contains("holds another sweep"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_failing_run_is_recorded_and_the_sweep_goes_on() {
    let dir = scratch("failing");
    // K = -800 is refused by the model (a spring rate must not be negative); the runs on
    // either side of it still run. Simulation over 0.5 s: z(t) = -0.1 + 0.1 cos(ω t),
    // ω = sqrt(k/m).
    let spec = spec(
        &dir,
        "[analysis]\nkind = \"simulate\"\nend = 0.5\nsteps = 50\n[[vary]]\nstatement = \"SPRINGDAMPER/1\"\n\
         argument = \"K\"\nvalues = [800.0, -800.0, 3200.0]\n",
    );
    let out = dir.join("out");
    let o = out.to_str().unwrap();
    let (code, stdout, err) = sweep(&[spec.to_str().unwrap(), "--out", o, "--jobs", "1"]);
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains("3 run(s), 1 failed"), "{stdout}");
    assert_eq!(sweep(&["merge", o]).0, 0);
    let rows = summary(&out);
    assert_eq!(rows[1]["status"], "failed");
    assert_eq!(rows[1]["exit_code"], "2");
    assert!(
        rows[1]["message"].contains("K must not be negative"),
        "{:?}",
        rows[1]
    );
    assert!(
        rows[1]["message"].contains("spring_mass.adm:25:"),
        "{:?}",
        rows[1]
    );
    for (row, k) in [(&rows[0], 800.0f64), (&rows[2], 3200.0)] {
        assert_eq!(row["status"], "ok");
        let z: f64 = row["block z"].parse().unwrap();
        let expected = -0.1 + 0.1 * ((k / 2.0).sqrt() * 0.5).cos();
        // The integrator's default ERROR (1e-3) keeps the position within 1 % of the 0.1 m
        // amplitude.
        assert!((z - expected).abs() < 1e-3, "k {k}: z {z} vs {expected}");
    }
    // Each run that ran has its time histories; the failed one its errors as JSON.
    let runs = out.join("shard-1-of-1/runs");
    let csv = std::fs::read_to_string(runs.join("000002.csv")).unwrap();
    assert!(
        csv.starts_with("time [s],block.x [m]") && csv.lines().count() == 52,
        "{}",
        &csv[..80]
    );
    let failed: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(runs.join("000001.json")).unwrap()).unwrap();
    assert!(failed["errors"][0]
        .as_str()
        .unwrap()
        .contains("must not be negative"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_specs_and_shards_are_input_errors() {
    let dir = scratch("bad");
    let bad = spec(&dir, "[analysis]\nkind = \"linear\"\n[[vary]]\nstatement = \"SPRINGDAMPER/9\"\nargument = \"K\"\nvalues = [1.0]\n");
    let out = dir.join("out");
    let (code, _, err) = sweep(&[bad.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(err.contains("SPRINGDAMPER/9"), "{err}");
    let good = spec(&dir, LINEAR_OVER_K);
    let (code, _, err) = sweep(&[
        good.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--shard",
        "3/2",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("--shard 3/2"), "{err}");
    let (code, _, err) = run(&["sweep", "merge", dir.join("nothing").to_str().unwrap()]);
    assert_eq!(code, 1);
    assert!(err.contains("plan.json"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_example_spec_runs() {
    let dir = scratch("example");
    let out = dir.join("out");
    let spec = root().join("examples/spring_mass_sweep.toml");
    let (code, _, err) = sweep(&[spec.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(sweep(&["merge", out.to_str().unwrap()]).0, 0);
    let rows = summary(&out);
    assert_eq!(rows.len(), 5);
    assert!(rows.iter().all(|r| r["status"] == "ok"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// Runs `linkage sweep SPEC --out OUT` with the environment `vars` (and no other scheduler
/// variable).
fn sweep_with_env(spec: &Path, out: &Path, vars: &[(&str, &str)]) -> (i32, String) {
    let mut cmd = std::process::Command::new(env!("CARGO_BIN_EXE_linkage"));
    cmd.args([
        "sweep",
        spec.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    for v in [
        "SLURM_ARRAY_TASK_ID",
        "SLURM_ARRAY_TASK_MIN",
        "SLURM_ARRAY_TASK_COUNT",
        "JOB_COMPLETION_INDEX",
        "JOB_COMPLETIONS",
    ] {
        cmd.env_remove(v);
    }
    cmd.envs(vars.iter().copied());
    let o = cmd.output().unwrap();
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stdout).into_owned(),
    )
}

#[test]
fn slurm_and_kubernetes_environments_choose_the_shard() {
    let dir = scratch("env");
    let spec = spec(&dir, LINEAR_OVER_K);
    let whole = dir.join("whole");
    assert_eq!(sweep_with_env(&spec, &whole, &[]).0, 0);
    assert!(whole.join("shard-1-of-1").is_dir());
    // A Slurm array --array=1-2 does half, a Kubernetes indexed Job of 2 the other half.
    let split = dir.join("split");
    let slurm = [
        ("SLURM_ARRAY_TASK_ID", "1"),
        ("SLURM_ARRAY_TASK_MIN", "1"),
        ("SLURM_ARRAY_TASK_COUNT", "2"),
    ];
    let (code, out) = sweep_with_env(&spec, &split, &slurm);
    assert_eq!(code, 0);
    assert!(out.contains("shard 1/2: 4 run(s)"), "{out}");
    let k8s = [("JOB_COMPLETION_INDEX", "1"), ("JOB_COMPLETIONS", "2")];
    let (code, out) = sweep_with_env(&spec, &split, &k8s);
    assert_eq!(code, 0);
    assert!(out.contains("shard 2/2: 3 run(s)"), "{out}");
    for d in [&whole, &split] {
        assert_eq!(sweep(&["merge", d.to_str().unwrap()]).0, 0);
    }
    assert_eq!(
        std::fs::read_to_string(whole.join("summary.csv")).unwrap(),
        std::fs::read_to_string(split.join("summary.csv")).unwrap()
    );
    let _ = std::fs::remove_dir_all(&dir);
}
