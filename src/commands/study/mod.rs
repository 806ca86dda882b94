//! `rotorshunt study STUDY.toml --out DIR [--force] [--allow-non-empty]`: a batch of
//! analysis or design cases built from one base problem by `--set`-style overrides (a
//! list and/or a cartesian sweep), run in parallel across cases. Each case writes its
//! files under `DIR/cases/<folder>/` and, last, `result.json` (atomically): a case whose
//! `result.json` records the same input hash and success is skipped on a re-run unless
//! `--force`. A failing case is recorded with its error and the others go on.
//!
//! The study owns only what it writes ([`folder`]): a manifest records it, a lock keeps a
//! second run out, and any other entry of `DIR` is left alone. The plan is iterated
//! lazily and bounded ([`plan`]).
//!
//! A study can be split into shards (`--shard K/N`, [`shard`]) that run at once into one
//! folder, e.g. as the tasks of a Slurm array ([`slurm`]); `study status` and `study merge`
//! read the folder at any time ([`state`]).

mod case;
mod run_case;
use run_case::{admit_case, case_budget, finished, run_case};
mod folder;
mod listing;
mod lock;
mod plan;
mod shard;
mod slurm;
mod state;

use super::design::design_report;
use super::{OutDir, TOOL};
use crate::commands::out::json_pretty;
use crate::commands::Error;
use case::InputHasher;
pub use case::{case_id, CaseResult, CaseStatus};
pub(crate) use folder::Ledger;
pub use folder::Manifest;
use folder::{CaseFolder, Identity, StudyLock, CASES, LOCK, MANIFEST, ROOT_OUTPUTS};
pub use listing::plan_cmd;
pub use plan::Case;
use plan::Plan;
use rayon::prelude::*;
use rotorshunt::analysis::regions::CatalogueRequest;
use rotorshunt::analysis::Interval;
pub use rotorshunt::problem::study::CaseKind;
use rotorshunt::problem::study::StudyFile;
use rotorshunt::problem::Problem;
use rotorshunt::progress::{Progress, Silent};
use rotorshunt::report::study::SummaryTable;
use rotorshunt::run::Budget;
use serde::Serialize;
pub use shard::{Shard, TaskRecord, MAX_SHARDS};
pub use slurm::{slurm_cmd, SlurmOptions};
pub use state::{merge_cmd, status_cmd, StatusReport};
use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;

/// Which share of the plan a run does.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum ShardRequest {
    /// The whole plan; inside a Slurm array task (`SLURM_ARRAY_TASK_ID` set), the task's
    /// shard of the count the `--out` folder records (`study slurm` writes it).
    #[default]
    Auto,
    /// `--shard K/N`.
    Shard(Shard),
    /// `--shards N`: shard `SLURM_ARRAY_TASK_ID` of N.
    Count(u32),
}

/// How `study` treats finished cases and the `--out` folder.
#[derive(Debug, Clone, Default)]
pub struct StudyOptions {
    /// Recompute cases that are already finished (`--force`).
    pub force: bool,
    /// Write into a `--out` folder that holds entries the study did not create
    /// (`--allow-non-empty`); they are never changed.
    pub allow_non_empty: bool,
    /// The share of the plan to run.
    pub shard: ShardRequest,
    /// The value of `SLURM_ARRAY_TASK_ID` in the environment, if set.
    pub array_task_id: Option<String>,
    /// Print the cases the run would do and touch nothing (`--dry-run`).
    pub dry_run: bool,
    /// The limits of each case's estimated cost (`--max-cost`); the number of cases is
    /// bounded by [`plan::MAX_STUDY_CASES`] instead.
    pub budget: Budget,
}

