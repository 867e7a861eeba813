//! linkage against Adams' own time histories: the Chrono Adams test models
//! (`projectchrono__chrono__data__adams__test_*.adm` of the shared corpus, third-party files
//! that are not part of this repository) with the request files Adams Solver wrote for them
//! (`*_ADAMS.req`). Skipped, with a notice, when the corpus folder is absent.
//!
//! Each case: read the `.acf` for `SIMULATE/…, END=, DTOUT=|STEPS=`, simulate with linkage,
//! evaluate the dataset's REQUESTs at every output ([`RequestSet`]) and compare with the
//! `.req` history at every output time (the times must agree).
//!
//! What is compared, per request (the models all have the same five):
//! - REQUEST/1 DISPLACEMENT of the part's CM marker from ground: x, y, z, and the orientation
//!   given by ψ, θ, φ, compared as the angle of the rotation between Adams' and linkage's
//!   orientation (the 3-1-3 angles themselves are ill-conditioned near θ = 0, where the
//!   Spherical case starts, and wrap at ±180°);
//! - REQUEST/2 VELOCITY and REQUEST/3 ACCELERATION (linear and angular);
//! - REQUEST/5: the joint reaction `JOINT(1, 0, comp, 0)` (force on the I marker and torque
//!   about it, ground axes), or the FORCE request / `FX(…)…TZ(…)` measures of the models
//!   without a joint;
//! - REQUEST/4: the Euler parameters `ORIENT(27, 1…4, I, J)` (P0 first), in the groups
//!   (P0, P1, P2) and (P3, 0, 0) as the .req stores them (F2 F3 F4 | F6 F7 F8; the unwritten
//!   F7, F8 are zero). P and −P are the same orientation; Adams' sign follows its 3-1-3
//!   angles and so does linkage's, but where ψ or φ is ±180° exactly in theory (a pendulum
//!   swinging in a plane of the ground axes: Revolute_Case02 throughout) the branch, and with
//!   it the sign, is decided by rounding noise; there, and only there, linkage's parameters
//!   are negated before the comparison ([`align_euler_parameter_signs`]) and the count is
//!   printed.
//!
//! Error measure: for every group of three components (x y z, vx vy vz, wx wy wz, fx fy fz,
//! tx ty tz, …) the worst absolute difference over the compared output times, divided by the
//! range the Adams signal covers (largest range of the three components over the run; for the
//! orientation, the largest angle the part turns through). The .req values are printed with 6
//! significant digits, so agreement better than about 1e-5 of the range cannot be expected.
//! Tolerance: [`TOL`] = 1e-3 of the range for every group. Adams integrated these models with
//! GSTIFF at ERROR = 1e-4, HMAX = 1e-5 (the .acf), so its own histories carry an integration
//! error: Revolute_Case01 and Spherical_Case01 describe the same planar pendulum (same mass,
//! same inertia about the hinge axis) and Adams' two histories of it differ by 2e-4 of the
//! range — exactly the difference linkage shows against the Spherical and Universal cases
//! while matching Revolute_Case01 to 1e-5. Accelerations and reactions get the same tolerance:
//! they follow algebraically from positions and velocities (measured: below 5e-4).
//! Groups Adams holds at rounding level (range below [`ROUNDING`] = 1e-9, e.g. the torque of
//! a spherical joint, ~1e-15) must match to 1e-9 absolutely.
//!
//! linkage is run with INTEGRATOR ERROR = [`LINKAGE_ERROR`] (1e-8) instead of the .acf's
//! 1e-4, so that its own error is negligible and the comparison measures the physics; a
//! second run at [`CHECK_ERROR`] (1e-6) tells up to when that holds: the comparison stops at
//! the first output where the two linkage runs differ by more than [`HORIZON`] (1e-4) of a
//! position, orientation or velocity range, and must cover at least [`MIN_HORIZON`] of the
//! run. For a conservative model of one part it also stops where Adams' own solution stops
//! keeping the energy (by more than [`ENERGY_HORIZON`] of the largest kinetic energy,
//! computed from Adams' displacement, velocity and Euler-parameter requests): from there
//! Adams no longer solves the equations it was given. Every case is compared over the whole
//! run but Distance_Case02 (a body hanging by a point 2 m from its centre of mass on a
//! distance constraint, tumbling): Adams' energy (29.41995 J at the start, kinetic energy up
//! to 37.8 J) holds to 3e-5 J up to 1.75 s, then drops by 0.036 J near 1.85 s and by 0.30 J
//! near 3.1 s, while linkage's runs at ERROR 1e-6 and 1e-8 agree to 1e-4 of every range over
//! the whole 5 s; it is compared up to 1.89 s. HMAX = 1e-5 of the .acf is not used (it only
//! serves GSTIFF's accuracy and would mean half a million steps).
//!
//! The Distance cases (a general constraint `DM(I, J) − L = 0`) are compared like the others:
//! their accelerations and reactions carry the constraint's exact second time derivative
//! (`System::acceleration_bias`); before that existed, linkage reported a vertical
//! acceleration of ~0 at the bottom of the Distance_Case01 swing where Adams (and linkage's
//! own velocity history) show the centripetal 19.6 m/s². Their FORCE request (REQUEST/5, the
//! wrench between ground and the part, recovered from the equations of motion because the
//! GCON's I marker is on ground) has a torque about the pivot that vanishes in theory; it
//! matches Adams' rounding-level zero (4e-14 N·m against forces of 2.5e3 N in
//! Distance_Case02) since the consistent-output solve no longer regularises the rotational
//! inertia of parts whose inertia is regular (a 1e-12 relative regularisation there made it
//! 4e-8 N·m).
//!
//! Every case must run: one whose elements linkage does not model (a statement linkage refuses
//! in force analyses, an element the model or the force set rejects) fails, as does a case
//! that runs and does not match.

