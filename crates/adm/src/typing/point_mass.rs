//! Typing of `POINT_MASS/id, MASS=r [, CM=id] [, QG=x,y,z] [, REULER=a,b,c | XG=…, ZG=…]
//! [, VX=r] [, VY=r] [, VZ=r] [, EXACT=X:Y:Z]` (ADM-ELEMENTS §13).
//!
//! Contract (in addition to the module contract of [`super`]): a point mass is typed as a
//! [`Part`] with three translational degrees of freedom: no inertia (`IP`, `IM`), no angular
//! velocity (`WX, WY, WZ`, `WM`) and no `VM`; its orientation (REULER or XG/ZG) is constant.
//! `EXACT` may name only X, Y and Z (an error at the argument otherwise).

use super::{header, Typer};
use crate::statement::Statement;
use crate::typed::*;

impl Typer {
    pub(super) fn point_mass(&mut self, st: &Statement, index: usize) -> Part {
        let mut velocity = [None; 6];
        for (v, key) in velocity.iter_mut().zip(["VX", "VY", "VZ"]) {
            *v = self.real(st, key).map(|r| r.value);
        }
        let exact = self.exact(st);
        if exact
            .iter()
            .any(|c| !matches!(c, ExactCoord::X | ExactCoord::Y | ExactCoord::Z))
        {
            if let Some(arg) = st.arg("EXACT") {
                let msg = format!(
                    "{}: a point mass has only the coordinates X, Y, Z (EXACT names a rotation)",
                    header(st, index).name
                );
                self.error(arg.span, msg);
            }
        }
        Part {
            header: header(st, index),
            ground: false,
            mass: self.real(st, "MASS"),
            cm: self.id_ref(st, "CM"),
            im: None,
            ip: None,
            qg: self.vec3(st, "QG"),
            reuler: self.vec3(st, "REULER"),
            xg: self.vec3(st, "XG"),
            zg: self.vec3(st, "ZG"),
            velocity,
            vm: None,
            wm: None,
            exact: exact
                .into_iter()
                .filter(|c| matches!(c, ExactCoord::X | ExactCoord::Y | ExactCoord::Z))
                .collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::parse_dataset;
    use crate::typed::ExactCoord;
    use std::sync::Arc;

    #[test]
    fn point_mass_is_a_part_with_translations_only() {
        let text = "t\nPART/1, GROUND\nPOINT_MASS/4, MASS = 2.5, CM = 40, QG = 1, 2, 3, \
                    REULER = 90D, 0, 0, VX = 1, VZ = -2, EXACT = X:Z\nMARKER/40\nEND\n";
        let ds = parse_dataset(Arc::from("m.adm"), text).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(ds.point_masses.len(), 1);
        let pm = &ds.point_masses[0];
        assert_eq!(pm.header.id, 4);
        assert_eq!(pm.header.name, "POINT_MASS_4");
        assert_eq!(pm.mass.as_ref().map(|m| m.value), Some(2.5));
        assert_eq!(pm.cm.map(|r| r.id), Some(40));
        assert_eq!(pm.qg.as_ref().map(|q| q.value), Some([1.0, 2.0, 3.0]));
        let psi = pm.reuler.as_ref().map(|r| r.value[0]).unwrap_or_default();
        assert!((psi - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        assert_eq!(pm.velocity, [Some(1.0), None, Some(-2.0), None, None, None]);
        assert_eq!(pm.exact, [ExactCoord::X, ExactCoord::Z]);
        assert!(ds.parts.iter().all(|p| p.header.id != 4));
    }

    #[test]
    fn point_mass_refuses_rotation_arguments() {
        let e = parse_dataset(
            Arc::from("m.adm"),
            "t\nPART/1, GROUND\nPOINT_MASS/4, MASS = 1, EXACT = X:PSI\nEND\n",
        )
        .err()
        .map(|d| d.to_string())
        .unwrap_or_default();
        assert!(e.contains("EXACT names a rotation"), "{e}");
        // IP is not an argument of POINT_MASS: an input error, or read leniently a warning
        // and not used.
        let text = "t\nPART/1, GROUND\nPOINT_MASS/4, MASS = 1, IP = 1, 1, 1\nEND\n";
        let e = parse_dataset(Arc::from("m.adm"), text)
            .err()
            .map(|d| d.to_string())
            .unwrap_or_default();
        assert!(e.contains("unknown argument 'IP' of POINT_MASS"), "{e}");
        let lenient = crate::ReadOptions {
            lenient_arguments: true,
        };
        let ds = crate::parse_dataset_with(Arc::from("m.adm"), text, lenient)
            .unwrap_or_else(|e| panic!("{e}"));
        assert!(
            ds.warnings.iter().any(|w| w.to_string().contains("IP")),
            "{:?}",
            ds.warnings
        );
        assert!(ds.point_masses[0].ip.is_none());
    }
}
