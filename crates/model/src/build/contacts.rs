//! CONTACT statements → [`ForceKind::Contact`] force elements (after the GRAPHICS are
//! attached to markers).
//!
//! Errors (at the statement or the id): the typing errors of `linkage_adm::contact`; an IGEOM
//! or JGEOM naming a GRAPHICS the model does not have; one side's geometries on several
//! bodies; both sides on the same body; an STL or OBJ file that cannot be read or holds no
//! triangle (with the file's name and the reader's message).
//!
//! A GRAPHICS CURVE geometry is its CURVE sampled into a polyline ([`sample_curve`]): a CID
//! naming no CURVE, or a curve not in its frame's xy plane, is an error.
//!
//! A contact whose geometry [`geometry_problem`] names (a missing or Parasolid file), whose
//! CURVE is a USER subroutine, or whose law is a USER subroutine, is left out of the model with a warning: coverage
//! names it and makes every force analysis refuse the model until it is deactivated, while
//! verify still runs.

use super::context::{origin, Ctx};
use crate::bodies::Marker;
use crate::contacts::{
    external_path, geometry_problem, mesh_format, sample_curve, Contact, ContactGeometry,
    GeometryError, Mesh, Polyline, Solid,
};
use crate::curves::Curve;
use crate::forces::{ForceElement, ForceKind};
use crate::graphics::Graphic;
use glam::DVec3;
use linkage_adm::contact::NormalLaw;
use linkage_adm::graphics::Shape;
use linkage_adm::{Dataset, IdRef};
use std::collections::HashMap;
use std::sync::Arc;

/// The model's CURVEs by id (as `build/curves.rs` made them).
pub(crate) struct CurveLookup<'a> {
    pub index: &'a HashMap<u64, usize>,
    pub curves: &'a [Curve],
}

