//! The verify JSON report written as it is serialised, without a value tree of the whole
//! document.
//!
//! The layout is the one every JSON report has (`serde_json::to_string_pretty` of the
//! document's value with [`crate::with_schema_version`]: keys sorted, two-space indents), byte
//! for byte. Only the long lists of a large model (the redundant equations, the near ties and
//! the misaligned joints: a chain of 10,000 loops has 30,000 of each of the first two) are
//! written one entry at a time: the redundant equations and near ties straight from the report
//! with their keys in sorted order (below), the misaligned joints each through its own small
//! value; the rest of the document is a small value tree. Memory is that of the report, where
//! the value tree of the whole document took three times the memory of the analysis.
//!
//! The keys written in sorted order here are those of [`RedundantJson`], [`DependencyJson`]
//! and [`EquationRef`]; the corpus test (`crates/cli/tests/verify_json_stream.rs`) compares
//! the result with the value tree, so a key added there and not here fails it.

use crate::verify::{DependencyJson, EquationRef, RedundantJson, VerifyJson};
use serde::ser::{Error as _, SerializeMap, SerializeSeq};
use serde::{Serialize, Serializer};
use std::io::Write;

/// One document of `linkage verify --format json`: a report, or the errors of a dataset that
/// could not be read (already a small value).
#[derive(Debug)]
pub enum VerifyDocument {
    Report(Box<StreamedVerify>),
    InputErrors(serde_json::Value),
}

/// A verify report split for streaming: the small part as a value, the long lists as they are.
#[derive(Debug)]
pub struct StreamedVerify {
    /// Every key of the document, the long lists empty.
    shell: serde_json::Map<String, serde_json::Value>,
    redundant: Vec<RedundantJson>,
    near_ties: Vec<EquationRef>,
    misaligned: Vec<crate::verify::MisalignedJson>,
}

impl StreamedVerify {
    /// Splits `report` (the long lists are moved, not copied).
    pub fn new(mut report: VerifyJson) -> Result<StreamedVerify, serde_json::Error> {
        let redundant = std::mem::take(&mut report.redundant);
        let near_ties = std::mem::take(&mut report.near_ties);
        let misaligned = std::mem::take(&mut report.misaligned);
        let shell = match crate::with_schema_version(serde_json::to_value(&report)?) {
            serde_json::Value::Object(map) => map,
            _ => return Err(serde_json::Error::custom("the report is not a JSON object")),
        };
        Ok(StreamedVerify {
            shell,
            redundant,
            near_ties,
            misaligned,
        })
    }
}

/// A list written one entry at a time, each through its own value (sorted keys).
struct EntryByEntry<'a, T>(&'a [T]);

impl<T: Serialize> Serialize for EntryByEntry<'_, T> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut seq = s.serialize_seq(Some(self.0.len()))?;
        for e in self.0 {
            let v = serde_json::to_value(e).map_err(S::Error::custom)?;
            seq.serialize_element(&v)?;
        }
        seq.end()
    }
}

/// A list of entries each written through `wrap` (sorted keys, no value).
struct Sorted<'a, T, W>(&'a [T], fn(&'a T) -> W);

impl<'a, T, W: Serialize> Serialize for Sorted<'a, T, W> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut seq = s.serialize_seq(Some(self.0.len()))?;
        for e in self.0 {
            seq.serialize_element(&(self.1)(e))?;
        }
        seq.end()
    }
}

/// An equation's keys (`element`, `equation`, `name`, `short`, `type`) after the `before` ones
/// and, where they sort, the `between` ones (after `equation` and `name`, before `short`).
fn equation_keys<M: SerializeMap>(
    map: &mut M,
    e: &EquationRef,
    between: impl FnOnce(&mut M) -> Result<(), M::Error>,
) -> Result<(), M::Error> {
    map.serialize_entry("element", &*e.element)?;
    map.serialize_entry("equation", e.equation)?;
    map.serialize_entry("name", &*e.name)?;
    between(map)?;
    map.serialize_entry("short", e.short)?;
    map.serialize_entry("type", &*e.kind)
}

struct SortedEquation<'a>(&'a EquationRef);

impl Serialize for SortedEquation<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut map = s.serialize_map(Some(5))?;
        equation_keys(&mut map, self.0, |_| Ok(()))?;
        map.end()
    }
}

struct SortedDependency<'a>(&'a DependencyJson);

impl Serialize for SortedDependency<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut map = s.serialize_map(Some(6))?;
        map.serialize_entry("coefficient", &self.0.coefficient)?;
        equation_keys(&mut map, &self.0.equation, |_| Ok(()))?;
        map.end()
    }
}

struct SortedRedundant<'a>(&'a RedundantJson);

impl Serialize for SortedRedundant<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let r = self.0;
        let mut map = s.serialize_map(Some(10))?;
        map.serialize_entry("consistent", &r.consistent)?;
        map.serialize_entry("depends_on", &Sorted(&r.depends_on, SortedDependency))?;
        equation_keys(&mut map, &r.equation, |m| {
            m.serialize_entry("near_tie", &r.near_tie)?;
            m.serialize_entry("residual", &r.residual)?;
            m.serialize_entry("residual_unit", r.residual_unit)
        })?;
        map.end()
    }
}

impl Serialize for StreamedVerify {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut map = s.serialize_map(Some(self.shell.len()))?;
        // The shell's keys are sorted (serde_json's map without `preserve_order`).
        for (k, v) in &self.shell {
            match k.as_str() {
                "redundant" => map.serialize_entry(k, &Sorted(&self.redundant, SortedRedundant))?,
                "near_ties" => map.serialize_entry(k, &Sorted(&self.near_ties, SortedEquation))?,
                "misaligned" => map.serialize_entry(k, &EntryByEntry(&self.misaligned))?,
                _ => map.serialize_entry(k, v)?,
            }
        }
        map.end()
    }
}

impl Serialize for VerifyDocument {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            VerifyDocument::Report(r) => r.serialize(s),
            VerifyDocument::InputErrors(v) => crate::with_schema_version(v.clone()).serialize(s),
        }
    }
}

/// Writes the documents as pretty JSON and a newline: the one document alone, several as a
/// list (what `linkage verify --format json` prints).
pub fn write_documents(out: impl Write, documents: &[VerifyDocument]) -> std::io::Result<()> {
    let mut out = std::io::BufWriter::new(out);
    match documents {
        [one] => serde_json::to_writer_pretty(&mut out, one)?,
        many => serde_json::to_writer_pretty(&mut out, many)?,
    }
    out.write_all(b"\n")?;
    out.flush()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn input_errors_get_the_schema_version_like_every_report() {
        let doc = VerifyDocument::InputErrors(serde_json::json!({
            "file": "x.adm", "errors": ["bad"], "warnings": []
        }));
        let mut out = Vec::new();
        write_documents(&mut out, std::slice::from_ref(&doc)).unwrap();
        let want = serde_json::to_string_pretty(&crate::with_schema_version(serde_json::json!({
            "file": "x.adm", "errors": ["bad"], "warnings": []
        })))
        .unwrap()
            + "\n";
        assert_eq!(String::from_utf8(out).unwrap(), want);
    }
}