/// The shard a run does (`None`: the whole plan), from its request, the task id of the
/// environment and the shard count the `--out` folder records.
fn resolve_shard(options: &StudyOptions, recorded: Option<u32>, cases: u64) -> Result<Option<Shard>, Error> {
    let shard = match (options.shard, options.array_task_id.as_deref()) {
        (ShardRequest::Shard(s), _) => {
            shard::check_count("--shard", s.count, cases)?;
            Some(s)
        }
        (ShardRequest::Count(n), Some(id)) => {
            shard::check_count("--shards", n, cases)?;
            Some(Shard::from_task_id(id, n)?)
        }
        (ShardRequest::Count(n), None) => {
            return Err(Error::Shard {
                source_name: "--shards".into(),
                value: n.to_string(),
                message: "takes the shard number from SLURM_ARRAY_TASK_ID, which is not set: outside a Slurm array task give --shard K/N".into(),
            })
        }
        (ShardRequest::Auto, None) => None,
        (ShardRequest::Auto, Some(id)) => match recorded {
            Some(n) => Some(Shard::from_task_id(id, n)?),
            None => {
                return Err(Error::Shard {
                    source_name: "SLURM_ARRAY_TASK_ID".into(),
                    value: id.into(),
                    message: "this is a Slurm array task, but the --out folder records no shard count (`rotorshunt study slurm` writes it): give --shards N with N written into the job script (SLURM_ARRAY_TASK_COUNT describes a submission, not the study), or --shard K/N, or --shard 0/1 for the whole plan".into(),
                })
            }
        },
    };
    if let (Some(s), Some(n)) = (shard, recorded) {
        if s.count != n {
            return Err(shard::count_mismatch(s, n));
        }
    }
    Ok(shard)
}

/// What became of one case in a run.
enum Outcome {
    /// Run now.
    Ran(CaseResult),
    /// Finished by an earlier run (or by another task meanwhile).
    Skipped(CaseResult),
    /// Another task holds it: its name and holder.
    Busy(String, Option<String>),
    /// Run again (`--force`), but its new result could not be written: the earlier
    /// result of the same inputs, which the folder still holds, and why.
    Kept(CaseResult, String),
}

/// Everything a case needs from its study.
struct Run<'a> {
    plan: &'a Plan,
    hasher: InputHasher,
    cases_dir: std::path::PathBuf,
    study: &'a str,
    inputs: &'a [(&'a Path, &'a str)],
    force: bool,
    task: TaskRecord,
    budget: Budget,
    /// Warnings on what the case folders held (records with entries that are not plain
    /// names), in the order found.
    notes: std::sync::Mutex<Vec<String>>,
}

impl Run<'_> {
    /// Run case `index` (or take its finished result).
    fn case(&self, index: u64) -> Outcome {
        let case = self.plan.case(index);
        let hash = self.hasher.of(&case, &self.plan.study);
        let t = Instant::now();
        let row = |status: CaseStatus, error: Option<String>, metrics| CaseResult {
            name: case.name.clone(),
            id: case_id(&case),
            slug: case.slug.clone(),
            kind: case.kind,
            overrides: case.overrides.clone(),
            input_hash: hash.clone(),
            status,
            error,
            metrics,
            seconds: t.elapsed().as_secs_f64(),
            task: self.task.clone(),
            tool: TOOL.into(),
        };
        let path = self.cases_dir.join(&case.slug);
        // The case lock is held until this function returns: through the commit.
        let (dir, _lock) = match folder::open_case(&path, self.study, &case.name) {
            Ok(CaseFolder::Held(ledger, lock)) => {
                if let Some(w) = ledger.ignored_warning() {
                    self.notes.lock().unwrap_or_else(|e| e.into_inner()).push(w);
                }
                (OutDir::planned(&path, self.inputs).with_ledger(*ledger), lock)
            }
            Ok(CaseFolder::Busy(holder)) => return Outcome::Busy(case.name.clone(), holder),
            // Not this study's folder: nothing is written into it, not even the result.
            Err(e) => return Outcome::Ran(row(CaseStatus::Failed, Some(e.to_string()), BTreeMap::new())),
        };
        if !self.force {
            if let Some(r) = finished(&dir, &case, &hash) {
                return Outcome::Skipped(r);
            }
        }
        let r = match run_case(&self.plan.base, &case, &self.plan.study, &dir, &self.budget) {
            Ok(m) => row(CaseStatus::Ok, None, m),
            Err(e) => row(CaseStatus::Failed, Some(e.to_string()), BTreeMap::new()),
        };
        // A failure never replaces a finished result that another task committed meanwhile
        // (on a filesystem whose locks do not reach across nodes).
        if r.status != CaseStatus::Ok {
            if let Some(done) = finished(&dir, &case, &hash) {
                return Outcome::Skipped(done);
            }
        }
        // result.json last, renamed into place: its presence marks the case finished.
        let written =
            json_pretty(&r, "result.json").and_then(|text| dir.write("result.json", (text + "\n").as_bytes()));
        match written {
            Ok(()) => Outcome::Ran(r),
            // The earlier result of the same inputs is still what the folder holds (the
            // write is atomic): it stays what the summary and `study status` show.
            Err(e) => match finished(&dir, &case, &hash) {
                Some(done) => Outcome::Kept(done, e.to_string()),
                None => Outcome::Ran(CaseResult {
                    status: CaseStatus::Failed,
                    error: Some(format!("cannot write result.json: {e}")),
                    ..r
                }),
            },
        }
    }
}