/// Every CONTACT of `ds` as a force element, in statement order.
pub(crate) fn contacts(
    ds: &Dataset,
    graphics: &[Graphic],
    markers: &[Marker],
    curve_of: &CurveLookup,
    cx: &mut Ctx,
) -> Vec<ForceElement> {
    let (typed, diagnostics) = linkage_adm::contact::type_contacts(ds);
    for d in diagnostics {
        if d.is_error() {
            cx.errors.push(d);
        } else {
            cx.warnings.push(d);
        }
    }
    if typed.is_empty() {
        return Vec::new();
    }
    let by_id: HashMap<u64, &Graphic> = graphics.iter().map(|g| (g.id, g)).collect();
    let mut meshes: HashMap<String, Arc<Mesh>> = HashMap::new();
    let mut polylines: HashMap<u64, Arc<Polyline>> = HashMap::new();
    let mut out = Vec::with_capacity(typed.len());
    for c in &typed {
        let label = format!("{} (CONTACT/{})", c.header.name, c.header.id);
        if let NormalLaw::User { .. } = c.normal {
            cx.warn(
                c.header.span,
                format!("{label}: its normal force is a USER subroutine; it is not modelled"),
            );
            continue;
        }
        if c.friction.user.is_some() {
            cx.warn(
                c.header.span,
                format!("{label}: its friction is a USER subroutine; it is not modelled"),
            );
            continue;
        }
        let mut ok = true;
        for (flips, geoms, key) in [
            (&c.iflip, &c.igeom, "IFLIP_GEOMETRY"),
            (&c.jflip, &c.jgeom, "JFLIP_GEOMETRY"),
        ] {
            for f in flips {
                let is_curve = geoms.iter().any(|g| g.id == f.id)
                    && by_id
                        .get(&f.id)
                        .is_some_and(|g| matches!(g.shape, Shape::Curve { .. }));
                if !is_curve {
                    cx.error(
                        f.span,
                        format!(
                            "{label}: {key} names GRAPHICS/{}, which is not a CURVE geometry \
                             of that side",
                            f.id
                        ),
                    );
                    ok = false;
                }
            }
        }
        let mut side = |ids: &[IdRef],
                        flips: &[IdRef],
                        key: &str,
                        cx: &mut Ctx|
         -> Option<Vec<ContactGeometry>> {
            let mut out = Vec::with_capacity(ids.len());
            for r in ids {
                let Some(g) = by_id.get(&r.id) else {
                    cx.error(
                        r.span,
                        format!(
                            "{label}: {key} names GRAPHICS/{}, which does not exist",
                            r.id
                        ),
                    );
                    ok = false;
                    continue;
                };
                if let Some(p) = geometry_problem(&ds.file, &g.shape) {
                    cx.warn(
                        r.span,
                        format!(
                            "{label}: {}; the contact is not modelled (deactivate it to run \
                             without it)",
                            p.describe(g.id)
                        ),
                    );
                    return None;
                }
                if let Shape::Curve { cid, .. } = g.shape {
                    if !curve_of.index.contains_key(&cid) && is_user_curve(ds, cid) {
                        cx.warn(
                            r.span,
                            format!(
                                "{label}: GRAPHICS/{}'s CURVE/{cid} is a USER subroutine; the \
                                 contact is not modelled (deactivate it to run without it)",
                                g.id
                            ),
                        );
                        return None;
                    }
                }
                let flip = flips.iter().any(|f| f.id == g.id);
                match solid(ds, g, flip, curve_of, &mut meshes, &mut polylines) {
                    Ok((marker, solid)) => out.push(ContactGeometry {
                        graphic: g.id,
                        name: g.name.clone(),
                        marker,
                        solid,
                    }),
                    Err(why) => {
                        cx.error(r.span, format!("{label}: GRAPHICS/{}: {why}", g.id));
                        ok = false;
                    }
                }
            }
            Some(out)
        };
        let (Some(ig), Some(jg)) = (
            side(&c.igeom, &c.iflip, "IGEOM", cx),
            side(&c.jgeom, &c.jflip, "JGEOM", cx),
        ) else {
            continue;
        };
        if !ok || ig.is_empty() || jg.is_empty() {
            continue;
        }
        let body_of = |g: &ContactGeometry| markers[g.marker].body;
        let same_body = |geoms: &[ContactGeometry], key: &str, cx: &mut Ctx| {
            let b = body_of(&geoms[0]);
            if let Some(other) = geoms.iter().find(|g| body_of(g) != b) {
                cx.error(
                    c.header.span,
                    format!(
                        "{label}: the {key} geometries are on several parts (GRAPHICS/{} and \
                         GRAPHICS/{}); each side must be on one part",
                        geoms[0].graphic, other.graphic
                    ),
                );
                return false;
            }
            true
        };
        if !same_body(&ig, "IGEOM", cx) || !same_body(&jg, "JGEOM", cx) {
            continue;
        }
        if body_of(&ig[0]) == body_of(&jg[0]) {
            cx.error(
                c.header.span,
                format!("{label}: the I and J geometries are on the same part"),
            );
            continue;
        }
        out.push(ForceElement {
            origin: origin("CONTACT", &c.header),
            kind: ForceKind::Contact(Box::new(Contact {
                i: ig[0].marker,
                j: jg[0].marker,
                i_geometries: ig,
                j_geometries: jg,
                normal: c.normal.clone(),
                friction: c.friction.clone(),
            })),
        });
    }
    out
}

/// Whether `CURVE/id` is a statement given by a FUNCTION (USER subroutine).
fn is_user_curve(ds: &Dataset, id: u64) -> bool {
    ds.statements
        .iter()
        .any(|s| s.keyword == "CURVE" && s.id == Some(id) && s.arg("FUNCTION").is_some())
}

