//! Where an analysis starts, and the one assembly entry point of every front end.
//!
//! An analysis starts from the input ([`Start::Input`]: the dataset's poses and velocities,
//! joint initial conditions and EXACT coordinates) or from where the last analysis of a
//! command file left the model ([`Start::Left`]). [`assemble`] turns that into the assembled
//! problem the stages run on:
//!
//! - from the input, or from a state left on a model whose constraints changed since: the
//!   model is compiled, ranked and assembled (the initial conditions), at the start's time,
//!   with the parts where the start has them ([`placed`]: every velocity given, the joint ICs
//!   and EXACT spent, as in Adams, where they apply to the first assembly only);
//! - from a state left on the same assembly ([`Left::assembly`] kept, nothing changed that
//!   assembly depends on): the assembly is taken over as it is, and the analysis continues
//!   from the left state. Nothing is compiled or assembled again.

use crate::error::Error;
use crate::source::Loaded;
use glam::DVec3;
use linkage_model::{ConstraintKind, Model};
use linkage_solve::coverage::Analysis;
use linkage_solve::pipeline::{Assembled, Assembly};
use linkage_solve::state::State;
use linkage_solve::tolerances::Tolerances;

/// Velocities of every part: CM velocity and angular velocity, ground axes.
pub type Velocities = Vec<(DVec3, DVec3)>;

/// Where the last analysis left the model.
pub struct Left {
    pub state: State,
    pub velocities: Velocities,
    /// The assembly the state was reached on, while nothing assembly depends on has changed
    /// (a command file drops it on DEACTIVATE, a redefinition, IC settings).
    pub assembly: Option<Assembly>,
}

/// Where an analysis starts.
pub enum Start {
    /// The input configuration of the dataset at time 0.
    Input,
    /// Where the last analysis left the model (boxed: a state and an assembly are large).
    Left(Box<Left>),
}

impl Start {
    /// The time the analysis starts at.
    pub fn time(&self) -> f64 {
        match self {
            Start::Input => 0.0,
            Start::Left(l) => l.state.time,
        }
    }
}

/// The assembled problem an analysis runs on, and the state it continues from when it took
/// over the last analysis's assembly.
pub struct Begun<'m> {
    pub assembled: Assembled<'m>,
    /// `Some`: the analysis continues from this state and these velocities (the assembly was
    /// taken over); `None`: it starts from the assembled configuration.
    pub from: Option<(State, Velocities)>,
}

impl Begun<'_> {
    /// Whether the model was compiled and assembled for this analysis (rather than the last
    /// analysis's assembly taken over).
    pub fn assembled_now(&self) -> bool {
        self.from.is_none()
    }

    /// The configuration the analysis starts from.
    pub fn state(&self) -> &State {
        match &self.from {
            Some((s, _)) => s,
            None => self.assembled.state(),
        }
    }
}

/// The model an analysis from `start` assembles: the loaded model for the input, else a copy
/// with the parts placed where the last analysis left them ([`placed`]). `None` when the start
/// keeps its assembly (no model to place: the loaded one is used as it is).
pub fn input_model(loaded: &Loaded, start: &Start) -> Option<Model> {
    match start {
        Start::Left(left) if left.assembly.is_none() => Some(placed(&loaded.model, left)),
        _ => None,
    }
}

/// The one assembly entry point: the analysis `analysis` of `loaded` from `start`, on `model`
/// (what [`input_model`] gave, or `None` for the loaded model). Refused statements are input
/// errors, all at once ([`Loaded::forces`]).
pub fn assemble<'m>(
    loaded: &'m Loaded,
    model: Option<&'m Model>,
    start: Start,
    analysis: Analysis,
) -> Result<Begun<'m>, Error> {
    let forces = loaded.forces(analysis)?;
    let start = match start {
        Start::Left(left) => match *left {
            Left {
                state,
                velocities,
                assembly: Some(assembly),
            } => {
                return Ok(Begun {
                    assembled: Assembled::from_assembly(&loaded.model, forces, assembly),
                    from: Some((state, velocities)),
                })
            }
            left => Start::Left(Box::new(left)),
        },
        Start::Input => Start::Input,
    };
    // The element state the last analysis left (the values its sensors stored, SENVAL)
    // carries on; the frictions start again at the assembled pose, as every IC does.
    let carried = match &start {
        Start::Left(left) => left.state.elements.clone(),
        Start::Input => Default::default(),
    };
    let assembled = Assembled::continuing(
        model.unwrap_or(&loaded.model),
        &loaded.drivers,
        forces,
        &Tolerances::default(),
        start.time(),
        &carried,
    );
    Ok(Begun {
        assembled,
        from: None,
    })
}

/// `model` with its parts where `left` has them and moving as it has them, every velocity
/// given, and the joint initial conditions and EXACT coordinates spent.
pub fn placed(model: &Model, left: &Left) -> Model {
    let mut m = model.clone();
    for (k, p) in m.parts.iter_mut().enumerate() {
        let pose = left.state.poses[k];
        p.p_gb = pose.p;
        p.r_gb = pose.r;
        let (v, w) = left.velocities[k];
        let w_cm = (pose.r * p.r_b_cm).transpose() * w;
        p.velocity = [v.x, v.y, v.z, w_cm.x, w_cm.y, w_cm.z].map(Some);
        p.exact.clear();
    }
    for c in &mut m.constraints {
        if let ConstraintKind::Joint { initial, .. } = &mut c.kind {
            initial.translation = (None, None);
            initial.rotation = (None, None);
        }
    }
    m
}
