//! Nonlinear finite-element parts (FE_PART, ADM-ELEMENTS §18) in the model.
//!
//! An FE_PART is a chain of nodes joined by two-node beam elements. Each node is a moving
//! body of the model ([`crate::Part`], appended after the dataset's parts and point masses,
//! named `<FE_PART name>.node_<label>`) whose frame is the node frame (x tangent to the beam,
//! y and z the section's axes) and whose centre of mass is the node. So every analysis sees
//! the beam through its ordinary machinery: 6 columns per node, markers on nodes are markers
//! on the node bodies, gravity acts on the node masses, and the elements are force elements
//! (the solver's `fe_beam` law) between consecutive nodes.
//!
//! Mass (lumped, [decided]): node n carries half of each adjacent element,
//! `m_n = ρ·A_n·Σ L_e/2`, and the rotary inertia of that length of section about the node
//! axes, `J_n = ρ·Σ L_e/2 · diag(Iyy + Izz, Iyy, Izz)` (with the product `−ρ·Iyz·ΣL_e/2`
//! between y and z), A and I of the node's own section.
//!
//! 3DCABLE nodes are translational only (as a POINT_MASS: zero rotary inertia, orientation
//! held by a rotation hold whose origin is the FE_PART): a cable has neither bending nor
//! torsion stiffness, so a node rotation would have nothing to hold it.

use crate::bodies::Origin;
use glam::DMat3;
pub use linkage_adm::fe_part::{FeKind, SectionConstants};
use linkage_adm::{Function, Located};

/// Statement keyword of the node bodies and of a cable node's rotation hold.
pub const FE_PART_STATEMENT: &str = "FE_PART";

/// Default number of fixed-boundary normal modes of the equivalent linear flexible body
/// (Adams: 20, changed by the environment variable [`NORMAL_MODES_VARIABLE`]).
pub const DEFAULT_NORMAL_MODES: usize = 20;

/// The environment variable that sets the number of normal modes of the Gruebler count.
pub const NORMAL_MODES_VARIABLE: &str = "MSC_NLFE_MNFSWAP_EIGENVALUES";

/// One node of an FE part.
#[derive(Clone, Debug, PartialEq)]
pub struct FeNode {
    pub label: u64,
    /// The node body: index into [`crate::Model::parts`].
    pub part: usize,
    /// Place along the beam, 0 … 1 (FE_NODE's `S`, else the arc-length fraction of the
    /// polyline through the nodes).
    pub s: f64,
}

/// A two-node beam element between nodes `a` and `b` (indices into [`FePart::nodes`]).
#[derive(Clone, Debug, PartialEq)]
pub struct FeElement {
    pub a: usize,
    pub b: usize,
    /// Undeformed chord length `L₀ = |p_b − p_a|` at the input configuration.
    pub length: f64,
    /// Mean of the two nodes' sections.
    pub section: SectionConstants,
    /// The element's reference frame E₀ (x along the chord, y and z the mean of the node
    /// sections' axes made normal to it) in node a's body axes: `R_aᵀ·E₀`.
    pub r_a_e: DMat3,
    /// E₀ in node b's body axes: `R_bᵀ·E₀`.
    pub r_b_e: DMat3,
}

/// A distributed load (FE_LOAD): force and torque per unit length, components along RM's
/// axes (ground's without RM), lumped on the nodes by their tributary lengths.
#[derive(Clone, Debug, PartialEq)]
pub struct FeLoad {
    pub origin: Origin,
    /// The RM marker (index into [`crate::Model::markers`]).
    pub rm: Option<usize>,
    pub force: [Option<Located<Function>>; 3],
    pub torque: [Option<Located<Function>>; 3],
    pub user: Option<Located<Function>>,
}

/// An FE_PART.
#[derive(Clone, Debug, PartialEq)]
pub struct FePart {
    pub origin: Origin,
    pub kind: FeKind,
    pub nodes: Vec<FeNode>,
    pub elements: Vec<FeElement>,
    /// Tributary length of each node (half of each adjacent element).
    pub tributary: Vec<f64>,
    pub density: f64,
    pub youngs_modulus: f64,
    /// `G = E / (2(1 + ν))`.
    pub shear_modulus: f64,
    /// Rayleigh damping `C = CRATIOM·M + CRATIOK·K`.
    pub cratiok: f64,
    pub cratiom: f64,
    pub loads: Vec<FeLoad>,
}

impl FePart {
    /// Node index (into [`FePart::nodes`]) of model part `part`, if it is one of this part's
    /// nodes.
    pub fn node_of_part(&self, part: usize) -> Option<usize> {
        self.nodes.iter().position(|n| n.part == part)
    }
}

/// The equivalent linear flexible body of the Adams Gruebler count: fixed-boundary normal
/// modes + 6 constraint modes per node that markers use + 6 rigid-body modes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ChapterCount {
    /// Normal modes asked for (20, or the environment variable).
    pub requested: usize,
    /// Degrees of freedom of the nodes no marker uses (the interior of the Craig–Bampton
    /// partition): at most this many normal modes exist.
    pub interior_dof: usize,
    /// `min(requested, interior_dof)`.
    pub normal_modes: usize,
    /// `6 ×` the nodes markers use.
    pub constraint_modes: usize,
    /// 6.
    pub rigid_modes: usize,
}

impl ChapterCount {
    /// The count for a part of `dof_per_node`-DOF nodes, `nodes` in all, `boundary` of them
    /// used by markers, `requested` normal modes.
    pub fn new(nodes: usize, boundary: usize, dof_per_node: usize, requested: usize) -> Self {
        let interior_dof = dof_per_node * nodes.saturating_sub(boundary);
        ChapterCount {
            requested,
            interior_dof,
            normal_modes: requested.min(interior_dof),
            constraint_modes: dof_per_node * boundary,
            rigid_modes: 6,
        }
    }

    /// Degrees of freedom counted for the part.
    pub fn total(&self) -> usize {
        self.normal_modes + self.constraint_modes + self.rigid_modes
    }
}

/// The number of normal modes the Gruebler count uses: the value of
/// [`NORMAL_MODES_VARIABLE`] when it is a non-negative integer, else
/// [`DEFAULT_NORMAL_MODES`]. (Tests pass the value to [`ChapterCount::new`] instead.)
pub fn requested_normal_modes() -> usize {
    normal_modes_from(std::env::var(NORMAL_MODES_VARIABLE).ok().as_deref())
}

/// [`requested_normal_modes`] from the variable's value.
pub fn normal_modes_from(value: Option<&str>) -> usize {
    value
        .and_then(|v| v.trim().parse::<usize>().ok())
        .unwrap_or(DEFAULT_NORMAL_MODES)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chapter_count_is_modes_plus_constraint_modes_plus_six() {
        // 21 nodes, markers on 2 of them: 20 + 12 + 6.
        let c = ChapterCount::new(21, 2, 6, 20);
        assert_eq!(c.total(), 38);
        // Fewer interior DOF than modes asked for: the interior limits them.
        let c = ChapterCount::new(6, 3, 6, 20);
        assert_eq!((c.normal_modes, c.total()), (18, 42));
        assert_eq!(normal_modes_from(Some("8")), 8);
        assert_eq!(normal_modes_from(Some("x")), 20);
        assert_eq!(normal_modes_from(None), 20);
    }
}