/// The marker and solid of a usable graphic (see [`crate::contacts`]); an EXTERNAL mesh is
/// read once per file, a CURVE sampled once; `flip` reverses a curve's solid side.
fn solid(
    ds: &Dataset,
    g: &Graphic,
    flip: bool,
    curve_of: &CurveLookup,
    meshes: &mut HashMap<String, Arc<Mesh>>,
    polylines: &mut HashMap<u64, Arc<Polyline>>,
) -> Result<(usize, Solid), GeometryError> {
    Ok(match &g.shape {
        Shape::Curve { cid, crm } => {
            let polyline = match polylines.get(cid) {
                Some(p) => p.clone(),
                None => {
                    let Some(&k) = curve_of.index.get(cid) else {
                        return Err(GeometryError::MissingCurve { cid: *cid });
                    };
                    let p = Arc::new(sample_curve(*cid, &curve_of.curves[k])?);
                    polylines.insert(*cid, p.clone());
                    p
                }
            };
            (*crm, Solid::Curve { polyline, flip })
        }
        Shape::Ellipsoid { cm, diameters } => (
            *cm,
            Solid::Ellipsoid {
                radii: DVec3::from(*diameters).abs() * 0.5,
            },
        ),
        Shape::Box { corner, extent } => (
            *corner,
            Solid::Box {
                extent: DVec3::from(*extent),
            },
        ),
        Shape::Cylinder {
            cm, length, radius, ..
        } => (
            *cm,
            Solid::Cylinder {
                length: *length,
                radius: radius.abs(),
            },
        ),
        Shape::Frustum {
            cm,
            length,
            top,
            bottom,
            ..
        } => (
            *cm,
            Solid::Frustum {
                length: *length,
                bottom: bottom.abs(),
                top: top.abs(),
            },
        ),
        Shape::Circle { cm, radius, .. } => (
            *cm,
            Solid::Disc {
                radius: radius.abs(),
            },
        ),
        Shape::Point { rm } => (*rm, Solid::Point),
        Shape::Plane { rm, .. } => (*rm, Solid::HalfSpace),
        Shape::External { rm, file: Some(f) } => {
            let mesh = match meshes.get(f) {
                Some(m) => m.clone(),
                None => {
                    let m = Arc::new(read_mesh(&ds.file, f)?);
                    meshes.insert(f.clone(), m.clone());
                    m
                }
            };
            (*rm, Solid::Mesh(mesh))
        }
        other => {
            return Err(GeometryError::NotASolid {
                kind: other.kind().to_string(),
            })
        }
    })
}

