//! Display geometry: the dataset's GRAPHICS statements attached to the model's markers.
//!
//! Contract: every drawable GRAPHICS statement ([`linkage_adm::graphics`]) becomes a
//! [`Graphic`] whose markers are indices into [`crate::Model::markers`] (so its body, and the
//! frame its dimensions are measured in, are the marker's). Dimensions stay in the dataset's
//! length unit. A GRAPHICS naming a marker the model does not have is a warning at that
//! marker's place (file:line:column) and is left out: geometry changes no result, so it never
//! stops an analysis.

use crate::bodies::Marker;
use linkage_adm::graphics::Shape;
use linkage_adm::{Dataset, Diagnostic, Span};
use std::collections::HashMap;

/// One GRAPHICS statement, resolved.
#[derive(Clone, Debug, PartialEq)]
pub struct Graphic {
    pub id: u64,
    /// Display name (`GRAPHICS_3` or its `adams_view_name`).
    pub name: String,
    pub span: Span,
    /// The shape, its markers as indices into the model's markers.
    pub shape: Shape<usize>,
}

/// The GRAPHICS of `ds` whose markers all exist in `markers` (in statement order); the typing
/// warnings and one warning per unknown marker are added to `warnings`.
pub fn resolve_graphics(
    ds: &Dataset,
    markers: &[Marker],
    warnings: &mut Vec<Diagnostic>,
) -> Vec<Graphic> {
    let (typed, typing_warnings) = linkage_adm::graphics::type_graphics(ds);
    warnings.extend(typing_warnings);
    if typed.is_empty() {
        return Vec::new();
    }
    let mut index: HashMap<u64, usize> = HashMap::with_capacity(markers.len());
    for (k, m) in markers.iter().enumerate() {
        index.entry(m.id).or_insert(k);
    }
    typed
        .iter()
        .filter_map(|g| match g.shape.try_map(|m| index.get(&m.id).copied()) {
            Ok(shape) => Some(Graphic {
                id: g.header.id,
                name: g.header.name.clone(),
                span: g.header.span,
                shape,
            }),
            Err(missing) => {
                warnings.push(Diagnostic::warning(
                    ds.file.clone(),
                    Some(missing.span),
                    format!(
                        "GRAPHICS/{} refers to MARKER/{}, which the model does not have; \
                         the graphic is not drawn",
                        g.header.id, missing.id
                    ),
                ));
                None
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use crate::bodies::Body;

    const MODEL: &str = "graphics\n\
        PART/1, GROUND\nMARKER/10, PART = 1, QP = 1, 2, 3\n\
        PART/2, MASS = 1, IP = 1, 1, 1, CM = 20\nMARKER/20, PART = 2\n\
        GRAPHICS/1, CYLINDER, CM = 20, LENGTH = 2, RADIUS = 0.5\n\
        GRAPHICS/2, BOX, CORNER = 10, X = 1, Y = 1, Z = 1\n\
        GRAPHICS/3, ELLIPSOID, CM = 99, XSCALE = 1, YSCALE = 1, ZSCALE = 1\nEND\n";

    #[test]
    fn graphics_attach_to_their_markers_and_an_unknown_marker_is_a_warning() {
        let ds = linkage_adm::parse_dataset("g.adm".into(), MODEL).expect("parses");
        let built = crate::build_model(&ds).expect("builds");
        let g = &built.model.graphics;
        assert_eq!(g.len(), 2);
        let cm = g[0].shape.markers()[0];
        assert_eq!(built.model.markers[cm].id, 20);
        assert_eq!(built.model.markers[cm].body, Body::Part(0));
        let corner = g[1].shape.markers()[0];
        assert_eq!(built.model.markers[corner].body, Body::Ground);
        let w: Vec<String> = built.warnings.iter().map(|w| w.to_string()).collect();
        let unknown = w
            .iter()
            .find(|w| w.contains("MARKER/99"))
            .unwrap_or_else(|| panic!("{w:?}"));
        // GRAPHICS/3 is on line 8; the marker id is its place.
        assert!(unknown.contains("g.adm:8:"), "{unknown}");
    }
}
