//! Typing of the nonlinear finite-element statements (ADM-ELEMENTS §18): FE_PART, FE_NODE,
//! SECTION, MATERIAL, FE_LOAD, and the node references of markers on an FE_PART
//! (`MARKER/id, FE_PART = f, NODE_LABEL = n | S = s`).
//!
//! Contract:
//! - Typed on demand from the dataset's statements ([`type_fe_data`]), as GRAPHICS is: the
//!   parser has resolved the argument keywords (their tables are complete), this module reads
//!   the values and checks what one statement can tell.
//! - FE_PART: `TYPE` is `3DBEAM` or `3DCABLE` (the planar `2DBEAMXY/YZ/ZX` are an error at
//!   the value: linkage has no planar reduction); `NODE_LABELS` at least two distinct labels;
//!   `COORDINATES` seven numbers per node (label, x, y, z in the FE_PART's BCS, then the
//!   node's 3-1-3 angles ψ, θ, φ in **radians**), one entry per label; `SECTION` six numbers
//!   per node (label, A, Iyy, Izz, Iyz, Jxx) or one SECTION statement id for every node;
//!   `MATERIAL` a MATERIAL id (required); `CRATIOK`, `CRATIOM` ≥ 0 (default 0).
//! - SECTION: AREA, IYY, IZZ, JXX required (IYZ default 0); MATERIAL: DENSITY and
//!   YOUNGS_MODULUS required (> 0), POISSONS_RATIO default 0.3 [decided: Adams View's steel].
//! - FE_LOAD: `FE_PART` required, components `FX … TZ` (expressions) or `FUNCTION = USER(…)`.
//! - References between statements are the model builder's business.

use super::Typer;
use crate::diagnostic::{Diagnostic, Span};
use crate::statement::{Statement, Value};
use crate::typed::{Dataset, FeMarkerNode, Function, Header, IdRef, Located, MarkerCarrier};

/// The kind of an FE_PART.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FeKind {
    /// `3DBEAM`: axial, bending, torsion.
    Beam3d,
    /// `3DCABLE`: axial (tension only), no bending or torsion stiffness.
    Cable3d,
}

/// One node of an FE_PART's `COORDINATES`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FeNodeCoordinates {
    pub label: u64,
    /// Position in the FE_PART's BCS.
    pub position: [f64; 3],
    /// 3-1-3 angles (radians) of the node's axes in the BCS: x tangent to the beam.
    pub angles: [f64; 3],
    pub span: Span,
}

/// Section constants: area, second moments about the section's y and z axes, product
/// `Iyz = ∫ y·z dA`, torsion constant Jxx.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SectionConstants {
    pub area: f64,
    pub iyy: f64,
    pub izz: f64,
    pub iyz: f64,
    pub jxx: f64,
}

/// The `SECTION` argument of an FE_PART.
#[derive(Clone, Debug, PartialEq)]
pub enum FeSections {
    /// Per node label.
    PerNode(Vec<(u64, SectionConstants, Span)>),
    /// One SECTION statement for every node.
    Statement(IdRef),
}

/// `FE_PART/id, TYPE, NODE_LABELS, COORDINATES, SECTION, MATERIAL [, CRATIOK] [, CRATIOM]
/// [, QG] [, REULER]`.
#[derive(Clone, Debug, PartialEq)]
pub struct FePartStatement {
    pub header: Header,
    pub kind: FeKind,
    pub labels: Vec<u64>,
    /// In the order of `labels`.
    pub nodes: Vec<FeNodeCoordinates>,
    pub sections: FeSections,
    pub material: IdRef,
    pub cratiok: f64,
    pub cratiom: f64,
    pub qg: Option<Located<[f64; 3]>>,
    pub reuler: Option<Located<[f64; 3]>>,
}

/// `SECTION/id`.
#[derive(Clone, Debug, PartialEq)]
pub struct SectionStatement {
    pub header: Header,
    pub constants: SectionConstants,
}

/// `MATERIAL/id, DENSITY, YOUNGS_MODULUS [, POISSONS_RATIO]`.
#[derive(Clone, Debug, PartialEq)]
pub struct MaterialStatement {
    pub header: Header,
    pub density: f64,
    pub youngs_modulus: f64,
    pub poissons_ratio: f64,
}

