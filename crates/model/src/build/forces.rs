//! The two-marker force elements (SFORCE, SPRINGDAMPER, BUSHING, FIELD, BEAM) resolved
//! against the markers and checked ([`crate::forces`] says what is resolved and checked), and
//! the resolver the vector forces share.

use super::context::{origin, Ctx};
use super::lookup::MarkerTable;
use crate::forces::{
    Beam, BeamDamping, Bushing, Field, ForceElement, ForceKind, Sforce, SpringDamper,
};
use linkage_adm::{Dataset, ForceDof, Header, IdRef, Located, Span};
use std::collections::HashSet;

/// Resolves the references of force elements and reports what is wrong with them.
pub(super) struct Resolver<'a, 'd> {
    pub cx: &'d mut Ctx,
    pub table: &'d MarkerTable<'a>,
}

impl Resolver<'_, '_> {
    pub fn error(&mut self, span: Span, msg: impl Into<String>) {
        self.cx.error(span, msg);
    }

    pub fn warn(&mut self, span: Span, msg: impl Into<String>) {
        self.cx.warn(span, msg);
    }

    /// False (after an error) when `h`'s id is already in `seen`.
    pub fn unique(&mut self, seen: &mut HashSet<u64>, statement: &str, h: &Header) -> bool {
        self.cx.unique(seen, statement, h)
    }

    /// A marker that exists on a part or ground. `fixed`: FLOATING is refused.
    pub fn marker(&mut self, r: IdRef, elem: &str, role: &str, fixed: bool) -> Option<usize> {
        let Some(&m) = self.table.index.get(&r.id) else {
            self.error(
                r.span,
                format!("{elem}: {role} marker {} does not exist", r.id),
            );
            return None;
        };
        if let Some(kind) = self.table.unsupported(m) {
            self.error(
                r.span,
                format!(
                    "{elem}: {role} marker {} is on a {kind}, which linkage does not model",
                    r.id
                ),
            );
            return None;
        }
        if fixed && self.table.markers[m].floating {
            self.error(
                r.span,
                format!(
                    "{elem}: {role} marker {} is FLOATING; {role} must be a fixed marker",
                    r.id
                ),
            );
            return None;
        }
        Some(m)
    }

    /// I and J of a two-marker element; a warning when both are on one body (unless the
    /// element acts on I only, J giving just a direction).
    fn pair(
        &mut self,
        i: IdRef,
        j: IdRef,
        h: &Header,
        action_only: bool,
    ) -> Option<(usize, usize)> {
        let mi = self.marker(i, &h.name, "I", true);
        let mj = self.marker(j, &h.name, "J", true);
        let (mi, mj) = (mi?, mj?);
        let body = self.table.markers[mi].body;
        if body == self.table.markers[mj].body && !action_only {
            let msg = format!(
                "{}: I marker {} and J marker {} are both on {}; the element exerts no net load",
                h.name,
                i.id,
                j.id,
                self.table.body_name(body)
            );
            self.warn(h.span, msg);
        }
        Some((mi, mj))
    }

    /// A value that must not be negative (stiffness, damping).
    fn non_negative(&mut self, v: Option<&Located<f64>>, what: &str, elem: &str) -> f64 {
        match v {
            Some(l) if l.value < 0.0 => {
                self.error(
                    l.span,
                    format!("{elem}: {what} must not be negative ({})", l.value),
                );
                0.0
            }
            Some(l) => l.value,
            None => 0.0,
        }
    }

    /// Three values that must not be negative (stiffness, damping per axis).
    fn non_negative3(&mut self, v: Option<&Located<[f64; 3]>>, what: &str, elem: &str) -> [f64; 3] {
        match v {
            Some(l) if l.value.iter().any(|x| *x < 0.0) => {
                self.error(
                    l.span,
                    format!("{elem}: {what} must not be negative ({:?})", l.value),
                );
                [0.0; 3]
            }
            Some(l) => l.value,
            None => [0.0; 3],
        }
    }

    /// A required positive BEAM property.
    fn positive(&mut self, v: Option<&Located<f64>>, key: &str, h: &Header) -> Option<f64> {
        match v {
            None => {
                self.error(h.span, format!("{}: {key} is missing", h.name));
                None
            }
            Some(l) if l.value <= 0.0 => {
                self.error(
                    l.span,
                    format!("{}: {key} must be positive ({})", h.name, l.value),
                );
                None
            }
            Some(l) => Some(l.value),
        }
    }
}

