//! # linkage-report — rendering analysis results
//!
//! Reports compute no physics: they turn the values returned by `linkage-solve` into human
//! text in the spirit of Adams' own output and into JSON with a stable schema.

pub mod coverage;
pub mod explain;
pub mod ic;
pub mod linear;
pub mod poses;
pub mod reactions;
pub mod sensors;
pub mod simulate;
pub mod statics;
pub mod units;
pub mod verify;