/// The study file read: its plan, base text and identity.
pub(crate) struct Loaded {
    pub(crate) plan: Plan,
    pub(crate) base_text: Vec<u8>,
    pub(crate) identity: Identity,
    /// The base problem with the study's `set`.
    pub(crate) base: Problem,
}

/// Read and check a study file: its plan, the base with the study's overrides and each
/// sweep value on its own (before any folder is touched), and its identity.
pub(crate) fn load_study(file: &Path) -> Result<Loaded, Error> {
    let plan = Plan::read(file)?;
    let base_text = rotorshunt::problem::read_input(&plan.base)?;
    // Before the folder is touched: the base with the study's overrides, each sweep value
    // on its own, and the per-case estimate of the base's cases.
    let base_name = plan.base.display().to_string();
    let base = Problem::from_bytes(&base_text, &base_name, &plan.study.set)?;
    plan.check_sweep(file, rotorshunt::problem::input::text_of(&base_text, &base_name)?, &base_name)?;
    let identity = Identity {
        study: std::fs::canonicalize(file).unwrap_or_else(|_| file.to_path_buf()).display().to_string(),
        plan: plan.survey(file, &base_text)?,
        cases: plan.len(),
    };
    Ok(Loaded { plan, base_text, identity, base })
}

/// `rotorshunt study STUDY.toml --out DIR [--force] [--allow-non-empty] [--shard K/N |
/// --shards N] [--dry-run]`: the text for standard output and the number of failed
/// cases. A sharded run does its shard's cases only and writes no summary
/// (`study merge` does).
pub fn study_cmd(
    file: &Path,
    out: &Path,
    options: StudyOptions,
    progress: &dyn Progress,
) -> Result<(String, usize), Error> {
    let Loaded { plan, base_text, identity, base } = load_study(file)?;
    // Before the folder is touched: the per-case estimate of the base's cases.
    let budget = case_budget(&options.budget);
    for kind in plan.kinds() {
        admit_case(&base, kind, &plan.study, &budget)?;
    }
    let found = folder::read_manifest(out).ok().flatten();
    let recorded = found.as_ref().filter(|m| m.plan_sha256.as_deref() == Some(&identity.plan)).and_then(|m| m.shards);
    if options.array_task_id.is_some() && options.shard == ShardRequest::Auto && found.is_some() && recorded.is_none() {
        // An array task in a folder of another plan: that refusal, not a missing count.
        folder::inspect_as(out, &identity, true, true)?;
    }
    let shard = resolve_shard(&options, recorded, plan.len())?;
    if options.dry_run {
        return Ok((listing::dry_run_text(&plan, &identity, shard), 0));
    }
    let inputs: [(&Path, &str); 2] = [(file, "the study file"), (&plan.base, "the study's base problem file")];
    // The folder is checked before anything is created in it, and again under the lock.
    let root = OutDir::planned(out, &inputs);
    let own_names: Vec<&str> = [MANIFEST, LOCK].into_iter().chain(ROOT_OUTPUTS).chain(folder::SUMMARY_FILES).collect();
    root.check_outputs(&own_names)?;
    let sharded = shard.is_some();
    let check_shards = |m: &Manifest| match (shard, m.shards) {
        (Some(s), Some(n)) if s.count != n => Err(shard::count_mismatch(s, n)),
        _ => Ok(()),
    };
    if let Some(m) = folder::inspect_as(out, &identity, options.allow_non_empty, sharded)? {
        check_shards(&m)?;
    }
    std::fs::create_dir_all(out)
        .map_err(|e| Error::Output { path: out.display().to_string(), message: e.to_string() })?;
    // A sharded run holds the folder's lock only while it sets the folder up.
    let lock = if sharded { StudyLock::wait(out, &identity.study)? } else { StudyLock::acquire(out, &identity.study)? };
    let found = folder::inspect_as(out, &identity, options.allow_non_empty, sharded)?;
    if let Some(m) = &found {
        check_shards(m)?;
    }
    let (ledger, mut notes) = folder::open_root_with(out, &identity, found, |m| {
        if let Some(s) = shard {
            m.shards.get_or_insert(s.count);
        }
        Ok(())
    })?;
    notes.extend(lock.taken_over.clone());
    ledger.claim(CASES, &out.join(CASES))?;
    let root = root.with_ledger(ledger);
    let cases_dir = out.join(CASES);
    // A link, file or special file at `cases` is refused, never followed.
    rotorshunt::files::ensure_dir(&cases_dir).map_err(|e| Error::io(&cases_dir, &e))?;
    let lock = if sharded {
        drop(lock);
        None
    } else {
        Some(lock)
    };
    let indices: Vec<u64> = match shard {
        Some(s) => shard::cases_of(&plan, s),
        None => (0..plan.len()).collect(),
    };
    let started = Instant::now();
    progress.phase("cases", indices.len() as u64);
    let run = Run {
        plan: &plan,
        hasher: InputHasher::new(&base_text),
        cases_dir,
        study: &identity.study,
        inputs: &inputs,
        force: options.force,
        task: TaskRecord::current(shard),
        budget,
        notes: std::sync::Mutex::new(Vec::new()),
    };
    // Cases in parallel (the outermost loop), each built from its index when it runs;
    // results in case order.
    let outcomes: Vec<Outcome> = indices
        .par_iter()
        .map(|&i| {
            let r = run.case(i);
            progress.advance(1);
            r
        })
        .collect();
    let mut case_notes = std::mem::take(&mut *run.notes.lock().unwrap_or_else(|e| e.into_inner()));
    case_notes.sort();
    notes.extend(case_notes);
    let mut rows: Vec<&CaseResult> = Vec::new();
    let mut busy = Vec::new();
    let mut kept = Vec::new();
    let mut skipped = 0;
    for o in &outcomes {
        match o {
            Outcome::Ran(r) => rows.push(r),
            Outcome::Kept(r, why) => {
                rows.push(r);
                kept.push((&r.name, why));
            }
            Outcome::Skipped(r) => {
                rows.push(r);
                skipped += 1;
            }
            Outcome::Busy(name, holder) => busy.push((name, holder)),
        }
    }
    if !sharded {
        write_summary(&root, &plan.columns(), &rows, progress)?;
    }
    drop(lock);
    let failed = rows.iter().filter(|r| r.status != CaseStatus::Ok).count();
    let mut text = match shard {
        None => format!(
            "study: {} cases ({} run, {} skipped as finished, {} failed) in {:.1} s; wrote summary/summary.{{csv,json,md}} and cases/ to {}\n",
            rows.len() + busy.len(),
            rows.len() - skipped,
            skipped,
            failed,
            started.elapsed().as_secs_f64(),
            out.display()
        ),
        Some(s) => format!(
            "study: shard {s} of {} cases: {} cases ({} run, {} skipped as finished, {} running in another task, {} failed) in {:.1} s; results in {} (`rotorshunt study merge {}` writes the summary)\n",
            plan.len(),
            indices.len(),
            rows.len() - skipped,
            skipped,
            busy.len(),
            failed,
            started.elapsed().as_secs_f64(),
            out.join(CASES).display(),
            out.display()
        ),
    };
    for r in rows.iter().filter(|r| r.status != CaseStatus::Ok) {
        text += &format!("failed: {}: {}\n", r.name, r.error.clone().unwrap_or_default());
    }
    for (name, why) in &kept {
        text += &format!(
            "not saved: {name}: cannot write result.json ({why}); the earlier result of the same inputs stays, in the summary too\n"
        );
    }
    for (name, holder) in &busy {
        text += &format!(
            "running in another task ({}): {name}: left to it{}\n",
            holder.as_deref().unwrap_or("holder not recorded"),
            if sharded { "" } else { ", not in this summary" }
        );
    }
    for n in notes {
        text += &n;
        text.push('\n');
    }
    Ok((text, failed))
}

