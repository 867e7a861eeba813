//! Typing of CONTACT statements (ADM-ELEMENTS §1), on demand like GRAPHICS:
//!
//! ```text
//! CONTACT/id, IGEOM=g1[,g2,…], JGEOM=g1[,g2,…] [, TYPE=…]
//!    { , IMPACT, STIFFNESS=k, DAMPING=c, DMAX=d, EXPONENT=e
//!    | , POISSON, PENALTY=p, RESTITUTION_COEFFICIENT=ε [, NORMAL_TRANSITION_VELOCITY=vn]
//!    | , NORMAL_FUNCTION=USER(…) }
//!    [ , COULOMB_FRICTION = ON | OFF | DYNAMICS_ONLY, MU_STATIC=μs, MU_DYNAMIC=μd,
//!        STICTION_TRANSITION_VELOCITY=vs, FRICTION_TRANSITION_VELOCITY=vd
//!    | , FRICTION_FUNCTION=USER(…) ]
//! ```
//!
//! Contract:
//! - Keywords are matched by exact spelling or unambiguous prefix (`STIFF` = `STIFFNESS`).
//! - Errors (at the statement or the value): no IGEOM or JGEOM; no normal law, or both IMPACT
//!   and POISSON; a parameter of the chosen law missing (Adams documents no statement
//!   defaults for them — the Adams View defaults seen in files are unit-dependent — so all of
//!   STIFFNESS, DAMPING, DMAX, EXPONENT, or PENALTY and RESTITUTION_COEFFICIENT are required);
//!   values out of range (STIFFNESS, DAMPING ≥ 0; DMAX, EXPONENT, PENALTY > 0;
//!   0 ≤ RESTITUTION_COEFFICIENT ≤ 1; MU ≥ 0; 0 < vs < vd); friction ON or DYNAMICS_ONLY
//!   without its four parameters.
//! - Decisions where Adams' text was not found (ADM-ELEMENTS marks them `[unconfirmed]`):
//!   COULOMB_FRICTION absent means OFF; DYNAMICS_ONLY ("friction in dynamic runs") has the
//!   same law as ON: the friction force depends on slip velocity only, so it is zero in
//!   static equilibrium either way; NORMAL_TRANSITION_VELOCITY defaults to
//!   [`DEFAULT_NORMAL_TRANSITION_VELOCITY`].
//! - Warnings: `AUGMENTED_LAGRANGIAN_FORMULATION` (the penalty law is used as written),
//!   `STICTION = ON` / `MAX_STICTION_DEFORMATION` (the stiction of the friction law is the
//!   velocity-based one of §1.3, no creep spring), an argument CONTACT does not have.
//! - IFLIP_GEOMETRY / JFLIP_GEOMETRY: GRAPHICS ids (of CURVE geometries) whose solid side is
//!   reversed.
//! - `TYPE` is informational (the geometries fix the kind) and is not checked.

use super::label;
use crate::diagnostic::{Diagnostic, Span};
use crate::statement::{Statement, Value};
use crate::typed::{Dataset, Header, IdRef};

/// NORMAL_TRANSITION_VELOCITY when not given (velocity units of the dataset): the band of
/// penetration velocity over which the POISSON law blends loading into unloading. A decision
/// (no Adams default found): small against impact speeds in m/s or mm/s models alike.
pub const DEFAULT_NORMAL_TRANSITION_VELOCITY: f64 = 1.0e-3;

const CONTACT_KEYS: &[&str] = &[
    "AUGMENTED_LAGRANGIAN_FORMULATION",
    "COULOMB_FRICTION",
    "DAMPING",
    "DMAX",
    "EXPONENT",
    "FACETING_TOLERANCE",
    "FRICTION_FUNCTION",
    "FRICTION_ROUTINE",
    "FRICTION_TRANSITION_VELOCITY",
    "IFLIP_GEOMETRY",
    "IGEOM",
    "IMPACT",
    "JFLIP_GEOMETRY",
    "JGEOM",
    "MAX_STICTION_DEFORMATION",
    "MU_DYNAMIC",
    "MU_STATIC",
    "NORMAL_FUNCTION",
    "NORMAL_ROUTINE",
    "NORMAL_TRANSITION_VELOCITY",
    "PENALTY",
    "POISSON",
    "RESTITUTION_COEFFICIENT",
    "STICTION",
    "STICTION_TRANSITION_VELOCITY",
    "STIFFNESS",
    "TYPE",
];