use linkage_adm::reqfile::{read_request_file, RequestFile, RequestHistory};
use linkage_adm::{parse_commands, read_dataset, Dataset, Value};
use linkage_model::frames::euler313_to_matrix;
use linkage_solve::constraints::drivers::ExpressionDrivers;
use linkage_solve::physics::applied::{AppliedForces, NoForces};
use linkage_solve::physics::forces::ForceSet;
use linkage_solve::physics::requests::RequestSet;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::dynamics::{run, IntegratorSettings, Output, Start};
use linkage_solve::tolerances::Tolerances;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Worst error / range of every compared group (module docs).
const TOL: f64 = 1e-3;
/// A group whose Adams range is below this is zero up to rounding; it must match absolutely.
const ROUNDING: f64 = 1e-9;
/// linkage's INTEGRATOR ERROR in the compared run (see the module docs).
const LINKAGE_ERROR: f64 = 1e-8;
/// linkage's INTEGRATOR ERROR of the check run that tells how far the compared run is
/// converged (BDF: ERROR bounds the error of the whole run, so 1e-6 against 1e-8 brackets
/// it).
const CHECK_ERROR: f64 = 1e-6;
/// Convergence threshold between linkage's runs at [`LINKAGE_ERROR`] and [`CHECK_ERROR`],
/// relative to a kinematic signal's range: a tenth of [`TOL`].
const HORIZON: f64 = 1e-4;
/// The comparison must cover at least this fraction of the run (50 outputs here).
const MIN_HORIZON: f64 = 0.1;

const PREFIX: &str = "projectchrono__chrono__data__adams__test_";

fn corpus_dir() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/corpus");
    if dir.is_dir() {
        Some(dir)
    } else {
        assert!(
            std::env::var_os("CI").is_none(),
            "corpus folder {} absent (required when CI is set)",
            dir.display()
        );
        println!(
            "notice: corpus folder {} absent; Adams reference comparisons skipped",
            dir.display()
        );
        None
    }
}

/// The cases of the corpus: models with an Adams request file beside them.
fn discovered_cases(dir: &Path) -> Vec<String> {
    let mut cases: Vec<String> = std::fs::read_dir(dir)
        .map(|rd| {
            rd.filter_map(|e| e.ok())
                .filter_map(|e| e.file_name().to_str().map(str::to_string))
                .filter_map(|n| {
                    n.strip_prefix(PREFIX)
                        .and_then(|r| r.strip_suffix("_ADAMS.req"))
                        .map(str::to_string)
                })
                .filter(|case| dir.join(format!("{PREFIX}{case}.adm")).is_file())
                .collect()
        })
        .unwrap_or_default();
    cases.sort();
    cases
}

