//! The names known to the expression language: constants, functions and their arities.
//!
//! Every function name maps to one [`Function`]; [`Function::lookup`] is case-sensitive on
//! upper-case names (the lexer upper-cases identifiers).

/// Defines a fieldless enum together with its Adams (upper-case) names.
macro_rules! named_enum {
    (
        $(#[$meta:meta])*
        $name:ident { $( $(#[$vmeta:meta])* $variant:ident => $text:literal ),+ $(,)? }
    ) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum $name {
            $( $(#[$vmeta])* $variant ),+
        }

        impl $name {
            /// Every variant, in declaration order.
            pub const ALL: &'static [$name] = &[$($name::$variant),+];

            /// The upper-case Adams name.
            pub fn name(self) -> &'static str {
                match self {
                    $($name::$variant => $text),+
                }
            }

            /// Looks a variant up by its upper-case Adams name.
            pub fn from_name(name: &str) -> Option<Self> {
                match name {
                    $($text => Some($name::$variant),)+
                    _ => None,
                }
            }
        }

        impl std::fmt::Display for $name {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(self.name())
            }
        }
    };
}

named_enum! {
    /// Named constants and system values.
    Constant {
        /// π.
        Pi => "PI",
        /// π/180 (degrees to radians).
        Dtor => "DTOR",
        /// 180/π (radians to degrees).
        Rtod => "RTOD",
        /// Simulation time, from [`crate::Env::time`].
        Time => "TIME",
        /// Analysis mode code, from [`crate::Env::mode`].
        Mode => "MODE",
    }
}

named_enum! {
    /// FORTRAN-like math intrinsics.
    Intrinsic {
        /// `ABS(x)` = |x|.
        Abs => "ABS",
        /// `ACOS(x)`, x in [-1, 1].
        Acos => "ACOS",
        /// `AINT(x)`: truncation toward zero.
        Aint => "AINT",
        /// `ANINT(x)`: nearest whole number, halves away from zero.
        Anint => "ANINT",
        /// `ASIN(x)`, x in [-1, 1].
        Asin => "ASIN",
        /// `ATAN(x)`.
        Atan => "ATAN",
        /// `ATAN2(y, x)` in (-π, π]; not both zero.
        Atan2 => "ATAN2",
        /// `COS(x)`.
        Cos => "COS",
        /// `COSH(x)`.
        Cosh => "COSH",
        /// `DIM(x, y)` = max(x − y, 0) (positive difference).
        Dim => "DIM",
        /// `EXP(x)`.
        Exp => "EXP",
        /// `LOG(x)`: natural logarithm, x > 0.
        Log => "LOG",
        /// `LOG10(x)`, x > 0.
        Log10 => "LOG10",
        /// `MAX(a, b, ...)`: largest argument (at least two).
        Max => "MAX",
        /// `MIN(a, b, ...)`: smallest argument (at least two).
        Min => "MIN",
        /// `MOD(a, b)` = a − AINT(a/b)·b (sign of a, FORTRAN convention), b ≠ 0.
        Mod => "MOD",
        /// `SIGN(a, b)` = |a| if b ≥ 0, −|a| otherwise.
        Sign => "SIGN",
        /// `SIN(x)`.
        Sin => "SIN",
        /// `SINH(x)`.
        Sinh => "SINH",
        /// `SQRT(x)`, x ≥ 0.
        Sqrt => "SQRT",
        /// `TAN(x)`.
        Tan => "TAN",
        /// `TANH(x)`.
        Tanh => "TANH",
    }
}

named_enum! {
    /// Special (Adams-specific) functions; formulas in [`crate::functions`].
    Special {
        /// `STEP(x, x0, h0, x1, h1)`: cubic step.
        Step => "STEP",
        /// `STEP5(x, x0, h0, x1, h1)`: quintic step.
        Step5 => "STEP5",
        /// `HAVSIN(x, x0, h0, x1, h1)`: haversine step.
        Havsin => "HAVSIN",
        /// `SHF(x, x0, a, w, phi, b)`: simple harmonic function.
        Shf => "SHF",
        /// `POLY(x, x0, a0, ..., a30)`: polynomial.
        Poly => "POLY",
        /// `CHEBY(x, x0, a0, ..., a30)`: Chebyshev series.
        Cheby => "CHEBY",
        /// `FORCOS(x, x0, w, a0, ..., a30)`: Fourier cosine series.
        Forcos => "FORCOS",
        /// `FORSIN(x, x0, w, a0, ..., a30)`: Fourier sine series.
        Forsin => "FORSIN",
        /// `IMPACT(x, xdot, x1, k, e, cmax, d)`: one-sided contact force.
        Impact => "IMPACT",
        /// `BISTOP(x, xdot, x1, x2, k, e, cmax, d)`: two-sided gap element.
        Bistop => "BISTOP",
        /// `AKISPL(x, z, id [, iord])`: Akima interpolation of a SPLINE.
        Akispl => "AKISPL",
        /// `CUBSPL(x, z, id [, iord])`: natural cubic-spline interpolation of a SPLINE.
        Cubspl => "CUBSPL",
    }
}

named_enum! {
    /// Kinematic and force measures between markers, evaluated by [`crate::Env::measure`].
    ///
    /// The positional marker arguments of each kind are given by [`MeasureKind::marker_roles`].
    MeasureKind {
        /// `DX(i[,j][,k])`: x component of Pi − Pj in k's axes.
        Dx => "DX",
        /// `DY(i[,j][,k])`.
        Dy => "DY",
        /// `DZ(i[,j][,k])`.
        Dz => "DZ",
        /// `DM(i[,j])`: distance.
        Dm => "DM",
        /// `VX(i[,j][,k][,l])`: relative velocity x component, in k's axes, derivative in l.
        Vx => "VX",
        /// `VY(i[,j][,k][,l])`.
        Vy => "VY",
        /// `VZ(i[,j][,k][,l])`.
        Vz => "VZ",
        /// `VM(i[,j][,l])`: magnitude of the relative velocity.
        Vm => "VM",
        /// `VR(i[,j][,l])`: radial (separation) velocity.
        Vr => "VR",
        /// `WX(i[,j][,k])`: relative angular velocity x component in k's axes.
        Wx => "WX",
        /// `WY(i[,j][,k])`.
        Wy => "WY",
        /// `WZ(i[,j][,k])`.
        Wz => "WZ",
        /// `WM(i[,j])`: magnitude of the relative angular velocity.
        Wm => "WM",
        /// `ACCX(i[,j][,k][,l])`: relative acceleration x component.
        Accx => "ACCX",
        /// `ACCY(i[,j][,k][,l])`.
        Accy => "ACCY",
        /// `ACCZ(i[,j][,k][,l])`.
        Accz => "ACCZ",
        /// `ACCM(i[,j][,l])`: magnitude of the relative acceleration.
        Accm => "ACCM",
        /// `WDTX(i[,j][,k][,l])`: relative angular acceleration x component.
        Wdtx => "WDTX",
        /// `WDTY(i[,j][,k][,l])`.
        Wdty => "WDTY",
        /// `WDTZ(i[,j][,k][,l])`.
        Wdtz => "WDTZ",
        /// `WDTM(i[,j][,l])`: magnitude of the relative angular acceleration.
        Wdtm => "WDTM",
        /// `AX(i[,j])`: rotation of i about j's x axis (continuous).
        Ax => "AX",
        /// `AY(i[,j])`.
        Ay => "AY",
        /// `AZ(i[,j])`.
        Az => "AZ",
        /// `PSI(i[,j])`: first body 3-1-3 angle.
        Psi => "PSI",
        /// `THETA(i[,j])`: second body 3-1-3 angle.
        Theta => "THETA",
        /// `PHI(i[,j])`: third body 3-1-3 angle.
        Phi => "PHI",
        /// `YAW(i[,j])`: first body 3-2-1 angle.
        Yaw => "YAW",
        /// `PITCH(i[,j])`: second body 3-2-1 angle.
        Pitch => "PITCH",
        /// `ROLL(i[,j])`: third body 3-2-1 angle.
        Roll => "ROLL",
        /// `FX(i[,j][,k])`: net force x component between markers, in k's axes.
        Fx => "FX",
        /// `FY(i[,j][,k])`.
        Fy => "FY",
        /// `FZ(i[,j][,k])`.
        Fz => "FZ",
        /// `FM(i[,j])`: net force magnitude.
        Fm => "FM",
        /// `TX(i[,j][,k])`: net torque x component.
        Tx => "TX",
        /// `TY(i[,j][,k])`.
        Ty => "TY",
        /// `TZ(i[,j][,k])`.
        Tz => "TZ",
        /// `TM(i[,j])`: net torque magnitude.
        Tm => "TM",
    }
}

named_enum! {
    /// Element force functions `NAME(id, jflag, comp [, rm])`, evaluated by
    /// [`crate::Env::element_force`].
    ElementForce {
        /// `JOINT(id, jflag, comp, rm)`.
        Joint => "JOINT",
        /// `JPRIM(id, jflag, comp, rm)`.
        Jprim => "JPRIM",
        /// `MOTION(id, jflag, comp, rm)`.
        Motion => "MOTION",
        /// `SFORCE(id, jflag, comp, rm)`.
        Sforce => "SFORCE",
        /// `SPDP(id, jflag, comp, rm)`: SPRINGDAMPER.
        Spdp => "SPDP",
        /// `BUSH(id, jflag, comp, rm)`.
        Bush => "BUSH",
        /// `FIELD(id, jflag, comp, rm)`.
        Field => "FIELD",
        /// `BEAM(id, jflag, comp, rm)`.
        Beam => "BEAM",
        /// `VFORCE(id, jflag, comp, rm)`.
        Vforce => "VFORCE",
        /// `VTORQUE(id, jflag, comp, rm)`.
        Vtorque => "VTORQUE",
        /// `GFORCE(id, jflag, comp, rm)`.
        Gforce => "GFORCE",
        /// `CONTACT(id, jflag, comp, rm)`: summed over the contact's incidents.
        Contact => "CONTACT",
    }
}

impl ElementForce {
    /// The statement keyword of the elements this function reads (`BUSH` reads `BUSHING/id`).
    pub fn statement(self) -> &'static str {
        match self {
            ElementForce::Joint => "JOINT",
            ElementForce::Jprim => "JPRIM",
            ElementForce::Motion => "MOTION",
            ElementForce::Sforce => "SFORCE",
            ElementForce::Spdp => "SPRINGDAMPER",
            ElementForce::Bush => "BUSHING",
            ElementForce::Field => "FIELD",
            ElementForce::Beam => "BEAM",
            ElementForce::Vforce => "VFORCE",
            ElementForce::Vtorque => "VTORQUE",
            ElementForce::Gforce => "GFORCE",
            ElementForce::Contact => "CONTACT",
        }
    }
}

named_enum! {
    /// References to solver states, evaluated by [`crate::Env::state`].
    StateKind {
        /// `VARVAL(id)`: value of VARIABLE/id.
        Varval => "VARVAL",
        /// `DIF(id)`: state of DIFF/id.
        Dif => "DIF",
        /// `DIF1(id)`: time derivative of the state of DIFF/id.
        Dif1 => "DIF1",
        /// `ARYVAL(id, n)`: n-th (1-based) value of ARRAY/id.
        Aryval => "ARYVAL",
        /// `PINVAL(id, n)`: value of the n-th (1-based) VARIABLE of PINPUT/id.
        Pinval => "PINVAL",
        /// `POUVAL(id, n)`: value of the n-th (1-based) VARIABLE of POUTPUT/id.
        Pouval => "POUVAL",
        /// `SENVAL(id)`: the value SENSOR/id stored when it last fired (0 before).
        Senval => "SENVAL",
    }
}

named_enum! {
    /// Components selected by the `comp` argument of element force functions.
    ForceComponent {
        /// comp = 1: force magnitude.
        Fm => "FM",
        /// comp = 2: force x.
        Fx => "FX",
        /// comp = 3: force y.
        Fy => "FY",
        /// comp = 4: force z.
        Fz => "FZ",
        /// comp = 5: torque magnitude.
        Tm => "TM",
        /// comp = 6: torque x.
        Tx => "TX",
        /// comp = 7: torque y.
        Ty => "TY",
        /// comp = 8: torque z.
        Tz => "TZ",
    }
}

impl ForceComponent {
    /// Maps the Adams `comp` code 1..=8 to a component.
    pub fn from_code(code: u32) -> Option<Self> {
        let index = usize::try_from(code).ok()?.checked_sub(1)?;
        Self::ALL.get(index).copied()
    }

    /// The Adams `comp` code 1..=8.
    pub fn code(self) -> u32 {
        match self {
            ForceComponent::Fm => 1,
            ForceComponent::Fx => 2,
            ForceComponent::Fy => 3,
            ForceComponent::Fz => 4,
            ForceComponent::Tm => 5,
            ForceComponent::Tx => 6,
            ForceComponent::Ty => 7,
            ForceComponent::Tz => 8,
        }
    }
}

/// The role of a positional marker argument of a measure.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum MarkerRole {
    /// The measured marker (required).
    I,
    /// The reference marker (default 0 = ground origin).
    J,
    /// The marker whose axes resolve the result (default 0 = ground axes).
    K,
    /// The marker whose frame time derivatives are taken in (default 0 = ground frame).
    L,
}

impl MeasureKind {
    /// The meaning of the positional arguments: `VX(i, j, k, l)` takes `[I, J, K, L]`, while
    /// `VM(i, j, l)` takes `[I, J, L]` (its third argument is the differentiation frame).
    /// The first argument is required, the others are optional and default to 0 (ground).
    pub fn marker_roles(self) -> &'static [MarkerRole] {
        use MarkerRole::{I, J, K, L};
        use MeasureKind::*;
        match self {
            Dx | Dy | Dz | Wx | Wy | Wz | Fx | Fy | Fz | Tx | Ty | Tz => &[I, J, K],
            Dm | Wm | Fm | Tm => &[I, J],
            Vx | Vy | Vz | Accx | Accy | Accz | Wdtx | Wdty | Wdtz => &[I, J, K, L],
            Vm | Vr | Accm | Wdtm => &[I, J, L],
            Ax | Ay | Az | Psi | Theta | Phi | Yaw | Pitch | Roll => &[I, J],
        }
    }
}

