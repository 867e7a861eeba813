//! The integrator's inner loop does not allocate (DESIGN §8): once the iteration matrix's
//! pattern is known and the buffers have reached their working size, HHT steps — residuals,
//! assembly, numeric LU refactorisation, solves, state updates — run without a single heap
//! allocation. A counting global allocator (this test binary's own) checks it.

use linkage_model::settings::IntegratorMethod;
use linkage_model::Model;
use linkage_solve::constraints::drivers::ExpressionDrivers;
use linkage_solve::physics::applied::{AppliedForces, NoForces, Regime};
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::dynamics::{IntegratorSettings, StepTolerance, Stepper};
use linkage_solve::tolerances::Tolerances;
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::Arc;

/// Counts the allocations (and reallocations) of the calling thread, then defers to the
/// system allocator. Per thread, so the test harness's other threads do not interfere.
struct Counting;

thread_local! {
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

fn count() {
    // `try_with`: the slot may be gone while the thread shuts down.
    let _ = ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
}

fn allocations() -> usize {
    ALLOCATIONS.with(|c| c.get())
}

// SAFETY: every call is forwarded unchanged to `System`, which upholds the contract; the
// counter is a const-initialised thread-local `Cell` that never allocates.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        System.alloc(layout)
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        count();
        System.alloc_zeroed(layout)
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        System.realloc(ptr, layout, new_size)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn model(text: &str) -> Model {
    let ds = linkage_adm::parse_dataset(Arc::from("chain.adm"), text).expect("parses");
    linkage_model::build_model(&ds).expect("builds").model
}

/// Allocations while an integrator starts and takes its first steps, and in later steps.
struct Counted {
    start: usize,
    steady: usize,
    /// Distance the last part's centre of mass travelled.
    travelled: f64,
}

/// Starts an integrator (HHT-α, or the BDF, whose order then rises to KMAX over the warm-up)
/// and runs `warm` steps, then counts the allocations of `counted` more; the step size
/// alternates between two values more than a factor 2 apart, so that every step refactorises
/// the iteration matrix.
fn allocations_in_steady_steps(
    m: &Model,
    forces: &dyn AppliedForces,
    warm: usize,
    counted: usize,
) -> Counted {
    let hht = steady_steps(m, forces, warm, counted, IntegratorMethod::Hht);
    let bdf = steady_steps(m, forces, warm, counted, IntegratorMethod::Bdf);
    assert_eq!(bdf.steady, 0, "allocations in {counted} steady BDF steps");
    assert!(bdf.travelled > 0.0);
    hht
}

fn steady_steps(
    m: &Model,
    forces: &dyn AppliedForces,
    warm: usize,
    counted: usize,
    method: IntegratorMethod,
) -> Counted {
    let d = ExpressionDrivers::new(m).expect("no functions");
    let a = Assembled::new(m, &d, forces, &Tolerances::default());
    assert!(a.failure().is_none());
    let ic = &a.ic;
    let p = a.problem(None, None);
    let v0 = vec![(glam::DVec3::ZERO, glam::DVec3::ZERO); m.parts.len()];
    let at_start = allocations();
    let settings = IntegratorSettings {
        method,
        ..IntegratorSettings::default()
    };
    let (mut integ, first) = Stepper::new(&p, &ic.assembly.state, &v0, &settings).expect("starts");
    let last = m.parts.len() - 1;
    let mut step = |k: usize| {
        let h = [1e-3, 2.5e-3][k % 2];
        let within = StepTolerance::new(1e-3, integ.error_per_run(), h, 1.0, 1e-12);
        let err = integ.try_step(h, within).expect("the step converges");
        assert!(err.is_finite());
        integ.accept(err, 1e-3);
    };
    for k in 0..warm {
        step(k);
    }
    let before = allocations();
    for k in warm..warm + counted {
        step(k);
    }
    let steady = allocations() - before;
    Counted {
        start: before - at_start,
        steady,
        travelled: (integ.state().poses[last].p - first.state.poses[last].p).length(),
    }
}

#[test]
fn swinging_pendulum_chain_steps_without_allocating() {
    // Gravity along x: the hanging chain swings, so every value of the matrix changes.
    let text =
        linkage_solve::generate::pendulum_chain(20).replace("JGRAV = -9.80665", "IGRAV = -9.80665");
    let c = allocations_in_steady_steps(&model(&text), &NoForces, 40, 40);
    // The counter counts: setting up the workspaces allocates.
    assert!(c.start > 100, "{}", c.start);
    assert_eq!(c.steady, 0, "allocations in 40 steady steps");
    // 0.14 s of free fall from rest: the tip has moved by centimetres, not by nothing.
    assert!(
        c.travelled > 1e-2,
        "the chain did not move: {}",
        c.travelled
    );
}

#[test]
fn parallelogram_chain_with_removed_rows_steps_without_allocating() {
    let text = linkage_solve::generate::parallelogram_chain(10, 60.0);
    let c = allocations_in_steady_steps(&model(&text), &NoForces, 40, 40);
    assert!(c.start > 100, "{}", c.start);
    assert_eq!(c.steady, 0, "allocations in 40 steady steps");
    assert!(
        c.travelled > 1e-3,
        "the chain did not move: {}",
        c.travelled
    );
}

#[test]
fn spring_damper_and_bushing_forces_evaluate_without_allocating() {
    // Force elements without expressions: their generalised forces (every corrector
    // iteration) allocate nothing.
    let text = linkage_solve::generate::pendulum_chain(3).replace(
        "END",
        "SPRINGDAMPER/1, I = 102, J = 1, TRANSLATIONAL, K = 100, C = 3, LENGTH = 0.5\n\
         SPRINGDAMPER/2, I = 112, J = 101, ROTATIONAL, KT = 30, CT = 2\n\
         BUSHING/1, I = 121, J = 1, K = 10, 20, 30, C = 1, 2, 3, KT = 4, 5, 6, CT = 0.4, 0.5, 0.6\n\
         END",
    );
    let m = model(&text);
    let forces = linkage_solve::physics::forces::ForceSet::new(&m).expect("force elements build");
    assert_eq!(forces.elements().len(), 3);
    let s = linkage_solve::state::State::input(&m);
    let v: Vec<(glam::DVec3, glam::DVec3)> = (0..3)
        .map(|k| (glam::DVec3::new(0.1 * k as f64, 0.2, 0.0), glam::DVec3::Z))
        .collect();
    let mut q = vec![0.0; 18];
    let before = allocations();
    for _ in 0..10 {
        q.fill(0.0);
        forces
            .add_forces(Regime::Dynamic, &s, &v, &mut q)
            .expect("forces evaluate");
    }
    assert_eq!(allocations() - before, 0);
    // Their Jacobians (matrix refreshes) reuse the dual numbers' gradient vectors once warm.
    let (mut dq, mut dv) = (Vec::with_capacity(1000), Vec::with_capacity(1000));
    let mut jacobians = || {
        dq.clear();
        dv.clear();
        forces
            .add_jacobians(Regime::Dynamic, &s, &v, &mut dq, Some(&mut dv))
            .expect("Jacobians evaluate");
    };
    jacobians();
    let before = allocations();
    for _ in 0..10 {
        jacobians();
    }
    assert_eq!(allocations() - before, 0);
    // The elements do act: the bushing holds the last link's tip (y = −3, velocity
    // (0.2, 0.2, 0) + ẑ × (0, −0.5, 0) = (0.7, 0.2, 0)) towards ground's origin:
    // F_y = −K_y·(−3) − C_y·0.2 = 60 − 0.4 N.
    assert!((q[13] - 59.6).abs() < 1e-9, "{q:?}");
}

/// A pendulum chain of 3 with force elements whose laws are expressions: a VARIABLE (through
/// VARVAL), distance, radial velocity, angle and angular velocity measures, STEP of TIME.
fn chain_with_expression_forces() -> String {
    linkage_solve::generate::pendulum_chain(3).replace(
        "END",
        "VARIABLE/1, FUNCTION = -100*(DM(102,1) - 0.4) - 3*VR(102,1)\n\
         SFORCE/1, I = 102, J = 1, TRANSLATION, FUNCTION = VARVAL(1)\n\
         SFORCE/2, I = 112, J = 101, ROTATION\n\
         , FUNCTION = -30*(AZ(112,101) - 10D) - 2*WZ(112,101,101)*STEP(TIME, 0, 1, 1, 2)\n\
         END",
    )
}

#[test]
fn expression_forces_evaluate_without_allocating() {
    let m = model(&chain_with_expression_forces());
    let forces = linkage_solve::physics::forces::ForceSet::new(&m).expect("force elements build");
    let s = linkage_solve::state::State::input(&m);
    let v = vec![(glam::DVec3::ZERO, glam::DVec3::ZERO); 3];
    let mut q = vec![0.0; 18];
    let (mut dq, mut dv) = (Vec::with_capacity(1000), Vec::with_capacity(1000));
    let mut evaluate = |q: &mut Vec<f64>| {
        q.fill(0.0);
        forces
            .add_forces(Regime::Dynamic, &s, &v, q)
            .expect("forces evaluate");
        dq.clear();
        dv.clear();
        forces
            .add_jacobians(Regime::Dynamic, &s, &v, &mut dq, Some(&mut dv))
            .expect("Jacobians evaluate");
    };
    evaluate(&mut q);
    let before = allocations();
    for _ in 0..10 {
        evaluate(&mut q);
    }
    assert_eq!(allocations() - before, 0);
    // At rest in the input pose: link 0's centre of mass is 0.5 from ground's origin, the
    // spring's free length 0.4, so SFORCE/1 = −100·0.1 = −10 N pulls it up the line towards
    // the origin: +10 N along y. SFORCE/2 = −30·(0 − 10°) = 5.236 N·m about z on link 1,
    // its reaction on link 0 (applied at link 0's centre of mass: no moment from SFORCE/1).
    let torque = 30.0 * 10f64.to_radians();
    assert!((q[1] - 10.0).abs() < 1e-9, "{q:?}");
    assert!((q[11] - torque).abs() < 1e-9, "{q:?}");
    assert!((q[5] + torque).abs() < 1e-9, "{q:?}");
    // ∂Q_y/∂y of part 0 = −100 (the spring's stiffness along its line).
    let kyy: f64 = dq
        .iter()
        .filter(|&&(i, j, _)| i == 1 && j == 1)
        .map(|t| t.2)
        .sum();
    assert!((kyy + 100.0).abs() < 1e-9, "{kyy}");
}

#[test]
fn chain_with_expression_forces_steps_without_allocating() {
    let m = model(&chain_with_expression_forces());
    let forces = linkage_solve::physics::forces::ForceSet::new(&m).expect("force elements build");
    let c = allocations_in_steady_steps(&m, &forces, 40, 40);
    assert!(c.start > 100, "{}", c.start);
    assert_eq!(c.steady, 0, "allocations in 40 steady steps");
    assert!(
        c.travelled > 1e-3,
        "the chain did not move: {}",
        c.travelled
    );
}

/// Allocations of a static equilibrium solve of `m` limited to `maxit` Newton iterations,
/// with IMBALANCE zero so that it never converges (every iteration is taken).
fn static_solve_allocations(
    m: &Model,
    maxit: usize,
) -> (usize, linkage_solve::stages::statics::Equilibrium) {
    let d = ExpressionDrivers::new(m).expect("no functions");
    let a = Assembled::new(m, &d, &NoForces, &Tolerances::default());
    assert!(a.failure().is_none());
    let settings = linkage_model::settings::EquilibriumSettings {
        imbalance: 0.0,
        maxit,
        ..Default::default()
    };
    let before = allocations();
    let eq = linkage_solve::stages::statics::equilibrium(
        m,
        &a.system,
        &a.kept,
        &a.drivers,
        &NoForces,
        a.state(),
        &settings,
    )
    .expect("the iteration runs");
    let counted = allocations() - before;
    assert!(!eq.converged);
    assert_eq!(eq.iterations, maxit);
    (counted, eq)
}

#[test]
fn static_newton_iterations_do_not_allocate() {
    // Gravity along x: the hanging chain is 90° from its equilibrium, so the first steps are
    // cut by ALIMIT (and projected back onto the joints) before Newton converges; the matrix
    // is refreshed at every iteration (the default PATTERN).
    let text =
        linkage_solve::generate::pendulum_chain(6).replace("JGRAV = -9.80665", "IGRAV = -9.80665");
    let m = model(&text);
    let (short, _) = static_solve_allocations(&m, 4);
    let (long, eq) = static_solve_allocations(&m, 16);
    // Setting up the workspace and the result allocate; twelve more iterations do not.
    assert!(short > 10, "{short}");
    assert_eq!(long, short, "allocations in 12 more Newton iterations");
    // The iterations did work: the chain now hangs along −x (links of length 1, the tip's
    // centre of mass 5.5 from the pivot), its imbalance at rounding level.
    let tip = eq.state.poses[5].p;
    assert!((tip.x + 5.5).abs() < 1e-6 && tip.y.abs() < 1e-6, "{tip:?}");
    assert!(eq.imbalance < 1e-9, "{}", eq.imbalance);
}