/// `m[r][c]` from 36 values written column by column.
fn matrix_by_columns(v: &[f64; 36]) -> [[f64; 6]; 6] {
    let mut m = [[0.0; 6]; 6];
    for (n, x) in v.iter().enumerate() {
        m[n % 6][n / 6] = *x;
    }
    m
}

/// The symmetric `m[r][c]` from the 21 values of its lower triangle written column by column
/// (column 1 rows 1..6, column 2 rows 2..6, …).
fn symmetric_by_columns(v: &[f64; 21]) -> [[f64; 6]; 6] {
    let mut m = [[0.0; 6]; 6];
    let lower = (0..6).flat_map(|c| (c..6).map(move |r| (r, c)));
    for ((r, c), x) in lower.zip(v) {
        m[r][c] = *x;
        m[c][r] = *x;
    }
    m
}

/// Resolves every two-marker force element of `ds`, in the order SFORCE, SPRINGDAMPER,
/// BUSHING, FIELD, BEAM (definition order within each kind).
pub(super) fn two_marker_elements(ds: &Dataset, rs: &mut Resolver, forces: &mut Vec<ForceElement>) {
    sforces(ds, rs, forces);
    springdampers(ds, rs, forces);
    bushings(ds, rs, forces);
    fields(ds, rs, forces);
    beams(ds, rs, forces);
}

/// `SFORCE`: I, J and FUNCTION (an error when it is missing).
fn sforces(ds: &Dataset, rs: &mut Resolver, forces: &mut Vec<ForceElement>) {
    let mut seen = HashSet::new();
    for s in &ds.sforces {
        let h = &s.header;
        if !rs.unique(&mut seen, "SFORCE", h) {
            continue;
        }
        let Some((i, j)) = rs.pair(s.i, s.j, h, s.action_only) else {
            continue;
        };
        let Some(function) = s.function.clone() else {
            rs.error(h.span, format!("{}: FUNCTION is missing", h.name));
            continue;
        };
        forces.push(ForceElement {
            origin: origin("SFORCE", h),
            kind: ForceKind::Sforce(Sforce {
                i,
                j,
                dof: s.dof,
                action_only: s.action_only,
                function,
            }),
        });
    }
}

/// `SPRINGDAMPER`: translational (K, C, LENGTH, FORCE) or rotational (KT, CT, ANGLE,
/// TORQUE), stiffness and damping not negative, everything else 0 when not given.
fn springdampers(ds: &Dataset, rs: &mut Resolver, forces: &mut Vec<ForceElement>) {
    let mut seen = HashSet::new();
    for s in &ds.springdampers {
        let h = &s.header;
        if !rs.unique(&mut seen, "SPRINGDAMPER", h) {
            continue;
        }
        let Some((i, j)) = rs.pair(s.i, s.j, h, false) else {
            continue;
        };
        let value = |v: &Option<Located<f64>>| v.as_ref().map_or(0.0, |l| l.value);
        let sd = match s.dof {
            ForceDof::Translational => SpringDamper {
                i,
                j,
                dof: s.dof,
                stiffness: rs.non_negative(s.k.as_ref(), "K", &h.name),
                damping: rs.non_negative(s.c.as_ref(), "C", &h.name),
                free: value(&s.length),
                preload: value(&s.force),
            },
            ForceDof::Rotational => SpringDamper {
                i,
                j,
                dof: s.dof,
                stiffness: rs.non_negative(s.kt.as_ref(), "KT", &h.name),
                damping: rs.non_negative(s.ct.as_ref(), "CT", &h.name),
                free: value(&s.angle),
                preload: value(&s.torque),
            },
        };
        forces.push(ForceElement {
            origin: origin("SPRINGDAMPER", h),
            kind: ForceKind::SpringDamper(sd),
        });
    }
}

