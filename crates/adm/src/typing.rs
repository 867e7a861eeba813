//! Typing: generic statements → the typed elements of a [`Dataset`].
//!
//! Contract:
//! - Types UNITS, ACCGRAV, PART, MARKER, JOINT, JPRIM, MOTION, COUPLER, GEAR and GCON
//!   (ADM-REFERENCE §2.1–2.9), the force elements SFORCE, SPRINGDAMPER, BUSHING, FIELD, BEAM,
//!   VFORCE, VTORQUE, GFORCE and the data elements VARIABLE, ARRAY, SPLINE (§2.10–2.11, see
//!   [`forces`]), POINT_MASS (as a [`Part`] without inertia, [`point_mass`]), SENSOR
//!   ([`sensor`]), FRICTION ([`friction`]) and the output
//!   statement REQUEST (§2.12); every other statement stays in
//!   generic form only.
//! - Checks what one statement can tell: value counts (`QP` needs 3 numbers), ids being
//!   non-negative integers, unit names, joint/jprim types, required arguments (JOINT `I`, `J`,
//!   type; MOTION target; COUPLER/GEAR `JOINTS`). References between elements are *not* checked
//!   (that is `linkage-model`'s job), duplicate ids are accepted.
//! - An argument given twice is a warning (the first one is used), as is a second UNITS or
//!   ACCGRAV statement (the last one is used).
//! - A MARKER without `PART=`/`POINT_MASS=`/`FLEX_BODY=`/`FE_PART=` belongs to the most recently
//!   read PART, POINT_MASS or FLEX_BODY statement (its [`IdRef`] then points at that statement's
//!   keyword); `None` when there is none.
//! - UNITS and ACCGRAV have no id: their [`Header`] has id 0 and the statement name as name.

use crate::diagnostic::{Diagnostic, Diagnostics, Span};
use crate::keywords::{self, Lookup};
use crate::parse::Parsed;
use crate::statement::{Argument, Statement, Value};
use crate::typed::*;
use std::sync::Arc;

/// Types the parsed statements of a dataset. `text` is the whole file (its line 1 is the title).
///
/// Returns the dataset with its warnings, or every error found (parse and typing errors).
pub(crate) fn type_dataset(
    file: Arc<str>,
    text: &str,
    parsed: Parsed,
) -> Result<Dataset, Diagnostics> {
    // The first line (as `split_lines` cuts it), without splitting the whole text.
    let first = text.split(['\n', '\r']).next().unwrap_or_default();
    let title = first.trim_start_matches('\u{feff}').trim_end().to_string();
    let mut ds = Dataset::empty(file.clone());
    ds.text = text.to_string();
    ds.title = title;
    ds.end_line = parsed.stop_line;
    // The typed lists sized once (the largest models are mostly parts, markers and joints).
    let count = |keyword: &str| {
        parsed
            .statements
            .iter()
            .filter(|st| st.keyword == keyword)
            .count()
    };
    ds.parts.reserve_exact(count("PART"));
    ds.markers.reserve_exact(count("MARKER"));
    ds.joints.reserve_exact(count("JOINT"));
    let mut typer = Typer {
        file,
        diagnostics: parsed.diagnostics,
        ds,
        carrier: None,
    };
    for (index, st) in parsed.statements.iter().enumerate() {
        typer.statement(st, index);
    }
    typer.ds.statements = parsed.statements;
    let Typer {
        mut diagnostics,
        mut ds,
        ..
    } = typer;
    diagnostics.sort_by_key(|d| d.span);
    let (errors, warnings): (Vec<_>, Vec<_>) =
        diagnostics.into_iter().partition(Diagnostic::is_error);
    if errors.is_empty() {
        ds.warnings = warnings;
        Ok(ds)
    } else {
        Err(Diagnostics(errors))
    }
}

/// Builds the typed elements, collecting diagnostics.
struct Typer {
    file: Arc<str>,
    diagnostics: Vec<Diagnostic>,
    ds: Dataset,
    /// The most recently read PART / POINT_MASS / FLEX_BODY (default MARKER carrier).
    carrier: Option<MarkerCarrier>,
}

