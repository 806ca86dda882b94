//! The listings of a study's plan: `study plan` (the cases, their kinds and costs, and
//! how the shards split them) and `study … --dry-run` (the cases a run would do). Both
//! write nothing.

use super::folder::Identity;
use super::plan::Plan;
use super::shard::{self, kind_cost, Shard};
use super::state::LISTED_CASES;
use super::{case_id, load_study, CaseKind, InputHasher, Loaded};
use crate::commands::out::json_pretty;
use crate::commands::Error;
use serde::Serialize;
use std::path::Path;

/// A case name on one line of a listing: control characters escaped.
pub(super) fn one_line(name: &str) -> String {
    name.chars().map(|c| if c.is_control() { c.escape_default().to_string() } else { c.to_string() }).collect()
}

fn kind_word(kind: CaseKind) -> &'static str {
    match kind {
        CaseKind::Regions => "regions",
        CaseKind::Design => "design",
    }
}

/// One case of a plan listing.
#[derive(Debug, Serialize)]
struct PlanEntry {
    index: u64,
    id: String,
    kind: CaseKind,
    shard: Option<u32>,
    name: String,
    folder: String,
    overrides: Vec<String>,
    /// The input hash its finished `result.json` records as `input_hash`: a run skips the
    /// case when it finds this hash there with success (for tools that prepare or check a
    /// folder). Not the provenance's `input_sha256` of a JSON output, which hashes the
    /// problem file alone.
    input_hash: String,
}

/// A plan listing in JSON.
#[derive(Debug, Serialize)]
struct PlanListing<'a> {
    study: &'a str,
    plan_sha256: &'a str,
    cases: u64,
    shards: Option<u32>,
    cost: std::collections::BTreeMap<&'static str, u64>,
    list: Vec<PlanEntry>,
}

fn header(plan: &Plan, id: &Identity) -> String {
    let design = (0..plan.len()).filter(|&i| plan.kind_of(i) == CaseKind::Design).count() as u64;
    format!(
        "# study {}: {} cases ({} regions, {} design), plan {}\n# ids (FOLDER@HASH, the hash of the kind and resolved overrides) stay with their case on any machine and across edits of the file; indices follow the file (listed cases, then the sweep with its last key fastest), so adding a listed case or a sweep value renumbers the cases after it and moves cases between shards: an --out folder accepts shards of its own plan only\n",
        id.study,
        plan.len(),
        plan.len() - design,
        design,
        id.plan
    )
}

fn shard_lines(plan: &Plan, shard_of: &[u32], count: u32) -> String {
    let mut cost = vec![0u64; count as usize];
    let mut cases = vec![0u64; count as usize];
    for (i, &s) in shard_of.iter().enumerate() {
        cost[s as usize] += kind_cost(plan.kind_of(i as u64));
        cases[s as usize] += 1;
    }
    let mut text = format!(
        "# {count} shards, 0-based (--shard 0/{count} to {}/{count}), balanced by expected cost (regions case {}, design case {}):",
        count - 1,
        shard::REGIONS_COST,
        shard::DESIGN_COST
    );
    for s in 0..count as usize {
        if s >= LISTED_CASES {
            text += &format!(" ... ({} more)", count as usize - s);
            break;
        }
        text += &format!(" {s}: {} cases, cost {};", cases[s], cost[s]);
    }
    if text.ends_with(';') {
        text.pop();
    }
    text + "\n"
}

fn listing(plan: &Plan, shard_of: Option<&[u32]>, indices: impl Iterator<Item = u64>) -> String {
    let mut text = String::from("index\tshard\tkind\tid\tname\n");
    for i in indices {
        let c = plan.case(i);
        let shard = shard_of.map_or_else(|| "-".to_string(), |s| s[i as usize].to_string());
        text += &format!("{i}\t{shard}\t{}\t{}\t{}\n", kind_word(c.kind), case_id(&c), one_line(&c.name));
    }
    text
}

/// `rotorshunt study plan STUDY.toml [--shards N] [--json]`: every case with its index,
/// id, kind and (with `--shards`) shard.
pub fn plan_cmd(file: &Path, shards: Option<u32>, json: bool) -> Result<String, Error> {
    let Loaded { plan, identity, base_text, .. } = load_study(file)?;
    if let Some(n) = shards {
        shard::check_count("--shards", n, plan.len())?;
    }
    let shard_of = shards.map(|n| shard::assign(&plan, n));
    if json {
        let hasher = InputHasher::new(&base_text);
        let list = (0..plan.len())
            .map(|i| {
                let c = plan.case(i);
                let input_hash = hasher.of(&c, &plan.study);
                PlanEntry {
                    index: i,
                    id: case_id(&c),
                    kind: c.kind,
                    shard: shard_of.as_ref().map(|s| s[i as usize]),
                    name: c.name,
                    folder: c.slug,
                    overrides: c.overrides,
                    input_hash,
                }
            })
            .collect();
        let cost = [("regions", shard::REGIONS_COST), ("design", shard::DESIGN_COST)].into_iter().collect();
        let l =
            PlanListing { study: &identity.study, plan_sha256: &identity.plan, cases: plan.len(), shards, cost, list };
        return Ok(json_pretty(&l, "the JSON output")? + "\n");
    }
    let mut text = header(&plan, &identity);
    if let (Some(n), Some(s)) = (shards, &shard_of) {
        text += &shard_lines(&plan, s, n);
    }
    Ok(text + &listing(&plan, shard_of.as_deref(), 0..plan.len()))
}

/// The text of `study … --dry-run`: the cases the run would do.
pub(crate) fn dry_run_text(plan: &Plan, id: &Identity, shard: Option<Shard>) -> String {
    let mut text = header(plan, id);
    match shard {
        None => {
            text += &format!("# dry run: all {} cases; nothing is written\n", plan.len());
            text + &listing(plan, None, 0..plan.len())
        }
        Some(s) => {
            let shard_of = shard::assign(plan, s.count);
            let mine: Vec<u64> = (0..plan.len()).filter(|&i| shard_of[i as usize] == s.index).collect();
            text += &shard_lines(plan, &shard_of, s.count);
            text += &format!("# dry run: shard {s}, {} of the {} cases; nothing is written\n", mine.len(), plan.len());
            text + &listing(plan, Some(&shard_of), mine.into_iter())
        }
    }
}