/// `KEY = number` of a command.
fn number(st: &linkage_adm::Statement, key: &str) -> Option<f64> {
    match st.arg(key)?.values.as_slice() {
        [Value::Number { value, .. }] => Some(*value),
        _ => None,
    }
}

/// Output times from the `.acf`'s SIMULATE command.
fn acf_times(path: &Path) -> Vec<f64> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let acf = parse_commands(Arc::from(path.display().to_string()), &text)
        .unwrap_or_else(|e| panic!("{e}"));
    let sim = acf
        .commands
        .iter()
        .find(|c| c.keyword == "SIMULATE")
        .unwrap_or_else(|| panic!("{}: no SIMULATE command", path.display()));
    let end = number(sim, "END").unwrap_or_else(|| panic!("SIMULATE without END"));
    let steps = match (number(sim, "DTOUT"), number(sim, "STEPS")) {
        (Some(dt), _) => (end / dt).round() as usize,
        (None, Some(n)) => n as usize,
        _ => panic!("SIMULATE without DTOUT or STEPS"),
    };
    (0..=steps).map(|k| end * k as f64 / steps as f64).collect()
}

/// Why linkage cannot run this model, if it cannot.
fn unsupported(ds: &Dataset) -> Option<String> {
    use linkage_solve::coverage::{findings, Analysis};
    let names: Vec<String> = findings(ds)
        .into_iter()
        .filter(|f| f.refuses(Analysis::Simulate))
        .map(|f| f.element)
        .collect();
    (!names.is_empty()).then(|| format!("linkage does not model or run {}", names.join(", ")))
}

/// Values of one request, six per output, in the .req's component order.
type Six = Vec<[f64; 6]>;

/// Angle (degrees) of the rotation between the orientations of two displacement rows.
fn rotation_between(a: &[f64; 6], b: &[f64; 6]) -> f64 {
    let rot = |v: &[f64; 6]| euler313_to_matrix([v[3], v[4], v[5]].map(f64::to_radians));
    let m = rot(a).transpose() * rot(b);
    let trace = m.x_axis.x + m.y_axis.y + m.z_axis.z;
    ((trace - 1.0) / 2.0).clamp(-1.0, 1.0).acos().to_degrees()
}

/// One group of three components of a request, compared over time.
struct Group {
    /// `REQUEST_2.lin`, `REQUEST_2.ang`, `REQUEST_1.orientation`.
    name: String,
    /// Index of the group in the request (0: components 1–3, 1: components 4–6).
    half: usize,
    /// The displacement angles, compared as a rotation.
    orientation: bool,
    /// Scale of the Adams signal: the largest range of its three components over the run
    /// (for an orientation, the largest angle the part turns through from its start).
    range: f64,
    tol: f64,
}

impl Group {
    /// Largest difference between `a` and `b` at output `k`, and the component it is in.
    fn error(&self, a: &[f64; 6], b: &[f64; 6], labels: &[&'static str; 6]) -> (f64, &'static str) {
        if self.orientation {
            return (rotation_between(a, b), "angle");
        }
        (3 * self.half..3 * self.half + 3)
            .map(|c| ((a[c] - b[c]).abs(), labels[c]))
            .fold((0.0, ""), |best, x| if x.0 > best.0 { x } else { best })
    }

    /// Whether Adams holds the group at rounding level (e.g. the torque of a spherical joint).
    fn rounding(&self) -> bool {
        self.range < ROUNDING
    }

    /// Error relative to the range (to [`ROUNDING`] for a group at rounding level).
    fn relative(&self, error: f64) -> f64 {
        error / self.range.max(ROUNDING)
    }

    fn ok(&self, error: f64) -> bool {
        if self.rounding() {
            error <= ROUNDING
        } else {
            self.relative(error) <= self.tol
        }
    }
}

/// The two groups of a request, with their scales from the Adams history.
fn groups(name: &str, adams: &RequestHistory) -> [Group; 2] {
    let range = |comps: [usize; 3]| {
        comps
            .iter()
            .map(|&c| {
                let (lo, hi) = adams
                    .values
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                        (lo.min(v[c]), hi.max(v[c]))
                    });
                hi - lo
            })
            .fold(0.0, f64::max)
    };
    let orientation = adams.type_code == 1;
    let turned = adams
        .values
        .iter()
        .map(|v| rotation_between(&adams.values[0], v))
        .fold(0.0, f64::max);
    [
        Group {
            name: format!("{name}.lin"),
            half: 0,
            orientation: false,
            range: range([0, 1, 2]),
            tol: TOL,
        },
        Group {
            name: format!("{name}.{}", if orientation { "orientation" } else { "ang" }),
            half: 1,
            orientation,
            range: if orientation {
                turned
            } else {
                range([3, 4, 5])
            },
            tol: TOL,
        },
    ]
}

