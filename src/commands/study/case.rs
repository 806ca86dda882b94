//! A case's recorded result and the hashes that identify a case and its inputs.

use super::plan::Case;
use super::{CaseKind, TaskRecord, TOOL};
use rotorshunt::problem::study::StudyFile;
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
/// kind and overrides, the study parameters, the tool version and the tool's default
/// settings (the base and the defaults hashed once). The settings a case ran with are
/// its file's, its overrides' and the defaults: a result computed under other defaults (a
/// basis or criterion of an earlier version) is another case's, and is computed again.
#[derive(Clone)]
pub(crate) struct InputHasher(Sha256);

impl InputHasher {
    pub(crate) fn new(base_text: &[u8]) -> InputHasher {
        let mut h = Sha256::new();
        h.update(base_text);
        h.update(rotorshunt::problem::default_settings_text().as_bytes());
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

/// The largest `result.json` read back (bytes): a case's metrics and warnings take a few
/// kilobytes, so anything near this is not the tool's record.
const MAX_RESULT_BYTES: u64 = 1 << 24;

/// Metrics that are counts (non-negative integers).
const COUNT_METRICS: [&str; 5] =
    ["regions", "regions_in_bands_before", "regions_in_bands_after", "floquet_evaluations", "basis_modes"];
/// Metrics that are text.
const TEXT_METRICS: [&str; 2] = ["design_status", "lowest_onset_region"];
/// Metrics that are true or false.
const FLAG_METRICS: [&str; 4] = ["verified", "clipped", "clipped_after", "basis_converged"];
/// The metric that lists warnings (texts).
const WARNINGS_METRIC: &str = "warnings";

/// Why one metric value is not of the kind [`super::run_case::run_case()`] writes for its key:
/// counts, texts, flags and the warning list by name, every other key a number (or
/// null where there is none).
fn metric_fault(key: &str, v: &serde_json::Value) -> Option<&'static str> {
    let (ok, why) = if COUNT_METRICS.contains(&key) {
        (v.as_u64().is_some(), "is not a count")
    } else if TEXT_METRICS.contains(&key) {
        (v.is_string() || v.is_null(), "is not a text")
    } else if FLAG_METRICS.contains(&key) {
        (v.is_boolean(), "is not true or false")
    } else if key == WARNINGS_METRIC {
        (v.as_array().is_some_and(|a| a.iter().all(serde_json::Value::is_string)), "is not a list of texts")
    } else {
        (v.as_f64().is_some_and(f64::is_finite) || v.is_null(), "is not a finite number")
    };
    (!ok).then_some(why)
}

impl CaseResult {
    /// Check a result read back from disk as input, against the case of the plan it
    /// stands for: the same case (name, folder, kind, overrides), a status that agrees
    /// with its error, a wall time that is a finite number of seconds ≥ 0, and every
    /// metric of the kind the tool writes. The first fault found, as `field: why`.
    pub(crate) fn check(&self, case: &Case) -> Result<(), String> {
        let fault = |field: &str, why: &str| Err(format!("{field} {why}"));
        if self.name != case.name || self.slug != case.slug {
            return fault("name", "is not the case's of this folder");
        }
        if self.kind != case.kind || self.overrides != case.overrides {
            return fault("kind and overrides", "are not the case's in the plan");
        }
        if !(self.seconds.is_finite() && self.seconds >= 0.0) {
            return Err(format!("seconds = {} is not a wall time (finite, ≥ 0)", self.seconds));
        }
        match (self.status, &self.error) {
            (CaseStatus::Ok, Some(_)) => return fault("error", "is given for a case whose status is ok"),
            (CaseStatus::Failed, None) => return fault("error", "is missing for a failed case"),
            _ => {}
        }
        if let Some((k, why)) = self.metrics.iter().find_map(|(k, v)| metric_fault(k, v).map(|why| (k, why))) {
            return Err(format!("metric `{k}` {why}"));
        }
        Ok(())
    }
}

/// The `result.json` of case folder `dir`, read back as input for `case`: `None` when
/// there is none, `Err(why)` when it is not a valid result of that case (a link or
/// special file, too large, not JSON of a result, or failing [`CaseResult::check`]).
pub(crate) fn read_result(dir: &std::path::Path, case: &Case) -> Option<Result<CaseResult, String>> {
    let path = dir.join("result.json");
    let bytes = match rotorshunt::files::standing(&path) {
        Ok(rotorshunt::files::Standing::Missing) => return None,
        Ok(rotorshunt::files::Standing::File(m)) if m.len() > MAX_RESULT_BYTES => {
            return Some(Err(format!("{} bytes, more than a result holds", m.len())))
        }
        _ => match rotorshunt::files::read(&path) {
            Ok(b) => b,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return None,
            Err(e) => return Some(Err(e.to_string())),
        },
    };
    Some(
        serde_json::from_slice::<CaseResult>(&bytes)
            .map_err(|e| format!("not a result ({e})"))
            .and_then(|r| r.check(case).map(|()| r)),
    )
}
