//! Compiles the utility-routine shim (`shim/utilities.c`) into a shared library that the crate
//! embeds and loads at run time (see `src/shim.rs`).

use std::path::PathBuf;
use std::process::Command;

fn main() {
    println!("cargo:rerun-if-changed=shim/utilities.c");
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    let lib = out.join("liblinkage_utilities.so");
    let compiler = cc::Build::new().get_compiler();
    let status = Command::new(compiler.path())
        .args(["-shared", "-fPIC", "-O2", "-o"])
        .arg(&lib)
        .arg("shim/utilities.c")
        .status()
        .expect("a C compiler runs (the utility-routine shim of user subroutines)");
    assert!(status.success(), "the utility-routine shim compiles");
}
