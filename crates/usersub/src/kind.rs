//! The subroutine families: which statement calls which subroutine, with which arguments.

use std::ffi::c_int;

/// A subroutine family of Adams' user-subroutine interface.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// SFORCE: `SFOSUB(ID, TIME, PAR, NPAR, DFLAG, IFLAG, RESULT)`, one value.
    Sfosub,
    /// VARIABLE: `VARSUB(ID, TIME, PAR, NPAR, DFLAG, IFLAG, VALUE)`.
    Varsub,
    /// DIFF: `DIFSUB(ID, TIME, PAR, NPAR, DFLAG, IFLAG, VALUE)`.
    Difsub,
    /// MOTION: `MOTSUB(ID, TIME, PAR, NPAR, IORD, IFLAG, VALUE)`; IORD 0, 1, 2 asks for the
    /// displacement, velocity or acceleration.
    Motsub,
    /// SENSOR: `SENSUB(ID, TIME, PAR, NPAR, IFLAG, VALUE)`.
    Sensub,
    /// GFORCE: `GFOSUB(ID, TIME, PAR, NPAR, DFLAG, IFLAG, RESULT)`, RESULT(6) = FX, FY, FZ,
    /// TX, TY, TZ in RM's axes.
    Gfosub,
    /// VFORCE: `VFOSUB(…, RESULT)`, RESULT(3) = FX, FY, FZ.
    Vfosub,
    /// VTORQUE: `VTOSUB(…, RESULT)`, RESULT(3) = TX, TY, TZ.
    Vtosub,
    /// REQUEST: `REQSUB(ID, TIME, PAR, NPAR, IFLAG, RESULT)`, RESULT(8) = the request's eight
    /// values (written as its F1 … F8 columns).
    Reqsub,
}

/// How the arguments after `NPAR` go: a flag (DFLAG or IORD) then IFLAG, or IFLAG alone.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Shape {
    Flagged,
    Plain,
}

impl Kind {
    /// The family a statement's `FUNCTION = USER(…)` calls (`None`: not supported).
    pub fn of_statement(keyword: &str) -> Option<Kind> {
        Some(match keyword {
            "SFORCE" => Kind::Sfosub,
            "VARIABLE" => Kind::Varsub,
            "DIFF" => Kind::Difsub,
            "MOTION" => Kind::Motsub,
            "SENSOR" => Kind::Sensub,
            "GFORCE" => Kind::Gfosub,
            "VFORCE" => Kind::Vfosub,
            "VTORQUE" => Kind::Vtosub,
            "REQUEST" => Kind::Reqsub,
            _ => return None,
        })
    }

    /// The default subroutine name (`SFOSUB`).
    pub fn name(self) -> &'static str {
        match self {
            Kind::Sfosub => "SFOSUB",
            Kind::Varsub => "VARSUB",
            Kind::Difsub => "DIFSUB",
            Kind::Motsub => "MOTSUB",
            Kind::Sensub => "SENSUB",
            Kind::Gfosub => "GFOSUB",
            Kind::Vfosub => "VFOSUB",
            Kind::Vtosub => "VTOSUB",
            Kind::Reqsub => "REQSUB",
        }
    }

    pub(crate) fn shape(self) -> Shape {
        match self {
            Kind::Sensub | Kind::Reqsub => Shape::Plain,
            _ => Shape::Flagged,
        }
    }

    /// How many values the subroutine writes.
    pub fn outputs(self) -> usize {
        match self {
            Kind::Reqsub => 8,
            Kind::Gfosub => 6,
            Kind::Vfosub | Kind::Vtosub => 3,
            _ => 1,
        }
    }
}

/// The leading members of Adams' C-interface structs (`struct sAdamsSforce`, …): the
/// statement's id and its USER parameters. The members after these are not filled; a C
/// subroutine given to linkage reads only `ID`, `NPAR` and `PAR` of its first argument.
#[repr(C)]
pub(crate) struct CHead {
    pub id: c_int,
    pub npar: c_int,
    pub par: *const f64,
}
