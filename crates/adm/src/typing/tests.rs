//! Unit tests of the typing layer: every typed statement, defaults, names, diagnostics.

use crate::diagnostic::{Severity, Span};
use crate::typed::*;
use crate::{parse_dataset, Diagnostics};
use std::sync::Arc;

fn read(body: &str) -> Result<Dataset, Diagnostics> {
    parse_dataset(Arc::from("t.adm"), &format!("title line\n{body}\nEND\n"))
}

fn ok(body: &str) -> Dataset {
    read(body).unwrap_or_else(|e| panic!("{e}"))
}

/// Errors as `(line, col, message)`.
fn errors(body: &str) -> Vec<(u32, u32, String)> {
    match read(body) {
        Ok(ds) => panic!("expected errors, got {ds:#?}"),
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

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-12
}

#[test]
fn title_is_line_one_verbatim() {
    let ds = parse_dataset(Arc::from("t"), "PART/1,MASS=40,CM=1;  \r\nPART/2\r\n")
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(ds.title, "PART/1,MASS=40,CM=1;");
    assert_eq!(ds.parts.len(), 1);
    let ds = parse_dataset(
        Arc::from("t"),
        "!ADAMS/View model name: FAST\nPART/1, GROUND\n",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(ds.title, "!ADAMS/View model name: FAST");
    assert_eq!(ds.end_line, None);
    let ds = parse_dataset(Arc::from("t"), "").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(ds.title, "");
}

#[test]
fn units_by_prefix_system_and_ucf() {
    let ds = ok("UNITS/\n, FORCE = POUND_F\n, MASS = pound_mass\n, LENGTH = INCH\n, TIME = SEC");
    let u = ds.units.unwrap_or_else(|| panic!("no units"));
    let name = |v: &Option<Located<String>>| v.as_ref().map(|l| l.value.clone());
    assert_eq!(name(&u.force).as_deref(), Some("POUND_FORCE"));
    assert_eq!(name(&u.mass).as_deref(), Some("POUND_MASS"));
    assert_eq!(name(&u.length).as_deref(), Some("INCH"));
    assert_eq!(name(&u.time).as_deref(), Some("SECOND"));
    assert_eq!(u.force.map(|l| l.span), Some(Span::new(3, 11)));
    assert_eq!(u.header.id, 0);
    assert_eq!(u.header.name, "UNITS");
    let u = ok("UNITS/SYSTEM = MKS, UCF = 2.5")
        .units
        .unwrap_or_else(|| panic!());
    assert_eq!(u.system.map(|s| s.value).as_deref(), Some("MKS"));
    assert_eq!(u.ucf.map(|s| s.value), Some(2.5));
}

#[test]
fn unknown_or_ambiguous_unit_is_an_error_at_the_value() {
    let e = errors("UNITS/FORCE = FURLONG");
    assert_eq!((e[0].0, e[0].1), (2, 15));
    assert!(e[0].2.starts_with("unknown value 'FURLONG' of 'FORCE'"));
    let e = errors("UNITS/FORCE = POUND");
    assert!(e[0].2.contains("POUNDAL") && e[0].2.contains("POUND_FORCE"));
}

#[test]
fn accgrav_components_default_to_zero() {
    let ds = ok("ACCGRAV/JGRAV = -9806.65");
    let g = ds.accgrav.unwrap_or_else(|| panic!());
    assert_eq!(g.gravity, [0.0, -9806.65, 0.0]);
    assert_eq!(g.header.span, Span::new(2, 1));
}

#[test]
fn part_every_field() {
    let ds = ok("!  adams_view_name='crank'\nPART/02, MASS = 1, CM = 0201, IM = 0202, IP = 0.04, 0.1, 0.1\n, QG = 1, 2, 3, REULER = 90D, 0, 0, VX = 1, WZ = 2, VM = 0201, WM = 0202, EXACT = X:PSI:THETA\nPART/01, GROUND\nPART/3, IP=1,2,3,4,5,6, XG=1,0,0, ZG=0,0,1");
    let p = &ds.parts[0];
    assert_eq!(p.header.id, 2);
    assert_eq!(p.header.name, "crank");
    assert_eq!(p.header.span, Span::new(3, 1));
    assert_eq!(p.header.statement, 0);
    assert!(!p.ground);
    assert_eq!(p.mass.as_ref().map(|m| m.value), Some(1.0));
    assert_eq!(p.cm.map(|r| (r.id, r.span)), Some((201, Span::new(3, 25))));
    assert_eq!(p.im.map(|r| r.id), Some(202));
    assert_eq!(
        p.ip.as_ref().map(|l| l.value),
        Some([0.04, 0.1, 0.1, 0.0, 0.0, 0.0])
    );
    assert_eq!(p.qg.as_ref().map(|l| l.value), Some([1.0, 2.0, 3.0]));
    assert!(p
        .reuler
        .as_ref()
        .is_some_and(|l| close(l.value[0], std::f64::consts::FRAC_PI_2)));
    assert_eq!(p.velocity, [Some(1.0), None, None, None, None, Some(2.0)]);
    assert_eq!(p.vm.map(|r| r.id), Some(201));
    assert_eq!(p.wm.map(|r| r.id), Some(202));
    assert_eq!(p.exact, [ExactCoord::X, ExactCoord::Psi, ExactCoord::Theta]);
    assert!(ds.parts[1].ground);
    assert_eq!(ds.parts[1].header.name, "PART_1", "leading zeros dropped");
    assert_eq!(
        ds.parts[2].ip.as_ref().map(|l| l.value),
        Some([1.0, 2.0, 3.0, 4.0, 5.0, 6.0])
    );
    assert_eq!(
        ds.parts[2].xg.as_ref().map(|l| l.value),
        Some([1.0, 0.0, 0.0])
    );
    assert_eq!(
        ds.parts[2].zg.as_ref().map(|l| l.value),
        Some([0.0, 0.0, 1.0])
    );
}

#[test]
fn wrong_value_count_is_an_error_at_the_argument() {
    assert_eq!(
        errors("MARKER/1, PART=1, QP = 1, 2"),
        [(
            2,
            19,
            "'QP' of MARKER/1 needs 3 values, found 2".to_string()
        )]
    );
    assert_eq!(
        errors("PART/2, IP = 1, 2, 3, 4")[0],
        (
            2,
            9,
            "'IP' of PART/2 needs 3 or 6 values, found 4".to_string()
        )
    );
    assert_eq!(errors("PART/2, MASS = 1, 2")[0].1, 9);
    assert_eq!(errors("PART/2, CM = 1.5")[0].1, 14);
    assert_eq!(errors("PART/2, CM = 90D")[0].1, 14);
    assert_eq!(errors("PART/2, EXACT = X:W")[0].1, 19);
}

#[test]
fn marker_carrier_defaults_to_last_part_point_mass_or_flex_body() {
    let ds = ok("MARKER/9\nPART/1, GROUND\nMARKER/1\nPART/2, MASS=1\nMARKER/2, QP = 0, 1, 0, ZP = 0, 0, 1, XP = 1, 0, 0, USEXP\nMARKER/3, PART = 1, FLOATING, RM = 2\nPOINT_MASS/5, MASS=1\nMARKER/4\nMARKER/5, FE_PART = 2, NODE_LABEL = 1\nFLEX_BODY/6\nMARKER/6");
    let carrier = |k: usize| {
        ds.markers[k].carrier.map(|c| match c {
            MarkerCarrier::Part(r) => ("PART", r.id),
            MarkerCarrier::PointMass(r) => ("POINT_MASS", r.id),
            MarkerCarrier::FlexBody(r) => ("FLEX_BODY", r.id),
            MarkerCarrier::FePart(r) => ("FE_PART", r.id),
        })
    };
    assert_eq!(carrier(0), None);
    assert_eq!(carrier(1), Some(("PART", 1)));
    assert_eq!(carrier(2), Some(("PART", 2)));
    assert_eq!(carrier(3), Some(("PART", 1)));
    assert_eq!(carrier(4), Some(("POINT_MASS", 5)));
    assert_eq!(carrier(5), Some(("FE_PART", 2)));
    assert_eq!(carrier(6), Some(("FLEX_BODY", 6)));
    let m = &ds.markers[2];
    assert_eq!(m.qp.as_ref().map(|l| l.value), Some([0.0, 1.0, 0.0]));
    assert_eq!(m.zp.as_ref().map(|l| l.value), Some([0.0, 0.0, 1.0]));
    assert_eq!(m.xp.as_ref().map(|l| l.value), Some([1.0, 0.0, 0.0]));
    assert!(m.usexp && !m.floating && m.reuler.is_none());
    assert!(ds.markers[3].floating);
    assert_eq!(ds.markers[3].rm.map(|r| r.id), Some(2));
}

#[test]
fn marker_with_two_carriers_is_an_error() {
    assert_eq!(
        errors("MARKER/1,FLEX_BODY=20,POINT_MASS=21,FLOATING")[0].1,
        23
    );
}

#[test]
fn joint_every_type_and_option() {
    let body = "JOINT/1, CONVEL, I=1, J=2\nJOINT/2, CYL, I=1, J=2, ICTRAN = 1, 2, ICROT = 90D\nJOINT/3, FIXED, I=1, J=2\nJOINT/4, HOOKE, I=1, J=2\nJOINT/5, PLANAR, I=1, J=2\nJOINT/6, RACKPIN, I=1, J=2, PD = 0.1\nJOINT/7, REV, I=1, J=2, IC = 0.5, 1\nJOINT/8, SCREW, I=1, J=2, PITCH = 10\nJOINT/9, SPHERICAL, I=1, J=2\nJOINT/10, TRANSLATIONAL, I=1, J=2\nJOINT/11, I=0102, J=0202, UNIVERSAL";
    let ds = ok(body);
    let kinds: Vec<JointType> = ds.joints.iter().map(|j| j.kind).collect();
    use JointType::*;
    assert_eq!(
        kinds,
        [
            Convel,
            Cylindrical,
            Fixed,
            Hooke,
            Planar,
            Rackpin,
            Revolute,
            Screw,
            Spherical,
            Translational,
            Universal
        ]
    );
    let cyl = &ds.joints[1];
    assert_eq!(
        cyl.ictran.as_ref().map(|l| l.value.clone()),
        Some(vec![1.0, 2.0])
    );
    assert!(cyl
        .icrot
        .as_ref()
        .is_some_and(|l| close(l.value[0], std::f64::consts::FRAC_PI_2)));
    assert_eq!(ds.joints[5].pd.as_ref().map(|l| l.value), Some(0.1));
    assert_eq!(
        ds.joints[6].ic.as_ref().map(|l| l.value.clone()),
        Some(vec![0.5, 1.0])
    );
    assert_eq!(ds.joints[7].pitch.as_ref().map(|l| l.value), Some(10.0));
    assert_eq!((ds.joints[10].i.id, ds.joints[10].j.id), (102, 202));
    assert_eq!(ds.joints[10].header.name, "JOINT_11");
}

#[test]
fn joint_missing_type_or_marker_is_an_error_at_the_statement() {
    assert_eq!(
        errors("JOINT/1, I=1, J=2"),
        [(2, 1, "JOINT/1 has no joint type; expected one of CONVEL, CYLINDRICAL, FIXED, HOOKE, PLANAR, RACKPIN, REVOLUTE, SCREW, SPHERICAL, TRANSLATIONAL, UNIVERSAL".to_string())]
    );
    // A word JOINT does not take is an unknown argument (Adams stops on it); the hint lists
    // what JOINT takes, the joint types among them.
    let e = errors("PART/1\nJOINT/4, HINGE, I=1, J=2");
    assert_eq!((e[0].0, e[0].1), (3, 10));
    assert_eq!(e[0].2, "unknown argument 'HINGE' of JOINT");
    assert_eq!(
        errors("JOINT/1, REVOLUTE, J=2"),
        [(2, 1, "JOINT/1 needs I = <marker id>".to_string())]
    );
    assert_eq!(errors("JOINT/1, REVOLUTE, FIXED, I=1, J=2")[0].1, 20);
}

#[test]
fn jprim_every_type() {
    let ds = ok("JPRIM/1, ATPOINT, I=1, J=2\nJPRIM/2, INLINE, I=1, J=2\nJPRIM/3, INPLANE, I=1, J=2\nJPRIM/4, ORIENT, I=1, J=2\nJPRIM/5, PARALLEL_AXES, I=1, J=2\nJPRIM/6, PERP, I=1, J=2\nJPRIM/7, PARA, I=3, J=4");
    use JprimType::*;
    let kinds: Vec<JprimType> = ds.jprims.iter().map(|j| j.kind).collect();
    assert_eq!(
        kinds,
        [
            Atpoint,
            Inline,
            Inplane,
            Orientation,
            ParallelAxes,
            Perpendicular,
            ParallelAxes
        ]
    );
    assert_eq!((ds.jprims[6].i.id, ds.jprims[6].j.id), (3, 4));
    assert_eq!(errors("JPRIM/2,I=10,J=20")[0].1, 1);
}

#[test]
fn motion_joint_and_marker_forms() {
    let ds = ok("MOTION/1, ROTATIONAL, JOINT = 1, FUNCTION = 30.0d * time\nMOTION/2, JOINT = 2, TRANSLATION, VELOCITY, FUNCTION = USER(1, 2)\\, ICDISP = 0.5, ICVEL = 1\nMOTION/3, I = 11, J = 12, B3, ACCELERATION, FUNCTION = VARVAL(3)\nMOTION/4, JOINT = 4, FUNCTION = 0");
    let m = &ds.motions[0];
    assert_eq!(
        m.target,
        MotionTarget::Joint {
            joint: IdRef {
                id: 1,
                span: Span::new(2, 31)
            },
            dof: Some(MotionDof::Rotation)
        }
    );
    assert_eq!(m.level, MotionLevel::Displacement);
    let f = m.function.as_ref().unwrap_or_else(|| panic!());
    assert_eq!(f.value.expr.text, "30.0d * time");
    assert!(!f.value.user);
    assert_eq!(f.span, Span::new(2, 45));
    let m = &ds.motions[1];
    assert!(matches!(
        m.target,
        MotionTarget::Joint {
            dof: Some(MotionDof::Translation),
            ..
        }
    ));
    assert_eq!(m.level, MotionLevel::Velocity);
    assert!(m.function.as_ref().is_some_and(|f| f.value.user));
    assert_eq!((m.icdisp, m.icvel), (Some(0.5), Some(1.0)));
    let m = &ds.motions[2];
    assert!(matches!(
        m.target,
        MotionTarget::Markers {
            i: IdRef { id: 11, .. },
            j: IdRef { id: 12, .. },
            axis: MotionAxis::B3
        }
    ));
    assert_eq!(m.level, MotionLevel::Acceleration);
    assert!(matches!(
        ds.motions[3].target,
        MotionTarget::Joint { dof: None, .. }
    ));
}

#[test]
fn motion_axis_with_expression_is_the_function() {
    let ds = ok("MOTION/1, I = 1, J = 2, Z = 0.1*TIME");
    let m = &ds.motions[0];
    assert!(matches!(
        m.target,
        MotionTarget::Markers {
            axis: MotionAxis::Z,
            ..
        }
    ));
    assert_eq!(
        m.function.as_ref().map(|f| f.value.expr.text.as_str()),
        Some("0.1*TIME")
    );
}

#[test]
fn motion_without_target_or_with_two_levels_is_an_error() {
    assert_eq!(errors("MOTION/1, FUNCTION = TIME")[0].1, 1);
    assert_eq!(errors("MOTION/1, I = 1, J = 2, FUNCTION = TIME")[0].1, 1);
    assert_eq!(
        errors("MOTION/1, JOINT = 1, VELOCITY, DISP, FUNCTION = TIME")[0].1,
        32
    );
    assert_eq!(errors("MOTION/1, JOINT = 1, X, FUNCTION = TIME")[0].1, 22);
}

#[test]
fn coupler_gear_gcon() {
    let ds = ok("COUPLER/1\n, JOINTS = 6, 8\n, TYPE = R:T\n, SCALES = 1, 18\nCOUPLER/2, JOINTS = 1, 2, 3, SCALES = 2, 3\nGEAR/1, JOINTS = 1, 2, CV = 5\nGCON/1\n, I = 0102, FUNCTION = DM(0202, 0102)-2");
    let c = &ds.couplers[0];
    assert_eq!(c.joints.iter().map(|j| j.id).collect::<Vec<_>>(), [6, 8]);
    assert_eq!(c.types, [CouplerDof::Rotation, CouplerDof::Translation]);
    assert_eq!(c.scales, [1.0, 18.0]);
    assert!(c.function.is_none());
    assert_eq!(ds.couplers[1].joints.len(), 3);
    assert!(ds.couplers[1].types.is_empty());
    assert_eq!(ds.gears[0].joints.len(), 2);
    assert_eq!(ds.gears[0].cv.map(|r| r.id), Some(5));
    let g = &ds.gcons[0];
    assert_eq!(g.i.map(|r| r.id), Some(102));
    assert_eq!(
        g.function.as_ref().map(|f| f.value.expr.text.as_str()),
        Some("DM(0202, 0102)-2")
    );
    assert_eq!(g.header.name, "GCON_1");
}

#[test]
fn coupler_and_gear_errors() {
    assert_eq!(errors("COUPLER/1, TYPE = R:R")[0].1, 1);
    assert_eq!(errors("COUPLER/1, JOINTS = 1, TYPE = R")[0].1, 12);
    assert_eq!(errors("COUPLER/1, JOINTS = 1, 2, TYPE = R")[0].1, 27);
    assert_eq!(errors("COUPLER/1, JOINTS = 1, 2, TYPE = R:Q")[0].1, 36);
    assert_eq!(errors("GEAR/1, JOINTS = 1, 2, 3")[0].1, 9);
}

#[test]
fn repeated_argument_and_statement_are_warnings() {
    let ds = ok("UNITS/FORCE=NEWTON\nUNITS/FORCE=DYNE\nPART/1, MASS=1, MASS=2");
    assert_eq!(ds.parts[0].mass.as_ref().map(|m| m.value), Some(1.0));
    assert_eq!(
        ds.units.and_then(|u| u.force).map(|f| f.value).as_deref(),
        Some("DYNE")
    );
    let spans: Vec<Option<Span>> = ds.warnings.iter().map(|w| w.span).collect();
    assert_eq!(spans, [Some(Span::new(3, 1)), Some(Span::new(4, 17))]);
    assert!(ds.warnings.iter().all(|w| w.severity == Severity::Warning));
}

#[test]
fn all_errors_are_reported_together_in_order() {
    let e = errors("PART/abc\nMARKER/1, QP = 1\nJOINT/1, I=1, J=2");
    let at: Vec<(u32, u32)> = e.iter().map(|(l, c, _)| (*l, *c)).collect();
    assert_eq!(at, [(2, 6), (3, 11), (4, 1)]);
}

#[test]
fn duplicate_ids_do_not_panic() {
    let ds = ok(
        "PART/1, GROUND\nPART/1, MASS = 1\nJOINT/1, REVOLUTE, I=1, J=2\nJOINT/1, FIXED, I=1, J=2",
    );
    assert_eq!(ds.parts.len(), 2);
    assert_eq!(ds.joints.len(), 2);
}

#[test]
fn statements_after_end_are_ignored_and_kept_generic_before() {
    let ds = ok("PART/1, GROUND\nGRAPHICS/1, CYLINDER, CM = 1\nLEONARDO/3");
    assert_eq!(ds.statements.len(), 3);
    assert_eq!(ds.end_line, Some(5));
    assert_eq!(ds.warnings.len(), 1);
    assert_eq!(
        ds.warnings[0].to_string(),
        "t.adm:4:1: warning: unknown statement 'LEONARDO' ignored"
    );
    let ds = parse_dataset(Arc::from("t"), "t\nPART/1, GROUND\nEND\nPART/x\n")
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(ds.parts.len(), 1);
}
