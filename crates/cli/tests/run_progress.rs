//! `linkage run` shows how far each dynamic simulation has come: the progress bar of
//! `linkage simulate` on a terminal (standard error a terminal), nothing otherwise.

mod common;
use common::root;
use std::path::{Path, PathBuf};
use std::process::Command;

/// A folder with `mechanisms/pendulum.adm` as `in.adm` and a command file `run.acf` that
/// simulates it for 2 s at HMAX = 1e-3 (2,000 steps or more).
fn pendulum_run(tag: &str) -> (PathBuf, PathBuf) {
    let dir = std::env::temp_dir().join(format!("linkage-progress-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(root().join("mechanisms/pendulum.adm"), dir.join("in.adm")).unwrap();
    let acf = dir.join("run.acf");
    std::fs::write(
        &acf,
        "in\nout\nINTEGRATOR/HMAX = 1e-3\nSIMULATE/DYNAMIC, END = 2, STEPS = 100\nSTOP\n",
    )
    .unwrap();
    (dir, acf)
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// What the bar writes: its percentage, the command and the simulation's time out of its end.
fn shows_bar(text: &str) -> bool {
    text.contains("% SIMULATE: t = ") && text.contains(" of 2")
}

#[test]
fn run_draws_no_progress_bar_when_standard_error_is_not_a_terminal() {
    let (dir, acf) = pendulum_run("pipe");
    let out = Command::new(env!("CARGO_BIN_EXE_linkage"))
        .args(["run", s(&acf)])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.is_empty(), "stderr of a run into a pipe: {stderr}");
    assert!(!shows_bar(&String::from_utf8_lossy(&out.stdout)));
}

#[test]
fn run_draws_the_progress_bar_of_simulate_on_a_terminal() {
    // `script` runs the command under a pseudo-terminal and copies what it draws.
    let (dir, acf) = pendulum_run("pty");
    let command = format!("{} run {}", env!("CARGO_BIN_EXE_linkage"), s(&acf));
    let out = match Command::new("script")
        .args(["-qec", &command, "/dev/null"])
        .current_dir(&dir)
        .output()
    {
        Ok(out) => out,
        Err(e) => {
            assert!(std::env::var_os("CI").is_none(), "script (util-linux): {e}");
            eprintln!("notice: no `script` to give the run a terminal ({e}); test skipped");
            return;
        }
    };
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let drawn = String::from_utf8_lossy(&out.stdout);
    assert!(shows_bar(&drawn), "the terminal shows: {drawn:?}");
    // The bar is cleared when the simulation ends: the summary follows.
    assert!(
        drawn.contains("\u{1b}[2K3 command(s) carried out, 101 output(s)"),
        "{drawn:?}"
    );
}
