//! Commands that change the model or its settings: `INTEGRATOR`, `EQUILIBRIUM`, `IC`,
//! `KINEMATICS`, `ACCGRAV` (with `/LIST`), statement redefinitions and
//! `ACTIVATE`/`DEACTIVATE`. Settings that assembly does not read keep the last assembly
//! ([`crate::session::Session::settings`]); a changed model is verified and assembled again by
//! the next analysis.

use super::Place;
use crate::error::RunError;
use crate::listing;
use crate::msg::MessageFile;
use crate::session::Session;
use linkage_adm::commands::Activation;
use linkage_adm::Statement;

/// A command that leaves a model that does not build: the command's place, then every
/// problem found.
pub fn failed_build(place: &Place, d: &linkage_adm::Diagnostics) -> RunError {
    place.refused(format!("the model no longer builds:\n{d}"))
}

/// `INTEGRATOR`, `EQUILIBRIUM`, `IC`, `KINEMATICS` or `ACCGRAV` as the command file's
/// statement `st` gives it (`LIST` prints the settings in force after the change).
pub fn settings(
    session: &mut Session,
    msg: &mut MessageFile,
    place: &Place,
    st: &Statement,
) -> Result<(), RunError> {
    let mut st = st.clone();
    let listed = st.args.iter().any(|a| a.key == "LIST");
    st.args.retain(|a| a.key != "LIST");
    if !st.args.is_empty() {
        session.settings(&st).map_err(|d| failed_build(place, &d))?;
    }
    let model = &session.loaded.model;
    if listed {
        msg.write(&listing::settings(&st.keyword, model))?;
    }
    if st.keyword == "KINEMATICS" {
        msg.write(&format!(
            " Note: KINEMATICS settings are accepted and change nothing: linkage's kinematic \
             analysis solves the positions to {} of the model's size (lengths) or radians, \
             tighter than Adams' default ERROR.",
            linkage_report::num::general(linkage_solve::tolerances::KINEMATIC_POSITION, 6)
        ))?;
    }
    if st.keyword == "INTEGRATOR" && !st.args.is_empty() {
        for note in &model.integrator.notes {
            msg.write(&format!(" Note: {note}"))?;
        }
        for issue in &model.integrator.warnings {
            msg.write(&format!(" Warning: {issue}"))?;
        }
    }
    Ok(())
}

/// A statement redefinition (`MOTION/5, FUNCTION = 2*TIME`).
pub fn redefine(session: &mut Session, place: &Place, st: &Statement) -> Result<(), RunError> {
    session
        .redefine(st)
        .map(|_| ())
        .map_err(|d| failed_build(place, &d))
}

/// `ACTIVATE` (`active`) or `DEACTIVATE` of the elements `a` selects.
pub fn activation(
    session: &mut Session,
    msg: &mut MessageFile,
    place: &Place,
    a: &Activation,
    active: bool,
) -> Result<(), RunError> {
    let keyword = a.element.keyword();
    session
        .set_active(keyword, |id| a.selects(id), active)
        .map_err(|d| failed_build(place, &d))?;
    msg.write(&format!(
        " {} {keyword}: {} element(s) of the dataset are now inactive",
        if active { "Activated" } else { "Deactivated" },
        session.inactive()
    ))
}
