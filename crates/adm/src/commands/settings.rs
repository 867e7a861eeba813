//! The settings commands: INTEGRATOR, EQUILIBRIUM, IC, KINEMATICS and ACCGRAV as edits
//! (ADM-REFERENCE §7.5, §9). A field is `Some` exactly when the command gives it; values are
//! checked for shape (one number, a count, a known word), not range: whether `ERROR = 0` can be
//! used is the runner's judgement, as it is for the dataset statements of the same name.

use super::args::{Args, Sink};
use super::tables::INTEGRATOR_METHODS;
use super::typed::*;

pub(super) fn integrator(a: &Args, sink: &mut Sink) -> IntegratorEdit {
    let method = a
        .one_of(INTEGRATOR_METHODS, "integrator", sink)
        .map(|m| match m {
            "GSTIFF" => IntegratorMethod::Gstiff,
            "WSTIFF" => IntegratorMethod::Wstiff,
            "HHT" => IntegratorMethod::Hht,
            "NEWMARK" => IntegratorMethod::Newmark,
            "HASTIFF" => IntegratorMethod::Hastiff,
            "CONSTANT_BDF" => IntegratorMethod::ConstantBdf,
            "ABAM" => IntegratorMethod::Abam,
            _ => IntegratorMethod::Rkf45,
        });
    let formulation = a
        .one_of(&crate::typed::INTEGRATOR_FORMULATIONS, "formulation", sink)
        .map(|f| match f {
            "I3" => Formulation::I3,
            "SI2" => Formulation::Si2,
            _ => Formulation::Si1,
        });
    IntegratorEdit {
        method,
        formulation,
        error: a.real("ERROR", sink),
        hmax: a.real("HMAX", sink),
        hmin: a.real("HMIN", sink),
        hinit: a.real("HINIT", sink),
        alpha: a.real("ALPHA", sink),
        beta: a.real("BETA", sink),
        gamma: a.real("GAMMA", sink),
        adaptivity: a.real("ADAPTIVITY", sink),
        kmax: a.count("KMAX", sink),
        maxit: a.count("MAXIT", sink),
        corrector: a
            .choice("CORRECTOR", &["ORIGINAL", "MODIFIED"], sink)
            .map(|c| match c {
                "ORIGINAL" => Corrector::Original,
                _ => Corrector::Modified,
            }),
        interpolate: a.on_off("INTERPOLATE", sink),
        pattern: a.pattern("PATTERN", sink),
        list: a.has("LIST"),
        default: a.has("DEFAULT"),
    }
}

pub(super) fn equilibrium(a: &Args, sink: &mut Sink) -> EquilibriumEdit {
    let mode = a
        .one_of(&["STATIC", "DYNAMIC"], "solution mode", sink)
        .map(|m| match m {
            "STATIC" => EquilibriumMode::Static,
            _ => EquilibriumMode::Dynamic,
        });
    let method = a
        .choice(
            "METHOD",
            &["ORIGINAL", "ADVANCED", "AGGRESSIVE", "ALL"],
            sink,
        )
        .map(|m| match m {
            "ORIGINAL" => StaticMethod::Original,
            "ADVANCED" => StaticMethod::Advanced,
            "AGGRESSIVE" => StaticMethod::Aggressive,
            _ => StaticMethod::All,
        });
    EquilibriumEdit {
        alimit: a.real("ALIMIT", sink),
        error: a.real("ERROR", sink),
        imbalance: a.real("IMBALANCE", sink),
        maxit: a.count("MAXIT", sink),
        pattern: a.pattern("PATTERN", sink),
        stability: a.real("STABILITY", sink),
        tlimit: a.real("TLIMIT", sink),
        mode,
        global_damping: a.real("GLOBAL_DAMPING", sink),
        settling_time: a.real("SETTLING_TIME", sink),
        acceleration_error: a.real("ACCELERATION_ERROR", sink),
        kinetic_energy_error: a.real("KINETIC_ENERGY_ERROR", sink),
        method,
        atol: a.real("ATOL", sink),
        rtol: a.real("RTOL", sink),
        maxitl: a.count("MAXITL", sink),
        etamax: a.real("ETAMAX", sink),
        eta: a.real("ETA", sink),
        list: a.has("LIST"),
        default: a.has("DEFAULT"),
    }
}

pub(super) fn ic(a: &Args, sink: &mut Sink) -> IcEdit {
    IcEdit {
        error: a.real("ERROR", sink),
        maxit: a.count("MAXIT", sink),
        pattern: a.pattern("PATTERN", sink),
        tlimit: a.real("TLIMIT", sink),
        alimit: a.real("ALIMIT", sink),
        verror: a.real("VERROR", sink),
        aerror: a.real("AERROR", sink),
        amaxit: a.count("AMAXIT", sink),
        apattern: a.pattern("APATTERN", sink),
        list: a.has("LIST"),
        default: a.has("DEFAULT"),
    }
}

pub(super) fn kinematics(a: &Args, sink: &mut Sink) -> KinematicsEdit {
    KinematicsEdit {
        error: a.real("ERROR", sink),
        maxit: a.count("MAXIT", sink),
        pattern: a.pattern("PATTERN", sink),
        tlimit: a.real("TLIMIT", sink),
        alimit: a.real("ALIMIT", sink),
        aerror: a.real("AERROR", sink),
        amaxit: a.count("AMAXIT", sink),
        apattern: a.pattern("APATTERN", sink),
        list: a.has("LIST"),
        default: a.has("DEFAULT"),
    }
}

pub(super) fn accgrav(a: &Args, sink: &mut Sink) -> AccgravEdit {
    AccgravEdit {
        igrav: a.real("IGRAV", sink),
        jgrav: a.real("JGRAV", sink),
        kgrav: a.real("KGRAV", sink),
        list: a.has("LIST"),
    }
}
