//! Dataset → [`Model`]: resolve references, place frames, move inertia to the centre of mass.
//!
//! One builder per statement family, called in a fixed order (the order of the diagnostics):
//! units, parts, markers, mass properties, joints and primitives, couplers and gears, motions,
//! general constraints, force elements, data elements (FE parts right after the markers:
//! their nodes are parts, the markers on them re-placed, [`fe_parts`]); then, for a model
//! without errors, the
//! analysis settings (IC, EQUILIBRIUM, INTEGRATOR). Every problem is collected (not just the
//! first) and returned as diagnostics carrying the position of the offending argument or
//! statement.

mod contacts;
mod context;
mod controls;
mod couplings;
mod curves;
mod cvcvs;
mod data;
pub mod fe_parts;
pub mod flex_bodies;
pub use controls::{read_adamsmat, MatrixFileError, ValuesError};
mod forces;
mod friction;
mod joints;
mod lookup;
mod markers;
mod mass;
mod motions;
mod parts;
pub mod point_masses;
pub(crate) mod references;
mod sensors;
mod units;
mod vector_forces;

use crate::forces::ForceElement;
use crate::functions::UserRoutines;
use crate::model::{Constraint, Model};
use context::{v3, Ctx};
use glam::DVec3;
use linkage_adm::{Dataset, Diagnostic, Diagnostics};
use lookup::MarkerTable;

/// Relative tolerance of the inertia validity check (principal moments, triangle inequality).
pub const INERTIA_RELATIVE_TOLERANCE: f64 = 1e-9;

/// Statement kinds the builder reads only in their typed form ([`Dataset::parts`],
/// [`Dataset::markers`], …), never as raw statements ([`Dataset::statements`]). They are the bulk of a large model, so dropping them
/// before building means a large model is never held as text, raw statements and model at
/// once. (Elements typed on demand from their raw statements — settings, GRAPHICS, contacts,
/// finite-element parts, control elements — must not be listed here.)
pub const TYPED_ONLY: [&str; 5] = ["PART", "MARKER", "JOINT", "JPRIM", "MOTION"];

/// The model and the non-fatal findings made while building it (dataset warnings included).
pub struct Built {
    pub model: Model,
    pub warnings: Vec<Diagnostic>,
}

/// Builds the model. Errors: unknown or duplicate ids, a joint whose markers are on the same
/// part, zero or several GROUND parts, negative mass, non-physical inertia, markers on
/// carriers linkage does not model (FLEX_BODY) used by constraints or
/// forces, invalid force or data elements ([`crate::forces`]), …
pub fn build_model(ds: &Dataset) -> Result<Built, Diagnostics> {
    build_model_with(ds, &UserRoutines::default())
}

/// [`build_model`] with the `USER(…)` calls linked through `user` (the subroutine libraries
/// the user gave).
pub fn build_model_with(ds: &Dataset, user: &UserRoutines) -> Result<Built, Diagnostics> {
    let mut cx = Ctx {
        user: user.clone(),
        file: ds.file.clone(),
        errors: Vec::new(),
        warnings: ds.warnings.clone(),
    };
    let units = units::build_units(ds, &mut cx);
    let gravity = ds.accgrav.as_ref().map_or(DVec3::ZERO, |g| v3(g.gravity));
    let part_statements = parts::parts(ds, &mut cx);
    let mut marker_statements = markers::markers(ds, &part_statements, &mut cx);
    let (mut parts, cm_in_bcs) = mass::moving_parts(&part_statements, &marker_statements, &mut cx);
    let mut markers = mass::body_markers(&marker_statements, &cm_in_bcs);
    let fe_parts = fe_parts::fe_parts(
        ds,
        &mut parts,
        &mut markers,
        &mut marker_statements,
        &mut cx,
    );
    let mut flex_bodies = flex_bodies::flex_bodies(
        ds,
        &units,
        gravity,
        &mut parts,
        &mut markers,
        &mut marker_statements,
        &mut cx,
    );
    let ground_name = part_statements.ground_name();
    let table = MarkerTable {
        index: &marker_statements.index,
        markers: &markers,
        placed: &marker_statements.placed,
        parts: &parts,
        ground_name: &ground_name,
    };
    let mut constraints = constraints(ds, &table, &mut cx);
    let mut forces = force_elements(ds, &table, &mut cx);
    let graphics = crate::graphics::resolve_graphics(ds, &markers, &mut cx.warnings);
    let data = data::data_elements(ds, &mut cx);
    let sensors = sensors::sensors(ds, &mut cx);
    let frictions = friction::frictions(ds, &constraints, &parts, &markers, &mut cx);
    let controls = controls::controls(ds, &data.variables, &data.arrays, &mut cx);
    let (curves, curve_index) = curves::curves(ds, &controls.matrices, &mut cx);
    curves::ptcvs(ds, &table, &curve_index, &mut cx, &mut constraints);
    cvcvs::cvcvs(ds, &table, &curve_index, &curves, &mut cx, &mut constraints);
    let curve_of = contacts::CurveLookup {
        index: &curve_index,
        curves: &curves,
    };
    forces.extend(contacts::contacts(
        ds, &graphics, &markers, &curve_of, &mut cx,
    ));
    point_masses::check_translational_use(&parts, &markers, &constraints, &forces, &mut cx);
    point_masses::hold_rotations(&parts, &mut markers, &mut constraints);
    flex_bodies::attach(
        &mut flex_bodies,
        &parts,
        &mut markers,
        &mut constraints,
        &mut forces,
    );
    references::check(
        ds,
        &references::Known::new(ds, &marker_statements.index),
        &mut cx,
    );
    if !cx.errors.is_empty() {
        return Err(Diagnostics(cx.errors));
    }
    let ic = crate::settings::ic_settings(ds, &ds.file, &mut cx.warnings);
    let equilibrium = crate::settings::equilibrium_settings(ds, &ds.file, &mut cx.warnings);
    let mut model = Model {
        file: ds.file.clone(),
        title: ds.title.clone(),
        units,
        gravity,
        ground_name,
        parts,
        markers,
        constraints,
        forces,
        variables: data.variables,
        arrays: data.arrays,
        splines: data.splines,
        sensors,
        frictions,
        controls,
        characteristic_length: 1.0,
        ic,
        equilibrium,
        integrator: crate::settings::integrator::resolve_integrator(ds),
        requests: Default::default(),
        graphics,
        fe_parts,
        curves,
        flex_bodies,
        user: user.clone(),
    };
    model.characteristic_length = characteristic_length(&model);
    model.requests =
        crate::requests::resolve_requests(&model.markers, &model.forces, ds, &model.user);
    Ok(Built {
        model,
        warnings: cx.warnings,
    })
}

