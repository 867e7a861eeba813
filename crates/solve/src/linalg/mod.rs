//! Linear algebra: sparse LU (one-off from triplets, and refactorised in place on a fixed
//! pattern), the one constrained (saddle-point) solve built on it ([`kkt`]), and the
//! shift-invert Arnoldi eigen solver.

pub mod eigs;
pub mod kkt;
pub mod linear;
pub mod triplet_lu;
