//! Typing of GRAPHICS statements: the display geometry of a dataset (Adams Solver GRAPHICS,
//! "graphics for display").
//!
//! Contract:
//! - GRAPHICS is read generically by the parser (its keyword table is partial), so the
//!   arguments are resolved here, by exact spelling or unambiguous prefix (`COR` = `CORNER`).
//! - One [`Graphic`] per GRAPHICS statement whose shape linkage can draw: CYLINDER, FRUSTUM,
//!   BOX, ELLIPSOID, CIRCLE, ARC, OUTLINE, LINK, SPDP and EXTERNAL (the last kept as its
//!   reference marker and file name), and the contact geometries POINT (`RM`: its origin)
//!   and PLANE (`RM`: its xy plane, `XMIN`…`YMAX` the drawn rectangle; spelling
//!   [unconfirmed], from the Adams View plane's limits), and CURVE (`CID`: the CURVE id, `CRM`:
//!   the marker of its frame). Other kinds (FORCE, TORUS…) are
//!   kept as [`Shape::Other`] with their kind: they are display-only and change no result.
//! - A shape missing an argument it cannot be drawn without (CYLINDER without `CM`, a BOX
//!   without `CORNER`, …) or with a value that is not a number gives a *warning* at the
//!   statement or the value, never an error: geometry changes no analysis.
//! - Dimensions are in the dataset's length unit, angles in radians (a `D` suffix converted);
//!   defaults where Adams has them (`SIDES`/`SEG` 20, `RANGLE` a full turn, LINK width a tenth
//!   of its length).

use super::label;
use crate::diagnostic::{Diagnostic, Span};
use crate::statement::{Argument, Statement, Value};
use crate::typed::{Dataset, Header, IdRef};

/// The argument keywords of GRAPHICS (display and contact forms), for prefix matching.
const GRAPHICS_KEYS: &[&str] = &[
    "ARC",
    "BOTTOM",
    "BOX",
    "CID",
    "CIRCLE",
    "CLOSE",
    "CM",
    "COILS",
    "CORNER",
    "CRM",
    "CURVE",
    "CYLINDER",
    "DA",
    "DB",
    "DC",
    "DEPTH",
    "EID",
    "ELEMENT",
    "ELLIPSOID",
    "EMARKER",
    "ETYPE",
    "EXTERNAL",
    "FACETING_TOLERANCE",
    "FILE",
    "FORCE",
    "FRUSTUM",
    "I",
    "J",
    "LA",
    "LB",
    "LC",
    "LENGTH",
    "LINK",
    "OUTLINE",
    "PLANE",
    "POINT",
    "RADIUS",
    "RANGLE",
    "RM",
    "SEG",
    "SIDES",
    "SPDP",
    "TOP",
    "TORUS",
    "WIDTH",
    "X",
    "XMAX",
    "XMIN",
    "XSCALE",
    "Y",
    "YMAX",
    "YMIN",
    "YSCALE",
    "Z",
    "ZSCALE",
];

/// Shapes that are a conditional keyword of GRAPHICS (OUTLINE is `OUTLINE = ids`).
const SHAPE_KEYS: &[&str] = &[
    "ARC",
    "BOX",
    "CIRCLE",
    "CURVE",
    "CYLINDER",
    "ELLIPSOID",
    "EXTERNAL",
    "FORCE",
    "FRUSTUM",
    "LINK",
    "PLANE",
    "POINT",
    "SPDP",
    "TORUS",
];

/// Default number of sides of a cylinder or frustum and of segments of a circle or arc (Adams
/// Solver's documented default for SIDES and SEG).
pub const DEFAULT_SEGMENTS: u32 = 20;

/// One GRAPHICS statement typed.
#[derive(Clone, Debug, PartialEq)]
pub struct Graphic {
    pub header: Header,
    pub shape: Shape,
}

