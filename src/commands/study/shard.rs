//! Shards of a study: `--shard K/N` (0-based K, like `SLURM_ARRAY_TASK_ID`), the
//! deterministic cost-balanced assignment of cases to shards, and the record of the task
//! that ran a case.
//!
//! The assignment is greedy longest-processing-time on a fixed cost per case kind
//! ([`kind_cost`]): the cases in order of decreasing cost (ties in plan order), each to
//! the shard with the least cost so far (ties to the lowest shard). It depends on the plan
//! and N only, never on the machine or earlier runs, so every task of an array, `status`
//! and `merge` compute the same split.

use super::plan::Plan;
use super::CaseKind;
use crate::commands::Error;
use serde::{Deserialize, Serialize};
use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// Expected cost of a regions case, in units of [`REGIONS_COST`] (one).
pub(crate) const REGIONS_COST: u64 = 1;
/// Expected cost of a design case relative to a regions case. Measured on a 2-core task
/// (two threads, docs/cluster.md, "Measured"): the 12 regions cases of
/// `problems/studies/resistance-speed.toml` took 19.7 s (1.6 s a case), 4 design cases of
/// `problems/design-widest-band.toml` at four speeds 139.9 s (35 s a case): a ratio of 21,
/// rounded to 20, since only its order of magnitude matters for balancing.
pub(crate) const DESIGN_COST: u64 = 20;

/// The expected cost of a case of `kind` ([`REGIONS_COST`], [`DESIGN_COST`]).
pub(crate) fn kind_cost(kind: CaseKind) -> u64 {
    match kind {
        CaseKind::Regions => REGIONS_COST,
        CaseKind::Design => DESIGN_COST,
    }
}

/// Shard `index` of `count` (0-based: `0/N` … `N-1/N`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// K, from 0 to `count - 1`.
    pub index: u32,
    /// N ≥ 1.
    pub count: u32,
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

fn shard_error(source: &str, value: &str, message: impl Into<String>) -> Error {
    Error::Shard { source_name: source.into(), value: value.into(), message: message.into() }
}

/// Most shards a study may be split into: Slurm's own default `MaxArraySize` is 1001, and
/// far larger arrays are rare; the limit keeps the per-shard tables small.
pub const MAX_SHARDS: u32 = 100_000;

/// A shard count N (`--shards`, `--tasks`) from its text.
pub(crate) fn parse_count(source: &str, text: &str) -> Result<u32, Error> {
    let n: u64 = text
        .trim()
        .parse()
        .map_err(|_| shard_error(source, text, "the number of shards must be a whole number from 1"))?;
    if n == 0 {
        return Err(shard_error(source, text, "the number of shards must be at least 1"));
    }
    if n > MAX_SHARDS as u64 {
        return Err(shard_error(source, text, format!("at most {MAX_SHARDS} shards")));
    }
    Ok(n as u32)
}

/// The shard number K of `count` shards from its text (`source` names where it came from).
pub(crate) fn parse_index(source: &str, text: &str, count: u32) -> Result<u32, Error> {
    let k: u64 = text.trim().parse().map_err(|_| {
        shard_error(source, text, format!("not a shard number: shards are numbered 0 to {} (0-based)", count - 1))
    })?;
    if k >= count as u64 {
        return Err(shard_error(
            source,
            text,
            format!("shard {k} of {count} does not exist: shards are numbered 0 to {} (0-based)", count - 1),
        ));
    }
    Ok(k as u32)
}

impl Shard {
    /// `--shard K/N`.
    pub fn parse(text: &str) -> Result<Shard, Error> {
        let (k, n) = text
            .split_once('/')
            .ok_or_else(|| shard_error("--shard", text, "give K/N: shard K (0-based, 0 to N-1) of N, e.g. 0/4"))?;
        let count = parse_count("--shard", n).map_err(|e| match e {
            Error::Shard { message, .. } => shard_error("--shard", text, message),
            e => e,
        })?;
        let index = parse_index("--shard", k, count).map_err(|e| match e {
            Error::Shard { message, .. } => shard_error("--shard", text, message),
            e => e,
        })?;
        Ok(Shard { index, count })
    }

    /// Shard `SLURM_ARRAY_TASK_ID` of `count` (`value`: the variable's value).
    pub(crate) fn from_task_id(value: &str, count: u32) -> Result<Shard, Error> {
        Ok(Shard { index: parse_index("SLURM_ARRAY_TASK_ID", value, count)?, count })
    }
}

/// The refusal of shard `s` in a folder whose study is split into `recorded` shards.
pub(crate) fn count_mismatch(s: Shard, recorded: u32) -> Error {
    shard_error(
        "--shard",
        &s.to_string(),
        format!(
            "the --out folder's study is split into {recorded} shards (by `study slurm` or its first sharded run), and {} shards would assign the cases differently: give K/{recorded}",
            s.count
        ),
    )
}