/// A callable function of the language (everything that is written `NAME(args)` except `IF`
/// and `USER`, which have their own AST nodes).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Function {
    /// A math intrinsic.
    Intrinsic(Intrinsic),
    /// A special function.
    Special(Special),
    /// A marker measure.
    Measure(MeasureKind),
    /// An element force function.
    ElementForce(ElementForce),
    /// A state reference.
    State(StateKind),
    /// `ORIENT(system, component, i [, j])`: a component of the orientation of marker i
    /// relative to marker j in one of the systems of [`crate::orient`].
    Orient,
}

/// Upper bound used for "any number of arguments".
pub(crate) const UNBOUNDED: usize = usize::MAX;

impl Function {
    /// Looks a function up by its upper-case name.
    pub fn lookup(name: &str) -> Option<Function> {
        if let Some(f) = Intrinsic::from_name(name) {
            return Some(Function::Intrinsic(f));
        }
        if let Some(f) = Special::from_name(name) {
            return Some(Function::Special(f));
        }
        if let Some(f) = MeasureKind::from_name(name) {
            return Some(Function::Measure(f));
        }
        if let Some(f) = ElementForce::from_name(name) {
            return Some(Function::ElementForce(f));
        }
        if name == "ORIENT" {
            return Some(Function::Orient);
        }
        if name == "POUTVAL" {
            // Another spelling of POUVAL (Adams' name) in some documents.
            return Some(Function::State(StateKind::Pouval));
        }
        StateKind::from_name(name).map(Function::State)
    }

