//! What the 3-D view draws: the model's GRAPHICS tessellated on their bodies, a symbol for
//! every joint and joint primitive at its I marker, a marker triad for EXTERNAL geometry, and
//! for a part with no GRAPHICS a stick figure (its CM to each of its markers) so that every
//! moving part is seen.
//!
//! Every mesh is in its body's frame (a part's CM frame, or ground): the viewer places it with
//! the part's pose of each frame. A shape whose markers are on different bodies (an OUTLINE
//! across parts, a LINK or SPDP between parts) is drawn as lines whose vertices each follow
//! their own body.

use crate::mesh::{self, Mesh};
use glam::{DMat3, DQuat, DVec3};
use linkage_adm::graphics::Shape;
use linkage_adm::{JointType, JprimType};
use linkage_model::{Body, ConstraintKind, Model};

/// Colours (sRGB) of the view.
pub const PART_COLOURS: [[u8; 3]; 6] = [
    [76, 120, 168],
    [245, 133, 24],
    [84, 162, 75],
    [178, 121, 162],
    [228, 87, 86],
    [114, 183, 178],
];
pub const GROUND_COLOUR: [u8; 3] = [150, 150, 150];
pub const JOINT_COLOUR: [u8; 3] = [60, 60, 60];
pub const HIGHLIGHT_COLOUR: [u8; 3] = [220, 0, 0];
pub const AXIS_COLOURS: [[u8; 3]; 3] = [[220, 40, 40], [40, 170, 40], [40, 70, 220]];

/// Size of joint symbols and default triads, relative to the model's characteristic length.
pub const SYMBOL_SCALE: f64 = 0.025;

/// Above this many moving parts, parts without GRAPHICS are drawn as lines only, and above
/// this many joints a joint is a short line along its z axis: a page of a 20,000-part chain
/// stays tens of megabytes, not hundreds.
pub const SOLID_SYMBOLS_LIMIT: usize = 500;

/// One drawable: a mesh on a body (`None`: ground), or with one body per vertex.
#[derive(Clone, Debug, PartialEq)]
pub struct Item {
    /// Index of the moving part (`None`: ground); ignored when `vertex_bodies` is given.
    pub body: Option<usize>,
    pub vertex_bodies: Option<Vec<Option<usize>>>,
    pub mesh: Mesh,
    pub colour: [u8; 3],
    /// What it shows (`GRAPHICS_3`, `JOINT_1 (REVOLUTE)`).
    pub label: String,
}

/// The drawables of a model.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Scene {
    pub items: Vec<Item>,
    /// Names of the moving parts (pose columns of every frame, in order).
    pub parts: Vec<String>,
    /// EXTERNAL geometry drawn as a triad: `GRAPHICS_7: file.xmt_txt`.
    pub externals: Vec<String>,
    /// Element names drawn highlighted.
    pub highlighted: Vec<String>,
    pub characteristic_length: f64,
}

fn body_index(b: Body) -> Option<usize> {
    match b {
        Body::Ground => None,
        Body::Part(k) => Some(k),
    }
}

fn colour_of(body: Option<usize>) -> [u8; 3] {
    body.map_or(GROUND_COLOUR, |k| PART_COLOURS[k % PART_COLOURS.len()])
}

