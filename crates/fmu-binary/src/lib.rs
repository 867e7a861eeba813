//! The platform binary of every FMU (`liblinkage_fmu_binary.so`, packed as
//! `binaries/<platform>/<model id>.so`): the FMI 3.0 and 2.0 co-simulation functions that
//! `linkage_fmu::fmi3` and `linkage_fmu::fmi2` define (`#[no_mangle] extern "C"`), exported
//! from this shared library. Nothing else lives here.

pub use linkage_fmu::{fmi2, fmi3};
