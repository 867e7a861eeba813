//! REQUEST statements resolved against the model (ADM-REFERENCE §2.12): their markers checked,
//! their `F1`…`F8` expressions parsed. Resolved with the model, reported only by the analyses
//! that write REQUEST columns: a model whose REQUESTs cannot be evaluated can still be
//! verified, assembled and simulated without them.

use crate::bodies::Marker;
use crate::bodies::Origin;
use crate::forces::ForceElement;
use crate::forces::ForceKind;
use crate::functions::parse_function;
use linkage_adm::{Dataset, Diagnostic, IdRef, Request, RequestKind};
use linkage_expr::{ElementForce, Expr};

/// What one request computes.
#[derive(Clone, Debug, PartialEq)]
pub enum RequestWhat {
    /// DISPLACEMENT, VELOCITY, ACCELERATION or FORCE of I relative to J in RM's axes (marker
    /// ids; 0 is the ground origin and axes).
    Standard {
        kind: RequestKind,
        i: u32,
        j: u32,
        rm: u32,
    },
    /// One entry per `Fn` written.
    Functions(Vec<RequestFunction>),
}

/// A function request's `Fn = expression`.
#[derive(Clone, Debug, PartialEq)]
pub struct RequestFunction {
    /// n, 1 to 8.
    pub component: usize,
    pub expr: Expr,
    /// The expression as written, for messages.
    pub text: String,
}

/// A resolved REQUEST.
#[derive(Clone, Debug, PartialEq)]
pub struct RequestDef {
    /// Column prefix: `REQUEST_3` or the Adams View name.
    pub name: String,
    /// `REQUEST_3 (REQUEST/3, line 40)` for messages.
    pub label: String,
    pub what: RequestWhat,
}

/// The REQUESTs of a dataset, and every problem found resolving them (sorted by place).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Requests {
    pub defs: Vec<RequestDef>,
    /// A marker id (I, J, RM) that is not a marker of the model, an expression that does not
    /// parse (located inside it), `FUNCTION = USER(…)` without a subroutine library (or a
    /// subroutine that cannot be found) or any other `FUNCTION =` (a REQUEST's FUNCTION names
    /// a user subroutine), a force component a rotational element does not have.
    pub issues: Vec<Diagnostic>,
}

fn request_origin(r: &Request) -> Origin {
    Origin {
        statement: "REQUEST",
        id: r.header.id,
        name: r.header.name.clone(),
        span: r.header.span,
        statement_index: r.header.statement,
    }
}

/// Resolves every REQUEST of `dataset` against the model built from it: its `markers` and its
/// force elements `forces`.
pub fn resolve_requests(
    markers: &[Marker],
    forces: &[ForceElement],
    dataset: &Dataset,
    user: &crate::functions::UserRoutines,
) -> Requests {
    let file = &dataset.file;
    let mut errors = Vec::new();
    let marker_ids: std::collections::HashMap<u64, usize> =
        markers.iter().enumerate().map(|(k, m)| (m.id, k)).collect();
    let known = crate::build::references::Known::new(dataset, &marker_ids);
    let mut defs = Vec::new();
    for r in &dataset.requests {
        let origin = request_origin(r);
        let label = origin.label();
        let mut marker = |role: &str, id: Option<IdRef>| -> u32 {
            let Some(id) = id else { return 0 };
            match u32::try_from(id.id) {
                Ok(m) if m == 0 || markers.iter().any(|mk| mk.id == u64::from(m)) => m,
                _ => {
                    errors.push(Diagnostic::error(
                        file.clone(),
                        Some(id.span),
                        format!("{label}: {role} marker {} does not exist", id.id),
                    ));
                    0
                }
            }
        };
        if let Some(f) = r.function.as_ref().filter(|f| f.value.user && user.given()) {
            // REQSUB: its eight RESULT values are the request's F1 … F8.
            let mut list = Vec::new();
            for k in 0..8 {
                match crate::functions::parse_component(file, f, &origin, "FUNCTION", user, k) {
                    Ok(expr) => list.push(RequestFunction {
                        component: k + 1,
                        expr,
                        text: f.value.expr.text.clone(),
                    }),
                    Err(d) => {
                        errors.push(d);
                        break;
                    }
                }
            }
            if list.len() == 8 {
                defs.push(RequestDef {
                    name: r.header.name.clone(),
                    label,
                    what: RequestWhat::Functions(list),
                });
            }
            continue;
        }
        if let Some(f) = &r.function {
            let what = if f.value.user {
                "FUNCTION calls a USER subroutine, which linkage cannot run"
            } else {
                "FUNCTION of a REQUEST must be USER(…), a user subroutine, which linkage \
                 cannot run"
            };
            errors.push(
                Diagnostic::error(file.clone(), Some(f.span), format!("{label}: {what}"))
                    .with_hint("write the outputs as F1 … F8 function expressions"),
            );
            continue;
        }
        let what = match r.kind {
            Some(kind) => {
                let i = marker("I", r.i);
                let j = marker("J", r.j);
                let rm = marker("RM", r.rm);
                RequestWhat::Standard { kind, i, j, rm }
            }
            None => {
                let mut list = Vec::new();
                for (k, f) in r.functions.iter().enumerate() {
                    let Some(f) = f else { continue };
                    let key = format!("F{}", k + 1);
                    match parse_function(file, f, &origin, &key, user) {
                        Ok(e) => {
                            for (span, why) in
                                crate::build::references::missing(&e, &f.value.expr, &known)
                            {
                                errors.push(Diagnostic::error(
                                    file.clone(),
                                    Some(span),
                                    format!("{label}: {key}: {why}"),
                                ));
                            }
                            if let Some(why) = wrong_force_component(forces, &e) {
                                errors.push(Diagnostic::error(
                                    file.clone(),
                                    Some(f.span),
                                    format!(
                                        "{label}: illegal function expression {key} = {}: {why}",
                                        f.value.expr.text.trim()
                                    ),
                                ));
                            }
                            list.push(RequestFunction {
                                component: k + 1,
                                expr: e,
                                text: f.value.expr.text.clone(),
                            })
                        }
                        Err(d) => errors.push(d),
                    }
                }
                RequestWhat::Functions(list)
            }
        };
        defs.push(RequestDef {
            name: r.header.name.clone(),
            label,
            what,
        });
    }
    errors.sort_by_key(|d| d.span);
    Requests {
        defs,
        issues: errors,
    }
}