/// `BUSHING`: stiffness and damping per axis (not negative), preloads; 0 when not given.
fn bushings(ds: &Dataset, rs: &mut Resolver, forces: &mut Vec<ForceElement>) {
    let mut seen = HashSet::new();
    for b in &ds.bushings {
        let h = &b.header;
        if !rs.unique(&mut seen, "BUSHING", h) {
            continue;
        }
        let Some((i, j)) = rs.pair(b.i, b.j, h, false) else {
            continue;
        };
        let value = |v: &Option<Located<[f64; 3]>>| v.as_ref().map_or([0.0; 3], |l| l.value);
        let bushing = Bushing {
            i,
            j,
            stiffness: rs.non_negative3(b.k.as_ref(), "K", &h.name),
            damping: rs.non_negative3(b.c.as_ref(), "C", &h.name),
            rotational_stiffness: rs.non_negative3(b.kt.as_ref(), "KT", &h.name),
            rotational_damping: rs.non_negative3(b.ct.as_ref(), "CT", &h.name),
            force: value(&b.force),
            torque: value(&b.torque),
        };
        forces.push(ForceElement {
            origin: origin("BUSHING", h),
            kind: ForceKind::Bushing(bushing),
        });
    }
}

/// `FIELD`: KMATRIX and CMATRIX read by columns (damping = CRATIO · stiffness without
/// CMATRIX), LENGTH and FORCE; a FUNCTION must be USER(…).
fn fields(ds: &Dataset, rs: &mut Resolver, forces: &mut Vec<ForceElement>) {
    let mut seen = HashSet::new();
    for f in &ds.fields {
        let h = &f.header;
        if !rs.unique(&mut seen, "FIELD", h) {
            continue;
        }
        let Some((i, j)) = rs.pair(f.i, f.j, h, false) else {
            continue;
        };
        let stiffness = f
            .kmatrix
            .as_ref()
            .map_or([[0.0; 6]; 6], |k| matrix_by_columns(&k.value));
        let damping = match (&f.cmatrix, &f.cratio) {
            (Some(c), _) => matrix_by_columns(&c.value),
            (None, Some(r)) => stiffness.map(|row| row.map(|k| k * r.value)),
            (None, None) => [[0.0; 6]; 6],
        };
        let user = f.function.clone();
        if user.as_ref().is_some_and(|u| !u.value.user) {
            rs.error(
                h.span,
                format!(
                    "{}: a FIELD FUNCTION must be USER(…) (a FIESUB subroutine)",
                    h.name
                ),
            );
            continue;
        }
        forces.push(ForceElement {
            origin: origin("FIELD", h),
            kind: ForceKind::Field(Box::new(Field {
                i,
                j,
                stiffness,
                damping,
                length: f.length.as_ref().map_or([0.0; 6], |l| l.value),
                force: f.force.as_ref().map_or([0.0; 6], |l| l.value),
                user,
            })),
        });
    }
}

/// `BEAM`: the seven section properties must be given and positive, the shear ratios and
/// CRATIO not negative; CMATRIX is the lower triangle by columns.
fn beams(ds: &Dataset, rs: &mut Resolver, forces: &mut Vec<ForceElement>) {
    let mut seen = HashSet::new();
    for b in &ds.beams {
        let h = &b.header;
        if !rs.unique(&mut seen, "BEAM", h) {
            continue;
        }
        let pair = rs.pair(b.i, b.j, h, false);
        let props = [
            rs.positive(b.length.as_ref(), "LENGTH", h),
            rs.positive(b.ixx.as_ref(), "IXX", h),
            rs.positive(b.iyy.as_ref(), "IYY", h),
            rs.positive(b.izz.as_ref(), "IZZ", h),
            rs.positive(b.area.as_ref(), "AREA", h),
            rs.positive(b.emodulus.as_ref(), "EMODULUS", h),
            rs.positive(b.gmodulus.as_ref(), "GMODULUS", h),
        ];
        let ratio = |rs: &mut Resolver, v: &Option<Located<f64>>, key: &str| {
            rs.non_negative(v.as_ref(), key, &h.name)
        };
        let (asy, asz) = (ratio(rs, &b.asy, "ASY"), ratio(rs, &b.asz, "ASZ"));
        let damping = match &b.cmatrix {
            Some(c) => BeamDamping::Matrix(Box::new(symmetric_by_columns(&c.value))),
            None => BeamDamping::Ratio(ratio(rs, &b.cratio, "CRATIO")),
        };
        let (
            Some((i, j)),
            [Some(length), Some(ixx), Some(iyy), Some(izz), Some(area), Some(emodulus), Some(gmodulus)],
        ) = (pair, props)
        else {
            continue;
        };
        forces.push(ForceElement {
            origin: origin("BEAM", h),
            kind: ForceKind::Beam(Box::new(Beam {
                i,
                j,
                length,
                ixx,
                iyy,
                izz,
                area,
                asy,
                asz,
                emodulus,
                gmodulus,
                damping,
                formulation: b
                    .formulation
                    .as_ref()
                    .map_or_else(Default::default, |f| f.value),
                formulation_span: b.formulation.as_ref().map(|f| f.span),
            })),
        });
    }
}