/// `<STATEMENT>/<id>` as written in messages.
fn label(st: &Statement) -> String {
    match st.id {
        Some(id) => format!("{}/{id}", st.keyword),
        None => st.keyword.clone(),
    }
}

fn header(st: &Statement, index: usize) -> Header {
    let name = st.view_name.clone().unwrap_or_else(|| match st.id {
        Some(id) => crate::statement::keyword_id(&st.keyword, '_', id),
        None => st.keyword.clone(),
    });
    Header {
        id: st.id.unwrap_or(0),
        name,
        span: st.span,
        statement: index,
    }
}

/// Whether an expression is a `USER(…)` subroutine call.
fn is_user_call(text: &str) -> bool {
    let t = text.trim_start();
    t.get(..4).is_some_and(|w| w.eq_ignore_ascii_case("USER"))
        && t.get(4..).is_some_and(|r| r.trim_start().starts_with('('))
}

/// Largest integer an f64 holds exactly; ids above it are rejected.
const MAX_EXACT_ID: f64 = 9_007_199_254_740_992.0;

impl Typer {
    fn error(&mut self, span: Span, msg: impl Into<String>) {
        self.diagnostics
            .push(Diagnostic::error(self.file.clone(), Some(span), msg));
    }

    fn warning(&mut self, span: Span, msg: impl Into<String>) {
        self.diagnostics
            .push(Diagnostic::warning(self.file.clone(), Some(span), msg));
    }

    fn statement(&mut self, st: &Statement, index: usize) {
        if !st.known {
            return;
        }
        match st.keyword.as_str() {
            "PART" => {
                self.carrier = st
                    .id
                    .map(|id| MarkerCarrier::Part(IdRef { id, span: st.span }))
            }
            "POINT_MASS" => {
                self.carrier = st
                    .id
                    .map(|id| MarkerCarrier::PointMass(IdRef { id, span: st.span }))
            }
            "FLEX_BODY" => {
                self.carrier = st
                    .id
                    .map(|id| MarkerCarrier::FlexBody(IdRef { id, span: st.span }))
            }
            _ => {}
        }
        let typed = matches!(
            st.keyword.as_str(),
            "UNITS"
                | "ACCGRAV"
                | "PART"
                | "POINT_MASS"
                | "SENSOR"
                | "FRICTION"
                | "MARKER"
                | "JOINT"
                | "JPRIM"
                | "MOTION"
                | "COUPLER"
                | "GEAR"
                | "GCON"
                | "SFORCE"
                | "SPRINGDAMPER"
                | "BUSHING"
                | "FIELD"
                | "BEAM"
                | "VFORCE"
                | "VTORQUE"
                | "GFORCE"
                | "VARIABLE"
                | "ARRAY"
                | "SPLINE"
                | "REQUEST"
                | "DIFF"
                | "LSE"
                | "TFSISO"
                | "GSE"
                | "MATRIX"
                | "PINPUT"
                | "POUTPUT"
        );
        if !typed {
            return;
        }
        self.warn_repeated_arguments(st);
        match st.keyword.as_str() {
            "UNITS" => {
                let units = self.units(st, index);
                if self.ds.units.is_some() {
                    self.warning(st.span, "UNITS given more than once; the last one is used");
                }
                self.ds.units = Some(units);
            }
            "ACCGRAV" => {
                let accgrav = self.accgrav(st, index);
                if self.ds.accgrav.is_some() {
                    self.warning(
                        st.span,
                        "ACCGRAV given more than once; the last one is used",
                    );
                }
                self.ds.accgrav = Some(accgrav);
            }
            "PART" => {
                let part = self.part(st, index);
                self.ds.parts.push(part);
            }
            "SENSOR" => {
                if let Some(sensor) = self.sensor(st, index) {
                    self.ds.sensors.push(sensor);
                }
            }
            "FRICTION" => {
                if let Some(f) = self.friction(st, index) {
                    self.ds.frictions.push(f);
                }
            }
            "POINT_MASS" => {
                let pm = self.point_mass(st, index);
                self.ds.point_masses.push(pm);
            }
            "MARKER" => {
                if let Some(m) = self.marker(st, index) {
                    self.ds.markers.push(m);
                }
            }
            "JOINT" => {
                if let Some(j) = self.joint(st, index) {
                    self.ds.joints.push(j);
                }
            }
            "JPRIM" => {
                if let Some(j) = self.jprim(st, index) {
                    self.ds.jprims.push(j);
                }
            }
            "MOTION" => {
                if let Some(m) = self.motion(st, index) {
                    self.ds.motions.push(m);
                }
            }
            "COUPLER" => {
                if let Some(c) = self.coupler(st, index) {
                    self.ds.couplers.push(c);
                }
            }
            "GEAR" => {
                if let Some(g) = self.gear(st, index) {
                    self.ds.gears.push(g);
                }
            }
            "GCON" => {
                let g = self.gcon(st, index);
                self.ds.gcons.push(g);
            }
            "REQUEST" => {
                if let Some(r) = self.request(st, index) {
                    self.ds.requests.push(r);
                }
            }
            _ => {
                if !self.control(st, index) {
                    self.force_or_data(st, index)
                }
            }
        }
    }

