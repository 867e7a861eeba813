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

/// The text table of reactions: one row per element, `FX FY FZ   TX TY TZ` in
/// [`crate::num::sci`] form, the name column as wide as the longest name. Forces judge their
/// rounding noise against the table's largest force, torques against the largest torque or
/// force (times one length unit).
pub fn reaction_table(s: &mut String, reactions: &[ReactionJson]) {
    use crate::num::{scale_of, sci_in};
    use std::fmt::Write;
    const DIGITS: usize = 7;
    let w = reactions
        .iter()
        .map(|r| r.name.chars().count())
        .max()
        .unwrap_or(0)
        .max(24);
    let _ = writeln!(
        s,
        "   {:<w$} {:>13} {:>13} {:>13}   {:>13} {:>13} {:>13}",
        "element", "FX", "FY", "FZ", "TX", "TY", "TZ"
    );
    let f_scale = scale_of(reactions.iter().flat_map(|r| r.force));
    // A torque is judged against the largest torque or the largest force times one length
    // unit, whichever is larger: joints that carry no torque show the noise of the force
    // arms, not values of their own.
    let t_scale = scale_of(reactions.iter().flat_map(|r| r.torque)).max(f_scale);
    for r in reactions {
        let f = r.force.map(|x| sci_in(x, DIGITS, f_scale));
        let t = r.torque.map(|x| sci_in(x, DIGITS, t_scale));
        let _ = writeln!(
            s,
            "   {:<w$} {:>13} {:>13} {:>13}   {:>13} {:>13} {:>13}",
            r.name, f[0], f[1], f[2], t[0], t[1], t[2]
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
        reaction_table(&mut s, &rows);
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
        reaction_table(&mut s, &rows);
        assert!(!s.contains("E-1"), "{s}");
    }
}
