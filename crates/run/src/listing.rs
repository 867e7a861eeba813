//! The settings in force, as `EQUILIBRIUM/LIST`, `INTEGRATOR/LIST`, `IC/LIST` and
//! `ACCGRAV/LIST` print them in the message file (Adams' layout: one `NAME = value` per line,
//! angles in radians with their unit).

use linkage_model::settings::{Formulation, IntegratorMethod};
use linkage_model::Model;
use std::fmt::Write;

fn pattern(p: &[bool]) -> String {
    p.iter().map(|&b| if b { 'T' } else { 'F' }).collect()
}

/// The lines of `<keyword>/LIST` for `model` (empty for a keyword without a listing).
pub fn settings(keyword: &str, model: &Model) -> String {
    let mut s = String::new();
    match keyword {
        "EQUILIBRIUM" => {
            let e = &model.equilibrium;
            let _ = writeln!(s, " Current EQUILIBRIUM settings are:");
            let _ = writeln!(s, "    ALIMIT         = {} (rad)", e.alimit);
            let _ = writeln!(s, "    ERROR          = {}", e.error);
            let _ = writeln!(s, "    IMBALANCE      = {}", e.imbalance);
            let _ = writeln!(s, "    MAXIT          = {}", e.maxit);
            let _ = writeln!(s, "    PATTERN        = {}", pattern(&e.pattern));
            let _ = writeln!(s, "    STABILITY      = {}", e.stability);
            let _ = writeln!(s, "    TLIMIT         = {}", e.tlimit);
            let _ = writeln!(
                s,
                "    METHOD         = {}",
                if e.dynamic { "DYNAMIC" } else { "STATIC" }
            );
            let _ = writeln!(s, "    GLOBAL_DAMPING = {}", e.global_damping);
            let _ = writeln!(s, "    SETTLING_TIME  = {}", e.settling_time);
            let _ = writeln!(s, "    ACCELERATION_ERROR   = {}", e.acceleration_error);
            let _ = write!(s, "    KINETIC_ENERGY_ERROR = {}", e.kinetic_energy_error);
        }
        "INTEGRATOR" => {
            let i = &model.integrator.settings;
            let opt = |x: Option<f64>| x.map_or("(none)".to_string(), |v| v.to_string());
            let method = match i.method {
                IntegratorMethod::Bdf => match i.formulation {
                    Formulation::I3 => "BDF-I3 (GSTIFF)",
                    Formulation::Si2 => "BDF-SI2 (GSTIFF)",
                },
                IntegratorMethod::Hht => "HHT-I3",
            };
            let _ = writeln!(s, " Current INTEGRATOR settings are ({method}):");
            let _ = writeln!(s, "    ERROR = {}", i.error);
            let _ = writeln!(s, "    HMAX  = {}", opt(i.hmax));
            let _ = writeln!(s, "    HINIT = {}", opt(i.hinit));
            let _ = writeln!(s, "    HMIN  = {}", i.hmin);
            match i.method {
                IntegratorMethod::Bdf => {
                    let _ = writeln!(s, "    KMAX  = {}", i.kmax);
                }
                IntegratorMethod::Hht => {
                    let _ = writeln!(s, "    ALPHA = {}", i.alpha);
                }
            }
            let _ = write!(s, "    MAXIT = {}", i.maxit);
            for note in &model.integrator.notes {
                let _ = write!(s, "\n    note: {note}");
            }
        }
        "IC" => {
            let c = &model.ic;
            let _ = writeln!(s, " Current IC settings are:");
            let _ = writeln!(s, "    ERROR   = {}", c.error);
            let _ = writeln!(s, "    MAXIT   = {}", c.maxit);
            let _ = writeln!(s, "    PATTERN = {}", pattern(&c.pattern));
            let _ = writeln!(s, "    TLIMIT  = {}", c.tlimit);
            let _ = writeln!(s, "    ALIMIT  = {} (rad)", c.alimit);
            let _ = writeln!(s, "    VERROR  = {}", c.verror);
            let _ = write!(s, "    AERROR  = {}", c.aerror);
        }
        "ACCGRAV" => {
            let g = model.gravity;
            let _ = write!(
                s,
                " Current ACCGRAV settings are:\n    IGRAV = {}\n    JGRAV = {}\n    KGRAV = {}",
                g.x, g.y, g.z
            );
        }
        _ => {
            let _ = write!(s, " {keyword} has no settings to list in linkage.");
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equilibrium_settings_are_listed_by_name() {
        let ds = linkage_adm::parse_dataset(
            std::sync::Arc::from("m.adm"),
            "m\nPART/1, GROUND\nEQUILIBRIUM/, STABILITY = 0.5, MAXIT = 7\nEND\n",
        )
        .expect("parses");
        let model = linkage_model::build_model(&ds).expect("builds").model;
        let text = settings("EQUILIBRIUM", &model);
        assert!(text.contains("    STABILITY      = 0.5\n"), "{text}");
        assert!(text.contains("    MAXIT          = 7\n"), "{text}");
        assert!(text.contains("    PATTERN        = TTTTTTTTTT\n"), "{text}");
    }
}