/// Our six values of a request in the .req's component order.
fn ours_for(columns: &[String], values: &[Vec<f64>], name: &str, adams: &RequestHistory) -> Six {
    let suffixes = match adams.type_code {
        1..=4 => adams.component_names().map(str::to_string),
        _ => ["f2", "f3", "f4", "f6", "f7", "f8"].map(str::to_string),
    };
    // A function request's unwritten F's are zero in the .req (REQUEST/4 writes F2, F3, F4
    // and F6 only); every other column must exist.
    let index: Vec<Option<usize>> = suffixes
        .iter()
        .map(|s| {
            let col = format!("{name}.{s}");
            let k = columns.iter().position(|c| *c == col);
            assert!(
                k.is_some() || adams.type_code > 4,
                "no column {col} in {columns:?}"
            );
            k
        })
        .collect();
    values
        .iter()
        .map(|row| {
            let mut six = [0.0; 6];
            for (dst, k) in six.iter_mut().zip(&index) {
                *dst = k.map_or(0.0, |k| row[k]);
            }
            six
        })
        .collect()
}

/// The markers `(i, j)` of a request whose functions are all `ORIENT(27, …, i, j)` (Euler
/// parameters).
fn euler_parameter_markers(r: &linkage_adm::Request) -> Option<(u64, u64)> {
    let mut markers = None;
    for f in r.functions.iter().flatten() {
        let e = linkage_expr::parse(&f.value.expr.text).ok()?;
        let linkage_expr::Expr::Call {
            func: linkage_expr::Function::Orient,
            args,
        } = &e
        else {
            return None;
        };
        let number = |k: usize| match args.get(k) {
            Some(linkage_expr::Expr::Number(x)) => Some(*x as u64),
            None => Some(0),
            _ => None,
        };
        if number(0)? != 27 {
            return None;
        }
        let ij = (number(2)?, number(3)?);
        if markers.is_some_and(|m| m != ij) {
            return None;
        }
        markers = Some(ij);
    }
    markers
}

/// Euler parameters P and −P are the same orientation. Adams gives them the sign of its body
/// 3-1-3 angles' formula (`P0 = cos(θ/2)·cos((ψ+φ)/2)`, …), as linkage's ORIENT does; where
/// ψ or φ is ±180° exactly in theory (a pendulum swinging in a plane of the ground axes),
/// which of the two the branch gives is decided by the sign of a rounding-level direction
/// cosine, differently in Adams and linkage, and the parameters come out negated. Our values
/// are negated at such outputs only (Adams' displacement request of the same markers shows
/// |ψ| or |φ| = 180.00000°); a sign difference anywhere else is left to fail. Returns how
/// many were negated.
fn align_euler_parameter_signs(
    reference: &RequestFile,
    (i, j): (u64, u64),
    adams: &RequestHistory,
    ours: &mut Six,
) -> usize {
    let angles = reference
        .requests
        .iter()
        .find(|h| h.type_code == 1 && h.i == i && h.j == j);
    let mut flips = 0;
    for (k, (a, o)) in adams.values.iter().zip(ours.iter_mut()).enumerate() {
        let dot = a[0] * o[0] + a[1] * o[1] + a[2] * o[2] + a[3] * o[3];
        let ambiguous = angles.is_some_and(|d| {
            let v = &d.values[k];
            v[3].abs() >= 179.99999 || v[5].abs() >= 179.99999
        });
        if dot < 0.0 && ambiguous {
            for x in o.iter_mut().take(4) {
                *x = -*x;
            }
            flips += 1;
        }
    }
    flips
}

