//! VFORCE, VTORQUE and GFORCE: components along RM's axes applied at I, the reaction on the
//! body that carries the floating marker JFLOAT.

use super::context::origin;
use super::forces::Resolver;
use crate::forces::{ForceElement, ForceKind, VectorForce, VectorKind};
use linkage_adm::{Dataset, Function, Header, IdRef, Located};
use std::collections::{HashMap, HashSet};

/// The parts common to VFORCE, VTORQUE and GFORCE.
struct VectorSource<'s> {
    statement: &'static str,
    kind: VectorKind,
    header: &'s Header,
    i: IdRef,
    jfloat: IdRef,
    rm: IdRef,
    force: [Option<Located<Function>>; 3],
    torque: [Option<Located<Function>>; 3],
    function: Option<Located<Function>>,
    /// Which of force/torque components this statement has.
    has: (bool, bool),
}

/// Resolves every VFORCE, then every VTORQUE, then every GFORCE. Errors: a duplicate id
/// (within a statement type), unusable markers (I and RM must be fixed), a FUNCTION that is
/// not USER(…). Warnings: a JFLOAT marker that is not FLOATING, I and JFLOAT on one body,
/// components not given (zero).
pub(super) fn vector_elements(ds: &Dataset, rs: &mut Resolver, forces: &mut Vec<ForceElement>) {
    let mut seen: HashMap<&str, HashSet<u64>> = HashMap::new();
    for s in vector_sources(ds) {
        if !rs.unique(seen.entry(s.statement).or_default(), s.statement, s.header) {
            continue;
        }
        if let Some(f) = vector_force(s, rs) {
            forces.push(f);
        }
    }
}

/// The three statement types as one list, in the order they are resolved.
fn vector_sources(ds: &Dataset) -> Vec<VectorSource<'_>> {
    let none3 = || [None, None, None];
    let vforces = ds.vforces.iter().map(|v| VectorSource {
        statement: "VFORCE",
        kind: VectorKind::Vforce,
        header: &v.header,
        i: v.i,
        jfloat: v.jfloat,
        rm: v.rm,
        force: v.force.clone(),
        torque: none3(),
        function: v.function.clone(),
        has: (true, false),
    });
    let vtorques = ds.vtorques.iter().map(|v| VectorSource {
        statement: "VTORQUE",
        kind: VectorKind::Vtorque,
        header: &v.header,
        i: v.i,
        jfloat: v.jfloat,
        rm: v.rm,
        force: none3(),
        torque: v.torque.clone(),
        function: v.function.clone(),
        has: (false, true),
    });
    let gforces = ds.gforces.iter().map(|g| VectorSource {
        statement: "GFORCE",
        kind: VectorKind::Gforce,
        header: &g.header,
        i: g.i,
        jfloat: g.jfloat,
        rm: g.rm,
        force: g.force.clone(),
        torque: g.torque.clone(),
        function: g.function.clone(),
        has: (true, true),
    });
    vforces.chain(vtorques).chain(gforces).collect()
}

/// One vector force resolved (`None` after an error).
fn vector_force(s: VectorSource, rs: &mut Resolver) -> Option<ForceElement> {
    let h = s.header;
    let i = rs.marker(s.i, &h.name, "I", true);
    let rm = rs.marker(s.rm, &h.name, "RM", true);
    let jfloat = rs.marker(s.jfloat, &h.name, "JFLOAT", false);
    let (i, rm, jfloat) = (i?, rm?, jfloat?);
    if !rs.table.markers[jfloat].floating {
        let msg = format!(
            "{}: JFLOAT marker {} is not FLOATING; the reaction acts on its part at I's position",
            h.name, s.jfloat.id
        );
        rs.warn(s.jfloat.span, msg);
    }
    let reaction = rs.table.markers[jfloat].body;
    if reaction == rs.table.markers[i].body {
        let msg = format!(
            "{}: I marker {} and JFLOAT marker {} are on the same body; the element exerts no net load",
            h.name, s.i.id, s.jfloat.id
        );
        rs.warn(h.span, msg);
    }
    if !components_given(&s, rs) {
        return None;
    }
    Some(ForceElement {
        origin: origin(s.statement, h),
        kind: ForceKind::Vector(Box::new(VectorForce {
            kind: s.kind,
            i,
            jfloat,
            reaction,
            rm,
            force: s.force,
            torque: s.torque,
            user: s.function,
        })),
    })
}

/// The components come from `USER(…)` or one expression each: false (after an error) for a
/// FUNCTION that is not USER(…); a warning naming the components not given (taken as zero).
fn components_given(s: &VectorSource, rs: &mut Resolver) -> bool {
    let h = s.header;
    match &s.function {
        Some(f) if !f.value.user => {
            rs.error(
                f.span,
                format!(
                    "{}: FUNCTION must be USER(…); give the components as {}",
                    h.name,
                    match s.kind {
                        VectorKind::Vforce => "FX, FY, FZ",
                        VectorKind::Vtorque => "TX, TY, TZ",
                        VectorKind::Gforce => "FX, FY, FZ, TX, TY, TZ",
                    }
                ),
            );
            false
        }
        Some(_) => true,
        None => {
            let names = [("FX", "TX"), ("FY", "TY"), ("FZ", "TZ")];
            let mut missing = Vec::new();
            for (k, (f, t)) in names.iter().enumerate() {
                if s.has.0 && s.force[k].is_none() {
                    missing.push(*f);
                }
                if s.has.1 && s.torque[k].is_none() {
                    missing.push(*t);
                }
            }
            missing.sort_unstable();
            if !missing.is_empty() {
                let msg = format!(
                    "{}: {} not given; taken as zero",
                    h.name,
                    missing.join(", ")
                );
                rs.warn(h.span, msg);
            }
            true
        }
    }
}