fn cell(v: Option<&serde_json::Value>) -> String {
    match v {
        None | Some(serde_json::Value::Null) => String::new(),
        Some(serde_json::Value::String(s)) => s.clone(),
        Some(x) => x.to_string(),
    }
}

/// The flags of a case's result a reader must not miss: `failed`, `infeasible`, `not
/// verified` (a design), `phi_op unstable` (no stable band around φ_op), `band clipped by the
/// window` (a band bounded by the end of the φ window, not by a tongue), `basis not
/// converged` (the reduced basis moved the answer beyond its tolerance at its largest
/// size).
fn flags(r: &CaseResult) -> Vec<&'static str> {
    let mut f = Vec::new();
    if r.status == CaseStatus::Failed {
        f.push("failed");
    }
    let m = |k: &str| r.metrics.get(k);
    if m("design_status").and_then(|v| v.as_str()) == Some("infeasible") {
        f.push("infeasible");
    } else if m("verified").and_then(|v| v.as_bool()) == Some(false) {
        f.push("not verified");
    }
    let unstable = match r.kind {
        CaseKind::Regions => m("band_width").is_some_and(|v| v.is_null()),
        CaseKind::Design => m("band_width_after").and_then(|v| v.as_f64()) == Some(0.0),
    };
    if unstable {
        f.push("phi_op unstable");
    }
    if ["clipped", "clipped_after"].iter().any(|k| m(k).and_then(|v| v.as_bool()) == Some(true)) {
        f.push("band clipped by the window");
    }
    if m("basis_converged").and_then(|v| v.as_bool()) == Some(false) {
        f.push("basis not converged");
    }
    f
}