/// The scene of `model`, with the constraint elements named in `highlight` (display names or
/// `JOINT/7` forms) drawn in [`HIGHLIGHT_COLOUR`].
pub fn scene(model: &Model, highlight: &[String]) -> Scene {
    let size = model.characteristic_length * SYMBOL_SCALE;
    let mut s = Scene {
        parts: model.parts.iter().map(|p| p.origin.name.clone()).collect(),
        characteristic_length: model.characteristic_length,
        ..Scene::default()
    };
    let mut drawn = vec![false; model.parts.len()];
    for g in &model.graphics {
        let markers = g.shape.markers();
        let bodies: Vec<Option<usize>> = markers
            .iter()
            .map(|&m| body_index(model.markers[m].body))
            .collect();
        let one_body = bodies.windows(2).all(|w| w[0] == w[1]);
        for b in bodies.iter().flatten() {
            drawn[*b] = true;
        }
        let body = bodies.first().copied().flatten();
        let frame = |m: usize| (model.markers[m].p_bm, model.markers[m].r_bm);
        let on_marker = |m: usize, mesh: Mesh| {
            let (p, r) = frame(m);
            mesh.transformed(p, r)
        };
        let mut push = |mesh: Mesh, colour: [u8; 3], vertex_bodies: Option<Vec<Option<usize>>>| {
            if !mesh.is_empty() {
                s.items.push(Item {
                    body,
                    vertex_bodies,
                    mesh,
                    colour,
                    label: g.name.clone(),
                });
            }
        };
        let colour = colour_of(body);
        match &g.shape {
            Shape::Cylinder {
                cm,
                length,
                radius,
                angle,
                sides,
            } => push(
                on_marker(*cm, mesh::cylinder(*radius, *length, *angle, *sides)),
                colour,
                None,
            ),
            Shape::Frustum {
                cm,
                length,
                top,
                bottom,
                angle,
                sides,
            } => push(
                on_marker(*cm, mesh::frustum(*bottom, *top, *length, *angle, *sides)),
                colour,
                None,
            ),
            Shape::Box { corner, extent } => {
                push(on_marker(*corner, mesh::cuboid(*extent)), colour, None)
            }
            Shape::Ellipsoid { cm, diameters } => push(
                on_marker(*cm, mesh::ellipsoid(*diameters, 16)),
                colour,
                None,
            ),
            Shape::Circle {
                cm,
                radius,
                segments,
            } => push(
                on_marker(*cm, mesh::arc(*radius, std::f64::consts::TAU, *segments)),
                colour,
                None,
            ),
            Shape::Arc {
                cm,
                radius,
                angle,
                segments,
            } => push(
                on_marker(*cm, mesh::arc(*radius, *angle, *segments)),
                colour,
                None,
            ),
            Shape::Link { i, j, width, depth } if one_body => {
                let (pi, ri) = frame(*i);
                let pj = frame(*j).0;
                let length = (pj - pi).length();
                let width = width.unwrap_or(length * 0.1);
                let depth = depth.unwrap_or(width * 0.5);
                push(
                    mesh::link(pi, pj, ri * DVec3::Z, width, depth),
                    colour,
                    None,
                )
            }
            Shape::Outline { markers } if one_body => {
                let points: Vec<DVec3> = markers.iter().map(|&m| frame(m).0).collect();
                push(mesh::polyline(&points), colour, None)
            }
            Shape::Outline { markers } => {
                let points: Vec<DVec3> = markers.iter().map(|&m| frame(m).0).collect();
                push(mesh::polyline(&points), colour, Some(bodies.clone()))
            }
            Shape::Link { i, j, .. } | Shape::SpringDamper { i, j, .. } => push(
                mesh::polyline(&[frame(*i).0, frame(*j).0]),
                colour,
                Some(bodies.clone()),
            ),
            Shape::External { rm, file } => {
                for (axis, c) in mesh::triad(size * 2.0).into_iter().zip(AXIS_COLOURS) {
                    push(on_marker(*rm, axis), c, None);
                }
                s.externals.push(format!(
                    "{}: {}",
                    g.name,
                    file.as_deref().unwrap_or("(no FILE)")
                ));
            }
            Shape::Point { rm } => {
                for (axis, c) in mesh::triad(size * 0.5).into_iter().zip(AXIS_COLOURS) {
                    push(on_marker(*rm, axis), c, None);
                }
            }
            Shape::Plane { rm, limits } => {
                let [x0, x1, y0, y1] = *limits;
                let corners = [(x0, y0), (x1, y0), (x1, y1), (x0, y1), (x0, y0)]
                    .map(|(x, y)| DVec3::new(x, y, 0.0));
                push(on_marker(*rm, mesh::polyline(&corners)), colour, None)
            }
            Shape::Curve { .. } | Shape::Other { .. } => {}
        }
    }
    stick_figures(model, &drawn, size, &mut s.items);
    joint_symbols(model, highlight, size, &mut s);
    s
}

