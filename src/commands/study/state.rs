//! Reading a study folder: `study status` (what is done, failed, missing and running,
//! and what to rerun) and `study merge` (the summary of every finished case). Neither
//! runs a case; `status` writes nothing.

use super::folder::{self, Manifest, Role, StudyLock, CASES, CASE_MANIFEST, LOCK, MANIFEST, SLURM_DIR};
use super::listing::one_line;
use super::shard;
use super::write_summary;
use super::{case_id, load_study, CaseResult, CaseStatus, InputHasher, Loaded, OutDir};
use crate::commands::out::json_pretty;
use crate::commands::Error;
use rayon::prelude::*;
use serde::Serialize;
use std::collections::HashSet;
use std::hash::{Hash, Hasher};
use std::path::Path;

/// Cases of each state that `study status` names one by one, and shards that `study
/// plan` lists; the rest are counted (`--json` lists them all).
pub(super) const LISTED_CASES: usize = 20;
/// Folders and results that a warning names one by one; the rest are counted.
const LISTED_WARNINGS: usize = 5;

/// The state of one case in a study folder.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase", tag = "state", content = "detail")]
pub enum CaseState {
    /// Finished with success, from the plan's inputs.
    Done,
    /// Finished with an error (the error).
    Failed(String),
    /// No result from the plan's inputs (none, or one of other inputs).
    Missing,
    /// A task holds its lock now (the holder, if recorded).
    Running(Option<String>),
}

/// One case that is not done, in a status report.
#[derive(Debug, Clone, Serialize)]
pub struct StatusCase {
    /// Index in the plan.
    pub index: u64,
    /// Stable id `FOLDER@HASH` of the case (`case_id`): its folder name and a hash of its
    /// kind and overrides.
    pub id: String,
    /// The case's name in the plan: the listed case's `name`, or the sweep's `key=value`
    /// pairs joined by commas.
    pub name: String,
    /// Shard index K (0-based, of the report's `shards`) the case is assigned to, as in
    /// `--shard K/N`.
    pub shard: u32,
    /// Why it is not done: failed (with its error), missing, or running (with the lock's
    /// holder); the JSON's `state` and `detail`.
    #[serde(flatten)]
    pub state: CaseState,
}

/// What `study status` finds in a study folder.
#[derive(Debug, Clone, Serialize)]
pub struct StatusReport {
    /// The study folder.
    pub dir: String,
    /// The study file (its manifest's).
    pub study: String,
    /// SHA-256 of the study file's plan as it is now.
    pub plan_sha256: String,
    /// Cases in the plan.
    pub cases: u64,
    /// Shards the counts and reruns refer to.
    pub shards: u32,
    /// Cases whose `result.json` is from the plan's current inputs and records success.
    pub done: u64,
    /// Cases whose `result.json` is from the plan's current inputs and records a failure,
    /// and that no task is running now.
    pub failed: u64,
    /// Cases without a result from the plan's inputs.
    pub missing: u64,
    /// Cases a task is running now.
    pub running: u64,
    /// The shards holding a failed or missing case, as a Slurm `--array` list (`1,3-4`).
    pub array: String,
    /// The same shards as `--shard K/N` values.
    pub rerun_shards: Vec<String>,
    /// Every case that is not done, in plan order.
    pub not_done: Vec<StatusCase>,
    /// What was ignored, and why.
    pub warnings: Vec<String>,
}

/// The plan's cases read from a study folder, for `status` and `merge`.
struct Survey {
    loaded: Loaded,
    manifest: Manifest,
    shards: u32,
    /// Per case: its state and, when finished from the plan's inputs, its result.
    states: Vec<(CaseState, Option<CaseResult>)>,
    warnings: Vec<String>,
}

fn warn_list(what: &str, items: &[String], why: &str) -> Option<String> {
    if items.is_empty() {
        return None;
    }
    let mut s = format!(
        "warning: {} {what} ({}",
        items.len(),
        items.iter().take(LISTED_WARNINGS).cloned().collect::<Vec<_>>().join(", ")
    );
    if items.len() > LISTED_WARNINGS {
        s += &format!(" and {} more", items.len() - LISTED_WARNINGS);
    }
    Some(s + "): " + why)
}

fn folder_key(name: &str) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    name.hash(&mut h);
    h.finish()
}

/// Whether the case folder's manifest records that the study wrote its `result.json`.
fn owns_result(case_dir: &Path) -> bool {
    rotorshunt::files::read_to_string(&case_dir.join(CASE_MANIFEST))
        .ok()
        .and_then(|t| Manifest::parse(&t, Role::Case).ok())
        .is_some_and(|m| m.created.contains("result.json"))
}

