//! The analyses, each consuming the previous stage's result: verify → assemble → ic → statics /
//! settle → linearize / dynamics (kinematics for zero-DOF models); explain reads verify.

pub mod assemble;
pub mod dynamics;
pub mod explain;
pub mod fe_modes;
pub mod ic;
pub mod kinematics;
pub mod linearize;
pub mod plant;
pub mod settle;
pub mod statics;
pub mod verify;