/// Every constraint, in the order joints, primitives, couplers, gears, motions, general
/// constraints (definition order within each kind); the point masses' rotation holds
/// ([`point_masses`]) are appended after them.
fn constraints(ds: &Dataset, table: &MarkerTable, cx: &mut Ctx) -> Vec<Constraint> {
    let mut constraints = Vec::new();
    let joint_index = joints::joints(ds, table, cx, &mut constraints);
    joints::jprims(ds, table, cx, &mut constraints);
    couplings::couplers(ds, &joint_index, cx, &mut constraints);
    couplings::gears(ds, table, &joint_index, cx, &mut constraints);
    motions::motions(ds, table, &joint_index, cx, &mut constraints);
    motions::gcons(ds, table, cx, &mut constraints);
    constraints
}

/// Every force element: the two-marker ones (SFORCE, SPRINGDAMPER, BUSHING, FIELD, BEAM),
/// then VFORCE, VTORQUE, GFORCE.
fn force_elements(ds: &Dataset, table: &MarkerTable, cx: &mut Ctx) -> Vec<ForceElement> {
    let mut rs = forces::Resolver { cx, table };
    let mut out = Vec::new();
    forces::two_marker_elements(ds, &mut rs, &mut out);
    vector_forces::vector_elements(ds, &mut rs, &mut out);
    out
}

/// Diagonal of the bounding box of the fixed markers and the centres of mass at the input
/// configuration; 1 when that is zero (a single point) or not finite.
fn characteristic_length(m: &Model) -> f64 {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for k in 0..m.markers.len() {
        if m.markers[k].floating {
            continue;
        }
        let (p, _) = m.marker_in_ground(k);
        lo = lo.min(p);
        hi = hi.max(p);
    }
    for p in &m.parts {
        lo = lo.min(p.p_gb);
        hi = hi.max(p.p_gb);
    }
    let d = (hi - lo).length();
    if d.is_finite() && d > 0.0 {
        d
    } else {
        1.0
    }
}

#[cfg(test)]
mod test_support;

#[cfg(test)]
mod tests {
    use super::test_support::{build_text, errors_in_order, ok, BASE};
    use crate::settings::{IntegratorIssue, IntegratorNote};

    #[test]
    fn errors_come_in_the_order_of_the_statement_families() {
        // Written in the reverse order of the builders: reported in builder order.
        let e = errors_in_order("t\nVARIABLE/1\nSFORCE/1, I = 9, J = 1, FUNCTION = 1\nJOINT/1, REVOLUTE, I = 9, J = 1\nMARKER/1, PART = 7\nPART/1, GROUND\nUNITS/, UCF = -1\nEND\n");
        let lines: Vec<u32> = e.iter().map(|(line, _, _)| *line).collect();
        assert_eq!(lines, [7, 5, 4, 3, 2], "{e:?}");
    }

    #[test]
    fn characteristic_length_is_the_bounding_box_diagonal() {
        // Markers at (0,0,0), (1,0,0), (0,2,0), (1,2,0) and CMs at (0,2,0) and (0,0,0);
        // floating markers do not count.
        let b = ok("");
        assert!((b.model.characteristic_length - 5f64.sqrt()).abs() < 1e-15);
        let single = build_text("t\nPART/1, GROUND\nEND\n").unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(single.model.characteristic_length, 1.0);
        assert!(BASE.starts_with("title"));
    }

    #[test]
    fn integrator_is_resolved_with_the_model_and_warns_nowhere_else() {
        let b = ok("INTEGRATOR/HASTIFF, ERROR = 1E-5, HMAX = -1, KMAX = 6, INTERPOLATE = ON");
        let integrator = &b.model.integrator;
        assert_eq!(integrator.settings.error, 1e-5);
        assert_eq!(integrator.settings.hmax, None);
        assert_eq!(
            integrator.notes,
            [
                IntegratorNote::MappedToBdf {
                    name: "HASTIFF".into(),
                    kmax: 6
                },
                IntegratorNote::WithoutEffect {
                    arguments: vec!["INTERPOLATE".into()]
                }
            ]
        );
        assert_eq!(
            integrator.warnings,
            [IntegratorIssue::NotPositive {
                key: "HMAX",
                value: -1.0
            }]
        );
        // Only `simulate` reports them: the build's own warnings do not carry them.
        assert!(b.warnings.is_empty(), "{:?}", b.warnings);
    }
}