/// A force component (1 FM, 2–4 FX–FZ) asked of a rotational SFORCE or SPRINGDAMPER, which
/// applies a torque only: Adams Solver refuses such a request at input ("Illegal function
/// expression on REQUEST/5 … SFORCE(1,0,2,101) … Wrong component: 2. No force in
/// corresponding object.", Adams Solver C++ 2012 on Chrono's RotSpring_Case01, whose `.msg` is
/// in the corpus). The element and component must be literal numbers to be checked here.
fn wrong_force_component(forces: &[ForceElement], e: &Expr) -> Option<String> {
    let literal = |x: &Expr| match x {
        Expr::Number(v) if v.fract() == 0.0 => Some(*v as u64),
        _ => None,
    };
    let mut found = None;
    e.walk(&mut |node| {
        let Expr::Call {
            func: linkage_expr::Function::ElementForce(kind),
            args,
        } = node
        else {
            return;
        };
        let statement = match kind {
            ElementForce::Sforce => "SFORCE",
            ElementForce::Spdp => "SPRINGDAMPER",
            _ => return,
        };
        let (Some(id), Some(comp)) = (
            args.first().and_then(literal),
            args.get(2).and_then(literal),
        ) else {
            return;
        };
        let rotational = forces.iter().any(|f| {
            f.origin.statement == statement
                && f.origin.id == id
                && match &f.kind {
                    ForceKind::Sforce(s) => s.dof == linkage_adm::ForceDof::Rotational,
                    ForceKind::SpringDamper(s) => s.dof == linkage_adm::ForceDof::Rotational,
                    _ => false,
                }
        });
        if rotational && (1..=4).contains(&comp) && found.is_none() {
            found = Some(format!(
                "wrong component {comp}: {statement}/{id} is rotational and applies no force \
                 (its torque is components 5 to 8)"
            ));
        }
    });
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    fn build(text: &str) -> crate::Model {
        let ds = linkage_adm::parse_dataset(std::sync::Arc::from("r.adm"), text).expect("parses");
        crate::build_model(&ds).expect("builds").model
    }

    const PARTS: &str = "r\nUNITS/, FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
                         PART/1, GROUND\nMARKER/1, PART = 1\nPART/2, MASS = 1, CM = 2, IP = 1, 1, 1\n\
                         MARKER/2, PART = 2\n";

    /// A standard request keeps its marker ids; a function request its parsed expressions with
    /// their components; nothing is reported.
    #[test]
    fn requests_resolve_markers_and_parse_functions() {
        let m = build(&format!(
            "{PARTS}REQUEST/1, DISPLACEMENT, I = 2, J = 1\nREQUEST/2, F2 = DX(2)\\F5 = TIME\nEND\n"
        ));
        assert!(m.requests.issues.is_empty(), "{:?}", m.requests.issues);
        assert_eq!(m.requests.defs.len(), 2);
        assert_eq!(
            m.requests.defs[0].what,
            RequestWhat::Standard {
                kind: RequestKind::Displacement,
                i: 2,
                j: 1,
                rm: 0
            }
        );
        let RequestWhat::Functions(f) = &m.requests.defs[1].what else {
            panic!("{:?}", m.requests.defs[1]);
        };
        let components: Vec<usize> = f.iter().map(|f| f.component).collect();
        assert_eq!(components, [2, 5]);
        assert_eq!(f[1].expr, linkage_expr::parse("TIME").unwrap());
    }

    /// An unknown marker and a syntax error are kept for the analyses that write REQUEST
    /// columns (the model still builds), sorted by place.
    #[test]
    fn request_problems_are_kept_not_raised() {
        let m = build(&format!(
            "{PARTS}REQUEST/1, DISPLACEMENT, I = 2, J = 9\nREQUEST/2, F1 = 1 + * 2\nEND\n"
        ));
        let messages: Vec<&str> = m
            .requests
            .issues
            .iter()
            .map(|d| d.message.as_str())
            .collect();
        assert_eq!(messages.len(), 2, "{messages:?}");
        assert!(
            messages[0].contains("J marker 9 does not exist"),
            "{messages:?}"
        );
        assert!(messages[1].contains("syntax error in F1"), "{messages:?}");
    }
}
