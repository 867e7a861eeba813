//! The units every report states: the one place where the dataset's UNITS become the names
//! and symbols of what a report prints.
//!
//! Contract:
//! - Built from [`linkage_model::units::Units::names`] (`[force, mass, length, time]` as the
//!   dataset gives them, `NONE` without a UNITS statement); nothing is converted, every value
//!   stays in model units.
//! - JSON ([`UnitsJson`], the `units` object of every JSON report) gives long names
//!   (`"newton"`, `"newton·millimeter"`, `"millimeter/second²"`); CSV headers give short
//!   symbols (`N`, `N·mm`, `mm/s²`) where a standard one exists, the long name otherwise.
//! - Angles are in degrees where a report prints them in degrees (3-1-3 angles, verify's
//!   residuals), in radians otherwise (linear mode shapes); angular velocities and
//!   accelerations are always per radian.
//! - Without a UNITS statement the quantities are "model force", "model length", … (symbols
//!   `F`, `M`, `L`, `T`) and the system reads "model units (no UNITS statement)".
//!
//! **CSV decision.** Each column header of a linkage CSV (`simulate --out`,
//! `static --format csv`, the `.csv` of `linkage run`) carries its unit as a suffix,
//! `PART_2.x [mm]`, `JOINT_1.tz [N·mm]`, `time [s]`: the file stays one header row and rows of
//! numbers (any CSV reader reads it), and the unit travels with the column it describes. A
//! column whose unit is not known (a function REQUEST's `.f2`) has no suffix. Readers take
//! the column's name with [`column_name`], which drops the suffix: `linkage compare` matches
//! columns by that name, so files written before and after the suffix compare.

use linkage_model::Model;
use serde::Serialize;

/// How a report prints angles.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Angle {
    Degree,
    Radian,
}

/// One base unit: its long name and its symbol.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Base {
    long: &'static str,
    symbol: &'static str,
}

const fn base(long: &'static str, symbol: &'static str) -> Base {
    Base { long, symbol }
}

/// Long name and symbol of a dataset unit name (force, mass, length or time: the names are
/// distinct across the four kinds). `None` for a name not in the table.
fn known(name: &str) -> Option<Base> {
    Some(match name {
        "NEWTON" => base("newton", "N"),
        "KNEWTON" => base("kilonewton", "kN"),
        "MEGANEWTON" => base("meganewton", "MN"),
        "CENTINEWTON" => base("centinewton", "cN"),
        "MILLINEWTON" => base("millinewton", "mN"),
        "MICRONEWTON" => base("micronewton", "µN"),
        "NANONEWTON" => base("nanonewton", "nN"),
        "DYNE" => base("dyne", "dyn"),
        "KILOGRAM_FORCE" => base("kilogram-force", "kgf"),
        "POUND_FORCE" => base("pound-force", "lbf"),
        "KPOUND_FORCE" => base("kilopound-force", "kip"),
        "OUNCE_FORCE" => base("ounce-force", "ozf"),
        "POUNDAL" => base("poundal", "pdl"),
        "KILOGRAM" => base("kilogram", "kg"),
        "GRAM" => base("gram", "g"),
        "MILLIGRAM" => base("milligram", "mg"),
        "MICROGRAM" => base("microgram", "µg"),
        "NANOGRAM" => base("nanogram", "ng"),
        "TONNE" => base("tonne", "t"),
        "POUND_MASS" => base("pound", "lb"),
        "KPOUND_MASS" => base("kilopound", "klb"),
        "OUNCE_MASS" => base("ounce", "oz"),
        "SLUG" => base("slug", "slug"),
        "SLINCH" => base("slinch", "slinch"),
        "US_TON" => base("US ton", "ton"),
        "METER" => base("meter", "m"),
        "KILOMETER" => base("kilometer", "km"),
        "CENTIMETER" => base("centimeter", "cm"),
        "MILLIMETER" => base("millimeter", "mm"),
        "MICROMETER" => base("micrometer", "µm"),
        "NANOMETER" => base("nanometer", "nm"),
        "ANGSTROM" => base("angstrom", "Å"),
        "INCH" => base("inch", "in"),
        "FOOT" => base("foot", "ft"),
        "YARD" => base("yard", "yd"),
        "MILE" => base("mile", "mi"),
        "MILS" => base("mil", "mil"),
        "MICROINCH" => base("microinch", "µin"),
        "SECOND" => base("second", "s"),
        "MILLISECOND" => base("millisecond", "ms"),
        "MICROSECOND" => base("microsecond", "µs"),
        "NANOSECOND" => base("nanosecond", "ns"),
        "MINUTE" => base("minute", "min"),
        "HOUR" => base("hour", "h"),
        "DAY" => base("day", "d"),
        _ => return None,
    })
}

