//! Forces and measures: applied force elements, joint friction, expression measures, element reactions and
//! REQUEST outputs, the FE_PART modal reduction (`fe_modes`). Read-only: what an element
//! carries from one accepted state to the next is data of the run's `State::elements`.

pub mod applied;
pub mod control_states;
pub mod controls;
pub mod fe_modes;
pub mod flex_inertia;
pub mod forces;
pub mod mass;
pub mod measures;
pub mod reactions;
pub mod requests;