    /// Force and data elements ([`forces`]).
    fn force_or_data(&mut self, st: &Statement, index: usize) {
        match st.keyword.as_str() {
            "SFORCE" => {
                if let Some(e) = self.sforce(st, index) {
                    self.ds.sforces.push(e);
                }
            }
            "SPRINGDAMPER" => {
                if let Some(e) = self.springdamper(st, index) {
                    self.ds.springdampers.push(e);
                }
            }
            "BUSHING" => {
                if let Some(e) = self.bushing(st, index) {
                    self.ds.bushings.push(e);
                }
            }
            "FIELD" => {
                if let Some(e) = self.field(st, index) {
                    self.ds.fields.push(e);
                }
            }
            "BEAM" => {
                if let Some(e) = self.beam(st, index) {
                    self.ds.beams.push(e);
                }
            }
            "VFORCE" => {
                if let Some(e) = self.vforce(st, index) {
                    self.ds.vforces.push(e);
                }
            }
            "VTORQUE" => {
                if let Some(e) = self.vtorque(st, index) {
                    self.ds.vtorques.push(e);
                }
            }
            "GFORCE" => {
                if let Some(e) = self.gforce(st, index) {
                    self.ds.gforces.push(e);
                }
            }
            "VARIABLE" => {
                let v = self.variable(st, index);
                self.ds.variables.push(v);
            }
            "ARRAY" => {
                if let Some(e) = self.array(st, index) {
                    self.ds.arrays.push(e);
                }
            }
            "SPLINE" => {
                if let Some(e) = self.spline(st, index) {
                    self.ds.splines.push(e);
                }
            }
            _ => {}
        }
    }

    fn warn_repeated_arguments(&mut self, st: &Statement) {
        // Statements have a handful of arguments: a scan of the earlier ones is cheaper than a
        // set per statement (a dataset has hundreds of thousands of statements).
        for (k, a) in st.args.iter().enumerate() {
            // A 2-D SPLINE has one `Y =` per curve.
            let repeatable = st.keyword == "SPLINE" && a.key == "Y";
            let repeated = st
                .args
                .get(..k)
                .is_some_and(|b| b.iter().any(|b| b.key == a.key));
            if repeated && !repeatable {
                let msg = format!(
                    "'{}' given more than once in {}; the first one is used",
                    a.key,
                    label(st)
                );
                self.warning(a.span, msg);
            }
        }
    }

    // ---- statements --------------------------------------------------------------------------

    fn units(&mut self, st: &Statement, index: usize) -> Units {
        Units {
            header: header(st, index),
            force: self.named(st, "FORCE", keywords::FORCE_UNITS),
            mass: self.named(st, "MASS", keywords::MASS_UNITS),
            length: self.named(st, "LENGTH", keywords::LENGTH_UNITS),
            time: self.named(st, "TIME", keywords::TIME_UNITS),
            system: self.named(st, "SYSTEM", keywords::UNIT_SYSTEMS),
            ucf: self.real(st, "UCF"),
        }
    }

