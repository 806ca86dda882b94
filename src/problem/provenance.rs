//! What produced an output: the tool, the problem file, its hash, the overrides and the
//! settings, recorded in every JSON output.

use super::Problem;
use serde::Serialize;

/// Tool name and version recorded in outputs.
pub const TOOL: &str = concat!("rotorshunt ", env!("CARGO_PKG_VERSION"));

/// What produced an output, recorded in every JSON file and JSON print-out: the tool
/// version, the problem file, the hash of its text and overrides, and the settings.
#[derive(Debug, Clone, Serialize)]
pub struct Provenance {
    /// Tool name and version, e.g. `rotorshunt 0.1.0`.
    pub tool: &'static str,
    /// Problem file as given.
    pub problem: String,
    /// SHA-256 of the problem text and the overrides ([`crate::problem::input_hash`]).
    pub input_sha256: String,
    /// The `--set key.path=value` overrides applied, in order.
    pub overrides: Vec<String>,
    /// Numerical settings in force.
    pub settings: crate::analysis::Settings,
    /// Plausibility warnings on the input (`crate::problem::plausibility`, and those a
    /// command finds on its ranges); absent when there are none.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<crate::problem::Warning>,
}

impl Provenance {
    /// The provenance of outputs computed from `p`, with its warnings.
    pub fn of(p: &Problem) -> Provenance {
        Provenance {
            tool: TOOL,
            problem: p.file.clone(),
            input_sha256: p.input_sha256.clone(),
            overrides: p.overrides.clone(),
            settings: p.settings.clone(),
            warnings: p.warnings.clone(),
        }
    }

    /// The provenance with further warnings (a command's, on its ranges).
    pub fn with(mut self, warnings: &[crate::problem::Warning]) -> Provenance {
        self.warnings.extend_from_slice(warnings);
        self
    }
}