/// Read every case of the folder's plan. `owned_only`: a result the case manifest does not
/// record as the study's is not taken (merge).
fn survey(dir: &Path, shards: Option<u32>, owned_only: bool) -> Result<Survey, Error> {
    let not_a_study =
        |reason: String| Error::NotAStudyFolder { dir: dir.display().to_string(), manifest: MANIFEST.into(), reason };
    let manifest = match folder::read_manifest(dir) {
        Ok(Some(m)) => m,
        Ok(None) => return Err(not_a_study("no such file".into())),
        Err(e) => return Err(not_a_study(e)),
    };
    let loaded = load_study(Path::new(&manifest.study))?;
    let mut warnings: Vec<String> = manifest.ignored_warning(&dir.join(MANIFEST)).into_iter().collect();
    if manifest.plan_sha256.as_deref() != Some(&loaded.identity.plan) {
        warnings.push(format!(
            "warning: the study file {} no longer gives the folder's plan (plan {} recorded, {} now): the cases are those of the file as it is now",
            manifest.study,
            manifest.plan_sha256.as_deref().map_or("none", |h| h.get(..12).unwrap_or(h)),
            &loaded.identity.plan[..12]
        ));
    }
    let shards = match shards.or(manifest.shards) {
        Some(n) => {
            shard::check_count("--shards", n, loaded.plan.len())?;
            n
        }
        None => 1,
    };
    let plan = &loaded.plan;
    let hasher = InputHasher::new(&loaded.base_text);
    let cases = dir.join(CASES);
    let stale = std::sync::Mutex::new(Vec::new());
    let foreign = std::sync::Mutex::new(Vec::new());
    let invalid = std::sync::Mutex::new(Vec::new());
    let states: Vec<(CaseState, Option<CaseResult>)> = (0..plan.len())
        .into_par_iter()
        .map(|i| {
            let case = plan.case(i);
            let case_dir = cases.join(&case.slug);
            let result = match super::case::read_result(&case_dir, &case) {
                Some(Ok(r)) => Some(r),
                Some(Err(why)) => {
                    invalid.lock().unwrap_or_else(|e| e.into_inner()).push(format!("{CASES}/{} ({why})", case.slug));
                    None
                }
                None => None,
            };
            let state = match result {
                Some(r) if r.input_hash == hasher.of(&case, &plan.study) => {
                    if owned_only && !owns_result(&case_dir) {
                        foreign.lock().unwrap_or_else(|e| e.into_inner()).push(format!("{CASES}/{}", case.slug));
                        (CaseState::Missing, None)
                    } else if r.status == CaseStatus::Ok {
                        (CaseState::Done, Some(r))
                    } else {
                        (CaseState::Failed(r.error.clone().unwrap_or_default()), Some(r))
                    }
                }
                Some(_) => {
                    stale.lock().unwrap_or_else(|e| e.into_inner()).push(format!("{CASES}/{}", case.slug));
                    (CaseState::Missing, None)
                }
                None => (CaseState::Missing, None),
            };
            match (&state.0, folder::case_running(&case_dir)) {
                (CaseState::Done, _) | (_, None) => state,
                (_, Some(holder)) => (CaseState::Running(holder), state.1),
            }
        })
        .collect();
    // Folders of cases that are not in the plan.
    let in_plan: HashSet<u64> = (0..plan.len()).map(|i| folder_key(&plan.case(i).slug)).collect();
    let mut outside = Vec::new();
    if let Ok(entries) = std::fs::read_dir(&cases) {
        for e in entries.flatten() {
            let name = e.file_name().to_string_lossy().into_owned();
            if !in_plan.contains(&folder_key(&name)) {
                outside.push(format!("{CASES}/{name}"));
            }
        }
    }
    outside.sort();
    let mut stale = stale.into_inner().unwrap_or_else(|e| e.into_inner());
    stale.sort();
    let mut foreign = foreign.into_inner().unwrap_or_else(|e| e.into_inner());
    foreign.sort();
    let mut invalid = invalid.into_inner().unwrap_or_else(|e| e.into_inner());
    invalid.sort();
    warnings.extend(warn_list(
        "folders not in the plan",
        &outside,
        "cases of an older plan, or not the study's: ignored",
    ));
    warnings.extend(warn_list(
        "results from other inputs",
        &stale,
        "computed for an older plan (other overrides, base or study parameters): ignored, the cases count as missing",
    ));
    warnings.extend(warn_list(
        "results that are not valid records",
        &invalid,
        "read back as input and refused: not merged, the cases count as missing and the next run recomputes them",
    ));
    warnings.extend(warn_list(
        "results not written by this study",
        &foreign,
        "their case manifest does not record them: not merged, the cases count as missing",
    ));
    Ok(Survey { loaded, manifest, shards, states, warnings })
}