#[cfg(test)]
mod tests {
    use crate::build::test_support::{errors, ok};
    use crate::forces::*;
    use crate::Body;
    use linkage_adm::{BeamFormulation, ForceDof, Span};

    #[test]
    fn two_marker_elements_resolve_markers_and_defaults() {
        let b = ok("SFORCE/1, I = 20, J = 1, FUNCTION = 10\nSPRINGDAMPER/1, I = 20, J = 2, K = 5, LENGTH = 1.5\nSPRINGDAMPER/2, I = 30, J = 21, ROTATIONAL, KT = 3, TORQUE = 2\nBUSHING/1, I = 30, J = 1, K = 1, 2, 3");
        let m = &b.model;
        assert_eq!(m.forces.len(), 4);
        let ForceKind::Sforce(s) = &m.forces[0].kind else {
            panic!("{:?}", m.forces[0])
        };
        assert_eq!((m.markers[s.i].id, m.markers[s.j].id), (20, 1));
        assert_eq!(s.function.value.expr.text, "10");
        assert_eq!(m.forces[0].origin.element(), "SFORCE/1");
        let ForceKind::SpringDamper(t) = &m.forces[1].kind else {
            panic!()
        };
        assert_eq!(
            (t.stiffness, t.damping, t.free, t.preload),
            (5.0, 0.0, 1.5, 0.0)
        );
        let ForceKind::SpringDamper(r) = &m.forces[2].kind else {
            panic!()
        };
        assert_eq!(
            (r.dof, r.stiffness, r.preload),
            (ForceDof::Rotational, 3.0, 2.0)
        );
        let ForceKind::Bushing(bu) = &m.forces[3].kind else {
            panic!()
        };
        assert_eq!(bu.stiffness, [1.0, 2.0, 3.0]);
        assert_eq!((bu.damping, bu.torque), ([0.0; 3], [0.0; 3]));
        assert!(b.warnings.is_empty(), "{:?}", b.warnings);
    }