/// The geometry of a GRAPHICS statement, in the frames of the markers it names (dataset
/// length unit, angles in radians). `M` is how a marker is named: an [`IdRef`] as written,
/// or (in `linkage-model`) the index of the resolved marker.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape<M = IdRef> {
    /// A cylinder whose bottom face is centred at `cm` and whose axis is `cm`'s z axis, from
    /// z = 0 to z = `length` (negative: downwards); `angle` the swept angle from `cm`'s x axis.
    Cylinder {
        cm: M,
        length: f64,
        radius: f64,
        angle: f64,
        sides: u32,
    },
    /// A frustum like the cylinder, radius `bottom` at z = 0 and `top` at z = `length`.
    Frustum {
        cm: M,
        length: f64,
        top: f64,
        bottom: f64,
        angle: f64,
        sides: u32,
    },
    /// A box with one corner at `corner`, edges `extent` along its x, y, z axes (signed).
    Box { corner: M, extent: [f64; 3] },
    /// An ellipsoid centred at `cm` with diameters `diameters` along its x, y, z axes
    /// (XSCALE, YSCALE, ZSCALE are diameters: Altair MotionSolve's Ellipsoid reference, which
    /// reads Adams datasets, documents them so).
    Ellipsoid { cm: M, diameters: [f64; 3] },
    /// A circle of `radius` about `cm`'s z axis, in its xy plane.
    Circle { cm: M, radius: f64, segments: u32 },
    /// An arc of `radius` about `cm`'s z axis from its x axis through `angle`.
    Arc {
        cm: M,
        radius: f64,
        angle: f64,
        segments: u32,
    },
    /// A polyline through the origins of `markers` (possibly on several parts).
    Outline { markers: Vec<M> },
    /// A link from marker `i` to marker `j`: a bar of `width` (in `i`'s xy plane) and `depth`
    /// (along `i`'s z axis) with rounded ends.
    Link {
        i: M,
        j: M,
        width: Option<f64>,
        depth: Option<f64>,
    },
    /// A spring-damper drawn between markers `i` and `j` with `coils` turns of diameter
    /// `diameter` (DA), when given.
    SpringDamper {
        i: M,
        j: M,
        coils: u32,
        diameter: Option<f64>,
    },
    /// Geometry in a file (STL, OBJ, Parasolid, …): drawn as `rm`'s triad; CONTACT reads
    /// STL and OBJ files, in `rm`'s frame.
    External { rm: M, file: Option<String> },
    /// A point at `rm`'s origin (a contact geometry).
    Point { rm: M },
    /// The xy plane of `rm` (its +z side is outside), drawn over `[xmin, xmax] × [ymin, ymax]`.
    Plane { rm: M, limits: [f64; 4] },
    /// The CURVE statement `cid` in `crm`'s frame (a 2-D contact geometry; not drawn).
    Curve { cid: u64, crm: M },
    /// Another kind (FORCE, TORUS, …): kept by name, not drawn.
    Other { kind: String },
}

impl<M: Copy> Shape<M> {
    /// Every marker the shape is drawn relative to.
    pub fn markers(&self) -> Vec<M> {
        match self {
            Shape::Cylinder { cm, .. }
            | Shape::Frustum { cm, .. }
            | Shape::Ellipsoid { cm, .. }
            | Shape::Circle { cm, .. }
            | Shape::Arc { cm, .. } => vec![*cm],
            Shape::Box { corner, .. } => vec![*corner],
            Shape::Outline { markers } => markers.clone(),
            Shape::Link { i, j, .. } | Shape::SpringDamper { i, j, .. } => vec![*i, *j],
            Shape::External { rm, .. } | Shape::Point { rm } | Shape::Plane { rm, .. } => {
                vec![*rm]
            }
            Shape::Curve { crm, .. } => vec![*crm],
            Shape::Other { .. } => Vec::new(),
        }
    }

    /// The kind as written in the dataset (`CYLINDER`, `BOX`, …).
    pub fn kind(&self) -> &str {
        match self {
            Shape::Cylinder { .. } => "CYLINDER",
            Shape::Frustum { .. } => "FRUSTUM",
            Shape::Box { .. } => "BOX",
            Shape::Ellipsoid { .. } => "ELLIPSOID",
            Shape::Circle { .. } => "CIRCLE",
            Shape::Arc { .. } => "ARC",
            Shape::Outline { .. } => "OUTLINE",
            Shape::Link { .. } => "LINK",
            Shape::SpringDamper { .. } => "SPDP",
            Shape::External { .. } => "EXTERNAL",
            Shape::Point { .. } => "POINT",
            Shape::Plane { .. } => "PLANE",
            Shape::Curve { .. } => "CURVE",
            Shape::Other { kind } => kind,
        }
    }

