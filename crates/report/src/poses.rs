//! Where the parts are, and how they move, as every report shows them: centre of mass in
//! ground and body 3-1-3 angles in degrees, velocities and accelerations in ground axes.

use linkage_model::frames::matrix_to_euler313;
use linkage_model::Model;
use linkage_solve::state::State;
use serde::Serialize;

#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct PartPoseJson {
    pub name: String,
    /// Centre of mass in ground coordinates.
    pub position: [f64; 3],
    /// Body 3-1-3 angles of the part's BCS in degrees.
    pub reuler: [f64; 3],
}

#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct PartStateJson {
    pub name: String,
    /// Centre of mass in ground.
    pub position: [f64; 3],
    /// 3-1-3 body angles of the part's axes in degrees.
    pub reuler: [f64; 3],
    /// CM velocity and angular velocity, ground axes.
    pub velocity: [f64; 3],
    pub angular_velocity: [f64; 3],
    /// CM acceleration and angular acceleration, ground axes (`null` when not computed).
    pub acceleration: Option<[f64; 3]>,
    pub angular_acceleration: Option<[f64; 3]>,
}

/// A vector as a JSON array.
pub(crate) fn a3(v: glam::DVec3) -> [f64; 3] {
    [v.x, v.y, v.z]
}

/// Poses of every part at `s`.
pub fn part_poses(model: &Model, s: &State) -> Vec<PartPoseJson> {
    model
        .parts
        .iter()
        .enumerate()
        .map(|(k, p)| PartPoseJson {
            name: p.origin.name.clone(),
            position: a3(s.poses[k].p),
            reuler: matrix_to_euler313(&s.poses[k].r).map(f64::to_degrees),
        })
        .collect()
}

/// Every part's state: pose at `state`, `velocities` and (when known) `accelerations`, each a
/// `(CM, angular)` pair per part in ground axes.
pub fn part_states(
    model: &Model,
    state: &State,
    velocities: &[(glam::DVec3, glam::DVec3)],
    accelerations: Option<&[(glam::DVec3, glam::DVec3)]>,
) -> Vec<PartStateJson> {
    part_poses(model, state)
        .into_iter()
        .enumerate()
        .map(|(k, pose)| PartStateJson {
            name: pose.name,
            position: pose.position,
            reuler: pose.reuler,
            velocity: a3(velocities[k].0),
            angular_velocity: a3(velocities[k].1),
            acceleration: accelerations.map(|a| a3(a[k].0)),
            angular_acceleration: accelerations.map(|a| a3(a[k].1)),
        })
        .collect()
}

/// `   name   (x, y, z)   (ψ, θ, φ)`: a part's centre of mass and 3-1-3 angles (degrees) in
/// the text reports.
pub fn pose_line(name: &str, position: [f64; 3], reuler: [f64; 3]) -> String {
    let p = position.map(|x| fixed(x, 6));
    let a = reuler.map(|x| fixed(x, 4));
    format!(
        "   {:<24} ({}, {}, {})   ({}, {}, {})",
        name, p[0], p[1], p[2], a[0], a[1], a[2]
    )
}

/// `x` with `decimals` decimals, never `-0.000…` (a value that rounds to zero prints as 0).
pub(crate) fn fixed(x: f64, decimals: usize) -> String {
    let s = format!("{x:.decimals$}");
    if s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.') {
        s[1..].to_string()
    } else {
        s
    }
}

#[cfg(test)]
mod fixed_tests {
    #[test]
    fn negative_zero_is_not_printed() {
        assert_eq!(super::fixed(-1e-17, 6), "0.000000");
        assert_eq!(super::fixed(-0.25, 6), "-0.250000");
        assert_eq!(super::fixed(-0.0, 4), "0.0000");
    }
}