/// Refuse more shards than cases (a shard would have nothing to do).
pub(crate) fn check_count(source: &str, count: u32, cases: u64) -> Result<(), Error> {
    if count as u64 > cases {
        return Err(shard_error(
            source,
            &count.to_string(),
            format!("more shards than the plan's {cases} cases: give at most {cases}"),
        ));
    }
    Ok(())
}

/// The shard (0 to `count - 1`) of every case of `plan`, by greedy longest-processing-time
/// on [`kind_cost`] (module docs). O(n log N) time, 4 bytes per case.
pub(crate) fn assign(plan: &Plan, count: u32) -> Vec<u32> {
    let n = plan.len();
    let mut shard_of = vec![0u32; n as usize];
    // Cases by decreasing cost, plan order within a cost: design, then regions.
    let mut order: Vec<(u64, u64)> = (0..n).map(|i| (kind_cost(plan.kind_of(i)), i)).collect();
    order.sort_by_key(|&(cost, i)| (Reverse(cost), i));
    let mut loads: BinaryHeap<Reverse<(u64, u32)>> = (0..count).map(|s| Reverse((0, s))).collect();
    for (cost, i) in order {
        if let Some(Reverse((load, s))) = loads.pop() {
            shard_of[i as usize] = s;
            loads.push(Reverse((load + cost, s)));
        }
    }
    shard_of
}

/// The cases of one shard, in plan order.
pub(crate) fn cases_of(plan: &Plan, shard: Shard) -> Vec<u64> {
    assign(plan, shard.count).iter().enumerate().filter(|(_, &s)| s == shard.index).map(|(i, _)| i as u64).collect()
}

/// Sorted, distinct numbers as a compact Slurm `--array` list: `3,7-9`.
pub fn array_expression(sorted: &[u32]) -> String {
    let mut parts = Vec::new();
    let mut i = 0;
    while i < sorted.len() {
        let start = sorted[i];
        let mut end = start;
        while i + 1 < sorted.len() && sorted[i + 1] == end + 1 {
            i += 1;
            end = sorted[i];
        }
        parts.push(if end == start { start.to_string() } else { format!("{start}-{end}") });
        i += 1;
    }
    parts.join(",")
}

/// Which task ran a case: recorded in its `result.json` and the summary.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct TaskRecord {
    /// The shard `K/N`, for a sharded run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shard: Option<String>,
    /// Host name of the machine that ran the case, as the operating system gives it.
    pub host: String,
    /// Operating-system process id of the `rotorshunt` process that ran the case on `host`.
    pub pid: u32,
    /// `SLURM_JOB_ID`, inside a Slurm job.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slurm_job_id: Option<String>,
    /// `SLURM_ARRAY_JOB_ID`, inside a Slurm array task.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slurm_array_job_id: Option<String>,
    /// `SLURM_ARRAY_TASK_ID`, inside a Slurm array task.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slurm_array_task_id: Option<String>,
}

impl TaskRecord {
    /// This process, running `shard` (if any).
    pub(crate) fn current(shard: Option<Shard>) -> TaskRecord {
        let var = |k: &str| std::env::var(k).ok().filter(|v| !v.is_empty());
        TaskRecord {
            shard: shard.map(|s| s.to_string()),
            host: gethostname::gethostname().to_string_lossy().into_owned(),
            pid: std::process::id(),
            slurm_job_id: var("SLURM_JOB_ID"),
            slurm_array_job_id: var("SLURM_ARRAY_JOB_ID"),
            slurm_array_task_id: var("SLURM_ARRAY_TASK_ID"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shard_texts() {
        assert_eq!(Shard::parse("0/1").unwrap(), Shard { index: 0, count: 1 });
        assert_eq!(Shard::parse("3/4").unwrap(), Shard { index: 3, count: 4 });
        for bad in ["0/0", "4/4", "5/4", "-1/4", "a/4", "1/b", "1", "1/4/5", "", "1/100001"] {
            let e = Shard::parse(bad).unwrap_err();
            assert!(matches!(e, Error::Shard { .. }), "{bad}: {e}");
            assert!(e.to_string().starts_with(&format!("--shard {bad}: ")), "{e}");
        }
        assert!(Shard::from_task_id("2", 4).is_ok());
        for bad in ["x", "", "4", "-1", "1.0"] {
            let e = Shard::from_task_id(bad, 4).unwrap_err();
            assert!(e.to_string().starts_with("SLURM_ARRAY_TASK_ID"), "{e}");
        }
    }

    #[test]
    fn compact_array_lists() {
        assert_eq!(array_expression(&[]), "");
        assert_eq!(array_expression(&[3]), "3");
        assert_eq!(array_expression(&[3, 7, 8, 9]), "3,7-9");
        assert_eq!(array_expression(&[0, 1, 2, 4, 6, 7]), "0-2,4,6-7");
    }
}
