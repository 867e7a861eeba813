//! Constraint reactions as every report shows them: force and torque on the I marker, in
//! ground axes, named after their element.

use crate::poses::a3;
use linkage_model::Model;
use linkage_solve::physics::reactions::Reaction;
use serde::Serialize;

#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct ReactionJson {
    pub name: String,
    pub element: String,
    #[serde(rename = "type")]
    pub kind: String,
    /// Force on the I marker, ground axes, model force units.
    pub force: [f64; 3],
    /// Torque about the I marker origin, ground axes, model force × length units.
    pub torque: [f64; 3],
}

/// Reactions named for reports.
pub fn reactions_json(model: &Model, reactions: &[Reaction]) -> Vec<ReactionJson> {
    reactions
        .iter()
        .map(|r| {
            let c = &model.constraints[r.element];
            ReactionJson {
                name: c.origin.name.clone(),
                element: c.origin.element(),
                kind: c.description().to_string(),
                force: a3(r.force),
                torque: a3(r.torque),
            }
        })
        .collect()
}

/// The model's force scale: the weight of its parts, `Σ m·|g| / UCF`, in its force unit (0
/// without gravity). A reaction far below it is rounding noise even when every reaction of a
/// table is (an unloaded mechanism's `1e-26 lbf`).
pub fn weight_scale(model: &Model) -> f64 {
    let mass: f64 = model.parts.iter().map(|p| p.mass.abs()).sum();
    let weight = mass * model.gravity.length() / model.ucf();
    if weight.is_finite() {
        weight
    } else {
        0.0
    }
}

/// The text table of reactions: one row per element, `FX FY FZ   TX TY TZ` in
/// [`crate::num::sci`] form, the name column as wide as the longest name. Forces judge their
/// rounding noise against the table's largest force or the model's force scale `model_force`
/// ([`weight_scale`]), whichever is larger; torques against the largest torque or that force
/// scale (times one length unit). A column or row whose values are all noise (printed as 0, not
/// all exactly 0) is named on a line after the table.
pub fn reaction_table(s: &mut String, reactions: &[ReactionJson], model_force: f64) {
    use crate::num::{denoise, scale_of, sci, sci_in, NOISE_RELATIVE};
    use std::fmt::Write;
    const DIGITS: usize = 7;
    const COLUMNS: [&str; 6] = ["FX", "FY", "FZ", "TX", "TY", "TZ"];
    let w = reactions
        .iter()
        .map(|r| r.name.chars().count())
        .max()
        .unwrap_or(0)
        .max(24);
    let _ = writeln!(
        s,
        "   {:<w$} {:>13} {:>13} {:>13}   {:>13} {:>13} {:>13}",
        "element", COLUMNS[0], COLUMNS[1], COLUMNS[2], COLUMNS[3], COLUMNS[4], COLUMNS[5]
    );
    let f_scale = scale_of(reactions.iter().flat_map(|r| r.force)).max(model_force);
    // A torque is judged against the largest torque or the largest force times one length
    // unit, whichever is larger: joints that carry no torque show the noise of the force
    // arms, not values of their own.
    let t_scale = scale_of(reactions.iter().flat_map(|r| r.torque)).max(f_scale);
    let six = |r: &ReactionJson| {
        let (f, t) = (r.force, r.torque);
        [f[0], f[1], f[2], t[0], t[1], t[2]]
    };
    let scales = [f_scale, f_scale, f_scale, t_scale, t_scale, t_scale];
    // Noise only: every value printed as 0, not every value exactly 0.
    let noise = |values: &mut dyn Iterator<Item = (f64, f64)>| {
        let (mut any, mut all) = (false, true);
        for (x, scale) in values {
            any |= x != 0.0;
            all &= denoise(x, scale) == 0.0;
        }
        any && all
    };
    let mut noisy_rows = Vec::new();
    for r in reactions {
        let v = six(r);
        let f = [0, 1, 2].map(|k| sci_in(v[k], DIGITS, f_scale));
        let t = [3, 4, 5].map(|k| sci_in(v[k], DIGITS, t_scale));
        let _ = writeln!(
            s,
            "   {:<w$} {:>13} {:>13} {:>13}   {:>13} {:>13} {:>13}",
            r.name, f[0], f[1], f[2], t[0], t[1], t[2]
        );
        if noise(&mut v.into_iter().zip(scales)) {
            noisy_rows.push(r.name.as_str());
        }
    }
    let noisy_columns: Vec<&str> = (0..6)
        .filter(|&k| noise(&mut reactions.iter().map(|r| (six(r)[k], scales[k]))))
        .map(|k| COLUMNS[k])
        .collect();
    let floor = format!(
        "below {NOISE_RELATIVE:e} of the force scale {}",
        sci(f_scale, 4)
    );
    if !noisy_columns.is_empty() {
        let _ = writeln!(
            s,
            "   {}: rounding noise only ({floor}), printed as 0",
            noisy_columns.join(", ")
        );
    }
    if !noisy_rows.is_empty() {
        let _ = writeln!(
            s,
            "   {}: no load, rounding noise only ({floor}), printed as 0",
            noisy_rows.join(", ")
        );
    }
}

