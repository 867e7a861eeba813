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
                kind: c.description(),
                force: a3(r.force),
                torque: a3(r.torque),
            }
        })
        .collect()
}
