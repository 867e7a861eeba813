//! The linearization report: Adams-style eigenvalue table, frequencies, damping ratios and
//! mode shapes; JSON.

use crate::units::{text_line, units_json, Angle, UnitsJson};
use linkage_adm::Diagnostic;
use linkage_model::Model;
use linkage_solve::stages::linearize::{LinearRun, Linearization, Solution};
use serde::Serialize;
use std::f64::consts::TAU;
use std::fmt::Write;

#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct EigenvalueJson {
    /// Cycles per time unit (Re λ / 2π).
    pub real: f64,
    /// Cycles per time unit (Im λ / 2π); a complex pair appears once, with `imag ≥ 0`.
    pub imag: f64,
}

#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct ComponentJson {
    pub magnitude: f64,
    pub phase_deg: f64,
}

#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct PartShapeJson {
    pub name: String,
    /// X, Y, Z translation of the centre of mass (ground axes).
    pub translation: Vec<ComponentJson>,
    /// Rotation about ground X, Y, Z.
    pub rotation: Vec<ComponentJson>,
}

#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct ModeJson {
    pub number: usize,
    /// Undamped natural frequency (cycles per time unit).
    pub frequency: f64,
    pub damping_ratio: f64,
    pub real: f64,
    pub imag: f64,
    /// A zero eigenvalue (a rigid-body motion at rounding-noise frequency): counted in
    /// `zero_eigenvalues`, not listed in the text report and the page.
    pub zero: bool,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shape: Option<Vec<PartShapeJson>>,
}

/// Which of `modes` are the `zero_eigenvalues` zero eigenvalues the solver counted: the modes
/// of smallest undamped frequency, a complex pair counting two eigenvalues, as long as they
/// fit in the count (the solver counts `|λ|` at or below its zero tolerance, so these are
/// exactly the smallest ones).
pub fn zero_modes(modes: &[ModeJson], zero_eigenvalues: usize) -> Vec<bool> {
    let mut order: Vec<usize> = (0..modes.len()).collect();
    order.sort_by(|&a, &b| modes[a].frequency.total_cmp(&modes[b].frequency));
    let mut zero = vec![false; modes.len()];
    let mut counted = 0;
    for k in order {
        let eigenvalues = if modes[k].imag > 0.0 { 2 } else { 1 };
        if counted + eigenvalues > zero_eigenvalues {
            break;
        }
        counted += eigenvalues;
        zero[k] = true;
    }
    zero
}

/// The real part and damping ratio of `mode` as the text shows them: zero when the real
/// part is rounding noise next to the largest `|λ|` of the table (`scale`, cycles per time
/// unit; [`crate::num::NOISE_RELATIVE`]).
fn shown_damping(mode: &ModeJson, scale: f64) -> (f64, f64) {
    let real = crate::num::denoise(mode.real, scale);
    if real == 0.0 {
        (0.0, 0.0)
    } else {
        (real, mode.damping_ratio)
    }
}

/// The JSON document of `linkage linear --format json`.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct LinearJson {
    pub file: String,
    pub title: String,
    /// Frequencies and eigenvalues in cycles per time unit; mode-shape rotations in radians.
    pub units: UnitsJson,
    /// Statements left out on request (`--deactivate`).
    pub left_out: Vec<crate::coverage::LeftOutJson>,
    /// Statements this analysis ran without (not modelled, not used by it).
    pub runs_without: Vec<crate::coverage::FindingJson>,
    pub operating_point: &'static str,
    /// Time of the operating point.
    pub time: f64,
    pub dof: usize,
    pub states: usize,
    /// `"dense"` (every eigenvalue) or `"shift-invert"` (those nearest `shift`).
    pub method: &'static str,
    /// Frequency the shift-invert solution looked around (cycles per time unit; 0: the lowest
    /// modes).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shift: Option<f64>,
    /// Eigenvalues computed (a complex pair counts 2) out of `states`.
    pub computed_eigenvalues: usize,
    pub eigenvalues: Vec<EigenvalueJson>,
    pub modes: Vec<ModeJson>,
    pub zero_eigenvalues: usize,
    pub expected_zero_eigenvalues: usize,
    pub warnings: Vec<String>,
    pub errors: Vec<String>,
}

