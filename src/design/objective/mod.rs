//! The design objectives, one module each, behind the [`Objective`] trait: what the
//! optimiser is asked to do (see the module docs of [`crate::design`]).
//!
//! An objective is a type holding its data (φ_op, bands, a response) that implements
//! [`Objective`]: its optimiser, candidate count, verification windows, cost, findings
//! and report lines. Its [`ObjectiveKind`] names it in the file (`design.objective`) and
//! builds it from the `[design]` keys and from the spec's JSON.
//!
//! Adding an objective is a module here and its kind in this module's list `KINDS` (one
//! file outside the module). Data under a key no objective has yet also needs the key in
//! [`ObjectiveKeys`] and [`FileKeys`] (here), in the spec's JSON
//! ([`crate::design::spec`]) and in the file format (`problem::file`, which hands it over
//! in `problem::design_keys`); findings of a new shape need a
//! [`crate::design::optimise::FindingsKind`].

pub mod clear_bands;
pub mod constraints;
mod contract;
pub mod min_peak;
pub mod widest_band;

pub use contract::{AnyObjective, CostAt, FileKeys, KeyRefusal, Objective, ObjectiveKeys};

use serde::{Deserialize, Serialize};
use std::sync::OnceLock;

/// Every objective's kind, in the order an unknown `design.objective` lists them.
const KINDS: [ObjectiveKind; 3] = [widest_band::KIND, clear_bands::KIND, min_peak::KIND];

/// How an objective's kind builds it from a `[design]` table's keys.
type FromFile = fn(&FileKeys<'_>) -> Result<AnyObjective, KeyRefusal>;
/// How an objective's kind builds it from the spec's JSON; the error is the missing key.
type FromJson = fn(&ObjectiveKeys<'_>) -> Result<AnyObjective, &'static str>;

/// The kind of an objective, as `design.objective` names it in a problem file and
/// `objective` in the spec's JSON (a string, one of [`ObjectiveKind::all`]'s keys).
#[derive(Clone, Copy)]
pub struct ObjectiveKind {
    key: &'static str,
    from_file: FromFile,
    from_json: FromJson,
    tolerances: bool,
}

impl ObjectiveKind {
    /// The kind named `key`, built by `from_file` and `from_json`.
    pub(crate) const fn new(key: &'static str, from_file: FromFile, from_json: FromJson) -> ObjectiveKind {
        ObjectiveKind { key, from_file, from_json, tolerances: false }
    }

    /// The kind, judged at the corners of `[design.tolerances]` by its optimiser.
    pub(crate) const fn judging_tolerances(self) -> ObjectiveKind {
        ObjectiveKind { tolerances: true, ..self }
    }

    /// Its name, e.g. `widest-stable-band`.
    pub fn key(self) -> &'static str {
        self.key
    }

    /// Whether the optimiser judges the objective at the corners of `[design.tolerances]`
    /// (the file layer refuses the table for an objective that does not).
    pub fn judges_tolerances(self) -> bool {
        self.tolerances
    }

    /// Every kind there is.
    pub fn all() -> &'static [ObjectiveKind] {
        &KINDS
    }

    /// The kind named `key`, if there is one.
    pub fn named(key: &str) -> Option<ObjectiveKind> {
        KINDS.iter().copied().find(|k| k.key == key)
    }

    /// Every kind's name, in [`ObjectiveKind::all`]'s order.
    pub fn keys() -> &'static [&'static str] {
        static KEYS: OnceLock<Vec<&'static str>> = OnceLock::new();
        KEYS.get_or_init(|| KINDS.iter().map(|k| k.key).collect())
    }

    /// The objective of this kind from a `[design]` table's keys, or the key to blame.
    pub fn build_from_file(self, keys: &FileKeys<'_>) -> Result<AnyObjective, KeyRefusal> {
        (self.from_file)(keys)
    }

    /// The objective of this kind from the spec's JSON, or the name of the missing key.
    pub fn build_from_json(self, keys: &ObjectiveKeys<'_>) -> Result<AnyObjective, &'static str> {
        (self.from_json)(keys)
    }
}

impl std::fmt::Debug for ObjectiveKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.key)
    }
}

impl PartialEq for ObjectiveKind {
    fn eq(&self, other: &Self) -> bool {
        self.key == other.key
    }
}

impl Eq for ObjectiveKind {}

impl Serialize for ObjectiveKind {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.key)
    }
}

/// Read as an enum of unit variants named by the kinds' keys, as serde reads a derived
/// enum (the same errors: an unknown name lists the known ones).
impl<'de> Deserialize<'de> for ObjectiveKind {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_enum("ObjectiveKind", ObjectiveKind::keys(), KindVisitor)
    }
}

/// The visitor of [`ObjectiveKind`]'s name.
struct KindVisitor;

impl<'de> serde::de::Visitor<'de> for KindVisitor {
    type Value = ObjectiveKind;

    fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("enum ObjectiveKind")
    }

    fn visit_enum<A: serde::de::EnumAccess<'de>>(self, data: A) -> Result<ObjectiveKind, A::Error> {
        use serde::de::VariantAccess;
        let (kind, variant) = data.variant_seed(KindName)?;
        variant.unit_variant()?;
        Ok(kind)
    }
}

/// The variant name of an [`ObjectiveKind`], checked against the kinds' keys.
struct KindName;

impl<'de> serde::de::DeserializeSeed<'de> for KindName {
    type Value = ObjectiveKind;

    fn deserialize<D: serde::Deserializer<'de>>(self, deserializer: D) -> Result<ObjectiveKind, D::Error> {
        deserializer.deserialize_identifier(self)
    }
}

impl serde::de::Visitor<'_> for KindName {
    type Value = ObjectiveKind;

    fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("variant identifier")
    }

    fn visit_str<E: serde::de::Error>(self, key: &str) -> Result<ObjectiveKind, E> {
        ObjectiveKind::named(key).ok_or_else(|| E::unknown_variant(key, ObjectiveKind::keys()))
    }

    fn visit_bytes<E: serde::de::Error>(self, key: &[u8]) -> Result<ObjectiveKind, E> {
        let key = String::from_utf8_lossy(key);
        ObjectiveKind::named(&key).ok_or_else(|| E::unknown_variant(&key, ObjectiveKind::keys()))
    }
}