/// A link to the case's main output file, relative to the study folder (none for a
/// failed case).
fn case_link(r: &CaseResult) -> String {
    if r.status == CaseStatus::Failed {
        return String::new();
    }
    let file = match r.kind {
        CaseKind::Regions => "regions.json",
        CaseKind::Design => "report.html",
    };
    format!("[{file}](../{CASES}/{}/{file})", r.slug)
}

/// The metrics' column order: the key figures first (lo before hi), then the rest by
/// name, then the counts of work and the warnings.
fn metric_rank(key: &str) -> (usize, &str) {
    const FIRST: [&str; 17] = [
        "design_status",
        "verified",
        "band_lo",
        "band_hi",
        "band_width",
        "clipped",
        "band_width_before",
        "band_width_after",
        "band_lo_after",
        "band_hi_after",
        "clipped_after",
        "strict_band_width_after",
        "load_margin_after",
        "phi_margin_below_after",
        "phi_margin_above_after",
        "lowest_onset",
        "lowest_onset_region",
    ];
    const LAST: [&str; 3] = ["regions", "floquet_evaluations", "warnings"];
    match (FIRST.iter().position(|k| *k == key), LAST.iter().position(|k| *k == key)) {
        (Some(i), _) => (i, ""),
        (None, Some(j)) => (FIRST.len() + 1 + j, ""),
        (None, None) => (FIRST.len(), key),
    }
}

/// The value case `r` gives the varied key `key` (its last `key=value` override), as text.
fn key_value(r: &CaseResult, key: &str) -> String {
    r.overrides
        .iter()
        .rev()
        .find_map(|o| o.split_once('=').filter(|(k, _)| k.trim() == key).map(|(_, v)| v.trim().to_string()))
        .unwrap_or_default()
}

