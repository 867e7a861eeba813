//! Unit tests of command typing: abbreviations, selections, errors with line:column.

use super::*;
use crate::diagnostic::Span;

/// Types `body` after a blank first line (so commands start on line 2).
fn typed(body: &str) -> Result<TypedCommandFile, Diagnostics> {
    parse_typed_commands(Arc::from("t.acf"), &format!("\n{body}\nSTOP\n"))
}

fn ok(body: &str) -> Vec<Command> {
    let t = typed(body).unwrap_or_else(|e| panic!("{e}"));
    t.commands.into_iter().map(|c| c.command).collect()
}

/// Errors as `(line, col, message)`.
fn errors(body: &str) -> Vec<(u32, u32, String)> {
    match typed(body) {
        Ok(t) => panic!("expected errors, got {:#?}", t.commands),
        Err(d) => {
            d.0.into_iter()
                .map(|d| {
                    let s = d.span.unwrap_or_default();
                    (s.line, s.col, d.message)
                })
                .collect()
        }
    }
}

#[test]
fn abbreviated_commands_and_arguments_resolve() {
    let cmds = ok("sim/dyn, end=10.0, dtout=5.0E-02\nequil/stab=10, err=1, imb=1, tlim=2, alim=2D, maxit=500\nint/gstiff, err=1e-4, hmax=1e-5, interp=on, corr=mod\nsim/stat");
    assert_eq!(
        cmds[0],
        Command::Simulate(Simulate {
            kind: SimulateKind::Dynamic,
            end: Some(10.0),
            duration: None,
            steps: None,
            dtout: Some(0.05),
        })
    );
    let Command::Equilibrium(e) = &cmds[1] else {
        panic!("{:?}", cmds[1])
    };
    assert_eq!(
        (e.stability, e.error, e.imbalance, e.tlimit, e.maxit),
        (Some(10.0), Some(1.0), Some(1.0), Some(2.0), Some(500))
    );
    assert!((e.alimit.unwrap() - 2f64.to_radians()).abs() < 1e-15);
    assert_eq!(e.pattern, None, "nothing that was not given");
    let Command::Integrator(i) = &cmds[2] else {
        panic!("{:?}", cmds[2])
    };
    assert_eq!(i.method, Some(IntegratorMethod::Gstiff));
    assert_eq!((i.error, i.hmax), (Some(1e-4), Some(1e-5)));
    assert_eq!(i.interpolate, Some(true));
    assert_eq!(i.corrector, Some(Corrector::Modified));
    assert!(
        matches!(&cmds[3], Command::Simulate(s) if s.kind == SimulateKind::Static && s.end.is_none())
    );
    assert_eq!(cmds[4], Command::Stop);
}

#[test]
fn deactivate_by_ids_and_range() {
    let cmds =
        ok("DEACTIVATE/JOINT, RANGE = 1301, 1321\ndeact/mot, id=4010, 3020\nACTIVATE/sforce, ID=7");
    let Command::Deactivate(d) = &cmds[0] else {
        panic!()
    };
    assert_eq!(d.element, ElementType::Joint);
    assert_eq!(d.ranges, vec![(1301, 1321)]);
    assert!(d.selects(1310) && !d.selects(1322));
    assert_eq!(
        cmds[1],
        Command::Deactivate(Activation {
            element: ElementType::Motion,
            ids: vec![4010, 3020],
            ranges: vec![],
        })
    );
    assert!(
        matches!(&cmds[2], Command::Activate(a) if a.element == ElementType::Sforce && a.ids == [7])
    );
}

#[test]
fn unknown_command_is_an_error_naming_it() {
    let e = errors("sim/stat\nFROBNICATE/1, X=2\n");
    assert_eq!(e.len(), 1, "{e:?}");
    assert_eq!((e[0].0, e[0].1), (3, 1));
    assert!(
        e[0].2.contains("unknown command 'FROBNICATE'"),
        "{}",
        e[0].2
    );
}

#[test]
fn every_error_is_reported_at_its_position() {
    let e = errors("sim/dyn, dtout=0.1\nequil/stab=1, bogus=2\nint/gstiff, hht\nDEACTIVATE/PART, ID=3\nsim/stat, err=1\nequil/err=1D");
    let at: Vec<(u32, u32)> = e.iter().map(|(l, c, _)| (*l, *c)).collect();
    assert_eq!(
        at,
        [(2, 1), (3, 15), (4, 13), (5, 12), (6, 11), (7, 11)],
        "{e:#?}"
    );
    assert!(e[0].2.contains("needs END"));
    assert!(e[1].2.contains("unknown argument 'BOGUS' of EQUILIBRIUM"));
    assert!(e[2].2.contains("more than one integrator"));
    assert!(e[3].2.contains("unknown argument 'PART' of DEACTIVATE"));
    assert!(e[4].2.contains("unknown argument 'ERR' of SIMULATE"));
    assert!(e[5].2.contains("not an angle"));
}