fn report(dir: &Path, s: &Survey) -> StatusReport {
    let plan = &s.loaded.plan;
    let shard_of = shard::assign(plan, s.shards);
    let mut r = StatusReport {
        dir: dir.display().to_string(),
        study: s.manifest.study.clone(),
        plan_sha256: s.loaded.identity.plan.clone(),
        cases: plan.len(),
        shards: s.shards,
        done: 0,
        failed: 0,
        missing: 0,
        running: 0,
        array: String::new(),
        rerun_shards: Vec::new(),
        not_done: Vec::new(),
        warnings: s.warnings.clone(),
    };
    let mut rerun = std::collections::BTreeSet::new();
    for (i, (state, _)) in s.states.iter().enumerate() {
        match state {
            CaseState::Done => {
                r.done += 1;
                continue;
            }
            CaseState::Failed(_) => r.failed += 1,
            CaseState::Missing => r.missing += 1,
            CaseState::Running(_) => r.running += 1,
        }
        if !matches!(state, CaseState::Running(_)) {
            rerun.insert(shard_of[i]);
        }
        let c = plan.case(i as u64);
        r.not_done.push(StatusCase {
            index: i as u64,
            id: case_id(&c),
            name: c.name,
            shard: shard_of[i],
            state: state.clone(),
        });
    }
    let rerun: Vec<u32> = rerun.into_iter().collect();
    r.array = shard::array_expression(&rerun);
    r.rerun_shards = rerun.iter().map(|k| format!("{k}/{}", s.shards)).collect();
    r
}

fn counts_line(r: &StatusReport) -> String {
    format!(
        "{} cases in {} shard{}: {} done, {} failed, {} missing, {} running",
        r.cases,
        r.shards,
        if r.shards == 1 { "" } else { "s" },
        r.done,
        r.failed,
        r.missing,
        r.running
    )
}

fn details(r: &StatusReport, dir: &Path) -> String {
    let mut text = String::new();
    for (word, pick) in [("failed", 0), ("missing", 1), ("running", 2)] {
        let of: Vec<&StatusCase> = r
            .not_done
            .iter()
            .filter(|c| {
                matches!(
                    (&c.state, pick),
                    (CaseState::Failed(_), 0) | (CaseState::Missing, 1) | (CaseState::Running(_), 2)
                )
            })
            .collect();
        for c in of.iter().take(LISTED_CASES) {
            let extra = match &c.state {
                CaseState::Failed(e) => format!(": {e}"),
                CaseState::Running(Some(h)) => format!(" ({h})"),
                _ => String::new(),
            };
            text += &format!("{word}: {} (case {}, shard {}){extra}\n", one_line(&c.name), c.index, c.shard);
        }
        if of.len() > LISTED_CASES {
            text += &format!("{word}: ... and {} more (--json lists every case)\n", of.len() - LISTED_CASES);
        }
    }
    if !r.array.is_empty() {
        text += &format!("rerun: --array={}\n", r.array);
        text += &format!(
            "rerun: {}\n",
            r.rerun_shards.iter().map(|s| format!("--shard {s}")).collect::<Vec<_>>().join(" ")
        );
        let script = dir.join(SLURM_DIR).join(super::slurm::ARRAY_SCRIPT);
        if script.is_file() {
            text += &format!("rerun: sbatch --array={} {}\n", r.array, script.display());
        }
    }
    for w in &r.warnings {
        text += w;
        text.push('\n');
    }
    text
}

/// `rotorshunt study status DIR [--shards N] [--json]`: the report and its text; the
/// folder is only read.
pub fn status_cmd(dir: &Path, shards: Option<u32>, json: bool) -> Result<(String, StatusReport), Error> {
    let s = survey(dir, shards, false)?;
    let r = report(dir, &s);
    let text = if json {
        json_pretty(&r, "the JSON output")? + "\n"
    } else {
        format!("study status {}: {} (study {})\n{}", dir.display(), counts_line(&r), r.study, details(&r, dir))
    };
    Ok((text, r))
}

/// `rotorshunt study merge DIR`: `summary/summary.{csv,json,md}` from every case finished from
/// the plan's inputs, in plan order, under the folder's lock (waiting for a task's
/// setup); the text and the report.
pub fn merge_cmd(dir: &Path, progress: &dyn rotorshunt::progress::Progress) -> Result<(String, StatusReport), Error> {
    let s = survey(dir, None, true)?;
    let study = Path::new(&s.manifest.study);
    let inputs: [(&Path, &str); 2] =
        [(study, "the study file"), (&s.loaded.plan.base, "the study's base problem file")];
    let root = OutDir::planned(dir, &inputs);
    let own_names: Vec<&str> = [MANIFEST, LOCK, folder::SUMMARY].into_iter().chain(folder::SUMMARY_FILES).collect();
    root.check_outputs(&own_names)?;
    let lock = StudyLock::wait(dir, &s.manifest.study)?;
    // The manifest as it is under the lock (a task may have set the folder up meanwhile).
    let manifest = match folder::read_manifest(dir) {
        Ok(Some(m)) => m,
        _ => s.manifest.clone(),
    };
    let root = root.with_ledger(folder::root_ledger(dir, manifest));
    let rows: Vec<&CaseResult> = s.states.iter().filter_map(|(_, r)| r.as_ref()).collect();
    write_summary(&root, &s.loaded.plan.columns(), &rows, progress)?;
    drop(lock);
    let r = report(dir, &s);
    let text = format!(
        "study merge {}: {}; wrote summary/summary.{{csv,json,md}} ({} cases) to {}\n{}",
        dir.display(),
        counts_line(&r),
        rows.len(),
        dir.display(),
        details(&r, dir)
    );
    Ok((text, r))
}
