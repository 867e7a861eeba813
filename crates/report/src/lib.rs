//! # linkage-report — rendering analysis results
//!
//! Reports compute no physics: they turn the values returned by `linkage-solve` into human
//! text in the spirit of Adams' own output and into JSON with a stable schema.

pub mod coverage;
pub mod element_columns;
pub mod explain;
pub mod flex;
pub mod friction;
pub mod ic;
pub mod linear;
/// Numbers as every report prints them (defined beside the dataset reader, so that the
/// solver's messages use them too).
pub use linkage_adm::num;
pub mod poses;
pub mod reactions;
pub mod sensors;
pub mod simulate;
pub mod statics;
pub mod units;
pub mod verify;