    /// The same shape with every marker renamed by `f`; the first marker `f` cannot rename
    /// (`None`) is the error.
    pub fn try_map<N>(&self, mut f: impl FnMut(M) -> Option<N>) -> Result<Shape<N>, M> {
        let mut g = |m: M| f(m).ok_or(m);
        Ok(match self {
            Shape::Cylinder {
                cm,
                length,
                radius,
                angle,
                sides,
            } => Shape::Cylinder {
                cm: g(*cm)?,
                length: *length,
                radius: *radius,
                angle: *angle,
                sides: *sides,
            },
            Shape::Frustum {
                cm,
                length,
                top,
                bottom,
                angle,
                sides,
            } => Shape::Frustum {
                cm: g(*cm)?,
                length: *length,
                top: *top,
                bottom: *bottom,
                angle: *angle,
                sides: *sides,
            },
            Shape::Box { corner, extent } => Shape::Box {
                corner: g(*corner)?,
                extent: *extent,
            },
            Shape::Ellipsoid { cm, diameters } => Shape::Ellipsoid {
                cm: g(*cm)?,
                diameters: *diameters,
            },
            Shape::Circle {
                cm,
                radius,
                segments,
            } => Shape::Circle {
                cm: g(*cm)?,
                radius: *radius,
                segments: *segments,
            },
            Shape::Arc {
                cm,
                radius,
                angle,
                segments,
            } => Shape::Arc {
                cm: g(*cm)?,
                radius: *radius,
                angle: *angle,
                segments: *segments,
            },
            Shape::Outline { markers } => Shape::Outline {
                markers: markers.iter().map(|m| g(*m)).collect::<Result<_, _>>()?,
            },
            Shape::Link { i, j, width, depth } => Shape::Link {
                i: g(*i)?,
                j: g(*j)?,
                width: *width,
                depth: *depth,
            },
            Shape::SpringDamper {
                i,
                j,
                coils,
                diameter,
            } => Shape::SpringDamper {
                i: g(*i)?,
                j: g(*j)?,
                coils: *coils,
                diameter: *diameter,
            },
            Shape::External { rm, file } => Shape::External {
                rm: g(*rm)?,
                file: file.clone(),
            },
            Shape::Point { rm } => Shape::Point { rm: g(*rm)? },
            Shape::Plane { rm, limits } => Shape::Plane {
                rm: g(*rm)?,
                limits: *limits,
            },
            Shape::Curve { cid, crm } => Shape::Curve {
                cid: *cid,
                crm: g(*crm)?,
            },
            Shape::Other { kind } => Shape::Other { kind: kind.clone() },
        })
    }
}

/// Types every GRAPHICS statement of `ds` (in statement order) and returns the graphics with
/// the warnings about those that cannot be drawn (each at its statement or value).
pub fn type_graphics(ds: &Dataset) -> (Vec<Graphic>, Vec<Diagnostic>) {
    let mut reader = Reader {
        file: ds.file.clone(),
        warnings: Vec::new(),
        text: &ds.text,
    };
    let graphics = ds
        .statements
        .iter()
        .enumerate()
        .filter(|(_, st)| st.known && st.keyword == "GRAPHICS")
        .filter_map(|(index, st)| {
            let shape = reader.shape(st)?;
            Some(Graphic {
                header: super::header(st, index),
                shape,
            })
        })
        .collect();
    (graphics, reader.warnings)
}

/// The canonical GRAPHICS keyword `written` stands for, if any (exact or unambiguous prefix).
fn canonical(written: &str) -> Option<&'static str> {
    let upper = written.to_ascii_uppercase();
    if let Some(exact) = GRAPHICS_KEYS.iter().find(|k| **k == upper) {
        return Some(exact);
    }
    let mut candidates = GRAPHICS_KEYS.iter().filter(|k| k.starts_with(&upper));
    match (candidates.next(), candidates.next()) {
        (Some(only), None) => Some(only),
        _ => None,
    }
}

struct Reader<'t> {
    file: std::sync::Arc<str>,
    warnings: Vec<Diagnostic>,
    /// The dataset's text, for file names as written (the lexer upper-cases bare words).
    text: &'t str,
}

/// The bare word that starts at `span` in `text` (1-based line, 1-based character column),
/// as written: up to a comma, blank or comment.
fn as_written(text: &str, span: Span) -> Option<String> {
    let line = text
        .lines()
        .nth(usize::try_from(span.line).ok()?.checked_sub(1)?)?;
    let from = usize::try_from(span.col).ok()?.checked_sub(1)?;
    let word: String = line
        .chars()
        .skip(from)
        .take_while(|c| !matches!(c, ',' | ' ' | '\t' | '!' | '\\'))
        .collect();
    (!word.is_empty()).then_some(word)
}