/// `FE_NODE/id, FE_PART, LABEL, S, …` (Adams View bookkeeping; S is the node's place along
/// the beam, 0 … 1).
#[derive(Clone, Debug, PartialEq)]
pub struct FeNodeStatement {
    pub header: Header,
    pub fe_part: IdRef,
    pub label: u64,
    pub s: Option<f64>,
}

/// `FE_LOAD/id, FE_PART [, RM], FX … TZ | FUNCTION = USER(…)`.
#[derive(Clone, Debug, PartialEq)]
pub struct FeLoadStatement {
    pub header: Header,
    pub fe_part: IdRef,
    pub rm: Option<IdRef>,
    /// FX, FY, FZ.
    pub force: [Option<Located<Function>>; 3],
    /// TX, TY, TZ.
    pub torque: [Option<Located<Function>>; 3],
    /// `FUNCTION = USER(…)`.
    pub user: Option<Located<Function>>,
}

/// The FE statements of a dataset.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FeData {
    pub parts: Vec<FePartStatement>,
    pub sections: Vec<SectionStatement>,
    pub materials: Vec<MaterialStatement>,
    pub nodes: Vec<FeNodeStatement>,
    pub loads: Vec<FeLoadStatement>,
    /// Per marker id on an FE_PART: its node reference (`None`: neither NODE_LABEL nor S).
    pub marker_nodes: Vec<(u64, Option<FeMarkerNode>)>,
}

impl FeData {
    /// Whether the dataset has any FE statement.
    pub fn is_empty(&self) -> bool {
        self.parts.is_empty() && self.loads.is_empty()
    }
}

/// Types every FE statement of `ds`. Returns the data and the diagnostics (errors and
/// warnings) found; a statement with an error is left out.
pub fn type_fe_data(ds: &Dataset) -> (FeData, Vec<Diagnostic>) {
    let mut t = Typer {
        file: ds.file.clone(),
        diagnostics: Vec::new(),
        ds: Dataset::empty(ds.file.clone()),
        carrier: None,
    };
    let mut out = FeData::default();
    for (index, st) in ds.statements.iter().enumerate() {
        if !st.known {
            continue;
        }
        match st.keyword.as_str() {
            "FE_PART" => out.parts.extend(t.fe_part(st, index)),
            "SECTION" => out.sections.extend(t.section(st, index)),
            "MATERIAL" => out.materials.extend(t.material(st, index)),
            "FE_NODE" => out.nodes.extend(t.fe_node(st, index)),
            "FE_LOAD" => out.loads.extend(t.fe_load(st, index)),
            _ => {}
        }
    }
    // Markers on FE parts are typed with the other markers (their NODE_LABEL or S too).
    out.marker_nodes = ds
        .markers
        .iter()
        .filter(|m| matches!(m.carrier, Some(MarkerCarrier::FePart(_))))
        .map(|m| (m.header.id, m.fe_node.clone()))
        .collect();
    (out, t.diagnostics)
}

impl Typer {
    fn fe_part(&mut self, st: &Statement, index: usize) -> Option<FePartStatement> {
        let header = super::header(st, index);
        let name = header.name.clone();
        let kind = self.fe_kind(st)?;
        let labels = self.fe_labels(st, &name)?;
        let nodes = self.fe_coordinates(st, &name, &labels)?;
        let sections = self.fe_sections(st, &name, &labels)?;
        let material = self.required_id(st, "MATERIAL", "MATERIAL")?;
        let cratiok = self.non_negative(st, "CRATIOK")?;
        let cratiom = self.non_negative(st, "CRATIOM")?;
        Some(FePartStatement {
            header,
            kind,
            labels,
            nodes,
            sections,
            material,
            cratiok,
            cratiom,
            qg: self.vec3(st, "QG"),
            reuler: self.vec3(st, "REULER"),
        })
    }

    fn fe_kind(&mut self, st: &Statement) -> Option<FeKind> {
        let Some(arg) = st.arg("TYPE") else {
            self.error(st.span, format!("{}: TYPE is required", super::label(st)));
            return None;
        };
        // `3DBEAM` may be read as the number 3 with a `D` suffix followed by a word: join.
        let text: String = arg
            .values
            .iter()
            .map(|v| match v {
                Value::Word { text, .. } | Value::Str { text, .. } => text.clone(),
                Value::Number { value, .. } => format!("{value}"),
                Value::Expr(e) => e.text.replace(' ', ""),
            })
            .collect::<String>()
            .to_ascii_uppercase();
        match text.as_str() {
            "3DBEAM" => Some(FeKind::Beam3d),
            "3DCABLE" => Some(FeKind::Cable3d),
            "2DBEAMXY" | "2DBEAMYZ" | "2DBEAMZX" => {
                let msg = format!(
                    "{}: TYPE = {text} is a planar beam, which linkage does not model \
                     (use 3DBEAM)",
                    super::label(st)
                );
                self.error(arg.span, msg);
                None
            }
            _ => {
                let msg = format!(
                    "{}: unknown TYPE '{text}' (expected 3DBEAM or 3DCABLE)",
                    super::label(st)
                );
                self.error(arg.span, msg);
                None
            }
        }
    }