fn modes_json(model: &Model, l: &Linearization) -> Vec<ModeJson> {
    l.modes
        .iter()
        .enumerate()
        .map(|(k, m)| ModeJson {
            number: k + 1,
            frequency: m.frequency,
            damping_ratio: m.damping_ratio,
            real: m.real / TAU,
            imag: m.imag / TAU,
            zero: false,
            shape: m.shape.as_ref().map(|sh| {
                sh.iter()
                    .map(|p| PartShapeJson {
                        name: model.parts[p.part].origin.name.clone(),
                        translation: p
                            .translation
                            .iter()
                            .map(|c| ComponentJson {
                                magnitude: c.magnitude,
                                phase_deg: c.phase_deg,
                            })
                            .collect(),
                        rotation: p
                            .rotation
                            .iter()
                            .map(|c| ComponentJson {
                                magnitude: c.magnitude,
                                phase_deg: c.phase_deg,
                            })
                            .collect(),
                    })
                    .collect()
            }),
        })
        .collect()
}

/// Builds the JSON document.
pub fn to_json(
    model: &Model,
    run: &LinearRun,
    static_first: bool,
    warnings: &[Diagnostic],
) -> LinearJson {
    let mut warnings: Vec<String> = warnings.iter().map(|w| w.to_string()).collect();
    let mut errors = Vec::new();
    let (mut method, mut shift, mut computed) = ("dense", None, 0);
    let (dof, modes, zeros, expected) = match &run.result {
        Ok(l) => {
            computed = l.computed_eigenvalues;
            let zeros_complete = match l.solution {
                Solution::Dense => true,
                Solution::ShiftInvert {
                    shift: s,
                    zeros_complete,
                    ..
                } => {
                    method = "shift-invert";
                    shift = Some(s / TAU);
                    zeros_complete
                }
            };
            if l.massless_parts > 0 {
                warnings.push(format!(
                    "There are {} zero-mass parts in the model; 1e-8 times the smallest nonzero mass is used for them during linearization.",
                    l.massless_parts
                ));
            }
            if zeros_complete && l.zero_eigenvalues != l.expected_zero_eigenvalues {
                warnings.push(format!(
                    "{} zero eigenvalues found, but the free motions without stiffness account for {}: check for missing stiffness or a near-singular pose",
                    l.zero_eigenvalues, l.expected_zero_eigenvalues
                ));
            }
            let mut modes = modes_json(model, l);
            let zero = zero_modes(&modes, l.zero_eigenvalues);
            for (m, zero) in modes.iter_mut().zip(zero) {
                m.zero = zero;
            }
            (
                l.dof,
                modes,
                l.zero_eigenvalues,
                l.expected_zero_eigenvalues,
            )
        }
        Err(e) => {
            errors.push(e.to_string());
            (0, Vec::new(), 0, 0)
        }
    };
    LinearJson {
        file: model.file.to_string(),
        title: model.title.clone(),
        units: units_json(model, Angle::Radian, true),
        left_out: Vec::new(),
        runs_without: Vec::new(),
        operating_point: if static_first {
            "static equilibrium"
        } else {
            "assembled configuration (initial conditions)"
        },
        time: 0.0,
        dof,
        states: 2 * dof,
        method,
        shift,
        computed_eigenvalues: computed,
        eigenvalues: modes
            .iter()
            .map(|m| EigenvalueJson {
                real: m.real,
                imag: m.imag,
            })
            .collect(),
        modes,
        zero_eigenvalues: zeros,
        expected_zero_eigenvalues: expected,
        warnings,
        errors,
    }
}