    /// The upper-case name.
    pub fn name(self) -> &'static str {
        match self {
            Function::Intrinsic(f) => f.name(),
            Function::Special(f) => f.name(),
            Function::Measure(f) => f.name(),
            Function::ElementForce(f) => f.name(),
            Function::State(f) => f.name(),
            Function::Orient => "ORIENT",
        }
    }

    /// Minimum and maximum number of arguments (`usize::MAX` = unbounded).
    pub fn arity(self) -> (usize, usize) {
        match self {
            Function::Intrinsic(f) => match f {
                Intrinsic::Atan2 | Intrinsic::Dim | Intrinsic::Mod | Intrinsic::Sign => (2, 2),
                Intrinsic::Max | Intrinsic::Min => (2, UNBOUNDED),
                _ => (1, 1),
            },
            Function::Special(f) => match f {
                Special::Step | Special::Step5 | Special::Havsin => (5, 5),
                Special::Shf => (6, 6),
                Special::Poly | Special::Cheby => (3, 33),
                Special::Forcos | Special::Forsin => (4, 34),
                Special::Impact => (7, 7),
                Special::Bistop => (8, 8),
                Special::Akispl | Special::Cubspl => (3, 4),
            },
            Function::Measure(m) => (1, m.marker_roles().len()),
            Function::ElementForce(_) => (3, 4),
            Function::State(StateKind::Aryval | StateKind::Pinval | StateKind::Pouval) => (2, 2),
            Function::State(_) => (1, 1),
            Function::Orient => (3, 4),
        }
    }
}