    fn accgrav(&mut self, st: &Statement, index: usize) -> Accgrav {
        let mut gravity = [0.0; 3];
        for (g, key) in gravity.iter_mut().zip(["IGRAV", "JGRAV", "KGRAV"]) {
            if let Some(v) = self.real(st, key) {
                *g = v.value;
            }
        }
        Accgrav {
            header: header(st, index),
            gravity,
        }
    }

    fn part(&mut self, st: &Statement, index: usize) -> Part {
        let ip = self.reals(st, "IP", &[3, 6]).map(|r| {
            let mut six = [0.0; 6];
            for (dst, src) in six.iter_mut().zip(&r.value) {
                *dst = *src;
            }
            Located {
                value: six,
                span: r.span,
            }
        });
        let mut velocity = [None; 6];
        for (v, key) in velocity
            .iter_mut()
            .zip(["VX", "VY", "VZ", "WX", "WY", "WZ"])
        {
            *v = self.real(st, key).map(|r| r.value);
        }
        Part {
            header: header(st, index),
            ground: Self::flag(st, "GROUND"),
            mass: self.real(st, "MASS"),
            cm: self.id_ref(st, "CM"),
            im: self.id_ref(st, "IM"),
            ip,
            qg: self.vec3(st, "QG"),
            reuler: self.vec3(st, "REULER"),
            xg: self.vec3(st, "XG"),
            zg: self.vec3(st, "ZG"),
            velocity,
            vm: self.id_ref(st, "VM"),
            wm: self.id_ref(st, "WM"),
            exact: self.exact(st),
        }
    }

    fn exact(&mut self, st: &Statement) -> Vec<ExactCoord> {
        let Some(arg) = st.arg("EXACT") else {
            return Vec::new();
        };
        let mut coords = Vec::new();
        for v in &arg.values {
            let coord = match v {
                Value::Word { text, .. } => match text.as_str() {
                    "X" => Some(ExactCoord::X),
                    "Y" => Some(ExactCoord::Y),
                    "Z" => Some(ExactCoord::Z),
                    "PSI" => Some(ExactCoord::Psi),
                    "THETA" => Some(ExactCoord::Theta),
                    "PHI" => Some(ExactCoord::Phi),
                    _ => None,
                },
                _ => None,
            };
            match coord {
                Some(c) => coords.push(c),
                None => {
                    let msg = "EXACT coordinates are X, Y, Z, PSI, THETA, PHI (colon-separated)";
                    self.error(v.span(), msg);
                }
            }
        }
        coords
    }

    fn marker(&mut self, st: &Statement, index: usize) -> Option<Marker> {
        type Make = fn(IdRef) -> MarkerCarrier;
        let kinds: [(&str, Make); 4] = [
            ("PART", MarkerCarrier::Part),
            ("POINT_MASS", MarkerCarrier::PointMass),
            ("FLEX_BODY", MarkerCarrier::FlexBody),
            ("FE_PART", MarkerCarrier::FePart),
        ];
        self.one_of(st, &kinds, "carrier (PART, POINT_MASS, FLEX_BODY, FE_PART)")
            .ok()?;
        let first = st.args.iter().find_map(|a| {
            kinds
                .iter()
                .find(|(k, _)| *k == a.key)
                .map(|(_, t)| (a, *t))
        });
        let carrier = match first {
            Some((arg, make)) => Some(make(self.id_ref(st, &arg.key)?)),
            None => self.carrier,
        };
        let fe_node = match carrier {
            Some(MarkerCarrier::FePart(_)) => self.marker_node(st),
            Some(MarkerCarrier::FlexBody(_)) if st.arg("NODE_ID").is_some() => {
                self.id_ref(st, "NODE_ID").map(|id| {
                    FeMarkerNode::Label(Located {
                        value: id.id,
                        span: id.span,
                    })
                })
            }
            _ => None,
        };
        Some(Marker {
            header: header(st, index),
            carrier,
            fe_node,
            qp: self.vec3(st, "QP"),
            reuler: self.vec3(st, "REULER"),
            zp: self.vec3(st, "ZP"),
            xp: self.vec3(st, "XP"),
            usexp: Self::flag(st, "USEXP"),
            floating: Self::flag(st, "FLOATING"),
            rm: self.id_ref(st, "RM"),
        })
    }