/// Reads an STL (ascii or binary) or OBJ mesh named `name` relative to the dataset's folder.
pub(crate) fn read_mesh(dataset_file: &str, name: &str) -> Result<Mesh, GeometryError> {
    let path = external_path(dataset_file, name);
    let fail = |why: String| GeometryError::Mesh {
        name: name.to_string(),
        why,
    };
    let (vertices, triangles) = match mesh_format(name) {
        Some("stl") => {
            let mut f = std::fs::File::open(&path).map_err(|e| fail(e.to_string()))?;
            let m = stl_io::read_stl(&mut f).map_err(|e| fail(e.to_string()))?;
            let vertices: Vec<DVec3> = m
                .vertices
                .iter()
                .map(|v| DVec3::new(v.0[0].into(), v.0[1].into(), v.0[2].into()))
                .collect();
            let triangles = m
                .faces
                .iter()
                .map(|t| t.vertices.map(|k| k as u32))
                .collect();
            (vertices, triangles)
        }
        Some(_) => {
            let options = tobj::LoadOptions {
                triangulate: true,
                single_index: true,
                ..Default::default()
            };
            let (models, _) = tobj::load_obj(&path, &options).map_err(|e| fail(e.to_string()))?;
            let mut vertices = Vec::new();
            let mut triangles = Vec::new();
            for m in &models {
                let base = u32::try_from(vertices.len()).map_err(|e| fail(e.to_string()))?;
                vertices.extend(
                    m.mesh
                        .positions
                        .chunks_exact(3)
                        .map(|p| DVec3::new(p[0].into(), p[1].into(), p[2].into())),
                );
                triangles.extend(
                    m.mesh
                        .indices
                        .chunks_exact(3)
                        .map(|t| [base + t[0], base + t[1], base + t[2]]),
                );
            }
            (vertices, triangles)
        }
        None => return Err(fail("not an STL or OBJ file".to_string())),
    };
    if triangles.is_empty() {
        return Err(fail("it holds no triangle".to_string()));
    }
    if vertices.iter().any(|v| !v.is_finite()) {
        return Err(fail(
            "a vertex coordinate is not a finite number".to_string(),
        ));
    }
    Ok(Mesh {
        file: name.to_string(),
        vertices,
        triangles,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A temp folder for one test.
    fn folder(tag: &str) -> std::path::PathBuf {
        let d = std::env::temp_dir().join(format!("linkage-mesh-{tag}-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    /// The binary STL of one triangle (80-byte header, count, normal, 3 vertices, attribute).
    fn binary_stl(tri: [[f32; 3]; 3]) -> Vec<u8> {
        let mut b = vec![0u8; 80];
        b.extend(1u32.to_le_bytes());
        for x in [0.0f32, 0.0, 1.0] {
            b.extend(x.to_le_bytes());
        }
        for v in tri {
            for x in v {
                b.extend(x.to_le_bytes());
            }
        }
        b.extend(0u16.to_le_bytes());
        b
    }

    #[test]
    fn stl_ascii_and_binary_and_obj_meshes_are_read_relative_to_the_dataset() {
        let d = folder("formats");
        let ds = d.join("model.adm");
        let ds = ds.to_str().unwrap();
        std::fs::write(
            d.join("tri.stl"),
            "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n\
             vertex 0 2 0\nendloop\nendfacet\nendsolid t\n",
        )
        .unwrap();
        std::fs::write(
            d.join("bin.STL"),
            binary_stl([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 2.0, 0.5]]),
        )
        .unwrap();
        std::fs::write(
            d.join("quad.obj"),
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n",
        )
        .unwrap();
        let a = read_mesh(ds, "tri.stl").unwrap();
        assert_eq!(a.triangles.len(), 1);
        assert!(a.vertices.contains(&DVec3::new(0.0, 2.0, 0.0)));
        let b = read_mesh(ds, "bin.STL").unwrap();
        assert_eq!(b.triangles.len(), 1);
        assert!(b.vertices.contains(&DVec3::new(0.0, 2.0, 0.5)));
        // The quad is triangulated into two triangles over its four vertices.
        let c = read_mesh(ds, "quad.obj").unwrap();
        assert_eq!((c.vertices.len(), c.triangles.len()), (4, 2));
        let e = read_mesh(ds, "absent.stl").unwrap_err().to_string();
        assert!(e.contains("absent.stl"), "{e}");
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn contacts_are_built_between_the_parts_of_their_geometries() {
        let text = "t\nPART/1, GROUND\nMARKER/1, PART = 1\n\
            PART/2, MASS = 1, IP = 1, 1, 1, CM = 20\nMARKER/20, PART = 2\n\
            GRAPHICS/1, ELLIPSOID, CM = 20, XSCALE = 2, YSCALE = 2, ZSCALE = 2\n\
            GRAPHICS/2, PLANE, RM = 1\n\
            GRAPHICS/3, EXTERNAL, RM = 1, FILE = surely_absent.xmt_txt\n\
            CONTACT/1, IGEOM = 1, JGEOM = 2, IMPACT, STIFFNESS = 1, DAMPING = 0, DMAX = 1, \
            EXPONENT = 1\n\
            CONTACT/2, IGEOM = 1, JGEOM = 3, IMPACT, STIFFNESS = 1, DAMPING = 0, DMAX = 1, \
            EXPONENT = 1\n\
            CONTACT/3, IGEOM = 1, JGEOM = 9, IMPACT, STIFFNESS = 1, DAMPING = 0, DMAX = 1, \
            EXPONENT = 1\nEND\n";
        let ds = linkage_adm::parse_dataset("c.adm".into(), text).unwrap();
        let err = crate::build_model(&ds)
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default();
        assert!(err.contains("GRAPHICS/9, which does not exist"), "{err}");
        let ds =
            linkage_adm::parse_dataset("c.adm".into(), &text.replace("JGEOM = 9", "JGEOM = 2"))
                .unwrap();
        let built = crate::build_model(&ds).unwrap();
        let contacts: Vec<&Contact> = built
            .model
            .forces
            .iter()
            .filter_map(|f| match &f.kind {
                ForceKind::Contact(c) => Some(c.as_ref()),
                _ => None,
            })
            .collect();
        // CONTACT/2 names a Parasolid file that is absent: left out, with a warning naming it.
        assert_eq!(contacts.len(), 2);
        assert_eq!(
            contacts[0].i_geometries[0].solid,
            Solid::Ellipsoid { radii: DVec3::ONE }
        );
        assert_eq!(contacts[0].j_geometries[0].solid, Solid::HalfSpace);
        assert!(built
            .warnings
            .iter()
            .any(|w| w.message.contains("surely_absent.xmt_txt")));
    }

    #[test]
    fn curve_geometries_are_sampled_and_their_errors_named() {
        let base = "t\nPART/1, GROUND\nMARKER/1, PART = 1\n\
            PART/2, MASS = 1, IP = 1, 1, 1, CM = 20\nMARKER/20, PART = 2\n\
            MATRIX/4, FULL = RORDER, ROWS = 4, COLUMNS = 3, VALUES = -1, 0, 0, -0.3, 0, 0, 0.4, 0, 0, 1, 0, 0\n\
            CURVE/5, OPEN, CURVE_POINTS, MATRIX = 4\n\
            CURVE/6, FUNCTION = USER(1)\n\
            GRAPHICS/1, ELLIPSOID, CM = 20, XSCALE = 2, YSCALE = 2, ZSCALE = 2\n\
            GRAPHICS/2, CURVE, CID = 5, CRM = 1\n\
            CONTACT/1, IGEOM = 1, JGEOM = 2, JFLIP_GEOMETRY = 2, IMPACT, STIFFNESS = 1, \
            DAMPING = 0, DMAX = 1, EXPONENT = 1\nEND\n";
        let build = |text: &str| {
            let ds = linkage_adm::parse_dataset("c.adm".into(), text).unwrap();
            crate::build_model(&ds)
        };
        let built = build(base).unwrap();
        let Some(ForceKind::Contact(c)) = built.model.forces.first().map(|f| &f.kind) else {
            panic!("no contact: {:?}", built.warnings);
        };
        let Solid::Curve { polyline, flip } = &c.j_geometries[0].solid else {
            panic!("{:?}", c.j_geometries[0].solid);
        };
        // A straight line: every sample on it, from x = −1 to 1, the flip read.
        assert!(*flip && !polyline.closed && polyline.points.len() > 2);
        assert!(polyline
            .points
            .iter()
            .all(|p| p.y.abs() < 1e-12 && p.z == 0.0));
        assert!((polyline.points[0].x + 1.0).abs() < 1e-12);
        assert!((polyline.points.last().unwrap().x - 1.0).abs() < 1e-12);
        let err = |text: String| {
            build(&text)
                .err()
                .map(|e| e.to_string())
                .unwrap_or_default()
        };
        let e = err(base.replace("CID = 5", "CID = 9"));
        assert!(e.contains("CURVE/9, which does not exist"), "{e}");
        let e = err(base.replace("JFLIP_GEOMETRY = 2", "JFLIP_GEOMETRY = 1"));
        assert!(e.contains("JFLIP_GEOMETRY names GRAPHICS/1"), "{e}");
        let e = err(base.replace("0.4, 0, 0", "0.4, 0, 0.5"));
        assert!(e.contains("not in its frame's xy plane"), "{e}");
        // A USER curve: the contact is left out with a warning naming it.
        let user = build(&base.replace("CID = 5", "CID = 6")).unwrap();
        assert!(user.model.forces.is_empty());
        assert!(user
            .warnings
            .iter()
            .any(|w| w.message.contains("CURVE/6 is a USER subroutine")));
    }
}
