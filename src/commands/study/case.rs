//! A case's recorded result and the hashes that identify a case and its inputs.

use super::plan::Case;
use super::{CaseKind, TaskRecord, TOOL};
use crate::problem::study::StudyFile;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use std::collections::BTreeMap;

/// Whether a case gave its result (`"ok"`/`"failed"` in `result.json` and the summaries).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum CaseStatus {
    /// The case ran to its result.
    Ok,
    /// The case failed; its error is recorded.
    Failed,
}

impl CaseStatus {
    /// The word in the summaries: `ok` or `failed`.
    pub fn word(self) -> &'static str {
        match self {
            CaseStatus::Ok => "ok",
            CaseStatus::Failed => "failed",
        }
    }
}

/// The recorded result of one case (`cases/<slug>/result.json`).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct CaseResult {
    /// The case's name in the plan: the listed case's `name`, or the sweep's `key=value`
    /// pairs joined by commas.
    pub name: String,
    /// Stable id: the folder name and a hash of the kind and resolved overrides
    /// ([`case_id`]); empty in results of older versions.
    #[serde(default)]
    pub id: String,
    /// Folder name of the case under `cases/` (its name made safe), which holds this
    /// `result.json`.
    pub slug: String,
    /// What the case ran: the region catalogue or the `[design]`.
    pub kind: CaseKind,
    /// The `key=value` overrides applied to the base problem: the study's `set`, then the
    /// case's own `set` or sweep values.
    pub overrides: Vec<String>,
    /// SHA-256 of the base problem text, the overrides and the study parameters.
    pub input_hash: String,
    /// Whether the case gave its result.
    pub status: CaseStatus,
    /// The error of a failed case.
    pub error: Option<String>,
    /// Key results (regions: count, lowest onset, band; design: status, band or intrusions).
    pub metrics: BTreeMap<String, serde_json::Value>,
    /// Wall time of the case (s).
    pub seconds: f64,
    /// The task that ran the case (host, pid, shard, Slurm ids).
    #[serde(default)]
    pub task: TaskRecord,
    /// Tool and version.
    pub tool: String,
}

/// The input hashes of one study's cases: SHA-256 of the base problem text, the case's
/// kind and overrides, the study parameters and the tool version (the base hashed once).
#[derive(Clone)]
pub(crate) struct InputHasher(Sha256);

impl InputHasher {
    pub(crate) fn new(base_text: &[u8]) -> InputHasher {
        let mut h = Sha256::new();
        h.update(base_text);
        InputHasher(h)
    }

    pub(crate) fn of(&self, case: &Case, study: &StudyFile) -> String {
        let mut h = self.0.clone();
        h.update(format!(
            "\n{:?}\n{:?}\n{:?} {:?} {:?} {:?}\n",
            case.kind, case.overrides, study.phi, study.beta_max, study.level, study.phi_op
        ));
        h.update(TOOL.as_bytes());
        format!("{:x}", h.finalize())
    }
}

/// Hex digits of the hash in a case id: 48 bits, enough to tell apart the cases that
/// share a folder name across edits of a plan.
const CASE_ID_HEX: usize = 12;

/// The stable id of a case: `FOLDER@HASH`, the case's folder name and the first
/// `CASE_ID_HEX` (12) hex digits of the SHA-256 of its kind and resolved overrides (the
/// study's `set`, then the case's). The same case gets the same id on any machine and in
/// any plan that holds it, whatever its index.
pub fn case_id(case: &Case) -> String {
    let mut h = Sha256::new();
    h.update(format!("rotorshunt case\n{:?}\n", case.kind));
    for o in &case.overrides {
        h.update(o.as_bytes());
        h.update(b"\n");
    }
    format!("{}@{}", case.slug, &format!("{:x}", h.finalize())[..CASE_ID_HEX])
}
