//! The analyses, each consuming the previous stage's result: verify → assemble → ic → statics /
//! settle → linearize / dynamics (kinematics for zero-DOF models); explain reads verify.

pub mod dynamics;
pub mod explain;
pub mod kinematics;
pub mod linearize;
pub mod plant;
pub mod settle;
pub mod statics;

// The initial-conditions rungs live in the pipeline layer and the FE_PART reduction in physics;
// their former paths stay valid for the crates that call them.
pub use crate::physics::fe_modes;
pub use crate::pipeline::{assemble, ic, verify};