/// A model ready to simulate.
struct Case {
    name: String,
    ds: Dataset,
    model: linkage_model::Model,
    drivers: ExpressionDrivers,
    forces: Box<dyn AppliedForces>,
    requests: RequestSet,
    times: Vec<f64>,
}

impl Case {
    /// The request columns at every output of a linkage run at INTEGRATOR ERROR `error`, and
    /// the numbers of steps taken and rejected.
    fn simulate(&self, error: f64) -> (Vec<Vec<f64>>, usize, usize) {
        let settings = IntegratorSettings {
            error,
            ..Default::default()
        };
        let assembled = Assembled::new(
            &self.model,
            &self.drivers,
            self.forces.as_ref(),
            &Tolerances::default(),
        );
        let result = run(
            &assembled,
            &self.times,
            &settings,
            Start::InitialConditions,
            |_| {},
        );
        let case = &self.name;
        let sim = result
            .simulation
            .as_ref()
            .unwrap_or_else(|| panic!("{case}: no simulation: {:?}", result.error));
        assert!(sim.failure.is_none(), "{case}: {:?}", sim.failure);
        let outputs: &[Output] = &sim.outputs;
        assert_eq!(outputs.len(), self.times.len(), "{case}: output count");
        let values: Vec<Vec<f64>> = outputs
            .iter()
            .map(|o| {
                self.requests
                    .evaluate(&self.model, &assembled.system, o)
                    .unwrap_or_else(|e| panic!("{e}"))
            })
            .collect();
        (values, sim.steps, sim.rejected)
    }
}

/// The case, ready to run; a case linkage cannot build or run fails here (never skipped).
fn load_case(dir: &Path, case: &str) -> Case {
    let adm = dir.join(format!("{PREFIX}{case}.adm"));
    let acf = dir.join(format!("{PREFIX}{case}.acf"));
    let ds = read_dataset(&adm).unwrap_or_else(|e| panic!("{e}"));
    if let Some(why) = unsupported(&ds) {
        panic!("{case}: {why}");
    }
    let model = match linkage_model::build_model(&ds) {
        Ok(b) => b.model,
        Err(e) => panic!("{case}: the model is not supported:\n{e}"),
    };
    let forces: Box<dyn AppliedForces> = if model.forces.is_empty() {
        Box::new(NoForces)
    } else {
        match ForceSet::new(&model) {
            Ok(f) => Box::new(f),
            Err(e) => panic!("{case}: force elements not supported:\n{e}"),
        }
    };
    let drivers = ExpressionDrivers::new(&model).unwrap_or_else(|e| panic!("{e}"));
    let requests = RequestSet::new(&model).unwrap_or_else(|e| panic!("{e}"));
    Case {
        name: case.to_string(),
        ds,
        model,
        drivers,
        forces,
        requests,
        times: acf_times(&acf),
    }
}

/// Relative change of total energy beyond which Adams' own solution of a conservative model
/// has left the exact one (see [`adams_energy_horizon`]).
const ENERGY_HORIZON: f64 = 5e-4;

