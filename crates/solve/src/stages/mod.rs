//! The analyses on a [`crate::pipeline::Assembled`] (verify → assemble → ic are the pipeline's
//! rungs): statics / settle → linearize (+ plant) / dynamics (kinematics for zero-DOF models);
//! explain reads verify; stable_equilibrium tries statics, its descent, then settle. Stages share the [`crate::kernel`]; one stage calls another only
//! through its public entry (a run from equilibrium calls statics and settle, settling calls
//! the dynamic simulate, the zero-DOF simulate calls kinematics, plant reads linearize).

pub mod dynamics;
pub mod explain;
pub mod kinematics;
pub mod linearize;
pub mod plant;
pub mod settle;
pub mod stable_equilibrium;
pub mod statics;
