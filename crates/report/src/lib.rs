//! # linkage-report — rendering analysis results
//!
//! Reports compute no physics: they turn the values returned by `linkage-solve` into human
//! text in the spirit of Adams' own output and into JSON with a stable schema.

pub mod coverage;
pub mod curve_contacts;
pub mod element_columns;
pub mod explain;
pub mod flex;
pub mod friction;
pub mod ic;
pub mod linear;
/// Numbers as every report prints them (defined beside the dataset reader, so that the
/// solver's messages use them too).
pub use linkage_adm::num;
pub mod poses;
pub mod reactions;
pub mod sensors;
pub mod simulate;
pub mod statics;
pub mod units;
pub mod verify;
pub mod verify_stream;

/// The version of the JSON reports' layout, stated in every report as `schema_version`
/// (raised when a key is removed or changes meaning; added keys keep it).
pub const JSON_SCHEMA_VERSION: u32 = 1;

/// `document` with `schema_version` (in each report when it is a list of reports).
pub fn with_schema_version(mut document: serde_json::Value) -> serde_json::Value {
    let stamp = |d: &mut serde_json::Value| {
        if let Some(map) = d.as_object_mut() {
            map.insert("schema_version".into(), JSON_SCHEMA_VERSION.into());
        }
    };
    match document.as_array_mut() {
        Some(reports) => reports.iter_mut().for_each(stamp),
        None => stamp(&mut document),
    }
    document
}