#[cfg(test)]
mod table_tests {
    use super::*;

    fn reaction(name: &str, force: [f64; 3], torque: [f64; 3]) -> ReactionJson {
        ReactionJson {
            name: name.to_string(),
            element: String::new(),
            kind: String::new(),
            force,
            torque,
        }
    }

    #[test]
    fn columns_align_with_long_names_and_noise_is_zero() {
        let rows = [
            reaction("crank_pivot", [5.160884, 30.56784, 0.0], [0.0; 3]),
            reaction(
                "a_joint_with_a_rather_long_name_indeed",
                [-5.993613, 12.87585, -0.0],
                [0.0, 0.0, -5.329071e-15],
            ),
            reaction("crank_drive", [0.0; 3], [0.0, 0.0, 8.362802]),
        ];
        let mut s = String::new();
        reaction_table(&mut s, &rows, 0.0);
        let lines: Vec<&str> = s.lines().collect();
        assert_eq!(lines.len(), 4);
        // Every row has the same length: the columns line up.
        assert!(lines.iter().all(|l| l.len() == lines[0].len()), "{s}");
        assert!(lines[1].contains(" 5.160884E+00  3.056784E+01  0.000000E+00"));
        // The torque at 6e-16 of the largest torque is printed as zero, without a sign.
        assert!(
            lines[2].ends_with(" 0.000000E+00  0.000000E+00  0.000000E+00"),
            "{s}"
        );
        assert!(lines[3].ends_with(" 8.362802E+00"));
        assert!(!s.contains("-0.000000E+00"));
        // Torques of joints that carry none, at the noise of the forces' arms.
        let rows = [
            reaction(
                "pivot",
                [16.43132, 31.8389, 0.0],
                [9.809354e-12, -1.116505e-11, 0.0],
            ),
            reaction(
                "rocker",
                [4.707578, -38.81407, 0.0],
                [0.0, 0.0, -1.332268e-14],
            ),
        ];
        let mut s = String::new();
        reaction_table(&mut s, &rows, 0.0);
        assert!(!s.contains("E-1"), "{s}");
    }

    #[test]
    fn an_unloaded_mechanism_prints_zero_reactions_and_says_they_are_noise() {
        // Every reaction at 1e-26 (rounding of an unloaded joint); the parts weigh 19.62 N.
        let rows = [
            reaction("pin", [1.2e-26, -3.4e-26, 0.0], [0.0, 0.0, 5.0e-27]),
            reaction("slider", [0.0, 2.0e-26, 0.0], [0.0; 3]),
        ];
        let mut s = String::new();
        reaction_table(&mut s, &rows, 19.62);
        assert!(!s.contains("E-2"), "{s}");
        let lines: Vec<&str> = s.lines().collect();
        assert!(
            lines[1].contains(" 0.000000E+00  0.000000E+00  0.000000E+00"),
            "{s}"
        );
        // The columns with noise (FX, FY, TZ: not FZ, TX, TY, which are exactly 0) and
        // both rows are named.
        assert_eq!(
            lines[3],
            "   FX, FY, TZ: rounding noise only (below 1e-11 of the force scale 1.962E+01), \
             printed as 0"
        );
        assert!(
            lines[4].starts_with("   pin, slider: no load, rounding noise only"),
            "{s}"
        );
        // Without the model's scale the table's own largest value is the scale: 1e-26 would
        // print as a result.
        let mut s = String::new();
        reaction_table(&mut s, &rows, 0.0);
        assert!(s.contains("-3.400000E-26"), "{s}");
    }

    #[test]
    fn the_force_scale_of_a_model_is_the_weight_of_its_parts() {
        let ds = linkage_adm::parse_dataset(
            std::sync::Arc::from("m.adm"),
            "m\nUNITS/, FORCE = NEWTON, MASS = KILOGRAM, LENGTH = MILLIMETER, TIME = SECOND\n\
             PART/1, GROUND\nPART/2, MASS = 2, IP = 1, 1, 1\n\
             PART/3, MASS = 0.5, IP = 1, 1, 1\nACCGRAV/, JGRAV = -9806.65\nEND\n",
        )
        .expect("parses");
        let model = linkage_model::build_model(&ds).expect("builds").model;
        // 2.5 kg × 9.80665 m/s² in newtons (g in mm/s², UCF 1000).
        assert!((weight_scale(&model) - 2.5 * 9.80665).abs() < 1e-9);
    }
}
