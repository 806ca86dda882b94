//! The study file (`rotorshunt study STUDY.toml`): a base problem, the kind and
//! parameters of its cases, and the cases as a list and/or a cartesian sweep of
//! `--set`-style overrides (docs/studies.md). Parsed here; expanded into cases
//! by the study command's plan.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// What a case runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum CaseKind {
    /// The region catalogue (and the band around `phi_op` if given).
    Regions,
    /// The `[design]` of the case's problem.
    Design,
}

/// The study file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
#[non_exhaustive]
pub struct StudyFile {
    /// Base problem file, relative to the study file.
    pub base: String,
    /// Default kind of the cases.
    #[serde(default = "default_kind")]
    pub kind: CaseKind,
    /// φ range of regions cases (rad/s).
    #[serde(default = "default_phi")]
    pub phi: [f64; 2],
    /// β_max of regions cases.
    #[serde(default = "default_beta_max")]
    pub beta_max: f64,
    /// Level β_op of regions cases (default β_max).
    #[serde(default)]
    pub level: Option<f64>,
    /// Operating frequency of regions cases: also report its stable band (rad/s).
    #[serde(default)]
    pub phi_op: Option<f64>,
    /// Overrides for every case.
    #[serde(default)]
    pub set: Vec<String>,
    /// Listed cases.
    #[serde(default)]
    pub cases: Vec<CaseFile>,
    /// Cartesian sweep: key path → list of values.
    #[serde(default)]
    pub sweep: BTreeMap<String, Vec<toml::Value>>,
}

fn default_kind() -> CaseKind {
    CaseKind::Regions
}
fn default_phi() -> [f64; 2] {
    [crate::analysis::DEFAULT_BAND_RANGE.lo, crate::analysis::DEFAULT_BAND_RANGE.hi]
}
fn default_beta_max() -> f64 {
    1.0
}

/// One listed case of the study file (`[[cases]]`).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
#[non_exhaustive]
pub struct CaseFile {
    /// The case's name (its folder name once made safe).
    pub name: String,
    /// Its kind, if not the study's.
    #[serde(default)]
    pub kind: Option<CaseKind>,
    /// Its overrides, after the study's `set`.
    #[serde(default)]
    pub set: Vec<String>,
}