    fn fe_labels(&mut self, st: &Statement, name: &str) -> Option<Vec<u64>> {
        let Some(arg) = st.arg("NODE_LABELS") else {
            self.error(st.span, format!("{name}: NODE_LABELS is required"));
            return None;
        };
        let mut labels = Vec::with_capacity(arg.values.len());
        for v in &arg.values {
            let id = self.as_id(st, "NODE_LABELS", v)?;
            if labels.contains(&id.id) {
                self.error(id.span, format!("{name}: node label {} repeated", id.id));
                return None;
            }
            labels.push(id.id);
        }
        if labels.len() < 2 {
            self.error(
                arg.span,
                format!("{name}: an FE_PART needs at least 2 nodes"),
            );
            return None;
        }
        Some(labels)
    }

    /// Groups of `width` numbers led by a node label, one group per label of `labels`.
    fn per_node<const W: usize>(
        &mut self,
        st: &Statement,
        key: &str,
        name: &str,
        labels: &[u64],
    ) -> Option<Vec<(u64, [f64; W], Span)>> {
        let arg = st.arg(key)?;
        let nums = self.numbers(st, arg)?;
        if nums.len() != labels.len() * (W + 1) {
            let msg = format!(
                "{name}: {key} needs {} numbers per node (label then {W} values) for {} nodes, \
                 found {}",
                W + 1,
                labels.len(),
                nums.len()
            );
            self.error(arg.span, msg);
            return None;
        }
        let mut out: Vec<(u64, [f64; W], Span)> = Vec::with_capacity(labels.len());
        for chunk in nums.chunks(W + 1) {
            let (label, span) = chunk[0];
            let known = labels.iter().find(|&&l| l as f64 == label);
            let Some(&label) = known else {
                self.error(
                    span,
                    format!("{name}: {key} names node {label}, not in NODE_LABELS"),
                );
                return None;
            };
            if out.iter().any(|(l, _, _)| *l == label) {
                self.error(span, format!("{name}: {key} gives node {label} twice"));
                return None;
            }
            let values: [f64; W] = std::array::from_fn(|c| chunk[c + 1].0);
            out.push((label, values, span));
        }
        // In the order of NODE_LABELS.
        out.sort_by_key(|(l, _, _)| labels.iter().position(|x| x == l));
        Some(out)
    }

    fn fe_coordinates(
        &mut self,
        st: &Statement,
        name: &str,
        labels: &[u64],
    ) -> Option<Vec<FeNodeCoordinates>> {
        if st.arg("COORDINATES").is_none() {
            self.error(st.span, format!("{name}: COORDINATES is required"));
            return None;
        }
        let rows = self.per_node::<6>(st, "COORDINATES", name, labels)?;
        Some(
            rows.into_iter()
                .map(|(label, v, span)| FeNodeCoordinates {
                    label,
                    position: [v[0], v[1], v[2]],
                    angles: [v[3], v[4], v[5]],
                    span,
                })
                .collect(),
        )
    }

    fn fe_sections(&mut self, st: &Statement, name: &str, labels: &[u64]) -> Option<FeSections> {
        let Some(arg) = st.arg("SECTION") else {
            self.error(st.span, format!("{name}: SECTION is required"));
            return None;
        };
        if arg.values.len() == 1 {
            let id = self.as_id(st, "SECTION", &arg.values[0])?;
            return Some(FeSections::Statement(id));
        }
        let rows = self.per_node::<5>(st, "SECTION", name, labels)?;
        let mut out = Vec::with_capacity(rows.len());
        for (label, [area, iyy, izz, iyz, jxx], span) in rows {
            let c = SectionConstants {
                area,
                iyy,
                izz,
                iyz,
                jxx,
            };
            if !self.section_ok(&c, span, &format!("{name}: node {label}")) {
                return None;
            }
            out.push((label, c, span));
        }
        Some(FeSections::PerNode(out))
    }

