//! Animations and plots made from reports that hold poses already: the steps of a
//! quasi-static series, the input and assembled configurations of `ic`, and the mode shapes
//! of `linear` (animated about the operating point).

use crate::scene::Frames;
use crate::svg::{Plot, Series};
use glam::{DMat3, DVec3};
use linkage_model::frames::{euler313_to_matrix, exp_so3};
use linkage_model::Model;
use linkage_report::linear::ModeJson;
use linkage_report::poses::PartPoseJson;
use linkage_report::statics::StaticJson;
use linkage_report::units::{units_json, Angle};

/// Frames per cycle of a mode-shape animation.
pub const MODE_FRAMES: usize = 36;

/// Largest displacement of a mode-shape animation, relative to the characteristic length, and
/// largest rotation in radians: the shape is scaled so that the larger of the two is reached.
pub const MODE_TRANSLATION: f64 = 0.08;
pub const MODE_ROTATION: f64 = 0.35;

/// A part's pose from a report's CM position and 3-1-3 angles in degrees.
pub fn pose_of(p: &PartPoseJson) -> (DVec3, DMat3) {
    (
        DVec3::from(p.position),
        euler313_to_matrix(p.reuler.map(f64::to_radians)),
    )
}

/// Frames named `label` through the listed configurations (`(time, poses)`).
pub fn frames_of(label: &str, steps: &[(f64, &[PartPoseJson])]) -> Frames {
    let mut f = Frames {
        label: label.into(),
        total: steps.len(),
        ..Frames::default()
    };
    for (t, parts) in steps {
        f.push(*t, parts.iter().map(pose_of));
    }
    f
}

/// The animation of a quasi-static series (its converged steps) and its plots: each part's
/// CM position and each element's reaction force against time.
pub fn statics_series(model: &Model, j: &StaticJson) -> (Option<Frames>, Vec<Plot>) {
    if j.steps.len() < 2 {
        return (None, Vec::new());
    }
    let steps: Vec<(f64, &[PartPoseJson])> = j
        .steps
        .iter()
        .filter(|s| s.converged)
        .map(|s| (s.time, s.parts.as_slice()))
        .collect();
    let frames = frames_of("time", &steps);
    let u = units_json(model, Angle::Degree, false);
    let x_label = format!("time [{}]", u.time);
    let mut plots = Vec::new();
    let names = j.steps[0].parts.iter().map(|p| p.name.clone());
    for (k, name) in names.enumerate().take(crate::history::MAX_PLOTS_PER_KIND) {
        plots.push(Plot {
            title: format!("{name}: CM position"),
            x_label: x_label.clone(),
            y_label: format!("position [{}]", u.length),
            series: (0..3)
                .map(|c| Series {
                    name: ["x", "y", "z"][c].into(),
                    points: j
                        .steps
                        .iter()
                        .filter_map(|s| s.parts.get(k).map(|p| (s.time, p.position[c])))
                        .collect(),
                })
                .collect(),
        });
    }
    let elements = j.steps[0].reactions.iter().map(|r| r.name.clone());
    for name in elements.take(crate::history::MAX_PLOTS_PER_KIND) {
        plots.push(Plot {
            title: format!("{name}: reaction force on I"),
            x_label: x_label.clone(),
            y_label: format!("force [{}]", u.force),
            series: (0..3)
                .map(|c| Series {
                    name: ["fx", "fy", "fz"][c].into(),
                    points: j
                        .steps
                        .iter()
                        .filter_map(|s| {
                            let r = s.reactions.iter().find(|r| r.name == name)?;
                            Some((s.time, r.force[c]))
                        })
                        .collect(),
                })
                .collect(),
        });
    }
    (Some(frames), plots)
}

/// The largest force imbalance of each Newton iteration of a static solve, as its base-10
/// logarithm (the imbalance falls by orders of magnitude; an exact zero is left out).
pub fn imbalance_plot(model: &Model, history: &[f64]) -> Plot {
    let u = units_json(model, Angle::Degree, false);
    Plot {
        title: "Static equilibrium: largest imbalance per Newton iteration".into(),
        x_label: "iteration".into(),
        y_label: format!("log10 imbalance [{}]", u.force),
        series: vec![Series {
            name: "log10 max |imbalance|".into(),
            points: history
                .iter()
                .enumerate()
                .filter(|(_, v)| **v > 0.0)
                .map(|(k, v)| (k as f64, v.log10()))
                .collect(),
        }],
    }
}