/// The model's force, mass, length and time units, and the UCF.
#[derive(Clone, Debug, PartialEq)]
struct Bases {
    names: [&'static str; 4],
    /// force, mass, length, time.
    bases: [Base; 4],
    ucf: f64,
}

/// What an unnamed (`NONE`) or unknown unit of each kind is called.
const GENERIC: [Base; 4] = [
    base("model force", "F"),
    base("model mass", "M"),
    base("model length", "L"),
    base("model time", "T"),
];

impl Bases {
    fn of(model: &Model) -> Bases {
        let names = model.units.names;
        let mut bases = GENERIC;
        for (b, name) in bases.iter_mut().zip(names) {
            if let Some(k) = known(name) {
                *b = k;
            }
        }
        Bases {
            names,
            bases,
            ucf: model.ucf(),
        }
    }

    /// Whether the dataset has no UNITS statement (every name `NONE`).
    fn unnamed(&self) -> bool {
        self.names.iter().all(|n| *n == "NONE")
    }
}

/// A quantity a report prints.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Quantity {
    Time,
    Length,
    Angle(Angle),
    Velocity,
    AngularVelocity,
    Acceleration,
    AngularAcceleration,
    Force,
    Torque,
}

/// `quantity` in `units`, long names (`long`) or symbols.
fn spell(b: &Bases, quantity: Quantity, long: bool) -> String {
    let pick = |x: Base| if long { x.long } else { x.symbol };
    let [force, _, length, time] = b.bases.map(pick);
    let radian = if long { "radian" } else { "rad" };
    match quantity {
        Quantity::Time => time.to_string(),
        Quantity::Length => length.to_string(),
        Quantity::Angle(Angle::Degree) => (if long { "degree" } else { "deg" }).to_string(),
        Quantity::Angle(Angle::Radian) => radian.to_string(),
        Quantity::Velocity => format!("{length}/{time}"),
        Quantity::AngularVelocity => format!("{radian}/{time}"),
        Quantity::Acceleration => format!("{length}/{time}²"),
        Quantity::AngularAcceleration => format!("{radian}/{time}²"),
        Quantity::Force => force.to_string(),
        Quantity::Torque => format!("{force}·{length}"),
    }
}

/// The dataset's UNITS names as written (`NONE` without a UNITS statement).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct DatasetUnitsJson {
    pub force: &'static str,
    pub mass: &'static str,
    pub length: &'static str,
    pub time: &'static str,
}

/// The `units` object of every JSON report: the dataset's units and the units of what the
/// report prints (long names; every value of the report is in these units).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct UnitsJson {
    /// `"NEWTON KILOGRAM MILLIMETER SECOND"`, or `"model units (no UNITS statement)"`.
    pub system: String,
    pub dataset: DatasetUnitsJson,
    /// Units consistency factor: `force × UCF = mass × acceleration`.
    pub ucf: f64,
    pub length: String,
    /// `"degree"` where the report prints angles in degrees, `"radian"` otherwise.
    pub angle: String,
    pub time: String,
    pub mass: String,
    pub force: String,
    /// Force × length.
    pub torque: String,
    pub velocity: String,
    /// Always radians per time unit.
    pub angular_velocity: String,
    pub acceleration: String,
    pub angular_acceleration: String,
    /// Frequencies (linear reports): cycles per time unit.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub frequency: Option<String>,
}

/// The `units` object of a report on `model` that prints angles as `angle`; `frequency` for
/// reports that print frequencies (cycles per time unit).
pub fn units_json(model: &Model, angle: Angle, frequency: bool) -> UnitsJson {
    let b = Bases::of(model);
    let long = |q| spell(&b, q, true);
    let [force, mass, length, time] = b.names;
    UnitsJson {
        system: if b.unnamed() {
            "model units (no UNITS statement)".to_string()
        } else {
            b.names.join(" ")
        },
        dataset: DatasetUnitsJson {
            force,
            mass,
            length,
            time,
        },
        ucf: b.ucf,
        length: long(Quantity::Length),
        angle: long(Quantity::Angle(angle)),
        time: long(Quantity::Time),
        mass: b.bases[1].long.to_string(),
        force: long(Quantity::Force),
        torque: long(Quantity::Torque),
        velocity: long(Quantity::Velocity),
        angular_velocity: long(Quantity::AngularVelocity),
        acceleration: long(Quantity::Acceleration),
        angular_acceleration: long(Quantity::AngularAcceleration),
        frequency: frequency.then(|| format!("cycle/{}", b.bases[3].long)),
    }
}