    fn joint(&mut self, st: &Statement, index: usize) -> Option<Joint> {
        use JointType::*;
        let all = [
            Convel,
            Cylindrical,
            Fixed,
            Hooke,
            Planar,
            Rackpin,
            Revolute,
            Screw,
            Spherical,
            Translational,
            Universal,
        ];
        let kinds = all.map(|t| (t.keyword(), t));
        let kind = self.one_of(st, &kinds, "joint type");
        let i = self.required_id(st, "I", "marker");
        let j = self.required_id(st, "J", "marker");
        let kind = match kind {
            Ok(Some(k)) => k,
            Ok(None) => {
                self.missing_type(st, keywords::JOINT_TYPES, "joint type");
                return None;
            }
            Err(()) => return None,
        };
        Some(Joint {
            header: header(st, index),
            kind,
            i: i?,
            j: j?,
            ic: self.reals(st, "IC", &[1, 2]),
            ictran: self.reals(st, "ICTRAN", &[1, 2]),
            icrot: self.reals(st, "ICROT", &[1, 2]),
            pd: self.real(st, "PD"),
            pitch: self.real(st, "PITCH"),
        })
    }

    fn missing_type(&mut self, st: &Statement, names: &[&str], what: &str) {
        let unknown = Self::unknown_words(st);
        let hint = if unknown.is_empty() {
            String::new()
        } else {
            format!(" ({} is not one)", unknown.join(", "))
        };
        let msg = format!(
            "{} has no {what}{hint}; expected one of {}",
            label(st),
            names.join(", ")
        );
        self.error(st.span, msg);
    }

    fn jprim(&mut self, st: &Statement, index: usize) -> Option<Jprim> {
        use JprimType::*;
        let all = [
            Atpoint,
            Inline,
            Inplane,
            Orientation,
            ParallelAxes,
            Perpendicular,
        ];
        let kinds: Vec<(&str, JprimType)> = all.iter().map(|t| (t.keyword(), *t)).collect();
        let kind = self.one_of(st, &kinds, "joint primitive type");
        let i = self.required_id(st, "I", "marker");
        let j = self.required_id(st, "J", "marker");
        let kind = match kind {
            Ok(Some(k)) => k,
            Ok(None) => {
                self.missing_type(st, keywords::JPRIM_TYPES, "joint primitive type");
                return None;
            }
            Err(()) => return None,
        };
        Some(Jprim {
            header: header(st, index),
            kind,
            i: i?,
            j: j?,
        })
    }