/// One cycle of a mode shape about the operating point `base` (each moving part's CM
/// position and orientation): part k at phase `ωt` is displaced by
/// `s·Σ_c m_c cos(ωt + φ_c)` along ground axis c and turned by the rotation vector built the
/// same way, `s` chosen so the largest displacement is [`MODE_TRANSLATION`] × `length` or
/// the largest rotation [`MODE_ROTATION`], whichever comes first. `None` without a shape.
pub fn mode_frames(base: &[(DVec3, DMat3)], mode: &ModeJson, length: f64) -> Option<Frames> {
    let shape = mode.shape.as_ref()?;
    let amplitude = |f: &dyn Fn(&linkage_report::linear::PartShapeJson) -> f64| {
        shape.iter().map(f).fold(0.0_f64, f64::max)
    };
    let largest = |v: &[linkage_report::linear::ComponentJson]| {
        v.iter().map(|c| c.magnitude).fold(0.0_f64, f64::max)
    };
    let t_max = amplitude(&|p| largest(&p.translation));
    let r_max = amplitude(&|p| largest(&p.rotation));
    let mut scale = f64::INFINITY;
    if t_max > 0.0 {
        scale = scale.min(MODE_TRANSLATION * length / t_max);
    }
    if r_max > 0.0 {
        scale = scale.min(MODE_ROTATION / r_max);
    }
    if !scale.is_finite() {
        scale = 0.0;
    }
    let mut f = Frames {
        label: format!(
            "mode {} ({} cycles/time)",
            mode.number,
            crate::text::number(mode.frequency)
        ),
        total: MODE_FRAMES,
        ..Frames::default()
    };
    let along = |v: &[linkage_report::linear::ComponentJson], phase: f64| {
        let mut out = DVec3::ZERO;
        for (c, comp) in v.iter().take(3).enumerate() {
            out[c] = comp.magnitude * (phase + comp.phase_deg.to_radians()).cos();
        }
        out
    };
    for k in 0..MODE_FRAMES {
        let phase = std::f64::consts::TAU * k as f64 / MODE_FRAMES as f64;
        let poses = base
            .iter()
            .enumerate()
            .map(|(p, (x, r))| match shape.get(p) {
                Some(s) => (
                    *x + along(&s.translation, phase) * scale,
                    exp_so3(along(&s.rotation, phase) * scale) * *r,
                ),
                None => (*x, *r),
            });
        f.push(k as f64 / MODE_FRAMES as f64, poses);
    }
    Some(f)
}

#[cfg(test)]
mod tests {
    use super::*;
    use linkage_report::linear::{ComponentJson, PartShapeJson};

    #[test]
    fn a_mode_shape_swings_the_largest_translation_to_its_share_of_the_model_size() {
        let mode = ModeJson {
            number: 1,
            frequency: 2.0,
            damping_ratio: 0.0,
            real: 0.0,
            imag: 2.0,
            zero: false,
            shape: Some(vec![PartShapeJson {
                name: "p".into(),
                translation: vec![
                    ComponentJson {
                        magnitude: 1.0,
                        phase_deg: 0.0,
                    },
                    ComponentJson {
                        magnitude: 0.5,
                        phase_deg: 90.0,
                    },
                    ComponentJson {
                        magnitude: 0.0,
                        phase_deg: 0.0,
                    },
                ],
                rotation: vec![
                    ComponentJson {
                        magnitude: 0.0,
                        phase_deg: 0.0
                    };
                    3
                ],
            }]),
        };
        let base = [(DVec3::new(1.0, 2.0, 3.0), DMat3::IDENTITY)];
        let f = mode_frames(&base, &mode, 10.0).expect("has a shape");
        assert_eq!(f.poses.len(), MODE_FRAMES);
        // Phase 0: x at its largest, 0.08 × 10 = 0.8 from the base; y (90°) at zero.
        let p0 = f.poses[0][0].0;
        assert!((p0 - DVec3::new(1.8, 2.0, 3.0)).length() < 1e-12, "{p0}");
        // A quarter cycle later: y = 0.5·0.8·cos(90° + 90°) = −0.4.
        let p = f.poses[MODE_FRAMES / 4][0].0;
        assert!((p - DVec3::new(1.0, 1.6, 3.0)).length() < 1e-12, "{p}");
    }
}