/// A part without GRAPHICS: a line from its CM to each of its markers and a small ball at the
/// CM.
fn stick_figures(model: &Model, drawn: &[bool], size: f64, items: &mut Vec<Item>) {
    // Each part's markers, found in one pass (O(markers), not parts × markers).
    let mut on_part: Vec<Vec<usize>> = vec![Vec::new(); model.parts.len()];
    for (m, mk) in model.markers.iter().enumerate() {
        if let Body::Part(k) = mk.body {
            if !drawn[k] {
                on_part[k].push(m);
            }
        }
    }
    for (k, part) in model.parts.iter().enumerate() {
        if drawn[k] {
            continue;
        }
        let light = model.parts.len() > SOLID_SYMBOLS_LIMIT;
        let mut m = if light {
            Mesh::default()
        } else {
            mesh::ellipsoid([size * 1.5; 3], 10)
        };
        for mk in on_part[k].iter().map(|&m| &model.markers[m]) {
            if light {
                m.append(&mesh::polyline(&[DVec3::ZERO, mk.p_bm]));
            } else if mk.p_bm.length() > 0.0 {
                m.append(&mesh::link(
                    DVec3::ZERO,
                    mk.p_bm,
                    mk.p_bm.any_orthonormal_vector(),
                    size * 0.8,
                    size * 0.8,
                ));
            }
        }
        items.push(Item {
            body: Some(k),
            vertex_bodies: None,
            mesh: m,
            colour: colour_of(Some(k)),
            label: format!("{} (no GRAPHICS)", part.origin.name),
        });
    }
}

/// A symbol at the I marker of every joint and joint primitive: a pin along z for a revolute
/// or cylindrical joint, a block along z for a translational one, a ball for spherical and
/// point joints, a cube for a fixed joint, a plate for a planar joint, crossed pins for a
/// universal joint.
fn joint_symbols(model: &Model, highlight: &[String], size: f64, s: &mut Scene) {
    let light = model.constraints.len() > SOLID_SYMBOLS_LIMIT;
    let highlight: std::collections::HashSet<&str> = highlight.iter().map(String::as_str).collect();
    for c in &model.constraints {
        let (shape, i) = match &c.kind {
            ConstraintKind::Joint { i, .. } | ConstraintKind::Jprim { i, .. } if light => (
                mesh::polyline(&[DVec3::new(0.0, 0.0, -size), DVec3::new(0.0, 0.0, size)]),
                *i,
            ),
            ConstraintKind::Joint { kind, i, .. } => (joint_mesh(*kind, size), *i),
            ConstraintKind::Jprim { kind, i, .. } => (jprim_mesh(*kind, size), *i),
            _ => continue,
        };
        let named = highlight.contains(c.origin.name.as_str())
            || highlight.contains(c.origin.element().as_str());
        if named {
            s.highlighted.push(c.origin.name.clone());
        }
        let mk = &model.markers[i];
        let kind = match &c.kind {
            ConstraintKind::Joint { kind, .. } => kind.keyword(),
            ConstraintKind::Jprim { kind, .. } => kind.keyword(),
            _ => "",
        };
        s.items.push(Item {
            body: body_index(mk.body),
            vertex_bodies: None,
            mesh: shape.transformed(mk.p_bm, mk.r_bm),
            colour: if named {
                HIGHLIGHT_COLOUR
            } else {
                JOINT_COLOUR
            },
            label: format!("{} ({kind})", c.origin.name),
        });
    }
}

fn pin(size: f64) -> Mesh {
    mesh::cylinder(size * 0.5, size * 3.0, std::f64::consts::TAU, 12)
        .transformed(DVec3::new(0.0, 0.0, -size * 1.5), DMat3::IDENTITY)
}

fn joint_mesh(kind: JointType, size: f64) -> Mesh {
    match kind {
        JointType::Revolute | JointType::Cylindrical | JointType::Screw => pin(size),
        JointType::Translational | JointType::Rackpin => mesh::cuboid([size, size, size * 4.0])
            .transformed(
                DVec3::new(-size * 0.5, -size * 0.5, -size * 2.0),
                DMat3::IDENTITY,
            ),
        JointType::Spherical => mesh::ellipsoid([size * 2.0; 3], 12),
        JointType::Fixed => {
            mesh::cuboid([size * 1.5; 3]).transformed(DVec3::splat(-size * 0.75), DMat3::IDENTITY)
        }
        JointType::Planar => mesh::cuboid([size * 4.0, size * 4.0, size * 0.3]).transformed(
            DVec3::new(-size * 2.0, -size * 2.0, -size * 0.15),
            DMat3::IDENTITY,
        ),
        JointType::Universal | JointType::Hooke | JointType::Convel => {
            let mut m = pin(size);
            m.append(&pin(size).transformed(
                DVec3::ZERO,
                DMat3::from_rotation_x(std::f64::consts::FRAC_PI_2),
            ));
            m
        }
    }
}

