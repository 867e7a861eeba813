//! Constraint equations: rows with analytic Jacobians and Hessians, the compiled system, the
//! constraint graph, sparse rank decisions and the motion drivers.

pub mod curve_contacts;
pub mod drivers;
pub mod graph;
pub mod hessian;
pub mod motion_data;
pub mod rank;
pub mod residuals;
pub mod rows;
pub mod system;