/// For a conservative model of one moving part (no force elements, no motions) whose
/// requests give its centre of mass's displacement and velocity and its orientation as Euler
/// parameters relative to ground: the first output where the energy of Adams' solution,
/// `½m|v|² + ½ωᵀI_gω − m g·x`, differs from the start's by more than [`ENERGY_HORIZON`] of the
/// largest kinetic energy of the run.
/// Adams' solution is compared only up to there (where it still solves the equations it was
/// given); `None` when the model or its requests do not allow the check.
fn adams_energy_horizon(c: &Case, reference: &RequestFile) -> Option<usize> {
    let m = &c.model;
    if m.parts.len() != 1
        || !m.forces.is_empty()
        || c.ds.statements.iter().any(|s| s.keyword == "MOTION")
    {
        return None;
    }
    let part = &m.parts[0];
    let on_ground_origin = |id: u64| {
        m.markers.iter().any(|k| {
            k.id == id
                && k.body == linkage_model::Body::Ground
                && k.p_bm.length() < 1e-12
                && (k.r_bm - glam::DMat3::IDENTITY)
                    .abs()
                    .to_cols_array()
                    .iter()
                    .all(|x| *x < 1e-12)
        })
    };
    // The part's CM marker: on the part, at its centre of mass.
    let cm = |id: u64| {
        m.markers.iter().find(|k| {
            k.id == id && k.body == linkage_model::Body::Part(0) && k.p_bm.length() < 1e-12
        })
    };
    let (mut d, mut v, mut e, mut marker) = (None, None, None, None);
    for r in &c.ds.requests {
        let h = reference.request(r.header.id)?;
        if let Some((i, j)) = euler_parameter_markers(r) {
            if cm(i).is_some() && on_ground_origin(j) {
                e = Some(h);
            }
        } else if cm(h.i).is_some() && on_ground_origin(h.j) {
            marker = cm(h.i);
            match h.type_code {
                1 => d = Some(h),
                2 => v = Some(h),
                _ => {}
            }
        }
    }
    let (d, v, e, marker) = (d?, v?, e?, marker?);
    // Kinetic and potential energy of output k.
    let energy = |k: usize| {
        let (x, w) = (&d.values[k], &v.values[k]);
        let q = &e.values[k];
        let r_marker =
            glam::DMat3::from_quat(glam::DQuat::from_xyzw(q[1], q[2], q[3], q[0]).normalize());
        let r_body = r_marker * marker.r_bm.transpose();
        let ig = r_body * part.inertia * r_body.transpose();
        let vel = glam::DVec3::new(w[0], w[1], w[2]);
        let omega = glam::DVec3::new(w[3], w[4], w[5]);
        let pos = glam::DVec3::new(x[0], x[1], x[2]);
        let kinetic = 0.5 * part.mass * vel.length_squared() + 0.5 * omega.dot(ig * omega);
        (kinetic, -part.mass * m.gravity.dot(pos))
    };
    let total = |k: usize| {
        let (t, u) = energy(k);
        t + u
    };
    let e0 = total(0);
    // The energy that moves: the largest kinetic energy of the run.
    let scale = (0..reference.times.len())
        .map(|k| energy(k).0)
        .fold(0.0, f64::max);
    (0..reference.times.len()).find(|&k| (total(k) - e0).abs() > ENERGY_HORIZON * scale)
}