fn jprim_mesh(kind: JprimType, size: f64) -> Mesh {
    match kind {
        JprimType::Atpoint => mesh::ellipsoid([size * 1.5; 3], 10),
        JprimType::Inplane => mesh::cuboid([size * 3.0, size * 3.0, size * 0.3]).transformed(
            DVec3::new(-size * 1.5, -size * 1.5, -size * 0.15),
            DMat3::IDENTITY,
        ),
        _ => pin(size * 0.7),
    }
}

/// Poses of every moving part over a run, thinned for the page.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Frames {
    pub times: Vec<f64>,
    /// One list per frame: each part's CM position (ground) and orientation.
    pub poses: Vec<Vec<(DVec3, DQuat)>>,
    /// Outputs of the run before thinning.
    pub total: usize,
    /// What the frames show (`time`, `mode 3, 12.5 Hz`).
    pub label: String,
}

impl Frames {
    /// Adds the poses at `time` (rotation matrices are turned into unit quaternions).
    pub fn push(&mut self, time: f64, poses: impl Iterator<Item = (DVec3, DMat3)>) {
        self.times.push(time);
        self.poses.push(
            poses
                .map(|(p, r)| (p, DQuat::from_mat3(&r).normalize()))
                .collect(),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn model(text: &str) -> Model {
        let ds = linkage_adm::parse_dataset("s.adm".into(), text).expect("parses");
        linkage_model::build_model(&ds).expect("builds").model
    }

    const PENDULUM: &str = "pendulum\n\
        PART/1, GROUND\nMARKER/10, PART = 1\n\
        PART/2, MASS = 1, IP = 1, 1, 1, CM = 20, QG = 0, -1, 0\n\
        MARKER/20, PART = 2\nMARKER/21, PART = 2, QP = 0, 1, 0\n\
        JOINT/1, REVOLUTE, I = 21, J = 10\n\
        GRAPHICS/5, CYLINDER, CM = 20, LENGTH = 1, RADIUS = 0.1\n\
        GRAPHICS/6, EXTERNAL, RM = 10, FILE = part.xmt_txt\nEND\n";

    #[test]
    fn a_cylinder_is_drawn_in_its_part_frame_at_its_marker() {
        let m = model(PENDULUM);
        let s = scene(&m, &[]);
        let cyl = s
            .items
            .iter()
            .find(|i| i.label == "GRAPHICS_5")
            .expect("drawn");
        assert_eq!(cyl.body, Some(0));
        // MARKER/20 is the CM: the rim is 0.1 from the body z axis through the CM.
        for p in &cyl.mesh.positions {
            let d = (p.x * p.x + p.y * p.y).sqrt();
            assert!(d < 1e-12 || (d - 0.1).abs() < 1e-12);
        }
        assert_eq!(s.externals.len(), 1);
        assert!(
            s.externals[0].eq_ignore_ascii_case("graphics_6: part.xmt_txt"),
            "{:?}",
            s.externals
        );
        // Its triad: three axes on ground.
        let triad: Vec<&Item> = s.items.iter().filter(|i| i.label == "GRAPHICS_6").collect();
        assert_eq!(triad.len(), 3);
        assert!(triad
            .iter()
            .all(|i| i.body.is_none() && i.mesh.lines.len() == 1));
    }

    #[test]
    fn highlighted_joints_are_red_and_named() {
        let m = model(PENDULUM);
        let s = scene(&m, &["JOINT/1".to_string()]);
        let j = s
            .items
            .iter()
            .find(|i| i.label.starts_with("JOINT_1"))
            .expect("symbol");
        assert_eq!(j.colour, HIGHLIGHT_COLOUR);
        assert_eq!(s.highlighted, ["JOINT_1"]);
        // The pin sits on the pendulum at MARKER/21 (1 above its CM), along z.
        let centre = j.mesh.positions.iter().fold(DVec3::ZERO, |a, p| a + *p)
            / j.mesh.positions.len() as f64;
        assert!(
            (centre - DVec3::new(0.0, 1.0, 0.0)).length() < 1e-12,
            "{centre}"
        );
    }
}
