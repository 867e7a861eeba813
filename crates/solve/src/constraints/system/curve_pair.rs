//! The two rows of a CVCV ([`crate::constraints::rows::curve_curve`]) and where their contact
//! starts: at the curve points nearest to IDISP and JDISP (each in its RM frame); with one of
//! them, the other curve's point nearest to that contact point at the input; with neither, the
//! closest pair of points of the two curves at the input configuration (the first solve's
//! search).

use crate::constraints::rows::curve_curve::{CurveContact, PairContact};
use crate::constraints::rows::{BodyFrame, Quantity};
use crate::state::State;
use glam::DVec3;
use linkage_model::curves::Curve;
use linkage_model::CurveOnCurve;
use std::sync::{Arc, Mutex};

/// `(label, short label, quantity)` of the normal and binormal rows of CVCV `c` whose IRM and
/// JRM frames are `frames`, on `curves` (I, J).
pub(super) fn curve_curve_rows(
    c: &CurveOnCurve,
    frames: [BodyFrame; 2],
    curves: [Arc<Curve>; 2],
    input: &State,
) -> [(&'static str, &'static str, Quantity); 2] {
    // A point given in one side's frame, in the other side's frame at the input.
    let across = |p: DVec3, from: usize| {
        let (pf, rf) = frames[from].eval(input);
        let (pt, rt) = frames[1 - from].eval(input);
        rt.transpose() * (pf + rf * p - pt)
    };
    let params = match (c.idisp, c.jdisp) {
        (Some(i), Some(j)) => [curves[0].nearest(i, None), curves[1].nearest(j, None)],
        (Some(i), None) => {
            let a = curves[0].nearest(i, None);
            let b = curves[1].nearest(across(curves[0].eval(a)[0], 0), None);
            [a, b]
        }
        (None, Some(j)) => {
            let b = curves[1].nearest(j, None);
            let a = curves[0].nearest(across(curves[1].eval(b)[0], 1), None);
            [a, b]
        }
        (None, None) => [f64::NAN; 2],
    };
    let contact = Arc::new(Mutex::new(PairContact {
        key: [f64::NAN; 12],
        params,
    }));
    let row = |axis: usize| {
        Quantity::CurveContact(Box::new(CurveContact {
            frames,
            curves: curves.clone(),
            axis,
            contact: Arc::clone(&contact),
        }))
    };
    [
        ("Curve Gap Along Common Normal", "Nc.d", row(0)),
        ("Curve Offset Along Binormal", "Bc.d", row(1)),
    ]
}