    fn motion(&mut self, st: &Statement, index: usize) -> Option<Motion> {
        let axes = [
            ("X", MotionAxis::X),
            ("Y", MotionAxis::Y),
            ("Z", MotionAxis::Z),
            ("B1", MotionAxis::B1),
            ("B2", MotionAxis::B2),
            ("B3", MotionAxis::B3),
        ];
        let dofs = [
            ("TRANSLATION", MotionDof::Translation),
            ("ROTATION", MotionDof::Rotation),
        ];
        let levels = [
            ("DISPLACEMENT", MotionLevel::Displacement),
            ("VELOCITY", MotionLevel::Velocity),
            ("ACCELERATION", MotionLevel::Acceleration),
        ];
        let axis = self.one_of(st, &axes, "axis (X, Y, Z, B1, B2, B3)");
        let dof = self.one_of(st, &dofs, "joint coordinate (TRANSLATION, ROTATION)");
        let level = self.one_of(st, &levels, "level (DISPLACEMENT, VELOCITY, ACCELERATION)");
        let (axis, dof, level) = (axis.ok()?, dof.ok()?, level.ok()?);

        // FUNCTION=, or the older `X = expression` form of a marker motion.
        let mut function = self.function(st, "FUNCTION");
        let axis_expr = Self::pick(st, &axes)
            .into_iter()
            .find(|(a, _)| !a.values.is_empty())
            .map(|(a, _)| a.key.clone());
        if let Some(key) = axis_expr {
            if function.is_some() {
                let msg = format!("{} gives both FUNCTION and '{key} = …'", label(st));
                self.error(st.span, msg);
                return None;
            }
            function = self.function(st, &key);
        }

        let target = if st.arg("JOINT").is_some() {
            if let Some(a) = st.arg("I").or(st.arg("J")) {
                let msg = format!("{} names both JOINT and I/J markers", label(st));
                self.error(a.span, msg);
                return None;
            }
            if let Some(axis_arg) = Self::pick(st, &axes).first() {
                let msg = format!(
                    "'{}' is for marker motions (I=, J=); a joint motion takes TRANSLATION or ROTATION",
                    axis_arg.0.key
                );
                self.error(axis_arg.0.span, msg);
                return None;
            }
            MotionTarget::Joint {
                joint: self.id_ref(st, "JOINT")?,
                dof,
            }
        } else if st.arg("I").is_some() || st.arg("J").is_some() {
            let i = self.required_id(st, "I", "marker");
            let j = self.required_id(st, "J", "marker");
            let Some(axis) = axis else {
                let msg = format!("{} needs one of X, Y, Z, B1, B2, B3", label(st));
                self.error(st.span, msg);
                return None;
            };
            MotionTarget::Markers { i: i?, j: j?, axis }
        } else {
            let msg = format!(
                "{} needs JOINT = <joint id>, or I = and J = <marker ids> with X, Y, Z, B1, B2 or B3",
                label(st)
            );
            self.error(st.span, msg);
            return None;
        };
        Some(Motion {
            header: header(st, index),
            target,
            level: level.unwrap_or_default(),
            function,
            icdisp: self.real(st, "ICDISP").map(|r| r.value),
            icvel: self.real(st, "ICVEL").map(|r| r.value),
        })
    }

    fn coupler(&mut self, st: &Statement, index: usize) -> Option<Coupler> {
        if st.arg("JOINTS").is_none() {
            let msg = format!("{} needs JOINTS = <joint ids>", label(st));
            self.error(st.span, msg);
            return None;
        }
        let joints = self.id_list(st, "JOINTS", &[2, 3])?;
        let mut types = Vec::new();
        if let Some(arg) = st.arg("TYPE") {
            for v in &arg.values {
                let dof = match v {
                    Value::Word { text, .. } if "TRANSLATIONAL".starts_with(text.as_str()) => {
                        Some(CouplerDof::Translation)
                    }
                    Value::Word { text, .. } if "ROTATIONAL".starts_with(text.as_str()) => {
                        Some(CouplerDof::Rotation)
                    }
                    _ => None,
                };
                match dof {
                    Some(d) => types.push(d),
                    None => {
                        self.error(v.span(), "COUPLER TYPE items are T or R (colon-separated)");
                        return None;
                    }
                }
            }
            if types.len() != joints.len() {
                let msg = format!(
                    "TYPE of {} has {} items for {} joints",
                    label(st),
                    types.len(),
                    joints.len()
                );
                self.error(arg.span, msg);
                return None;
            }
        }
        let counts: &[usize] = if joints.len() == 3 {
            &[1, 2, 3]
        } else {
            &[1, 2]
        };
        let scales = match st.arg("SCALES") {
            Some(_) => self.reals(st, "SCALES", counts)?.value,
            None => Vec::new(),
        };
        Some(Coupler {
            header: header(st, index),
            joints,
            types,
            scales,
            function: self.function(st, "FUNCTION"),
        })
    }

    fn gear(&mut self, st: &Statement, index: usize) -> Option<Gear> {
        if st.arg("JOINTS").is_none() {
            let msg = format!("{} needs JOINTS = <joint id>, <joint id>", label(st));
            self.error(st.span, msg);
            return None;
        }
        Some(Gear {
            header: header(st, index),
            joints: self.id_list(st, "JOINTS", &[2])?,
            cv: self.id_ref(st, "CV"),
        })
    }

