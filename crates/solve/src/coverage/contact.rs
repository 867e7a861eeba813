//! What coverage says about CONTACT statements: a contact is modelled, but a geometry it
//! names may not be usable (`linkage_model::contacts::geometry_problem`): an EXTERNAL file
//! that is missing or in a format linkage does not read (Parasolid), a CURVE given by a USER
//! subroutine, or a display-only shape. Each such geometry is a finding at its id in IGEOM/JGEOM, refused by
//! every force analysis, so the user can `--deactivate` the contact.

use super::Reason;
use linkage_adm::contact::Contact;
use linkage_adm::graphics::Shape;
use linkage_adm::{Dataset, IdRef, Span};
use linkage_model::contacts::{geometry_problem, GeometryProblem};
use std::collections::HashMap;

/// The typed contacts (by statement index) and graphics (by id) of a dataset, read once.
pub(super) struct ContactGeometries {
    contacts: HashMap<usize, Contact>,
    graphics: HashMap<u64, Shape<IdRef>>,
    /// CURVE ids given by a USER subroutine (`FUNCTION = USER(…)`).
    user_curves: std::collections::HashSet<u64>,
}

impl ContactGeometries {
    /// `None` when the dataset has no CONTACT.
    pub(super) fn new(ds: &Dataset) -> Option<ContactGeometries> {
        if !ds.statements.iter().any(|s| s.keyword == "CONTACT") {
            return None;
        }
        let contacts = linkage_adm::contact::type_contacts(ds)
            .0
            .into_iter()
            .map(|c| (c.header.statement, c))
            .collect();
        let graphics = linkage_adm::graphics::type_graphics(ds)
            .0
            .into_iter()
            .map(|g| (g.header.id, g.shape))
            .collect();
        let user_curves = ds
            .statements
            .iter()
            .filter(|s| s.keyword == "CURVE" && s.arg("FUNCTION").is_some())
            .filter_map(|s| s.id)
            .collect();
        Some(ContactGeometries {
            contacts,
            graphics,
            user_curves,
        })
    }

    /// The unusable geometries of the contact at statement `index`: place, reason, detail.
    pub(super) fn problems(&self, ds: &Dataset, index: usize) -> Vec<(Span, Reason, String)> {
        let Some(c) = self.contacts.get(&index) else {
            return Vec::new();
        };
        let mut out = Vec::new();
        for r in c.igeom.iter().chain(&c.jgeom) {
            let Some(shape) = self.graphics.get(&r.id) else {
                continue;
            };
            if let Shape::Curve { cid, .. } = shape {
                if self.user_curves.contains(cid) {
                    let detail = format!(
                        "GRAPHICS/{}'s CURVE/{cid} is a USER subroutine, which linkage cannot \
                         evaluate; the contact cannot be computed (deactivate it to run without it)",
                        r.id
                    );
                    out.push((r.span, Reason::NotModelled, detail));
                    continue;
                }
            }
            if let Some(p) = geometry_problem(&ds.file, shape) {
                let reason = match p {
                    GeometryProblem::Missing(_) => Reason::ExternalFileMissing,
                    _ => Reason::NotModelled,
                };
                let detail = format!(
                    "{}; the contact cannot be computed (deactivate it to run without it)",
                    p.describe(r.id)
                );
                out.push((r.span, reason, detail));
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use crate::coverage::{findings, Analysis, Reason};
    use std::sync::Arc;

    #[test]
    fn a_contact_on_a_parasolid_file_is_named_with_the_file_and_refused() {
        let text = "t\nPART/1, GROUND\nMARKER/1, PART = 1\n\
            PART/2, MASS = 1, IP = 1, 1, 1, CM = 20\nMARKER/20, PART = 2\n\
            GRAPHICS/1, BOX, CORNER = 20, X = 1, Y = 1, Z = 1\n\
            GRAPHICS/2, EXTERNAL, RM = 1, FILE = nowhere.xmt_txt\n\
            GRAPHICS/3, PLANE, RM = 1\n\
            CONTACT/1, IGEOM = 1, JGEOM = 2, IMPACT, STIFFNESS = 1, DAMPING = 0, DMAX = 1, \
            EXPONENT = 1\n\
            CONTACT/2, IGEOM = 1, JGEOM = 3, IMPACT, STIFFNESS = 1, DAMPING = 0, DMAX = 1, \
            EXPONENT = 1\n\
            CURVE/1, FUNCTION = USER(1)\n\
            GRAPHICS/4, CURVE, CID = 1, CRM = 1\n\
            CONTACT/3, IGEOM = 4, JGEOM = 3, IMPACT, STIFFNESS = 1, DAMPING = 0, DMAX = 1, \
            EXPONENT = 1\nEND\n";
        let ds = linkage_adm::parse_dataset(Arc::from("t.adm"), text).unwrap();
        let f = findings(&ds);
        // CONTACT/1, the USER CURVE/1 itself (USER-call check), CONTACT/3.
        assert_eq!(f.len(), 3, "{f:?}");
        assert_eq!(f[1].element, "CURVE/1");
        // A CURVE geometry on a USER curve is named as not modelled, with the reason.
        assert_eq!(f[2].element, "CONTACT/3");
        assert_eq!(f[2].reason, Reason::NotModelled);
        assert!(
            f[2].detail.contains("CURVE/1 is a USER subroutine"),
            "{}",
            f[2].detail
        );
        assert!(f[2].refuses(Analysis::Simulate));
        assert_eq!(f[0].element, "CONTACT/1");
        assert_eq!(f[0].reason, Reason::ExternalFileMissing);
        assert!(f[0].detail.contains("nowhere.xmt_txt"), "{}", f[0].detail);
        assert!(Analysis::ALL.iter().all(|a| f[0].refuses(*a)));
        // At the JGEOM id, on CONTACT/1's line.
        assert_eq!(f[0].span.line, 9);
    }
}
