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
        let cm =
            p.cm.and_then(|r| marker_on_part(markers, cx, r, k, "CM", name));
        let c = cm.map_or(DVec3::ZERO, |m| markers.placed[m].p);
        let im = match p.im {
            Some(r) => marker_on_part(markers, cx, r, k, "IM", name),
            None => cm,
        };
        let inertia = inertia_about_cm(p, mass, c, im.map(|m| &markers.placed[m]), cx);
        let point_mass = k >= parts.rigid;
        if mass > 0.0 && p.ip.is_none() && !point_mass {
            cx.warn(
                p.header.span,
                format!("{name}: MASS given without IP: its inertia is zero"),
            );
        }
        let (qg, r) = parts.bcs[k];
        cm_in_bcs.push(c);
        out.push(Part {
            origin: origin(if point_mass { "POINT_MASS" } else { "PART" }, &p.header),
            mass,
            inertia,
            p_gb: qg + r * c,
            r_gb: r,
            p_b_bcs: -c,
            velocity: p.velocity,
            r_b_cm: cm.map_or(DMat3::IDENTITY, |m| markers.placed[m].r),
            exact: p.exact.clone(),
            point_mass,
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

#[cfg(test)]
mod tests {
    use crate::build::test_support::{build_text, errors_in_order};
    use glam::{DMat3, DVec3};

    #[test]
    fn inertia_about_im_is_moved_to_the_centre_of_mass() {
        // CM at (0, 1, 0) of the BCS, IP given about IM at the BCS origin: the parallel-axis
        // theorem removes m·1² from Ixx and Izz.
        let b = build_text("t\nPART/1, GROUND\nPART/2, QG = 5, 0, 0, MASS = 2, CM = 3, IM = 4, IP = 10, 20, 30\nMARKER/3, PART = 2, QP = 0, 1, 0\nMARKER/4, PART = 2\nMARKER/5, PART = 2, QP = 1, 1, 0\nEND\n")
            .unwrap_or_else(|e| panic!("{e}"));
        let p = &b.model.parts[0];
        assert_eq!(p.mass, 2.0);
        assert_eq!(p.p_gb, DVec3::new(5.0, 1.0, 0.0));
        assert_eq!(p.p_b_bcs, DVec3::new(0.0, -1.0, 0.0));
        let expect = DMat3::from_diagonal(DVec3::new(8.0, 20.0, 28.0));
        assert!((p.inertia - expect)
            .abs()
            .to_cols_array()
            .iter()
            .all(|x| *x < 1e-12));
        // Markers are stored relative to the centre of mass.
        assert_eq!(b.model.markers[0].p_bm, DVec3::ZERO);
        assert_eq!(b.model.markers[1].p_bm, DVec3::new(0.0, -1.0, 0.0));
        assert_eq!(b.model.markers[2].p_bm, DVec3::new(1.0, 0.0, 0.0));
        assert!(b.warnings.is_empty(), "{:?}", b.warnings);
    }

    #[test]
    fn mass_errors_and_warnings() {
        let e = errors_in_order("t\nPART/1, GROUND\nMARKER/9, PART = 1\nPART/2, MASS = -1, CM = 9\nPART/3, MASS = 1, CM = 8, IP = 1, 1, -5\nEND\n");
        assert_eq!(
            e[0],
            (
                4,
                9,
                "PART_2: mass must not be negative (MASS = -1)".to_string()
            )
        );
        assert_eq!(
            e[1],
            (4, 25, "PART_2: CM marker 9 is not on this part".to_string())
        );
        assert_eq!(
            e[2],
            (5, 24, "PART_3: CM marker 8 does not exist".to_string())
        );
        assert!(
            e[3].2.starts_with(
                "PART_3: non-physical inertia about the centre of mass: negative principal moment"
            ),
            "{}",
            e[3].2
        );
        let b = build_text(
            "t\nPART/1, GROUND\nPART/2, MASS = 1\nPART/3, MASS = 1, IP = 1, 1, 3\nEND\n",
        )
        .unwrap_or_else(|e| panic!("{e}"));
        let w: Vec<&str> = b.warnings.iter().map(|w| w.message.as_str()).collect();
        assert_eq!(w[0], "PART_2: MASS given without IP: its inertia is zero");
        assert!(
            w[1].starts_with(
                "PART_3: non-physical inertia about the centre of mass: principal moments"
            ),
            "{}",
            w[1]
        );
        assert_eq!(w.len(), 2);
    }
}