/// The normal-force law of a contact.
#[derive(Clone, Debug, PartialEq)]
pub enum NormalLaw {
    /// `Fn = k·g^e + STEP(g, 0, 0, dmax, c)·ġ` (g penetration, ġ its rate), not below zero.
    Impact {
        stiffness: f64,
        damping: f64,
        dmax: f64,
        exponent: f64,
    },
    /// Penalty `p` with restitution `ε` (see `linkage-solve`'s contact law for the equation).
    Poisson {
        penalty: f64,
        restitution: f64,
        transition_velocity: f64,
    },
    /// `NORMAL_FUNCTION = USER(…)`: a subroutine linkage cannot run.
    User { span: Span },
}

/// When Coulomb friction acts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrictionMode {
    /// No friction (`COULOMB_FRICTION = OFF` or absent).
    Off,
    /// In every analysis (`ON`).
    On,
    /// In dynamic runs only (`DYNAMICS_ONLY`).
    DynamicsOnly,
}

/// Coulomb friction of a contact (ADM-ELEMENTS §1.3).
#[derive(Clone, Debug, PartialEq)]
pub struct Friction {
    pub mode: FrictionMode,
    pub mu_static: f64,
    pub mu_dynamic: f64,
    /// STICTION_TRANSITION_VELOCITY vs.
    pub stiction_velocity: f64,
    /// FRICTION_TRANSITION_VELOCITY vd (> vs).
    pub friction_velocity: f64,
    /// `FRICTION_FUNCTION = USER(…)`, when given.
    pub user: Option<Span>,
}

impl Friction {
    /// No friction.
    pub fn off() -> Friction {
        Friction {
            mode: FrictionMode::Off,
            mu_static: 0.0,
            mu_dynamic: 0.0,
            stiction_velocity: 0.0,
            friction_velocity: 0.0,
            user: None,
        }
    }
}

/// One CONTACT statement typed.
#[derive(Clone, Debug, PartialEq)]
pub struct Contact {
    pub header: Header,
    /// GRAPHICS ids of the I side (all on one part).
    pub igeom: Vec<IdRef>,
    /// GRAPHICS ids of the J side (all on one part).
    pub jgeom: Vec<IdRef>,
    /// IFLIP_GEOMETRY / JFLIP_GEOMETRY: the I / J GRAPHICS CURVE ids whose solid side is
    /// reversed (2-D curve contacts; empty when absent).
    pub iflip: Vec<IdRef>,
    pub jflip: Vec<IdRef>,
    pub normal: NormalLaw,
    pub friction: Friction,
}

/// Types every CONTACT statement of `ds` (statement order). The diagnostics are errors (the
/// contact is left out) and warnings, each at its statement or value.
pub fn type_contacts(ds: &Dataset) -> (Vec<Contact>, Vec<Diagnostic>) {
    let mut r = Reader {
        file: ds.file.clone(),
        out: Vec::new(),
    };
    let contacts = ds
        .statements
        .iter()
        .enumerate()
        .filter(|(_, st)| st.keyword == "CONTACT")
        .filter_map(|(index, st)| r.contact(st, index))
        .collect();
    (contacts, r.out)
}

fn canonical(written: &str) -> Option<&'static str> {
    let upper = written.to_ascii_uppercase();
    if let Some(exact) = CONTACT_KEYS.iter().find(|k| **k == upper) {
        return Some(exact);
    }
    let mut candidates = CONTACT_KEYS.iter().filter(|k| k.starts_with(&upper));
    match (candidates.next(), candidates.next()) {
        (Some(only), None) => Some(only),
        _ => None,
    }
}

struct Reader {
    file: std::sync::Arc<str>,
    out: Vec<Diagnostic>,
}

impl Reader {
    fn error(&mut self, span: Span, msg: String) {
        self.out
            .push(Diagnostic::error(self.file.clone(), Some(span), msg));
    }

    fn warn(&mut self, span: Span, msg: String) {
        self.out
            .push(Diagnostic::warning(self.file.clone(), Some(span), msg));
    }