/// The plot of the study's key figure against its first numeric varied key with at
/// least two values: one line per combination of the other keys' values. None when the
/// study has no such key or figure.
fn sweep_figure(columns: &[String], rows: &[&CaseResult]) -> Option<rotorshunt::report::plot::CurvePlot> {
    let ok: Vec<&&CaseResult> = rows.iter().filter(|r| r.status == CaseStatus::Ok).collect();
    let x = columns.iter().position(|k| {
        let values: Vec<Option<f64>> = ok.iter().map(|r| key_value(r, k).parse::<f64>().ok()).collect();
        let mut distinct: Vec<f64> = values.iter().flatten().copied().collect();
        distinct.sort_by(f64::total_cmp);
        distinct.dedup();
        values.iter().all(Option::is_some) && distinct.len() >= 2
    })?;
    let y = rotorshunt::report::study::PLOTTED_FIGURES
        .into_iter()
        .find(|f| ok.iter().any(|r| r.metrics.get(*f).and_then(|v| v.as_f64()).is_some()))?;
    let mut series: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    for r in &ok {
        let name: Vec<String> = columns
            .iter()
            .enumerate()
            .filter(|(i, _)| *i != x)
            .map(|(_, k)| format!("{k} = {}", key_value(r, k)))
            .collect();
        let name = name.join(", ");
        // A band width is 0 where φ_op is unstable (no band), as a design's is.
        let value = match r.metrics.get(y) {
            Some(serde_json::Value::Null) if y.contains("band_width") => Some(0.0),
            v => v.and_then(|v| v.as_f64()),
        };
        let (Ok(px), Some(py)) = (key_value(r, &columns[x]).parse::<f64>(), value) else {
            continue;
        };
        match series.iter_mut().find(|s| s.0 == name) {
            Some(s) => s.1.push((px, py)),
            None => series.push((name, vec![(px, py)])),
        }
    }
    for s in &mut series {
        s.1.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    let title = format!("Study: {y} against {}", columns[x]);
    let y_label =
        if y.contains("band_width") { format!("{y} (rad/s; 0: phi_op unstable)") } else { format!("{y} (−)") };
    Some(rotorshunt::report::study::sweep_plot(&title, &columns[x], &y_label, series))
}

/// `summary/` of the study folder `root`, swapped whole: `summary.json`, `summary.csv` and
/// `summary.md`, one row per case with the values of the keys its cases vary (`columns`,
/// [`plan::Plan::columns`]), its status, flags and key figures (and, in Markdown, a link to
/// its output), and `figure.{svg,png}`, the key figure against a swept key, when there is
/// one ([`sweep_figure`]).
pub(crate) fn write_summary(
    root: &OutDir,
    columns: &[String],
    rows: &[&CaseResult],
    progress: &dyn Progress,
) -> Result<(), Error> {
    let dir = root.sub(folder::SUMMARY)?;
    let mut keys: Vec<String> = rows
        .iter()
        .flat_map(|r| r.metrics.keys().cloned())
        .collect::<std::collections::BTreeSet<String>>()
        .into_iter()
        .collect();
    keys.sort_by(|a, b| metric_rank(a).cmp(&metric_rank(b)));
    #[derive(Serialize)]
    struct Summary<'a> {
        tool: &'static str,
        cases: &'a [&'a CaseResult],
    }
    let json = json_pretty(&Summary { tool: TOOL, cases: rows }, "the JSON output")? + "\n";
    dir.write("summary.json", json.as_bytes())?;
    let mut header = vec!["case".to_string()];
    header.extend(columns.iter().cloned());
    header.extend(["kind".to_string(), "status".into(), "flags".into()]);
    header.extend(keys.iter().cloned());
    header.extend(["seconds".to_string(), "error".into()]);
    let cells = rows
        .iter()
        .map(|r| {
            let mut rec = vec![r.name.clone()];
            rec.extend(columns.iter().map(|k| key_value(r, k)));
            rec.extend([format!("{:?}", r.kind).to_lowercase(), r.status.word().into(), flags(r).join("; ")]);
            rec.extend(keys.iter().map(|k| cell(r.metrics.get(k))));
            rec.push(format!("{:.2}", r.seconds));
            rec.push(r.error.clone().unwrap_or_default());
            rec
        })
        .collect();
    let table = SummaryTable { header, rows: cells };
    dir.write("summary.csv", &table.csv().map_err(|e| dir.error("summary.csv", e))?)?;
    let links: Vec<String> = rows.iter().map(|r| case_link(r)).collect();
    let mut md = table.markdown(&links);
    if let Some(plot) = sweep_figure(columns, rows) {
        dir.figure("figure", &plot)?;
        md += &format!("\n![{}](figure.png)\n", plot.title);
    }
    dir.write("summary.md", md.as_bytes())?;
    dir.commit("study", progress)
}
