//! Linear algebra: sparse LU (one-off from triplets, and refactorised in place on a fixed
//! pattern, [`linear`], optionally with its pivot sequence kept across refactorisations,
//! [`refactor`]; refactorised in place on a repeating triplet list, bit for bit a fresh
//! factorisation, [`triplet_lu`]), the one constrained (saddle-point) solve built on it
//! ([`kkt`]), and the shift-invert Arnoldi eigen solver ([`eigs`]).

pub mod eigs;
pub mod kkt;
pub mod linear;
pub mod refactor;
pub mod triplet_lu;
