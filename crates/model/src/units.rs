//! Units and the units consistency factor (UCF): `force × UCF = mass × acceleration`, all in
//! model units. From SI factors f (model unit in SI units): `UCF = f_F · f_T² / (f_M · f_L)`.

/// SI value of one model unit of each kind.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Units {
    pub force: f64,
    pub mass: f64,
    pub length: f64,
    pub time: f64,
    /// Names as written (for reports), e.g. `["NEWTON", "KILOGRAM", "METER", "SECOND"]`.
    pub names: [&'static str; 4],
    /// An explicit `UCF=` overrides the derived factor.
    pub ucf_override: Option<f64>,
}

impl Default for Units {
    /// Adams' default system when no UNITS statement is given: consistent (UCF = 1); reported
    /// as NONE.
    fn default() -> Self {
        Units {
            force: 1.0,
            mass: 1.0,
            length: 1.0,
            time: 1.0,
            names: ["NONE"; 4],
            ucf_override: Some(1.0),
        }
    }
}

impl Units {
    /// Units consistency factor.
    pub fn ucf(&self) -> f64 {
        self.ucf_override
            .unwrap_or(self.force * self.time * self.time / (self.mass * self.length))
    }
}

const LBF: f64 = 4.448_221_615_260_5;
const LBM: f64 = 0.453_592_37;

/// SI factor of a force unit name (full upper-case Adams name).
pub fn force_unit(name: &str) -> Option<(f64, &'static str)> {
    Some(match name {
        "NEWTON" => (1.0, "NEWTON"),
        "KNEWTON" => (1e3, "KNEWTON"),
        "MEGANEWTON" => (1e6, "MEGANEWTON"),
        "CENTINEWTON" => (1e-2, "CENTINEWTON"),
        "MILLINEWTON" => (1e-3, "MILLINEWTON"),
        "MICRONEWTON" => (1e-6, "MICRONEWTON"),
        "NANONEWTON" => (1e-9, "NANONEWTON"),
        "DYNE" => (1e-5, "DYNE"),
        "KILOGRAM_FORCE" => (9.806_65, "KILOGRAM_FORCE"),
        "POUND_FORCE" => (LBF, "POUND_FORCE"),
        "KPOUND_FORCE" => (1e3 * LBF, "KPOUND_FORCE"),
        "OUNCE_FORCE" => (LBF / 16.0, "OUNCE_FORCE"),
        "POUNDAL" => (LBM * 0.3048, "POUNDAL"),
        _ => return None,
    })
}

/// SI factor of a mass unit name.
pub fn mass_unit(name: &str) -> Option<(f64, &'static str)> {
    Some(match name {
        "KILOGRAM" => (1.0, "KILOGRAM"),
        "GRAM" => (1e-3, "GRAM"),
        "MILLIGRAM" => (1e-6, "MILLIGRAM"),
        "MICROGRAM" => (1e-9, "MICROGRAM"),
        "NANOGRAM" => (1e-12, "NANOGRAM"),
        "TONNE" => (1e3, "TONNE"),
        "POUND_MASS" => (LBM, "POUND_MASS"),
        "KPOUND_MASS" => (1e3 * LBM, "KPOUND_MASS"),
        "OUNCE_MASS" => (LBM / 16.0, "OUNCE_MASS"),
        "SLUG" => (LBF / 0.3048, "SLUG"),
        "SLINCH" => (LBF / 0.0254, "SLINCH"),
        "US_TON" => (2000.0 * LBM, "US_TON"),
        _ => return None,
    })
}

/// SI factor of a length unit name.
pub fn length_unit(name: &str) -> Option<(f64, &'static str)> {
    Some(match name {
        "METER" => (1.0, "METER"),
        "KILOMETER" => (1e3, "KILOMETER"),
        "CENTIMETER" => (1e-2, "CENTIMETER"),
        "MILLIMETER" => (1e-3, "MILLIMETER"),
        "MICROMETER" => (1e-6, "MICROMETER"),
        "NANOMETER" => (1e-9, "NANOMETER"),
        "ANGSTROM" => (1e-10, "ANGSTROM"),
        "INCH" => (0.0254, "INCH"),
        "FOOT" => (0.3048, "FOOT"),
        "YARD" => (0.9144, "YARD"),
        "MILE" => (1609.344, "MILE"),
        "MILS" => (2.54e-5, "MILS"),
        "MICROINCH" => (2.54e-8, "MICROINCH"),
        _ => return None,
    })
}

/// SI factor of a time unit name.
pub fn time_unit(name: &str) -> Option<(f64, &'static str)> {
    Some(match name {
        "SECOND" => (1.0, "SECOND"),
        "MILLISECOND" | "MILLISECONDS" => (1e-3, "MILLISECOND"),
        "MICROSECOND" => (1e-6, "MICROSECOND"),
        "NANOSECOND" => (1e-9, "NANOSECOND"),
        "MINUTE" => (60.0, "MINUTE"),
        "HOUR" => (3600.0, "HOUR"),
        "DAY" => (86400.0, "DAY"),
        _ => return None,
    })
}

/// `SYSTEM=` shorthands: (force, mass, length, time) names.
pub fn system_units(name: &str) -> Option<[&'static str; 4]> {
    Some(match name {
        "MKS" => ["NEWTON", "KILOGRAM", "METER", "SECOND"],
        "CGS" => ["DYNE", "GRAM", "CENTIMETER", "SECOND"],
        "FPS" => ["POUND_FORCE", "POUND_MASS", "FOOT", "SECOND"],
        "IPS" => ["POUND_FORCE", "POUND_MASS", "INCH", "SECOND"],
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn units(f: &str, m: &str, l: &str, t: &str) -> Units {
        Units {
            force: force_unit(f).unwrap().0,
            mass: mass_unit(m).unwrap().0,
            length: length_unit(l).unwrap().0,
            time: time_unit(t).unwrap().0,
            names: ["", "", "", ""],
            ucf_override: None,
        }
    }

    #[test]
    fn ucf_of_common_systems() {
        assert!((units("NEWTON", "KILOGRAM", "METER", "SECOND").ucf() - 1.0).abs() < 1e-15);
        assert!((units("NEWTON", "KILOGRAM", "MILLIMETER", "SECOND").ucf() - 1000.0).abs() < 1e-9);
        // lbf-lbm-in-s: g_c = 386.088 lbm·in/(lbf·s²) (ADM-REFERENCE §2.1).
        assert!(
            (units("POUND_FORCE", "POUND_MASS", "INCH", "SECOND").ucf() - 386.0886).abs() < 1e-3
        );
        // lbf-slug-ft-s is consistent.
        assert!((units("POUND_FORCE", "SLUG", "FOOT", "SECOND").ucf() - 1.0).abs() < 1e-12);
        // FAST's kN-kg-m-s is not: UCF = 1000.
        assert!((units("KNEWTON", "KILOGRAM", "METER", "SECOND").ucf() - 1000.0).abs() < 1e-9);
    }
}