    /// An error unless A, Iyy, Izz, Jxx are positive and Iyz² < Iyy·Izz.
    fn section_ok(&mut self, c: &SectionConstants, span: Span, what: &str) -> bool {
        let positive = [c.area, c.iyy, c.izz, c.jxx]
            .iter()
            .all(|v| v.is_finite() && *v > 0.0);
        if !positive || !c.iyz.is_finite() || c.iyz * c.iyz >= c.iyy * c.izz {
            let msg = format!(
                "{what}: section constants must have A, Iyy, Izz, Jxx > 0 and Iyz² < Iyy·Izz \
                 (A = {}, Iyy = {}, Izz = {}, Iyz = {}, Jxx = {})",
                c.area, c.iyy, c.izz, c.iyz, c.jxx
            );
            self.error(span, msg);
            return false;
        }
        true
    }

    fn non_negative(&mut self, st: &Statement, key: &str) -> Option<f64> {
        match self.real(st, key) {
            None => Some(0.0),
            Some(r) if r.value >= 0.0 && r.value.is_finite() => Some(r.value),
            Some(r) => {
                let msg = format!(
                    "{}: {key} must be ≥ 0 (found {})",
                    super::label(st),
                    r.value
                );
                self.error(r.span, msg);
                None
            }
        }
    }

    fn required_real(&mut self, st: &Statement, key: &str) -> Option<f64> {
        if st.arg(key).is_none() {
            self.error(st.span, format!("{} needs {key}", super::label(st)));
            return None;
        }
        self.real(st, key).map(|r| r.value)
    }

    fn section(&mut self, st: &Statement, index: usize) -> Option<SectionStatement> {
        let header = super::header(st, index);
        let c = SectionConstants {
            area: self.required_real(st, "AREA")?,
            iyy: self.required_real(st, "IYY")?,
            izz: self.required_real(st, "IZZ")?,
            iyz: self.real(st, "IYZ").map_or(0.0, |r| r.value),
            jxx: self.required_real(st, "JXX")?,
        };
        let what = header.name.clone();
        self.section_ok(&c, st.span, &what)
            .then_some(SectionStatement {
                header,
                constants: c,
            })
    }

    fn material(&mut self, st: &Statement, index: usize) -> Option<MaterialStatement> {
        let header = super::header(st, index);
        let density = self.required_real(st, "DENSITY")?;
        let youngs_modulus = self.required_real(st, "YOUNGS_MODULUS")?;
        let poissons_ratio = self.real(st, "POISSONS_RATIO").map_or(0.3, |r| r.value);
        if !(density > 0.0 && youngs_modulus > 0.0 && (-1.0..0.5).contains(&poissons_ratio)) {
            let msg = format!(
                "{}: a material needs DENSITY > 0, YOUNGS_MODULUS > 0 and −1 ≤ POISSONS_RATIO \
                 < 0.5 (found {density}, {youngs_modulus}, {poissons_ratio})",
                header.name
            );
            self.error(st.span, msg);
            return None;
        }
        Some(MaterialStatement {
            header,
            density,
            youngs_modulus,
            poissons_ratio,
        })
    }

    fn fe_node(&mut self, st: &Statement, index: usize) -> Option<FeNodeStatement> {
        let header = super::header(st, index);
        let fe_part = self.required_id(st, "FE_PART", "FE_PART")?;
        let label = self.required_id(st, "LABEL", "node label")?.id;
        Some(FeNodeStatement {
            header,
            fe_part,
            label,
            s: self.real(st, "S").map(|r| r.value),
        })
    }

    fn fe_load(&mut self, st: &Statement, index: usize) -> Option<FeLoadStatement> {
        let header = super::header(st, index);
        let fe_part = self.required_id(st, "FE_PART", "FE_PART")?;
        let force = ["FX", "FY", "FZ"].map(|k| self.function(st, k));
        let torque = ["TX", "TY", "TZ"].map(|k| self.function(st, k));
        let user = self.function(st, "FUNCTION");
        if user.is_none() && force.iter().chain(&torque).all(Option::is_none) {
            let msg = format!("{}: needs FX … TZ or FUNCTION = USER(…)", header.name);
            self.error(st.span, msg);
            return None;
        }
        Some(FeLoadStatement {
            header,
            fe_part,
            rm: self.id_ref(st, "RM"),
            force,
            torque,
            user,
        })
    }