#[test]
fn ambiguous_abbreviations_are_errors() {
    let e = errors("sim/d, end=1\nDEACTIVATE/S, ID=1");
    assert!(
        e[0].2.contains("ambiguous argument 'D' of SIMULATE"),
        "{e:?}"
    );
    assert_eq!((e[0].0, e[0].1), (2, 5));
    assert!(
        e[1].2.contains("ambiguous argument 'S' of DEACTIVATE"),
        "{e:?}"
    );
}

#[test]
fn simulate_conflicts_and_ranges() {
    let e = errors(
        "sim/dyn, end=1, dur=2\nsim/dyn, end=1, steps=0\nsim/init, vel, end=1\nsim/stat, vel",
    );
    let msgs: Vec<&str> = e.iter().map(|(_, _, m)| m.as_str()).collect();
    assert!(msgs[0].contains("more than one end time"), "{msgs:?}");
    assert!(
        msgs[1].contains("STEPS' of SIMULATE must be at least 1"),
        "{msgs:?}"
    );
    assert!(
        msgs[2].contains("does not apply to INITIAL_CONDITIONS"),
        "{msgs:?}"
    );
    assert!(
        msgs[3].contains("applies to INITIAL_CONDITIONS only"),
        "{msgs:?}"
    );
    let cmds = ok("sim/init, vel\nsim/stat, end=1, steps=10\nsim/kin, dur=0.5, steps=5");
    assert_eq!(
        cmds[0],
        Command::Simulate(Simulate {
            kind: SimulateKind::InitialConditions(Some(IcPhase::Velocity)),
            end: None,
            duration: None,
            steps: None,
            dtout: None,
        })
    );
    assert!(matches!(&cmds[1], Command::Simulate(s) if s.steps == Some(10) && s.end == Some(1.0)));
    assert!(
        matches!(&cmds[2], Command::Simulate(s) if s.kind == SimulateKind::Kinematic && s.duration == Some(0.5))
    );
}

#[test]
fn linear_eigensol_and_statemat() {
    let cmds = ok("LINEAR/EIGENSOL, COORDS = 1, 25, NODAMPING, RM=366\nlin/state, pin=1, pout=2, form=matlab, file=Plant_A");
    assert_eq!(
        cmds[0],
        Command::Linear(Linear::Eigensol(Eigensol {
            nodamping: true,
            coordinates: Some(ModeRange { first: 1, last: 25 }),
            rm: Some(366),
            ..Eigensol::default()
        }))
    );
    let Command::Linear(Linear::Statemat(s)) = &cmds[1] else {
        panic!("{:?}", cmds[1])
    };
    assert_eq!((s.pinput, s.poutput), (Some(1), Some(2)));
    assert_eq!(s.format, Some(MatrixFormat::Matlab));
    assert_eq!(s.file, "Plant_A", "file names keep their case");
    let e = errors("LINEAR/STATEMAT, PINPUT=1\nLINEAR/EIGENSOL, FILE=x, COORDS=5,2");
    assert!(e[0].2.contains("needs FILE"), "{e:?}");
    assert!(
        e[1].2
            .contains("'FILE' is not an argument of LINEAR/EIGENSOL"),
        "{e:?}"
    );
    assert!(
        e[2].2.contains("first mode 5 is after last mode 2"),
        "{e:?}"
    );
}

#[test]
fn redefinitions_keep_the_statement_with_canonical_keys() {
    let cmds = ok("VARIABLE/9105, FUNC=STEP(TIME,15.0,0.0,30.0,2*PI)\nMOTION/3150, VEL, ICDISP = 0\nPART/3, MASS=2.5\nSENSOR/4, EVALUATE=DX(1,2)");
    let Command::Redefine(v) = &cmds[0] else {
        panic!()
    };
    assert_eq!((v.element, v.id), ("VARIABLE", 9105));
    assert!(matches!(
        v.statement.arg("FUNCTION").map(|a| a.values.as_slice()),
        Some([crate::Value::Expr(e)]) if e.text == "STEP(TIME,15.0,0.0,30.0,2*PI)"
    ));
    let Command::Redefine(m) = &cmds[1] else {
        panic!()
    };
    assert!(m.statement.arg("VELOCITY").is_some());
    assert!(m.statement.arg("ICDISP").is_some());
    assert!(matches!(&cmds[2], Command::Redefine(p) if p.element == "PART"));
    assert_eq!(cmds[3].name(), "SENSOR");
    let e = errors("MARKER/3, QPP=1,2,3");
    assert!(
        e[0].2.contains("unknown argument 'QPP' of MARKER/3"),
        "{e:?}"
    );
}

