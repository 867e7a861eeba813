//! `UNITS/`: the unit system or the four units given one by one, and the units consistency
//! factor.

use super::context::Ctx;
use crate::units::{self, Units};
use linkage_adm::{Dataset, Span};

/// Looks up a unit name: SI factor and canonical name.
type UnitLookup = fn(&str) -> Option<(f64, &'static str)>;

/// The model's units. No `UNITS/` (or one with nothing, or `SYSTEM = NONE`): consistent
/// units, UCF 1. Otherwise force, mass, length and time come from `SYSTEM` and are overridden
/// one by one (`FORCE =`, …); those not given are Newton, kilogram, millimetre, second.
/// Errors: an unknown system or unit name, a UCF that is not positive.
pub(crate) fn build_units(ds: &Dataset, cx: &mut Ctx) -> Units {
    let Some(u) = &ds.units else {
        return Units::default();
    };
    let mut names: [Option<(String, Span)>; 4] = [None, None, None, None];
    if let Some(sys) = &u.system {
        match units::system_units(&sys.value) {
            Some(n) => {
                for (slot, name) in names.iter_mut().zip(n) {
                    *slot = Some((name.to_string(), sys.span));
                }
            }
            None if sys.value == "NONE" => {}
            None => cx.error(sys.span, format!("unknown unit system '{}'", sys.value)),
        }
    }
    for (slot, given) in names
        .iter_mut()
        .zip([&u.force, &u.mass, &u.length, &u.time])
    {
        if let Some(g) = given {
            *slot = Some((g.value.clone(), g.span));
        }
    }
    let lookups: [UnitLookup; 4] = [
        units::force_unit,
        units::mass_unit,
        units::length_unit,
        units::time_unit,
    ];
    let defaults = ["NEWTON", "KILOGRAM", "MILLIMETER", "SECOND"];
    let mut out = Units {
        ucf_override: None,
        ..Units::default()
    };
    let mut factors = [1.0; 4];
    let mut all_none = true;
    for k in 0..4 {
        let (name, span) = match &names[k] {
            Some((n, s)) => {
                all_none = false;
                (n.as_str(), Some(*s))
            }
            None => (defaults[k], None),
        };
        match lookups[k](name) {
            Some((f, canon)) => {
                factors[k] = f;
                out.names[k] = canon;
            }
            None => cx.error(
                span.unwrap_or(u.header.span),
                format!("unknown unit '{name}'"),
            ),
        }
    }
    if all_none && u.ucf.is_none() {
        // `UNITS/` with nothing or SYSTEM=NONE: consistent, UCF 1.
        return Units::default();
    }
    out.force = factors[0];
    out.mass = factors[1];
    out.length = factors[2];
    out.time = factors[3];
    if let Some(ucf) = &u.ucf {
        if ucf.value <= 0.0 {
            cx.error(ucf.span, "UCF must be positive");
        }
        out.ucf_override = Some(ucf.value);
    }
    out
}

#[cfg(test)]
mod tests {
    use crate::build::test_support::{build_text, errors_in_order};

    fn ucf(units: &str) -> f64 {
        build_text(&format!("t\nPART/1, GROUND\n{units}\nEND\n"))
            .unwrap_or_else(|e| panic!("{e}"))
            .model
            .ucf()
    }

    #[test]
    fn units_from_a_system_overridden_one_by_one() {
        assert_eq!(ucf(""), 1.0);
        assert_eq!(ucf("UNITS/"), 1.0);
        assert_eq!(ucf("UNITS/, SYSTEM = MKS"), 1.0);
        // Newton, kilogram, millimetre: UCF = 1 / 1e-3.
        assert!((ucf("UNITS/, SYSTEM = MKS, LENGTH = MILLIMETER") - 1000.0).abs() < 1e-9);
        // Not given: Newton, kilogram, millimetre, second.
        assert!((ucf("UNITS/, FORCE = NEWTON") - 1000.0).abs() < 1e-9);
        assert_eq!(ucf("UNITS/, SYSTEM = MKS, UCF = 2"), 2.0);
        let b = build_text("t\nPART/1, GROUND\nUNITS/, SYSTEM = MKS, LENGTH = MILLIMETER\nEND\n")
            .unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(
            b.model.units.names,
            ["NEWTON", "KILOGRAM", "MILLIMETER", "SECOND"]
        );
    }

    #[test]
    fn a_non_positive_ucf_is_an_error() {
        // Unknown names are refused when the dataset is read; the UCF's value here.
        let e = errors_in_order("t\nPART/1, GROUND\nUNITS/, SYSTEM = MKS, UCF = 0\nEND\n");
        assert_eq!(e, [(3, 23, "UCF must be positive".to_string())]);
    }
}