    /// NODE_LABEL or S of a marker on an FE_PART (`None`: neither, or an error reported).
    pub(super) fn marker_node(&mut self, st: &Statement) -> Option<FeMarkerNode> {
        if st.arg("NODE_LABEL").is_some() {
            let id = self.id_ref(st, "NODE_LABEL")?;
            return Some(FeMarkerNode::Label(Located {
                value: id.id,
                span: id.span,
            }));
        }
        let s = self.real(st, "S")?;
        if !(0.0..=1.0).contains(&s.value) {
            let msg = format!(
                "{}: S = {} is outside the beam (0 … 1)",
                super::label(st),
                s.value
            );
            self.error(s.span, msg);
            return None;
        }
        Some(FeMarkerNode::S(s))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::parse_dataset;
    use std::sync::Arc;

    fn data(text: &str) -> (FeData, Vec<Diagnostic>) {
        let ds = parse_dataset(Arc::from("m.adm"), text).unwrap_or_else(|e| panic!("{e}"));
        type_fe_data(&ds)
    }

    const BEAM: &str = "t\nPART/1, GROUND\nFE_PART/2, TYPE = 3DBEAM, NODE_LABELS = 1, 2, 3\n\
        , COORDINATES = 1, 0, 0, 0, 0, 0, 0, 2, 1, 0, 0, 0, 0, 0\n\
        , 3, 2, 0, 0, 90D, 0, 0\n\
        , SECTION = 1, 2, 3, 4, 0, 5, 2, 2, 3, 4, 0, 5, 3, 2, 3, 4, 0.5, 5\n\
        , MATERIAL = 1, CRATIOK = 0.01\n\
        MATERIAL/1, NAME = steel, DENSITY = 7.8E-6, YOUNGS_MODULUS = 2.1E5\n\
        MARKER/5, FE_PART = 2, NODE_LABEL = 3\nMARKER/6, FE_PART = 2, S = 0.4\n\
        FE_NODE/1, FE_PART = 2, LABEL = 2, S = 0.5\n\
        FE_LOAD/1, FE_PART = 2, FY = -1\nEND\n";

    #[test]
    fn fe_part_reads_nodes_sections_and_material() {
        let (d, diags) = data(BEAM);
        assert!(diags.is_empty(), "{diags:?}");
        let p = &d.parts[0];
        assert_eq!(p.kind, FeKind::Beam3d);
        assert_eq!(p.labels, [1, 2, 3]);
        assert_eq!(p.nodes[2].position, [2.0, 0.0, 0.0]);
        assert!((p.nodes[2].angles[0] - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        assert_eq!(p.material.id, 1);
        assert_eq!(p.cratiok, 0.01);
        assert_eq!(p.cratiom, 0.0);
        let FeSections::PerNode(s) = &p.sections else {
            panic!("per-node sections expected")
        };
        assert_eq!(s[2].1.iyz, 0.5);
        assert_eq!(s[0].1.jxx, 5.0);
        let m = &d.materials[0];
        assert_eq!(
            (m.density, m.youngs_modulus, m.poissons_ratio),
            (7.8e-6, 2.1e5, 0.3)
        );
        assert_eq!(d.nodes[0].s, Some(0.5));
        assert!(d.loads[0].force[1].is_some());
        assert!(matches!(
            &d.marker_nodes[..],
            [(5, Some(FeMarkerNode::Label(l))), (6, Some(FeMarkerNode::S(s)))]
                if l.value == 3 && s.value == 0.4
        ));
    }

    #[test]
    fn fe_part_errors_name_the_argument() {
        let bad = BEAM.replace(", 3, 2, 0, 0, 90D, 0, 0\n", "");
        let (_, diags) = data(&bad);
        assert!(
            diags
                .iter()
                .any(|d| d.message.contains("COORDINATES needs 7 numbers per node")),
            "{diags:?}"
        );
        let planar = BEAM.replace("3DBEAM", "2DBEAMXY");
        let (d, diags) = data(&planar);
        assert!(d.parts.is_empty());
        assert!(diags[0].message.contains("planar beam"), "{diags:?}");
        let cable = BEAM.replace("3DBEAM", "3DCABLE");
        assert_eq!(data(&cable).0.parts[0].kind, FeKind::Cable3d);
    }
}