/// Fortran-style `1.23456E-01` (Adams' number format), with `-0` shown as `0`.
pub fn fortran_e(x: f64, digits: usize) -> String {
    if x == 0.0 || !x.is_finite() {
        return if x.is_finite() {
            format!("{:.digits$}E+00", 0.0)
        } else {
            format!("{x}")
        };
    }
    let e = x.abs().log10().floor() as i32;
    let mut m = x / 10f64.powi(e);
    let mut e = e;
    if format!("{:.digits$}", m.abs()).starts_with("10") {
        m /= 10.0;
        e += 1;
    }
    format!(
        "{m:.digits$}E{}{:02}",
        if e < 0 { '-' } else { '+' },
        e.abs()
    )
}

/// Human report in the layout of Adams' eigenvalue table.
pub fn to_text(j: &LinearJson) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "LINEARIZATION: {}", j.title);
    let _ = writeln!(s, "  file: {}", j.file);
    let _ = writeln!(s, "{}", text_line(&j.units));
    s.push_str(&crate::coverage::analysis_text(
        &j.left_out,
        &j.runs_without,
    ));
    let _ = writeln!(s, "  operating point: {}", j.operating_point);
    if j.modes.is_empty() && !j.errors.is_empty() {
        // No operating point: no eigenvalue table to show.
        for w in &j.warnings {
            let _ = writeln!(s, "warning: {w}");
        }
        for e in &j.errors {
            let _ = writeln!(s, "error: {e}");
        }
        return s;
    }
    let _ = writeln!(
        s,
        "  This model has {} kinematic states (displacements and velocities).",
        j.states
    );
    if let Some(shift) = j.shift {
        let which = if shift == 0.0 {
            "the lowest".to_string()
        } else {
            format!("those nearest {} cycles/second", fortran_e(shift, 5))
        };
        let _ = writeln!(
            s,
            "  Computed {} of the {} eigenvalues ({} mode{}): {which} (sparse shift-invert).",
            j.computed_eigenvalues,
            j.states,
            j.modes.len(),
            if j.modes.len() == 1 { "" } else { "s" },
        );
    }
    let _ = writeln!(s);
    let _ = writeln!(
        s,
        "               E I G E N V A L U E S  at time = {}",
        fortran_e(j.time, 5)
    );
    let _ = writeln!(s, "    Number    Real(cycles/second)      Imag.(cycles/second)   Undamped freq.   Damping ratio");
    let listed: Vec<&ModeJson> = j.modes.iter().filter(|m| !m.zero).collect();
    let scale = crate::num::scale_of(listed.iter().map(|m| m.frequency));
    for m in &listed {
        let (real, ratio) = shown_damping(m, scale);
        let imag = if m.imag > 0.0 {
            format!("+/- {:>16}", fortran_e(m.imag, 5))
        } else {
            " ".repeat(20)
        };
        let _ = writeln!(
            s,
            "    {:>6}    {:>16}      {imag}   {:>14}   {:>13}",
            m.number,
            fortran_e(real, 5),
            fortran_e(m.frequency, 5),
            fortran_e(ratio, 5)
        );
    }
    let hidden = j.modes.len() - listed.len();
    if hidden > 0 {
        let _ = writeln!(
            s,
            "    ({hidden} mode{} at zero frequency, rounding noise of rigid-body motions, not listed: see the zero eigenvalues below)",
            if hidden == 1 { "" } else { "s" }
        );
    }
    for m in &listed {
        let Some(shape) = &m.shape else { continue };
        let _ = writeln!(s);
        let _ = writeln!(
            s,
            "Mode {}: undamped natural freq. = {}, damping ratio = {}",
            m.number,
            fortran_e(m.frequency, 6),
            fortran_e(shown_damping(m, scale).1, 6)
        );
        let _ = writeln!(
            s,
            "   {:<20} {:>22} {:>22} {:>22} {:>22} {:>22} {:>22}",
            "part", "X", "Y", "Z", "RX", "RY", "RZ"
        );
        for p in shape {
            let cells: Vec<String> = p
                .translation
                .iter()
                .chain(p.rotation.iter())
                .map(|c| {
                    // The phase of a component that rounds to zero is noise: shown as 0.
                    let magnitude = crate::poses::fixed(c.magnitude, 4);
                    let phase = if magnitude == "0.0000" {
                        0.0
                    } else {
                        c.phase_deg
                    };
                    format!("{magnitude} @ {:>7.2}°", crate::num::denoise(phase, 1.0))
                })
                .collect();
            let _ = writeln!(
                s,
                "   {:<20} {:>22} {:>22} {:>22} {:>22} {:>22} {:>22}",
                p.name, cells[0], cells[1], cells[2], cells[3], cells[4], cells[5]
            );
        }
    }
    let _ = writeln!(s);
    let among = if j.shift.is_some() {
        " among the computed ones"
    } else {
        ""
    };
    let _ = writeln!(s, "{} zero eigenvalues{among} (rigid-body motions); {} expected from the free motions without stiffness.", j.zero_eigenvalues, j.expected_zero_eigenvalues);
    for w in &j.warnings {
        let _ = writeln!(s, "warning: {w}");
    }
    for e in &j.errors {
        let _ = writeln!(s, "error: {e}");
    }
    s
}

