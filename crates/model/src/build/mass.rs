//! Mass properties of the moving parts: mass, centre of mass (CM marker), inertia (IP about
//! the IM marker's axes) moved to the centre of mass; then every marker re-expressed in its
//! part's body frame, whose origin is the centre of mass.

use super::context::{origin, Ctx};
use super::markers::MarkerStatements;
use super::parts::PartStatements;
use super::INERTIA_RELATIVE_TOLERANCE;
use crate::bodies::{Body, Marker, Part};
use crate::inertia::{
    check_physical, rotate_tensor, tensor_from_ip, to_centre_of_mass, InertiaDefect,
};
use glam::{DMat3, DVec3};
use linkage_adm::IdRef;

/// The moving parts with their mass properties, and each part's centre of mass in its BCS.
/// Errors: a negative or non-finite mass, a CM or IM marker that does not exist or is on
/// another part, an inertia with a negative principal moment. Warnings: an inertia that
/// breaks the triangle inequality (used as given), MASS without IP.
pub(crate) fn moving_parts(
    parts: &PartStatements,
    markers: &MarkerStatements,
    cx: &mut Ctx,
) -> (Vec<Part>, Vec<DVec3>) {
    let mut out = Vec::with_capacity(parts.moving.len());
    let mut cm_in_bcs = Vec::with_capacity(parts.moving.len());
    for (k, p) in parts.moving.iter().enumerate() {
        let name = p.header.name.as_str();
        let mass = mass(p, cx);
        let cm = p
            .cm
            .and_then(|r| marker_on_part(markers, cx, r, k, "CM", name));
        let c = cm.map_or(DVec3::ZERO, |m| markers.placed[m].p);
        let im = match p.im {
            Some(r) => marker_on_part(markers, cx, r, k, "IM", name),
            None => cm,
        };
        let inertia = inertia_about_cm(p, mass, c, im.map(|m| &markers.placed[m]), cx);
        if mass > 0.0 && p.ip.is_none() {
            cx.warn(
                p.header.span,
                format!("{name}: MASS given without IP: its inertia is zero"),
            );
        }
        let (qg, r) = parts.bcs[k];
        cm_in_bcs.push(c);
        out.push(Part {
            origin: origin("PART", &p.header),
            mass,
            inertia,
            p_gb: qg + r * c,
            r_gb: r,
            p_b_bcs: -c,
            velocity: p.velocity,
            r_b_cm: cm.map_or(DMat3::IDENTITY, |m| markers.placed[m].r),
            exact: p.exact.clone(),
        });
    }
    (out, cm_in_bcs)
}

/// `MASS` (0 when not given; an error and 0 when negative or not finite).
fn mass(p: &linkage_adm::Part, cx: &mut Ctx) -> f64 {
    match &p.mass {
        Some(m) if m.value < 0.0 || !m.value.is_finite() => {
            cx.error(
                m.span,
                format!(
                    "{}: mass must not be negative (MASS = {})",
                    p.header.name, m.value
                ),
            );
            0.0
        }
        Some(m) => m.value,
        None => 0.0,
    }
}

/// The marker `r` when it is on moving part `part`; an error naming `what` (CM, IM) otherwise.
fn marker_on_part(
    markers: &MarkerStatements,
    cx: &mut Ctx,
    r: IdRef,
    part: usize,
    what: &str,
    part_name: &str,
) -> Option<usize> {
    match markers.index.get(&r.id) {
        Some(&m) if markers.placed[m].body == Body::Part(part) => Some(m),
        Some(_) => {
            cx.error(
                r.span,
                format!("{part_name}: {what} marker {} is not on this part", r.id),
            );
            None
        }
        None => {
            cx.error(
                r.span,
                format!("{part_name}: {what} marker {} does not exist", r.id),
            );
            None
        }
    }
}

/// The inertia about the centre of mass `c` (in BCS) in BCS axes: `IP` is given about the IM
/// marker in its axes (the BCS origin and axes without IM), rotated to the BCS
/// (`R I Rᵀ`) and moved by the parallel-axis theorem. Zero without `IP`.
fn inertia_about_cm(
    p: &linkage_adm::Part,
    mass: f64,
    c: DVec3,
    im: Option<&super::markers::PlacedMarker>,
    cx: &mut Ctx,
) -> DMat3 {
    let Some(ip) = &p.ip else {
        return DMat3::ZERO;
    };
    let name = p.header.name.as_str();
    let t = tensor_from_ip(ip.value);
    let (p_im, r_im) = im.map_or((DVec3::ZERO, DMat3::IDENTITY), |m| (m.p, m.r));
    let about_im = rotate_tensor(&t, &r_im);
    let inertia = to_centre_of_mass(&about_im, mass, p_im - c);
    match check_physical(&inertia, INERTIA_RELATIVE_TOLERANCE) {
        Ok(()) => {}
        Err(InertiaDefect::Negative(why)) => cx.error(
            ip.span,
            format!("{name}: non-physical inertia about the centre of mass: {why}"),
        ),
        Err(InertiaDefect::Triangle(why)) => cx.warn(
            ip.span,
            format!(
                "{name}: non-physical inertia about the centre of mass: {why}; no \
                 rigid body has it, but no principal moment is negative, so the \
                 analyses use it as given (as Adams does)"
            ),
        ),
    }
    inertia
}

/// Every marker in its body frame: a part's markers relative to its centre of mass
/// (`p_BM = p_bcs − c_bcs`; the axes are the BCS axes), ground markers as placed.
pub(crate) fn body_markers(markers: &MarkerStatements, cm_in_bcs: &[DVec3]) -> Vec<Marker> {
    markers
        .statements
        .iter()
        .zip(&markers.placed)
        .map(|(m, placed)| {
            let p_bm = match placed.body {
                Body::Part(k) => placed.p - cm_in_bcs[k],
                Body::Ground => placed.p,
            };
            Marker {
                id: m.header.id,
                name: m.header.name.clone(),
                span: m.header.span,
                body: placed.body,
                p_bm,
                r_bm: placed.r,
                floating: m.floating,
            }
        })
        .collect()
}
