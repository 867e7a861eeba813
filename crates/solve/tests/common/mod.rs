//! What the solver's integration tests share.
#![allow(dead_code)]

pub mod analyses;
pub mod beam_modes;
pub mod cart_pendulum;

use std::path::{Path, PathBuf};

/// The corpus folder (`../shared/corpus` beside the repository), or `None` with a notice when
/// it is missing; under CI (`CI` set) a missing corpus fails the test.
pub fn corpus() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/corpus");
    if dir.is_dir() {
        return Some(dir);
    }
    assert!(
        std::env::var_os("CI").is_none(),
        "the corpus folder {} is missing",
        dir.display()
    );
    eprintln!("notice: {} is missing; corpus test skipped", dir.display());
    None
}