#[test]
fn accepted_options_commands_keep_their_arguments() {
    let cmds = ok("DEBUG/EPRINT\noutput/nosep, reqsave\nPREF/NTHREADS=4\nENVIRONMENT/NAME=MDI_Contact, VALUE=off\naccg/kgrav=-9.81");
    let Command::Debug(d) = &cmds[0] else {
        panic!()
    };
    assert!(d.has("EPRINT"));
    let Command::Output(o) = &cmds[1] else {
        panic!()
    };
    assert!(o.has("NOSEPARATOR") && o.has("REQSAVE"));
    let Command::Preferences(p) = &cmds[2] else {
        panic!()
    };
    assert_eq!(p.get("NTHREADS"), Some(&OptionValue::Count(4)));
    assert_eq!(
        cmds[3],
        Command::Environment(Environment {
            name: Some("MDI_Contact".into()),
            value: Some("off".into()),
            unset: false,
            list: false,
        })
    );
    assert_eq!(
        cmds[4],
        Command::Accgrav(AccgravEdit {
            kgrav: Some(-9.81),
            ..AccgravEdit::default()
        })
    );
}

#[test]
fn file_commands() {
    let cmds = ok("file/model=C:\\models\\Test, out=run1\nFILE/COMMAND=more");
    assert_eq!(
        cmds[0],
        Command::File(FileCommand {
            model: Some("C:\\models\\Test".into()),
            output_prefix: Some("run1".into()),
            command: None,
        })
    );
    assert!(matches!(&cmds[1], Command::File(f) if f.command.as_deref() == Some("more")));
    let e = errors("FILE/OUTPUT_PREFIX=x");
    assert!(e[0].2.contains("FILE needs MODEL"), "{e:?}");
}

#[test]
fn stop_is_the_last_command_and_keeps_its_line() {
    let t = typed("sim/stat").unwrap();
    let last = t.commands.last().unwrap();
    assert_eq!(last.command, Command::Stop);
    assert_eq!(last.span, Span::new(3, 1));
    assert_eq!(t.commands[0].span, Span::new(2, 1));
}

#[test]
fn repeated_argument_is_a_warning() {
    let t = typed("equil/err=1, err=2").unwrap();
    assert_eq!(t.warnings.len(), 1);
    assert!(matches!(&t.commands[0].command, Command::Equilibrium(e) if e.error == Some(1.0)));
}

#[test]
fn ic_kinematics_patterns_and_state_files() {
    let cmds = ok("IC/ERR=1E-8, PATTERN=T:F:F, ALIM=5D, APAT=F:T\nKIN/maxit=30, aerror=1e-5\nequil/dyn, global=0.5, settling=2\nSAVE/SYSTEM, FILE=MyState\nRELOAD/STATES, FILE=MyState\nint/list");
    let Command::Ic(ic) = &cmds[0] else { panic!() };
    assert_eq!(ic.error, Some(1e-8));
    assert_eq!(ic.pattern, Some(vec![true, false, false]));
    assert_eq!(ic.apattern, Some(vec![false, true]));
    assert!((ic.alimit.unwrap() - 5f64.to_radians()).abs() < 1e-15);
    assert!(
        matches!(&cmds[1], Command::Kinematics(k) if k.maxit == Some(30) && k.aerror == Some(1e-5))
    );
    assert!(matches!(&cmds[2], Command::Equilibrium(e)
        if e.mode == Some(EquilibriumMode::Dynamic) && e.global_damping == Some(0.5)
        && e.settling_time == Some(2.0)));
    assert_eq!(
        cmds[3],
        Command::Save(StateFile {
            what: SavedState::System,
            file: "MyState".into(),
            output_prefix: None,
        })
    );
    assert!(matches!(&cmds[4], Command::Reload(r) if r.what == SavedState::States));
    assert_eq!(
        cmds[5],
        Command::Integrator(IntegratorEdit {
            list: true,
            ..IntegratorEdit::default()
        })
    );
    let e = errors("KIN/VERROR=1\nIC/PATTERN=T:X\nDEACTIVATE/JOINT, ID=1, RANGE=5, 3\nDEACTIVATE/JOINT, ID=0\nequil/maxit=2.5");
    let msgs: Vec<&str> = e.iter().map(|(_, _, m)| m.as_str()).collect();
    assert!(
        msgs[0].contains("unknown argument 'VERROR' of KINEMATICS"),
        "{msgs:?}"
    );
    assert!(msgs[1].contains("list of T and F"), "{msgs:?}");
    assert!(msgs[2].contains("RANGE of DEACTIVATE is empty"), "{msgs:?}");
    assert!(msgs[3].contains("positive integers"), "{msgs:?}");
    assert!(msgs[4].contains("non-negative integer"), "{msgs:?}");
}
