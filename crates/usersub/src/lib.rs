//! # linkage-usersub: Adams user subroutines run inside linkage
//!
//! `FUNCTION = USER(r1, …, rn)` with `ROUTINE = lib::name` calls a subroutine in a shared
//! library the user compiled (Fortran or C), as Adams Solver does. This crate
//!
//! * finds and loads the libraries, only from the places the user chose ([`search`]);
//! * finds the entry point in either calling convention Adams accepts ([`linker`]): Fortran
//!   (every argument by reference, LOGICAL as a 4-byte integer, CHARACTER lengths hidden at the
//!   end, gfortran/Intel names `sfosub_`) and C (mixed-case names such as `Sfosub`, the
//!   statement's struct first: `void Sfosub(const struct sAdamsSforce*, double time, int
//!   dflag, int iflag, double* result)`);
//! * calls it with IFLAG set once (the initialisation pass) and then for values, DFLAG set on
//!   the calls that difference its partials ([`routine`]);
//! * answers the utility routines it calls back into — SYSFNC, SYSARY, TIMGET, ERRMES,
//!   USRMES, GTARAY ([`callbacks`]) and STEP, POLY, IMPACT, BISTOP, AKISPL, CUBSPL (by the
//!   expression language's functions, `utilities`), in both conventions (`sysfnc_`,
//!   `c_sysfnc`) — through a small shim library (`shim/utilities.c`).
//!
//! The model asks [`Linker`] for each USER call ([`linkage_model::functions::UserLinker`]);
//! front ends make one with [`user_routines`] from `--user-lib PATH`.

pub mod callbacks;
pub mod error;
pub mod kind;
pub mod linker;
pub mod routine;
pub mod search;
mod shim;
mod utilities;

pub use error::UserError;
pub use kind::Kind;
pub use linker::{user_routines, Linker};
pub use routine::DIFFERENCE_STEP;