#[cfg(test)]
mod tests {
    use super::{fortran_e, shown_damping, zero_modes, ModeJson};

    fn mode(frequency: f64, real: f64, imag: f64) -> ModeJson {
        ModeJson {
            number: 0,
            frequency,
            damping_ratio: if frequency > 0.0 {
                -real / frequency
            } else {
                0.0
            },
            real,
            imag,
            zero: false,
            shape: None,
        }
    }

    #[test]
    fn the_zero_eigenvalues_are_the_smallest_modes_a_pair_counting_two() {
        // Cylindrical_Case02 of the corpus: a real 6.9e-18 Hz eigenvalue and a 1.4e-17 Hz
        // pair are the 3 zero eigenvalues; the 2.5 Hz pair is a mode.
        let modes = [
            mode(2.5, -0.01, 2.49998),
            mode(6.9e-18, -6.9e-18, 0.0),
            mode(1.4e-17, 2.7e-18, 1.38e-17),
        ];
        assert_eq!(zero_modes(&modes, 3), [false, true, true]);
        assert_eq!(zero_modes(&modes, 1), [false, true, false]);
        // A count that would split a pair leaves the pair listed.
        assert_eq!(zero_modes(&modes, 2), [false, true, false]);
        assert_eq!(zero_modes(&modes, 0), [false, false, false]);
    }

    #[test]
    fn a_real_part_at_rounding_noise_has_no_damping() {
        // MODEL_test10 of the corpus: -5.5e-16 ± 0.54 Hz is undamped; -0.01 ± 2.5 Hz is not.
        let noisy = mode(0.539767, -5.45553e-16, 0.539767);
        assert_eq!(shown_damping(&noisy, 0.539767), (0.0, 0.0));
        let damped = mode(2.5, -0.01, 2.49998);
        assert_eq!(shown_damping(&damped, 2.5), (-0.01, 0.004));
    }

    #[test]
    fn numbers_print_like_adams() {
        // ADM-REFERENCE §12: λ = −1 ± 9.94987i rad/s prints as −1.59155E-01 ± 1.58357E+00.
        assert_eq!(fortran_e(-1.0 / std::f64::consts::TAU, 5), "-1.59155E-01");
        assert_eq!(fortran_e(9.94987 / std::f64::consts::TAU, 5), "1.58357E+00");
        assert_eq!(fortran_e(-0.0, 5), "0.00000E+00");
        assert_eq!(fortran_e(99999.9, 3), "1.000E+05");
    }
}