    fn gcon(&mut self, st: &Statement, index: usize) -> Gcon {
        Gcon {
            header: header(st, index),
            i: self.id_ref(st, "I"),
            function: self.function(st, "FUNCTION"),
        }
    }
}

/// The text of a value, as written (a number as its value).
fn value_text(v: &Value) -> String {
    match v {
        Value::Expr(e) => e.text.clone(),
        Value::Str { text, .. } | Value::Word { text, .. } => text.clone(),
        Value::Number { value, .. } => value.to_string(),
    }
}

/// The text of an argument's values (items joined with `, `).
fn text_of(arg: &Argument) -> String {
    arg.values
        .iter()
        .map(value_text)
        .collect::<Vec<_>>()
        .join(", ")
}

impl Typer {
    /// `key = free text`.
    fn text(st: &Statement, key: &str) -> Option<Located<String>> {
        let arg = st.arg(key)?;
        Some(Located {
            value: text_of(arg),
            span: arg.values.first().map_or(arg.span, Value::span),
        })
    }

    /// `REQUEST/id` (ADM-REFERENCE §2.12): one of the three forms of [`Request`].
    fn request(&mut self, st: &Statement, index: usize) -> Option<Request> {
        let kinds = [
            ("DISPLACEMENT", RequestKind::Displacement),
            ("VELOCITY", RequestKind::Velocity),
            ("ACCELERATION", RequestKind::Acceleration),
            ("FORCE", RequestKind::Force),
        ];
        let kind = self
            .one_of(
                st,
                &kinds,
                "quantity (DISPLACEMENT, VELOCITY, ACCELERATION, FORCE)",
            )
            .ok()?;
        const F: [&str; 8] = ["F1", "F2", "F3", "F4", "F5", "F6", "F7", "F8"];
        let functions = F.map(|k| self.function(st, k));
        let function = self.function(st, "FUNCTION");
        let first_f = st.args.iter().find(|a| F.contains(&a.key.as_str()));
        if let (Some(kind), Some(other)) = (kind, first_f.or(st.arg("FUNCTION"))) {
            let msg = format!(
                "{} is a {} request and also gives '{}'; a request is either a quantity with \
                 I=, J=, or F1…F8 expressions, or FUNCTION=USER(…)",
                label(st),
                kind.keyword(),
                other.key
            );
            self.error(other.span, msg);
            return None;
        }
        if let (Some(f), Some(_)) = (first_f, st.arg("FUNCTION")) {
            let msg = format!(
                "{} gives both '{}' and FUNCTION; use F1…F8 expressions or FUNCTION=USER(…)",
                label(st),
                f.key
            );
            self.error(f.span, msg);
            return None;
        }
        let (i, j, rm) = if kind.is_some() {
            let i = self.required_id(st, "I", "marker");
            (Some(i?), self.id_ref(st, "J"), self.id_ref(st, "RM"))
        } else {
            (
                self.id_ref(st, "I"),
                self.id_ref(st, "J"),
                self.id_ref(st, "RM"),
            )
        };
        if kind.is_none() && first_f.is_none() && function.is_none() {
            let msg = format!(
                "{} defines no output (no DISPLACEMENT, VELOCITY, ACCELERATION, FORCE, F1…F8 \
                 or FUNCTION)",
                label(st)
            );
            self.warning(st.span, msg);
        }
        let cnames = st
            .arg("CNAMES")
            .map(|a| a.values.iter().map(value_text).collect())
            .unwrap_or_default();
        Some(Request {
            header: header(st, index),
            kind,
            i,
            j,
            rm,
            functions,
            function,
            comment: Self::text(st, "COMMENT"),
            title: Self::text(st, "TITLE"),
            cnames,
            results_name: Self::text(st, "RESULTS_NAME"),
        })
    }
}

pub mod contact;
pub(crate) mod controls;
pub mod fe_part;
pub mod flex_body;
mod forces;
pub(crate) mod friction;
pub mod graphics;
mod point_mass;
mod sensor;
mod values;

#[cfg(test)]
mod tests;