    fn arg<'s>(st: &'s Statement, key: &str) -> Option<&'s crate::statement::Argument> {
        st.args.iter().find(|a| canonical(&a.key) == Some(key))
    }

    /// A number argument; `Err(())` (with an error) when it is not a finite number.
    fn number(&mut self, st: &Statement, key: &str) -> Result<Option<(f64, Span)>, ()> {
        let Some(a) = Self::arg(st, key) else {
            return Ok(None);
        };
        match a.values.first() {
            Some(Value::Number { value, span, .. }) if value.is_finite() => {
                Ok(Some((*value, *span)))
            }
            _ => {
                self.error(a.span, format!("{}: {key} expects a number", label(st)));
                Err(())
            }
        }
    }

    /// A required number in `range` (described by `what`).
    fn required(
        &mut self,
        st: &Statement,
        key: &str,
        law: &str,
        ok: impl Fn(f64) -> bool,
        what: &str,
    ) -> Option<f64> {
        match self.number(st, key) {
            Err(()) => None,
            Ok(None) => {
                self.error(st.span, format!("{}: {law} needs {key} = …", label(st)));
                None
            }
            Ok(Some((v, span))) if !ok(v) => {
                self.error(
                    span,
                    format!("{}: {key} must be {what} (got {v})", label(st)),
                );
                None
            }
            Ok(Some((v, _))) => Some(v),
        }
    }

    fn ids(&mut self, st: &Statement, key: &str) -> Option<Vec<IdRef>> {
        let Some(a) = Self::arg(st, key) else {
            self.error(st.span, format!("{} needs {key} = GRAPHICS ids", label(st)));
            return None;
        };
        let mut ids = Vec::with_capacity(a.values.len());
        for v in &a.values {
            match v {
                Value::Number { value, span, .. }
                    if *value >= 0.0 && value.fract() == 0.0 && *value < 9.0e15 =>
                {
                    ids.push(IdRef {
                        id: *value as u64,
                        span: *span,
                    })
                }
                other => {
                    let msg = format!("{}: {key} expects GRAPHICS ids", label(st));
                    self.error(other.span(), msg);
                    return None;
                }
            }
        }
        if ids.is_empty() {
            self.error(a.span, format!("{}: {key} names no GRAPHICS", label(st)));
            return None;
        }
        Some(ids)
    }

    /// The place of a `USER(…)` value of `key`, if the argument is given.
    fn user(st: &Statement, key: &str) -> Option<Span> {
        Self::arg(st, key).map(|a| a.values.first().map_or(a.span, Value::span))
    }

    fn contact(&mut self, st: &Statement, index: usize) -> Option<Contact> {
        for a in &st.args {
            match canonical(&a.key) {
                None => self.warn(
                    a.span,
                    format!(
                        "{}: {} is not an argument of CONTACT; ignored",
                        label(st),
                        a.key
                    ),
                ),
                Some("AUGMENTED_LAGRANGIAN_FORMULATION") => self.warn(
                    a.span,
                    format!(
                        "{}: AUGMENTED_LAGRANGIAN_FORMULATION is not applied: the POISSON \
                         penalty law is used as written",
                        label(st)
                    ),
                ),
                Some("MAX_STICTION_DEFORMATION") => self.warn(
                    a.span,
                    format!(
                        "{}: MAX_STICTION_DEFORMATION is not used: contact stiction is the \
                         velocity-based one of the friction law (no creep spring)",
                        label(st)
                    ),
                ),
                Some("STICTION")
                    if a.values.first().is_some_and(
                        |v| matches!(v, Value::Word { text, .. } if text != "OFF"),
                    ) =>
                {
                    self.warn(
                        a.span,
                        format!(
                            "{}: STICTION = ON is read as the velocity-based stiction of the \
                             friction law (no creep spring)",
                            label(st)
                        ),
                    )
                }
                _ => {}
            }
        }
        let igeom = self.ids(st, "IGEOM");
        let jgeom = self.ids(st, "JGEOM");
        let iflip = match Self::arg(st, "IFLIP_GEOMETRY") {
            Some(_) => self.ids(st, "IFLIP_GEOMETRY"),
            None => Some(Vec::new()),
        };
        let jflip = match Self::arg(st, "JFLIP_GEOMETRY") {
            Some(_) => self.ids(st, "JFLIP_GEOMETRY"),
            None => Some(Vec::new()),
        };
        let normal = self.normal(st);
        let friction = self.friction(st);
        Some(Contact {
            header: super::header(st, index),
            igeom: igeom?,
            jgeom: jgeom?,
            iflip: iflip?,
            jflip: jflip?,
            normal: normal?,
            friction: friction?,
        })
    }

    fn normal(&mut self, st: &Statement) -> Option<NormalLaw> {
        if let Some(span) = Self::user(st, "NORMAL_FUNCTION") {
            return Some(NormalLaw::User { span });
        }
        let impact = Self::arg(st, "IMPACT").is_some();
        let poisson = Self::arg(st, "POISSON").is_some();
        match (impact, poisson) {
            (true, true) => {
                self.error(
                    st.span,
                    format!("{}: give IMPACT or POISSON, not both", label(st)),
                );
                None
            }
            (false, false) => {
                self.error(
                    st.span,
                    format!(
                        "{} needs a normal-force law: IMPACT or POISSON (or NORMAL_FUNCTION)",
                        label(st)
                    ),
                );
                None
            }
            (true, false) => {
                let nonneg = |v: f64| v >= 0.0;
                let pos = |v: f64| v > 0.0;
                let k = self.required(st, "STIFFNESS", "IMPACT", nonneg, "≥ 0");
                let c = self.required(st, "DAMPING", "IMPACT", nonneg, "≥ 0");
                let d = self.required(st, "DMAX", "IMPACT", pos, "> 0");
                let e = self.required(st, "EXPONENT", "IMPACT", pos, "> 0");
                Some(NormalLaw::Impact {
                    stiffness: k?,
                    damping: c?,
                    dmax: d?,
                    exponent: e?,
                })
            }
            (false, true) => {
                let p = self.required(st, "PENALTY", "POISSON", |v| v > 0.0, "> 0");
                let r = self.required(
                    st,
                    "RESTITUTION_COEFFICIENT",
                    "POISSON",
                    |v| (0.0..=1.0).contains(&v),
                    "between 0 and 1",
                );
                let vn = match self.number(st, "NORMAL_TRANSITION_VELOCITY") {
                    Err(()) => return None,
                    Ok(None) => DEFAULT_NORMAL_TRANSITION_VELOCITY,
                    Ok(Some((v, span))) if v <= 0.0 => {
                        let msg = format!(
                            "{}: NORMAL_TRANSITION_VELOCITY must be > 0 (got {v})",
                            label(st)
                        );
                        self.error(span, msg);
                        return None;
                    }
                    Ok(Some((v, _))) => v,
                };
                Some(NormalLaw::Poisson {
                    penalty: p?,
                    restitution: r?,
                    transition_velocity: vn,
                })
            }
        }
    }

    fn friction(&mut self, st: &Statement) -> Option<Friction> {
        if let Some(span) = Self::user(st, "FRICTION_FUNCTION") {
            return Some(Friction {
                user: Some(span),
                ..Friction::off()
            });
        }
        let mode = match Self::arg(st, "COULOMB_FRICTION") {
            None => FrictionMode::Off,
            Some(a) => match a.values.first() {
                Some(Value::Word { text, .. }) if text == "ON" => FrictionMode::On,
                Some(Value::Word { text, .. }) if text == "OFF" => FrictionMode::Off,
                Some(Value::Word { text, .. }) if text == "DYNAMICS_ONLY" => {
                    FrictionMode::DynamicsOnly
                }
                _ => {
                    let msg = format!(
                        "{}: COULOMB_FRICTION expects ON, OFF or DYNAMICS_ONLY",
                        label(st)
                    );
                    self.error(a.span, msg);
                    return None;
                }
            },
        };
        if mode == FrictionMode::Off {
            return Some(Friction::off());
        }
        let law = "COULOMB_FRICTION";
        let nonneg = |v: f64| v >= 0.0;
        let ms = self.required(st, "MU_STATIC", law, nonneg, "≥ 0");
        let md = self.required(st, "MU_DYNAMIC", law, nonneg, "≥ 0");
        let vs = self.required(st, "STICTION_TRANSITION_VELOCITY", law, |v| v > 0.0, "> 0");
        let vd = self.required(st, "FRICTION_TRANSITION_VELOCITY", law, |v| v > 0.0, "> 0");
        let (vs, vd) = (vs?, vd?);
        if vd <= vs {
            let span = Self::arg(st, "FRICTION_TRANSITION_VELOCITY").map_or(st.span, |a| a.span);
            let msg = format!(
                "{}: FRICTION_TRANSITION_VELOCITY ({vd}) must exceed \
                 STICTION_TRANSITION_VELOCITY ({vs})",
                label(st)
            );
            self.error(span, msg);
            return None;
        }
        Some(Friction {
            mode,
            mu_static: ms?,
            mu_dynamic: md?,
            stiction_velocity: vs,
            friction_velocity: vd,
            user: None,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn contacts(body: &str) -> (Vec<Contact>, Vec<Diagnostic>) {
        let text = format!("title\n{body}\nEND\n");
        let ds = crate::parse_dataset("t.adm".into(), &text).expect("parses");
        type_contacts(&ds)
    }

    #[test]
    fn corpus_impact_contact_with_friction_is_typed() {
        let (c, d) = contacts(
            "CONTACT/1\n, IGEOM = 33792\n, JGEOM = 4117, 4118\n, IMPACT\n, STIFFNESS = 5.7E+005\n\
             , DAMPING = 57.1\n, DMAX = 0.0039\n, EXPONENT = 2.2\n, COULOMB_FRICTION = ON\n\
             , MU_STATIC = 0.9\n, MU_DYNAMIC = 0.8\n, STICTION_TRANSITION_VELOCITY = 3.9\n\
             , FRICTION_TRANSITION_VELOCITY = 39.4",
        );
        assert!(d.is_empty(), "{d:?}");
        let c = &c[0];
        assert_eq!(c.igeom.iter().map(|g| g.id).collect::<Vec<_>>(), [33792]);
        assert_eq!(
            c.jgeom.iter().map(|g| g.id).collect::<Vec<_>>(),
            [4117, 4118]
        );
        assert_eq!(
            c.normal,
            NormalLaw::Impact {
                stiffness: 5.7e5,
                damping: 57.1,
                dmax: 0.0039,
                exponent: 2.2
            }
        );
        assert_eq!(c.friction.mode, FrictionMode::On);
        assert_eq!((c.friction.mu_static, c.friction.mu_dynamic), (0.9, 0.8));
        assert_eq!(
            (c.friction.stiction_velocity, c.friction.friction_velocity),
            (3.9, 39.4)
        );
    }

    #[test]
    fn poisson_defaults_and_friction_off_by_default() {
        let (c, d) = contacts(
            "CONTACT/4, TYPE = SOLID_TO_SOLID, IGEOM = 7, JGEOM = 4, POISSON, PENALTY = 1000, \
             RESTITUTION_COEFFICIENT = 1",
        );
        assert!(d.is_empty(), "{d:?}");
        assert_eq!(
            c[0].normal,
            NormalLaw::Poisson {
                penalty: 1000.0,
                restitution: 1.0,
                transition_velocity: DEFAULT_NORMAL_TRANSITION_VELOCITY
            }
        );
        assert_eq!(c[0].friction.mode, FrictionMode::Off);
    }

    #[test]
    fn missing_and_out_of_range_parameters_are_errors_at_their_place() {
        let (c, d) = contacts(
            "CONTACT/1, IGEOM = 1, JGEOM = 2, IMPACT, STIFFNESS = 1, DAMPING = 1, DMAX = 0, \
             EXPONENT = 1.5, COULOMB_FRICTION = DYNAMICS_ONLY, MU_STATIC = 1, MU_DYNAMIC = 1, \
             STICTION_TRANSITION_VELOCITY = 2, FRICTION_TRANSITION_VELOCITY = 1\n\
             CONTACT/2, IGEOM = 1, POISSON, PENALTY = 1",
        );
        assert!(c.is_empty());
        let msgs: Vec<String> = d.iter().map(|d| d.to_string()).collect();
        let has = |s: &str| msgs.iter().any(|m| m.contains(s));
        assert!(has("DMAX must be > 0"), "{msgs:?}");
        assert!(has("must exceed STICTION_TRANSITION_VELOCITY"), "{msgs:?}");
        assert!(has("CONTACT/2 needs JGEOM"), "{msgs:?}");
        assert!(has("POISSON needs RESTITUTION_COEFFICIENT"), "{msgs:?}");
        assert!(d.iter().all(Diagnostic::is_error));
        // The out-of-range DMAX is reported at its value on line 2.
        let dmax = d.iter().find(|d| d.message.contains("DMAX")).expect("dmax");
        assert_eq!(dmax.span.map(|s| s.line), Some(2));
    }

    #[test]
    fn user_laws_and_stiction_options_are_kept_or_warned() {
        let (c, d) = contacts(
            "CONTACT/1, IGEOM = 1, JGEOM = 2, NORMAL_FUNCTION = USER(1, 2), STICTION = ON, \
             MAX_STICTION_DEFORMATION = 0.01",
        );
        assert!(matches!(c[0].normal, NormalLaw::User { .. }));
        assert_eq!(d.len(), 2, "{d:?}");
        assert!(d.iter().all(|d| !d.is_error()));
    }
}