impl Reader<'_> {
    fn warn(&mut self, span: Span, msg: String) {
        self.warnings
            .push(Diagnostic::warning(self.file.clone(), Some(span), msg));
    }

    fn arg<'s>(st: &'s Statement, key: &str) -> Option<&'s Argument> {
        st.args.iter().find(|a| canonical(&a.key) == Some(key))
    }

    /// The numbers of `key`, or a warning when one is not a number.
    fn numbers(&mut self, st: &Statement, key: &str) -> Option<Vec<f64>> {
        let arg = Self::arg(st, key)?;
        let mut out = Vec::with_capacity(arg.values.len());
        for v in &arg.values {
            match v {
                Value::Number { value, .. } if value.is_finite() => out.push(*value),
                other => {
                    let msg = format!(
                        "{}: '{key}' expects numbers; the graphic is not drawn",
                        label(st)
                    );
                    self.warn(other.span(), msg);
                    return None;
                }
            }
        }
        Some(out)
    }

    fn number(&mut self, st: &Statement, key: &str) -> Option<f64> {
        self.numbers(st, key)?.first().copied()
    }

    fn marker(&mut self, st: &Statement, key: &str) -> Option<IdRef> {
        let arg = Self::arg(st, key)?;
        match arg.values.first() {
            Some(Value::Number { value, span, .. })
                if *value >= 0.0 && value.fract() == 0.0 && *value < 9.0e15 =>
            {
                Some(IdRef {
                    id: *value as u64,
                    span: *span,
                })
            }
            _ => {
                let msg = format!("{}: '{key}' expects a marker id", label(st));
                self.warn(arg.span, msg);
                None
            }
        }
    }

    /// A value the shape cannot be drawn without: a warning at the statement when missing.
    fn required<T>(&mut self, st: &Statement, key: &str, value: Option<T>) -> Option<T> {
        if value.is_none() && Self::arg(st, key).is_none() {
            let msg = format!("{} needs {key} = …; the graphic is not drawn", label(st));
            self.warn(st.span, msg);
        }
        value
    }

    fn count(&mut self, st: &Statement, key: &str) -> u32 {
        self.number(st, key)
            .filter(|n| *n >= 1.0)
            .map_or(DEFAULT_SEGMENTS, |n| n.min(1000.0) as u32)
    }

    fn shape(&mut self, st: &Statement) -> Option<Shape> {
        let kind = st
            .args
            .iter()
            .filter(|a| a.values.is_empty())
            .find_map(|a| canonical(&a.key).filter(|k| SHAPE_KEYS.contains(k)));
        if kind.is_none() {
            if let Some(markers) = Self::arg(st, "OUTLINE").map(|a| a.values.clone()) {
                return self.outline(st, &markers);
            }
            let msg = format!("{} names no shape; it is not drawn", label(st));
            self.warn(st.span, msg);
            return None;
        }
        let full_turn = std::f64::consts::TAU;
        Some(match kind? {
            "CYLINDER" => {
                let cm = self.marker(st, "CM");
                let length = self.number(st, "LENGTH");
                let radius = self.number(st, "RADIUS");
                Shape::Cylinder {
                    cm: self.required(st, "CM", cm)?,
                    length: self.required(st, "LENGTH", length)?,
                    radius: self.required(st, "RADIUS", radius)?,
                    angle: self.number(st, "RANGLE").unwrap_or(full_turn),
                    sides: self.count(st, "SIDES"),
                }
            }
            "FRUSTUM" => {
                let cm = self.marker(st, "CM");
                let length = self.number(st, "LENGTH");
                let top = self.number(st, "TOP");
                let bottom = self.number(st, "BOTTOM");
                Shape::Frustum {
                    cm: self.required(st, "CM", cm)?,
                    length: self.required(st, "LENGTH", length)?,
                    top: self.required(st, "TOP", top)?,
                    bottom: self.required(st, "BOTTOM", bottom)?,
                    angle: self.number(st, "RANGLE").unwrap_or(full_turn),
                    sides: self.count(st, "SIDES"),
                }
            }
            "BOX" => {
                let corner = self.marker(st, "CORNER");
                let extent = [
                    self.number(st, "X").unwrap_or(0.0),
                    self.number(st, "Y").unwrap_or(0.0),
                    self.number(st, "Z").unwrap_or(0.0),
                ];
                Shape::Box {
                    corner: self.required(st, "CORNER", corner)?,
                    extent,
                }
            }
            "ELLIPSOID" => {
                let cm = self.marker(st, "CM");
                Shape::Ellipsoid {
                    cm: self.required(st, "CM", cm)?,
                    diameters: [
                        self.number(st, "XSCALE").unwrap_or(1.0),
                        self.number(st, "YSCALE").unwrap_or(1.0),
                        self.number(st, "ZSCALE").unwrap_or(1.0),
                    ],
                }
            }
            "CIRCLE" => {
                let cm = self.marker(st, "CM");
                let radius = self.number(st, "RADIUS");
                Shape::Circle {
                    cm: self.required(st, "CM", cm)?,
                    radius: self.required(st, "RADIUS", radius)?,
                    segments: self.count(st, "SEG"),
                }
            }
            "ARC" => {
                let cm = self.marker(st, "CM");
                let radius = self.number(st, "RADIUS");
                Shape::Arc {
                    cm: self.required(st, "CM", cm)?,
                    radius: self.required(st, "RADIUS", radius)?,
                    angle: self.number(st, "RANGLE").unwrap_or(full_turn),
                    segments: self.count(st, "SEG"),
                }
            }
            "LINK" => {
                let i = self.marker(st, "I");
                let j = self.marker(st, "J");
                Shape::Link {
                    i: self.required(st, "I", i)?,
                    j: self.required(st, "J", j)?,
                    width: self.number(st, "WIDTH"),
                    depth: self.number(st, "DEPTH"),
                }
            }
            "SPDP" => {
                let i = self.marker(st, "I");
                let j = self.marker(st, "J");
                Shape::SpringDamper {
                    i: self.required(st, "I", i)?,
                    j: self.required(st, "J", j)?,
                    coils: self
                        .number(st, "COILS")
                        .filter(|c| *c >= 0.0)
                        .map_or(0, |c| c.min(500.0) as u32),
                    diameter: self.number(st, "DA"),
                }
            }
            "EXTERNAL" => {
                let rm = self.marker(st, "RM");
                let file = Self::arg(st, "FILE").and_then(|a| match a.values.first() {
                    Some(Value::Word { text, span }) => Some(
                        as_written(self.text, *span)
                            .filter(|w| w.eq_ignore_ascii_case(text))
                            .unwrap_or_else(|| text.clone()),
                    ),
                    Some(Value::Str { text, .. }) => Some(text.clone()),
                    Some(Value::Expr(e)) => Some(e.text.trim().to_string()),
                    _ => None,
                });
                Shape::External {
                    rm: self.required(st, "RM", rm)?,
                    file,
                }
            }
            "POINT" => {
                let rm = self.marker(st, "RM");
                Shape::Point {
                    rm: self.required(st, "RM", rm)?,
                }
            }
            "PLANE" => {
                let rm = self.marker(st, "RM");
                let rm = self.required(st, "RM", rm)?;
                let mut limits = [0.0; 4];
                for (l, key) in limits.iter_mut().zip(["XMIN", "XMAX", "YMIN", "YMAX"]) {
                    *l = self.number(st, key).unwrap_or(0.0);
                }
                Shape::Plane { rm, limits }
            }
            "CURVE" => {
                let crm = self.marker(st, "CRM");
                let crm = self.required(st, "CRM", crm)?;
                let cid = self.marker(st, "CID");
                let cid = self.required(st, "CID", cid)?;
                Shape::Curve { cid: cid.id, crm }
            }
            other => Shape::Other {
                kind: other.to_string(),
            },
        })
    }

    fn outline(&mut self, st: &Statement, values: &[Value]) -> Option<Shape> {
        let mut markers = Vec::with_capacity(values.len());
        for v in values {
            match v {
                Value::Number { value, span, .. } if *value >= 0.0 && value.fract() == 0.0 => {
                    markers.push(IdRef {
                        id: *value as u64,
                        span: *span,
                    })
                }
                other => {
                    let msg = format!("{}: OUTLINE expects marker ids", label(st));
                    self.warn(other.span(), msg);
                    return None;
                }
            }
        }
        if markers.len() < 2 {
            let msg = format!("{}: an OUTLINE needs at least two markers", label(st));
            self.warn(st.span, msg);
            return None;
        }
        Some(Shape::Outline { markers })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn graphics(body: &str) -> (Vec<Graphic>, Vec<Diagnostic>) {
        let text = format!("title\n{body}\nEND\n");
        let ds = crate::parse_dataset("t.adm".into(), &text).expect("parses");
        type_graphics(&ds)
    }

    #[test]
    fn corpus_shapes_are_typed_with_their_dimensions() {
        let (g, w) = graphics(
            "GRAPHICS/1, CYLINDER, CM = 3, LENGTH = 0.157, RADIUS = 0.0375\n\
             GRAPHICS/2, BOX, COR = 0202, X = 2500, Y = 1700, Z = 2\n\
             GRAPHICS/3\n, FRUSTUM\n, CM = 5\n, LENGTH = 0.15\n, SIDES = 18\n, TOP = 0.17\n, BOTTOM = 0.34\n\
             GRAPHICS/4, ELLIPSOID, CM = 3, XSCALE = 40, YSCALE = 30, ZSCALE = 20\n\
             GRAPHICS/5, OUTLINE = 5121, 5122, 5123, 5121\n\
             GRAPHICS/6, ARC, CM = 3, RADIUS = 2, RANGLE = 90D, SEG = 8\n\
             GRAPHICS/7, EXTERNAL, RM = 2335, FILE = Only_AGV.xmt_txt, ELEMENT = SOLID3\n\
             GRAPHICS/8, FORCE, ETYPE = SFORCE, EID = 1, EMARKER = 176\n\
             GRAPHICS/9, LINK, I = 3, J = 4, WIDTH = 0.1, DEPTH = 0.05\n\
             GRAPHICS/10, POINT, RM = 6\n\
             GRAPHICS/11, PLANE, RM = 7, XMIN = -1, XMAX = 2, YMIN = -3, YMAX = 4",
        );
        assert!(w.is_empty(), "{w:?}");
        assert_eq!(g.len(), 11);
        assert!(matches!(g[9].shape, Shape::Point { rm } if rm.id == 6));
        assert!(
            matches!(g[10].shape, Shape::Plane { rm, limits } if rm.id == 7 && limits == [-1.0, 2.0, -3.0, 4.0])
        );
        match &g[0].shape {
            Shape::Cylinder {
                cm,
                length,
                radius,
                sides,
                ..
            } => {
                assert_eq!(cm.id, 3);
                assert_eq!((*length, *radius, *sides), (0.157, 0.0375, 20));
            }
            s => panic!("{s:?}"),
        }
        assert_eq!(
            g[1].shape,
            Shape::Box {
                corner: g[1].shape.markers()[0],
                extent: [2500.0, 1700.0, 2.0]
            }
        );
        assert_eq!(g[1].shape.markers()[0].id, 202);
        assert!(matches!(
            g[2].shape,
            Shape::Frustum { top, bottom, sides: 18, .. } if top == 0.17 && bottom == 0.34
        ));
        assert!(
            matches!(g[3].shape, Shape::Ellipsoid { diameters, .. } if diameters == [40.0, 30.0, 20.0])
        );
        let ids: Vec<u64> = g[4].shape.markers().iter().map(|m| m.id).collect();
        assert_eq!(ids, [5121, 5122, 5123, 5121]);
        assert!(
            matches!(g[5].shape, Shape::Arc { angle, segments: 8, .. } if (angle - std::f64::consts::FRAC_PI_2).abs() < 1e-15)
        );
        assert!(
            matches!(&g[6].shape, Shape::External { rm, file: Some(f) } if rm.id == 2335 && f == "Only_AGV.xmt_txt")
        );
        assert_eq!(g[7].shape.kind(), "FORCE");
        assert_eq!(g[8].shape.markers().len(), 2);
    }

    #[test]
    fn a_shape_missing_its_marker_is_a_warning_at_its_line() {
        let (g, w) = graphics("GRAPHICS/1, CYLINDER, LENGTH = 1, RADIUS = 2\nGRAPHICS/2, BOX");
        assert!(g.is_empty());
        assert_eq!(w.len(), 2, "{w:?}");
        assert_eq!(w[0].span.map(|s| s.line), Some(2));
        assert!(w[0].message.contains("GRAPHICS/1 needs CM"), "{}", w[0]);
        assert!(!w[0].is_error());
    }
}
