//! What constraint and force resolution look markers up in, and the marker checks every
//! constraint shares.

use super::context::Ctx;
use super::markers::PlacedMarker;
use crate::bodies::{Body, Marker, Part};
use linkage_adm::{Header, IdRef};
use std::collections::HashMap;

/// The markers and parts as built, for resolving the references of constraints and forces.
pub(crate) struct MarkerTable<'a> {
    /// Marker id → index into `markers`.
    pub index: &'a HashMap<u64, usize>,
    pub markers: &'a [Marker],
    /// Per marker: its placement, with the carrier linkage does not model (POINT_MASS, …).
    pub placed: &'a [PlacedMarker],
    pub parts: &'a [Part],
    pub ground_name: &'a str,
}

impl MarkerTable<'_> {
    /// Display name of a body.
    pub fn body_name(&self, b: Body) -> &str {
        match b {
            Body::Ground => self.ground_name,
            Body::Part(k) => &self.parts[k].origin.name,
        }
    }

    /// The carrier linkage does not model that marker `m` is on, if any.
    pub fn unsupported(&self, m: usize) -> Option<&'static str> {
        self.placed.get(m).and_then(|p| p.unsupported)
    }

    /// A marker a constraint `elem` can use: it exists, is fixed (not FLOATING) and is on a
    /// part or ground. An error at the reference otherwise.
    pub fn constraint_marker(&self, cx: &mut Ctx, r: IdRef, elem: &str) -> Option<usize> {
        let Some(&m) = self.index.get(&r.id) else {
            cx.error(r.span, format!("{elem}: marker {} does not exist", r.id));
            return None;
        };
        if let Some(kind) = self.unsupported(m) {
            cx.error(
                r.span,
                format!(
                    "{elem}: marker {} is on a {kind}, which linkage does not model",
                    r.id
                ),
            );
            None
        } else if self.markers[m].floating {
            cx.error(
                r.span,
                format!(
                    "{elem}: marker {} is FLOATING; a constraint needs a fixed marker",
                    r.id
                ),
            );
            None
        } else {
            Some(m)
        }
    }

    /// The I and J markers of a constraint when both resolved and they are on two different
    /// bodies; an error at the statement when they share one.
    pub fn two_bodies(
        &self,
        cx: &mut Ctx,
        i: Option<usize>,
        j: Option<usize>,
        h: &Header,
    ) -> Option<(usize, usize)> {
        let (i, j) = (i?, j?);
        let body = self.markers[i].body;
        if body == self.markers[j].body {
            cx.error(
                h.span,
                format!(
                    "{}: I marker {} and J marker {} are both on {}",
                    h.name,
                    self.markers[i].id,
                    self.markers[j].id,
                    self.body_name(body)
                ),
            );
            return None;
        }
        Some((i, j))
    }

    /// The I and J markers of a two-marker constraint statement (`constraint_marker` for
    /// each, then [`MarkerTable::two_bodies`]).
    pub fn constraint_pair(
        &self,
        cx: &mut Ctx,
        i: IdRef,
        j: IdRef,
        h: &Header,
    ) -> Option<(usize, usize)> {
        let mi = self.constraint_marker(cx, i, &h.name);
        let mj = self.constraint_marker(cx, j, &h.name);
        self.two_bodies(cx, mi, mj, h)
    }
}