    #[test]
    fn field_matrix_is_read_by_columns_and_cratio_scales_it() {
        let k: Vec<String> = (0..36).map(|n| n.to_string()).collect();
        let b = ok(&format!(
            "FIELD/1, I = 20, J = 30, KMATRIX = {}, CRATIO = 0.5, LENGTH = 1, 2, 3, 4, 5, 6",
            k.join(", ")
        ));
        let ForceKind::Field(f) = &b.model.forces[0].kind else {
            panic!()
        };
        // Value n sits in row n mod 6, column n div 6.
        assert_eq!(f.stiffness[1][0], 1.0);
        assert_eq!(f.stiffness[0][1], 6.0);
        assert_eq!(f.stiffness[5][5], 35.0);
        assert_eq!(f.damping[0][1], 3.0);
        assert_eq!(f.length, [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
        assert_eq!(f.force, [0.0; 6]);
    }

    #[test]
    fn beam_properties_and_symmetric_damping_matrix() {
        let c: Vec<String> = (1..=21).map(|n| n.to_string()).collect();
        let b = ok(&format!("BEAM/1, I = 20, J = 1, LENGTH = 2, IXX = 3, IYY = 4, IZZ = 5, AREA = 6, ASY = 1.2, EMODULUS = 7, GMODULUS = 8, CMATRIX = {}", c.join(", ")));
        let ForceKind::Beam(beam) = &b.model.forces[0].kind else {
            panic!()
        };
        assert_eq!(
            [
                beam.length,
                beam.ixx,
                beam.iyy,
                beam.izz,
                beam.area,
                beam.emodulus,
                beam.gmodulus
            ],
            [2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0]
        );
        assert_eq!((beam.asy, beam.asz), (1.2, 0.0));
        assert_eq!(beam.formulation, BeamFormulation::Linear);
        let BeamDamping::Matrix(m) = &beam.damping else {
            panic!()
        };
        // Column 1 = values 1..6, column 2 rows 2..6 = values 7..11, …, (6,6) = 21.
        assert_eq!((m[0][0], m[5][0], m[0][5]), (1.0, 6.0, 6.0));
        assert_eq!((m[1][1], m[2][1], m[1][2]), (7.0, 8.0, 8.0));
        assert_eq!(m[5][5], 21.0);
        let e = errors("BEAM/2, I = 20, J = 1, LENGTH = 0, IXX = 3, IYY = 4, IZZ = 5, EMODULUS = 7, GMODULUS = 8");
        assert_eq!(e[0], (12, 1, "BEAM_2: AREA is missing".to_string()));
        assert_eq!(
            e[1],
            (12, 24, "BEAM_2: LENGTH must be positive (0)".to_string())
        );
    }

    #[test]
    fn vector_forces_resolve_jfloat_to_its_part() {
        let b = ok("VFORCE/1, I = 20, JFLOAT = 31, RM = 1, FX = 1\\FY = 2\\FZ = 3\nVTORQUE/1, I = 20, JFLOAT = 31, RM = 30, TZ = 1\nGFORCE/1, I = 30, JFLOAT = 22, RM = 20, FUNCTION = USER(1)");
        let m = &b.model;
        let ForceKind::Vector(v) = &m.forces[0].kind else {
            panic!()
        };
        assert_eq!(v.kind, VectorKind::Vforce);
        assert_eq!(v.reaction, Body::Part(1));
        assert_eq!(m.markers[v.jfloat].id, 31);
        assert_eq!(m.markers[v.rm].id, 1);
        assert!(v.force.iter().all(Option::is_some) && v.torque.iter().all(Option::is_none));
        let ForceKind::Vector(g) = &m.forces[2].kind else {
            panic!()
        };
        assert_eq!((g.kind, g.reaction), (VectorKind::Gforce, Body::Part(0)));
        assert!(g.user.as_ref().is_some_and(|u| u.value.user));
        // VTORQUE without TX, TY: a warning at the statement.
        assert_eq!(b.warnings.len(), 1, "{:?}", b.warnings);
        assert_eq!(b.warnings[0].span, Some(Span::new(13, 1)));
        assert!(b.warnings[0].message.contains("TX, TY not given"));
    }

    #[test]
    fn reference_errors_point_at_the_argument() {
        let e = errors("SFORCE/1, I = 99, J = 1, FUNCTION = 1\nSPRINGDAMPER/1, I = 22, J = 1\nVFORCE/1, I = 20, JFLOAT = 31, RM = 77, FX = 1");
        assert_eq!(
            e,
            [
                (12, 15, "SFORCE_1: I marker 99 does not exist".to_string()),
                (
                    13,
                    21,
                    "SPRINGDAMPER_1: I marker 22 is FLOATING; I must be a fixed marker".to_string()
                ),
                (14, 37, "VFORCE_1: RM marker 77 does not exist".to_string()),
            ]
        );
        let e = errors("BUSHING/1, I = 20, J = 1, C = 1, -2, 3\nSPRINGDAMPER/2, I = 20, J = 1, K = -1\nSFORCE/2, I = 20, J = 1");
        assert_eq!((e[0].0, e[0].1), (12, 27));
        assert!(e[0].2.contains("C must not be negative"), "{}", e[0].2);
        assert_eq!((e[1].0, e[1].1), (13, 32));
        assert_eq!(e[2], (14, 1, "SFORCE_2: FUNCTION is missing".to_string()));
        let e =
            errors("SFORCE/1, I = 20, J = 1, FUNCTION = 1\nSFORCE/1, I = 20, J = 1, FUNCTION = 2");
        assert_eq!(e, [(13, 1, "duplicate SFORCE id 1".to_string())]);
    }

    #[test]
    fn same_body_is_a_warning_except_for_action_only() {
        let b = ok("SFORCE/1, I = 20, J = 21, FUNCTION = 1\nSFORCE/2, I = 20, J = 21, ACTIONONLY, FUNCTION = 1");
        assert_eq!(b.warnings.len(), 1);
        assert_eq!(b.warnings[0].span, Some(Span::new(12, 1)));
        assert!(b.warnings[0].message.contains("exerts no net load"));
    }
}
