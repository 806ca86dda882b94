//! The design objectives, one module each, behind the [`Objective`] trait: what the
//! optimiser is asked to do (see the module docs of [`crate::design`]).
//!
//! An objective is a type holding its data (φ_op, bands, a response) that implements
//! [`Objective`]: its optimiser, candidate count, verification windows, cost, findings
//! and report lines. Its [`ObjectiveKind`] names it in the file (`design.objective`) and
//! builds it from the `[design]` keys and from the spec's JSON.
//!
//! Adding an objective is a module here and its kind in this module's list `KINDS` (one
//! file outside the module). Data of its own, which no objective has yet, goes in the
//! table `[design.objective_options]` of the problem file, which the objective reads into
//! a type of its own ([`read_options`]) and gives back as [`ObjectiveKeys::options`] (the
//! spec's JSON keeps it as `objective_options`): no other file changes. Findings of a new
//! shape need a [`crate::design::optimise::FindingsKind`].

pub mod clear_bands;
pub mod constraints;
mod contract;
pub mod min_peak;
pub mod widest_band;

pub use contract::{read_options, AnyObjective, CostAt, FileKeys, KeyRefusal, Objective, ObjectiveKeys, OPTIONS_KEY};

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

    /// The objective of this kind from a `[design]` table's keys, or the key to blame
    /// (`[design.objective_options]` given to an objective that takes none among them).
    pub fn build_from_file(self, keys: &FileKeys<'_>) -> Result<AnyObjective, KeyRefusal> {
        let objective = (self.from_file)(keys)?;
        if keys.options.is_some() && objective.keys().options.is_none() {
            let reason = format!("{} takes no options: drop the table [{OPTIONS_KEY}]", self.key);
            return Err(KeyRefusal::new(OPTIONS_KEY, &reason));
        }
        Ok(objective)
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

#[cfg(test)]
mod tests {
    //! The seam for an objective with data of its own: everything below is what such an
    //! objective's module holds (a kind, its options type, its builders, its trait impl);
    //! nothing outside the module names it except the registry `KINDS` (left out here, as
    //! the test's objective is not one of the tool's).
    use super::widest_band::WidestStableBand;
    use super::*;
    use crate::design::optimise::{Context, FindingsKind};
    use crate::design::spec::DesignSpec;
    use crate::design::{DesignError, DesignOutcome};

    /// The widest band around φ_op, no narrower than a width of its own key.
    #[derive(Debug)]
    struct FloorBand {
        band: WidestStableBand,
        options: serde_json::Value,
    }

    /// Its own keys, checked by name.
    #[derive(serde::Deserialize)]
    #[serde(deny_unknown_fields)]
    struct FloorOptions {
        /// The narrowest band accepted (rad/s).
        min_width: f64,
    }

    const KIND: ObjectiveKind = ObjectiveKind::new("floor-band", from_file, from_json);

    fn from_file(k: &FileKeys<'_>) -> Result<AnyObjective, KeyRefusal> {
        let phi_op = k.phi_op.ok_or_else(|| KeyRefusal::new("design.phi_op", "needs phi_op"))?;
        let Some(options) = read_options::<FloorOptions>(k.options)? else {
            return Err(KeyRefusal::new(OPTIONS_KEY, "needs min_width (rad/s)"));
        };
        if options.min_width.is_nan() || options.min_width <= 0.0 {
            return Err(KeyRefusal::new(&format!("{OPTIONS_KEY}.min_width"), "must be positive"));
        }
        let options = k.options.cloned().unwrap_or_default();
        Ok(AnyObjective::new(FloorBand { band: WidestStableBand { phi_op }, options }))
    }

    fn from_json(k: &ObjectiveKeys<'_>) -> Result<AnyObjective, &'static str> {
        let phi_op = k.phi_op.ok_or("phi_op")?;
        let options = k.options.ok_or("objective_options")?.clone();
        Ok(AnyObjective::new(FloorBand { band: WidestStableBand { phi_op }, options }))
    }

    impl Objective for FloorBand {
        fn kind(&self) -> ObjectiveKind {
            KIND
        }
        fn keys(&self) -> ObjectiveKeys<'_> {
            ObjectiveKeys { options: Some(&self.options), ..self.band.keys() }
        }
        fn most_candidates(&self, spec: &DesignSpec) -> usize {
            self.band.most_candidates(spec)
        }
        fn optimise(&self, ctx: &Context<'_>, out: &mut DesignOutcome) -> Result<(), DesignError> {
            self.band.optimise(ctx, out)
        }
        fn findings(&self) -> FindingsKind {
            self.band.findings()
        }
        fn question(&self, spec: &DesignSpec, variables: &str, speeds: &str, constrained: bool) -> String {
            self.band.question(spec, variables, speeds, constrained)
        }
        fn page_one(&self, s: &mut String, o: &DesignOutcome) {
            self.band.page_one(s, o)
        }
        fn optimiser_method(&self, starts: usize) -> String {
            self.band.optimiser_method(starts)
        }
        fn history_axes(&self) -> (&'static str, &'static str) {
            self.band.history_axes()
        }
    }

    fn file_keys(options: Option<&serde_json::Value>) -> FileKeys<'_> {
        FileKeys { phi_op: Some(1230.0), bands: &[], response: None, min_band_width: false, options }
    }

    #[test]
    fn an_objective_reads_its_own_keys_and_refuses_unknown_ones() {
        let given = serde_json::json!({ "min_width": 150.0 });
        let built = KIND.build_from_file(&file_keys(Some(&given))).unwrap();
        assert_eq!(built.keys().options, Some(&given));
        assert_eq!(built.phi_op(), Some(1230.0));
        // The spec's JSON gives the same keys back, and they build the same objective.
        let again = KIND.build_from_json(&built.keys()).unwrap();
        assert_eq!(again, built);
        // An unknown key is refused by name, under the table's key path.
        let typo = serde_json::json!({ "min_widht": 150.0 });
        let refusal = KIND.build_from_file(&file_keys(Some(&typo))).unwrap_err();
        assert_eq!(refusal.key, OPTIONS_KEY);
        assert!(refusal.reason.contains("min_widht"), "{}", refusal.reason);
        let zero = serde_json::json!({ "min_width": 0.0 });
        assert_eq!(
            KIND.build_from_file(&file_keys(Some(&zero))).unwrap_err().key,
            "design.objective_options.min_width"
        );
        assert_eq!(KIND.build_from_file(&file_keys(None)).unwrap_err().key, OPTIONS_KEY);
    }
}
