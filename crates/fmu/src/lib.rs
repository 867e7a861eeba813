//! # linkage-fmu — an Adams Controls plant as an FMI co-simulation FMU
//!
//! Two builds use this crate:
//!
//! - the **cdylib** crate `linkage-fmu-binary` (`liblinkage_fmu_binary.so`) is the platform binary of every FMU: it exports the
//!   FMI 3.0 ([`fmi3`]) and FMI 2.0 ([`fmi2`]) co-simulation functions, each a thin C boundary
//!   (panics caught, errors as FMI status with the message to the importer's logger) over an
//!   [`instance::Instance`], which steps a [`linkage_api::cosim::Plant`];
//! - this crate is also the packager `linkage fmu` calls ([`export`]): the model description
//!   ([`description`]), the resources (the dataset, the files it names and
//!   `linkage-fmu.json`, [`config`]) and the binary, zipped ([`zip`]).
//!
//! ```text
//! MODEL.adm ─export─▶ PLANT.fmu = modelDescription.xml
//!                                 resources/{MODEL.adm, files it names, linkage-fmu.json}
//!                                 binaries/x86_64-linux/<id>.so   (FMI 3.0)
//!                                 binaries/linux64/<id>.so        (FMI 2.0)
//! ```
//!
//! Value references ([`config::Layout`]): 0 is time (FMI 3.0's independent variable), then
//! the inputs (the PINPUT's VARIABLEs in order), the outputs (the POUTPUT's), the parameters
//! (statement arguments `set` changes before the model is loaded) and the Boolean
//! `initial_static` (a static equilibrium before the first step).

pub mod config;
pub mod description;
pub mod export;
mod ffi;
pub mod fmi2;
pub mod fmi3;
pub mod instance;
pub mod zip;