/// The `units:` line of every text report's header (two leading spaces, no newline):
/// `  units: NEWTON KILOGRAM MILLIMETER SECOND (UCF 1000); torque newton·millimeter, angles
/// in degrees`, and the frequencies' unit when the report has them.
pub fn text_line(u: &UnitsJson) -> String {
    let mut s = format!(
        "  units: {} (UCF {}); torque {}, angles in {}s",
        u.system, u.ucf, u.torque, u.angle
    );
    if let Some(f) = &u.frequency {
        s.push_str(&format!(", frequencies in {f}"));
    }
    s
}

/// The unit of a linkage CSV column by its component (the part of its name after the last
/// `.`; `time` for the time column): CM positions and displacements, 3-1-3 angles (degrees),
/// velocities, angular velocities, accelerations, angular accelerations, forces, torques.
fn column_quantity(name: &str) -> Option<Quantity> {
    let component = match name.rsplit_once('.') {
        Some((_, c)) => c,
        None if name == "time" => return Some(Quantity::Time),
        None => return None,
    };
    Some(match component {
        "x" | "y" | "z" => Quantity::Length,
        "psi" | "theta" | "phi" => Quantity::Angle(Angle::Degree),
        "vx" | "vy" | "vz" => Quantity::Velocity,
        "wx" | "wy" | "wz" => Quantity::AngularVelocity,
        "ax" | "ay" | "az" => Quantity::Acceleration,
        "wdx" | "wdy" | "wdz" => Quantity::AngularAcceleration,
        "fx" | "fy" | "fz" | "normal" => Quantity::Force,
        "slip" => Quantity::Velocity,
        "tx" | "ty" | "tz" => Quantity::Torque,
        _ => return None,
    })
}

/// Column headers with their units for the CSVs of a run of `model`.
#[derive(Clone, Debug, PartialEq)]
pub struct CsvUnits(Bases);

impl CsvUnits {
    pub fn of(model: &Model) -> CsvUnits {
        CsvUnits(Bases::of(model))
    }

    /// `name` with its unit, `PART_2.x [mm]`; `name` as it is when its unit is not known.
    pub fn header(&self, name: &str) -> String {
        match column_quantity(name) {
            Some(q) => format!("{name} [{}]", spell(&self.0, q, false)),
            None => name.to_string(),
        }
    }
}

/// The name of a CSV column from its header field: without the ` [unit]` suffix
/// (`PART_2.x [mm]` → `PART_2.x`), surrounding spaces trimmed; a field without a suffix as
/// it is.
pub fn column_name(field: &str) -> &str {
    let field = field.trim();
    match field.strip_suffix(']').and_then(|f| f.rsplit_once(" [")) {
        Some((name, _)) => name.trim_end(),
        None => field,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bases(names: [&'static str; 4]) -> Bases {
        let mut bases = GENERIC;
        for (b, n) in bases.iter_mut().zip(names) {
            if let Some(k) = known(n) {
                *b = k;
            }
        }
        Bases {
            names,
            bases,
            ucf: 1.0,
        }
    }

    #[test]
    fn derived_units_of_a_millimeter_model() {
        let b = bases(["NEWTON", "KILOGRAM", "MILLIMETER", "SECOND"]);
        assert_eq!(spell(&b, Quantity::Torque, true), "newton·millimeter");
        assert_eq!(spell(&b, Quantity::Torque, false), "N·mm");
        assert_eq!(spell(&b, Quantity::Acceleration, false), "mm/s²");
        assert_eq!(spell(&b, Quantity::AngularVelocity, true), "radian/second");
        assert_eq!(spell(&b, Quantity::Angle(Angle::Degree), false), "deg");
    }

    #[test]
    fn a_model_without_units_says_so() {
        let b = bases(["NONE"; 4]);
        assert!(b.unnamed());
        assert_eq!(spell(&b, Quantity::Torque, false), "F·L");
        assert_eq!(
            spell(&b, Quantity::Velocity, true),
            "model length/model time"
        );
    }

    #[test]
    fn csv_columns_carry_their_unit_and_readers_drop_it() {
        let u = CsvUnits(bases(["POUND_FORCE", "POUND_MASS", "INCH", "SECOND"]));
        assert_eq!(u.header("time"), "time [s]");
        assert_eq!(u.header("PART_2.theta"), "PART_2.theta [deg]");
        assert_eq!(u.header("JOINT_1.tz"), "JOINT_1.tz [lbf·in]");
        assert_eq!(u.header("REQUEST_1.wdx"), "REQUEST_1.wdx [rad/s²]");
        assert_eq!(u.header("REQUEST_2.f2"), "REQUEST_2.f2");
        assert_eq!(column_name("JOINT_1.tz [lbf·in]"), "JOINT_1.tz");
        assert_eq!(column_name(" time [s] "), "time");
        assert_eq!(column_name("REQUEST_2.f2"), "REQUEST_2.f2");
        assert_eq!(column_name("odd]"), "odd]");
    }
}