impl std::fmt::Display for Function {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Formats "expects N arguments" style text for arity errors.
pub(crate) fn arity_message(name: &str, (min, max): (usize, usize), got: usize) -> String {
    let plural = |n: usize| if n == 1 { "argument" } else { "arguments" };
    let expected = if min == max {
        format!("{min} {}", plural(min))
    } else if max == UNBOUNDED {
        format!("at least {min} {}", plural(min))
    } else {
        format!("{min} to {max} arguments")
    };
    format!("{name} expects {expected}, got {got}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_do_not_collide() {
        let mut seen = std::collections::HashSet::new();
        let all: Vec<Function> = Intrinsic::ALL
            .iter()
            .map(|&f| Function::Intrinsic(f))
            .chain(Special::ALL.iter().map(|&f| Function::Special(f)))
            .chain(MeasureKind::ALL.iter().map(|&f| Function::Measure(f)))
            .chain(ElementForce::ALL.iter().map(|&f| Function::ElementForce(f)))
            .chain(StateKind::ALL.iter().map(|&f| Function::State(f)))
            .chain([Function::Orient])
            .collect();
        for f in all {
            assert!(seen.insert(f.name()), "duplicate {}", f.name());
            assert_eq!(Function::lookup(f.name()), Some(f));
            assert!(Constant::from_name(f.name()).is_none());
        }
        assert_eq!(MeasureKind::ALL.len(), 38);
    }

    #[test]
    fn force_component_codes() {
        for code in 1..=8 {
            assert_eq!(
                ForceComponent::from_code(code).map(|c| c.code()),
                Some(code)
            );
        }
        assert_eq!(ForceComponent::from_code(0), None);
        assert_eq!(ForceComponent::from_code(9), None);
    }
}
