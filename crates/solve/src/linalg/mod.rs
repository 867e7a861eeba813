//! Linear algebra: sparse LU (one-off from triplets, and refactorised in place on a fixed
//! pattern) and the shift-invert Arnoldi eigen solver.

pub mod eigs;
pub mod linear;