fn run_case(case: &str) {
    let Some(dir) = corpus_dir() else { return };
    let c = load_case(&dir, case);
    let reference: RequestFile = read_request_file(&dir.join(format!("{PREFIX}{case}_ADAMS.req")))
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(reference.times.len(), c.times.len(), "{case}: output count");
    for (t, r) in c.times.iter().zip(&reference.times) {
        assert!((t - r).abs() < 1e-9, "{case}: output time {t} vs Adams {r}");
    }
    let columns = c.requests.columns();
    let (fine, steps, rejected) = c.simulate(LINKAGE_ERROR);
    let (check, _, _) = c.simulate(CHECK_ERROR);
    let ours = |rows: &[Vec<f64>], r: &linkage_adm::Request, adams| -> Six {
        ours_for(&columns, rows, &r.header.name, adams)
    };
    // Requests with their Adams history, our two runs and their groups.
    let mut compared = Vec::new();
    let mut notes = Vec::new();
    for r in &c.ds.requests {
        let adams = reference
            .request(r.header.id)
            .unwrap_or_else(|| panic!("{case}: REQUEST/{} is not in the .req file", r.header.id));
        let (mut f, g) = (ours(&fine, r, adams), ours(&check, r, adams));
        if let Some((i, j)) = euler_parameter_markers(r) {
            let flips = align_euler_parameter_signs(&reference, (i, j), adams, &mut f);
            if flips > 0 {
                notes.push(format!(
                    "  {}: Euler parameters of opposite sign at {flips} outputs, where Adams' \
                     ψ or φ is ±180° to rounding (compared as the same orientation)",
                    r.header.name
                ));
            }
        }
        compared.push((adams, f, g, groups(&r.header.name, adams)));
    }
    // Convergence horizon: the first output where linkage's two runs differ by more than
    // HORIZON of a kinematic signal's range.
    let n = c.times.len();
    let horizon = (0..n)
        .find(|&k| {
            compared.iter().any(|(adams, f, g, groups)| {
                adams.type_code <= 2
                    && groups.iter().any(|grp| {
                        !grp.rounding()
                            && grp.relative(grp.error(&f[k], &g[k], &adams.component_names()).0)
                                > HORIZON
                    })
            })
        })
        .unwrap_or(n);
    // …and up to where Adams' own solution keeps the energy of a conservative model.
    let adams_horizon = adams_energy_horizon(&c, &reference);
    let horizon = horizon.min(adams_horizon.unwrap_or(n));
    let t_end = c.times[n - 1];
    let t_horizon = if horizon < n { c.times[horizon] } else { t_end };
    println!(
        "{case}: {n} outputs to t = {t_end}; linkage ERROR {LINKAGE_ERROR:e}: {steps} steps \
         ({rejected} rejected)"
    );
    for note in &notes {
        println!("  {note}");
    }
    if let Some(k) = adams_horizon.filter(|k| *k == horizon) {
        println!(
            "  compared up to t = {}: from there the energy of Adams' solution differs from \
             its start by more than {ENERGY_HORIZON:e} of it (the model is conservative)",
            c.times[k]
        );
    } else if horizon < n {
        println!(
            "  compared up to t = {t_horizon}: from there linkage's runs at ERROR \
             {LINKAGE_ERROR:e} and {CHECK_ERROR:e} differ by more than {HORIZON:e} of a \
             position, orientation or velocity range, so linkage's solution is not converged \
             to the comparison's resolution (nor, with a larger error, is Adams')"
        );
    }
    println!(
        "  {:<26} {:>12} {:>8} {:>8} {:>12} {:>10} {:>8}",
        "signal", "worst error", "at", "time", "Adams range", "relative", "tol"
    );
    let mut failed = Vec::new();
    for (adams, f, _, groups) in &compared {
        let labels = adams.component_names();
        for grp in groups {
            let (mut worst, mut comp, mut at) = (0.0, "", 0.0);
            for (k, (a, o)) in adams.values.iter().zip(f).enumerate().take(horizon) {
                let (e, label) = grp.error(a, o, &labels);
                if e > worst {
                    (worst, comp, at) = (e, label, c.times[k]);
                }
            }
            let ok = grp.ok(worst);
            let (range, rel, tol) = if grp.rounding() {
                ("(rounding)".to_string(), "abs".to_string(), ROUNDING)
            } else {
                (
                    format!("{:.4e}", grp.range),
                    format!("{:.2e}", grp.relative(worst)),
                    grp.tol,
                )
            };
            println!(
                "  {:<26} {:>12.4e} {:>8} {:>8.3} {:>12} {:>10} {:>8.0e}{}",
                grp.name,
                worst,
                comp,
                at,
                range,
                rel,
                tol,
                if ok { "" } else { "  MISMATCH" }
            );
            if !ok {
                failed.push(grp.name.clone());
            }
        }
    }
    let mut problems = Vec::new();
    if !failed.is_empty() {
        problems.push(format!("{} do not match Adams", failed.join(", ")));
    }
    if t_horizon < MIN_HORIZON * t_end {
        problems.push(format!(
            "linkage's solution is converged only up to t = {t_horizon}, less than {MIN_HORIZON} \
             of the run"
        ));
    }
    assert!(problems.is_empty(), "{case}: {}", problems.join("; "));
}

macro_rules! cases {
    ($($test:ident => $case:literal),* $(,)?) => {
        $(
            #[test]
            fn $test() {
                run_case($case);
            }
        )*

        /// Every case of the corpus has its test above.
        #[test]
        fn every_reference_case_has_a_test() {
            let Some(dir) = corpus_dir() else { return };
            let mut ours = vec![$($case.to_string()),*];
            ours.sort();
            assert_eq!(discovered_cases(&dir), ours);
        }
    };
}

cases! {
    distance_case01 => "Distance_Case01",
    distance_case02 => "Distance_Case02",
    revolute_case01 => "Revolute_Case01",
    revolute_case02 => "Revolute_Case02",
    spherical_case01 => "Spherical_Case01",
    trans_spring_case01 => "TransSpring_Case01",
    universal_case01 => "Universal_Case01",
    universal_case02 => "Universal_Case02",
}
