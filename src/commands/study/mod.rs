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

mod folder;
mod plan;
mod shard;
mod slurm;
mod state;

use super::bounds::{self, Names};
use super::design::{design_estimate, design_report, DESIGN};
use super::{OutDir, TOOL};
use crate::analysis::cost::{self, Budget, CatalogueWork, Dense, PointCost};
use crate::analysis::floquet::FloquetSystem;
use crate::analysis::modes::whirl_modes_of;
use crate::analysis::regions::seeds_for;
use crate::analysis::regions::{band, catalogue, CatalogueRequest};
use crate::analysis::Criterion;
use crate::analysis::Interval;
use crate::analysis::Rotor;
use crate::commands::out::json_pretty;
use crate::problem::Problem;
use crate::progress::{Progress, Silent};
use crate::Error;
pub(crate) use folder::Ledger;
use folder::{CaseFolder, Identity, StudyLock, CASES, LOCK, MANIFEST, ROOT_OUTPUTS};
pub use folder::{Manifest, Role};
pub use plan::{Case, MAX_STUDY_CASES};
use plan::{Plan, StudyFile};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
pub use shard::{array_expression, Shard, TaskRecord, MAX_SHARDS};
pub use slurm::{slurm_cmd, SlurmOptions};
pub use state::{merge_cmd, plan_cmd, planned_inputs, status_cmd, CaseState, StatusReport};
use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;

/// What a case runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum CaseKind {
    /// The region catalogue (and the band around `phi_op` if given).
    Regions,
    /// The `[design]` of the case's problem.
    Design,
}

/// The recorded result of one case (`cases/<slug>/result.json`).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct CaseResult {
    /// Case name.
    pub name: String,
    /// Stable id: the folder name and a hash of the kind and resolved overrides
    /// ([`case_id`]); empty in results of older versions.
    #[serde(default)]
    pub id: String,
    /// Directory name.
    pub slug: String,
    /// Kind.
    pub kind: CaseKind,
    /// Overrides.
    pub overrides: Vec<String>,
    /// SHA-256 of the base problem text, the overrides and the study parameters.
    pub input_hash: String,
    /// `ok` or `failed`.
    pub status: String,
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

fn metric(v: impl Serialize) -> serde_json::Value {
    serde_json::to_value(v).unwrap_or(serde_json::Value::Null)
}

/// The names of a study's inputs in a refusal.
const STUDY: Names<'static> = Names {
    phi: "the study's `phi`",
    grid: "the study's `phi` (its range)",
    load: "the study's `beta_max` or `level`",
    periods: "the study",
};

/// A case's budget: the cases run in parallel, so each may hold a share of the memory.
fn case_budget(budget: &Budget) -> Budget {
    budget.share(rayon::current_num_threads() as f64)
}

/// The rotor and reduced system of a regions case, its work admitted within `budget`
/// before the whirls and the search: the catalogue of the study's range and, with
/// `phi_op`, the band.
fn regions_case_system(problem: &Problem, study: &StudyFile, budget: &Budget) -> Result<(Rotor, FloquetSystem), Error> {
    bounds::admit_dense(budget, "a regions case", problem, Dense::ReducedAndWhirls)?;
    let rotor = Rotor::new(&problem.model)?;
    let fs = FloquetSystem::new(&rotor, &problem.settings, problem.model.speed)?;
    let level = study.level.unwrap_or(study.beta_max);
    let range = Interval::new(study.phi[0], study.phi[1]);
    let (s, criterion, pc) = (problem.regions.clone(), Criterion::of(&fs.settings), PointCost::of(&fs));
    let seeds = seeds_for(&fs, None, range, criterion.max_order)?;
    let work = CatalogueWork { range, beta_max: study.beta_max, level, track: false };
    let mut estimate = cost::catalogue(&pc, &s, &criterion, &seeds, &work);
    if study.phi_op.is_some() {
        estimate = estimate.then(cost::band(&pc, &s, &criterion, &seeds, range, level));
    }
    bounds::admit(budget, "a regions case", &estimate, &STUDY)?;
    Ok((rotor, fs))
}

/// Admit a case of `kind` on `problem` (the study's per-case estimate).
fn admit_case(problem: &Problem, kind: CaseKind, study: &StudyFile, budget: &Budget) -> Result<(), Error> {
    match kind {
        CaseKind::Regions => regions_case_system(problem, study, budget).map(|_| ()),
        CaseKind::Design => match problem.design.as_ref() {
            Some(spec) => bounds::admit(budget, "a design case", &design_estimate(problem, spec, budget)?, &DESIGN),
            // Reported by the case itself (NoDesign).
            None => Ok(()),
        },
    }
}

/// Run one case into its folder; its metrics. Its estimated work is admitted within
/// `budget` first (a case beyond it fails with the cost error).
fn run_case(
    base: &Path,
    case: &Case,
    study: &StudyFile,
    dir: &OutDir,
    budget: &Budget,
) -> Result<BTreeMap<String, serde_json::Value>, Error> {
    let problem = Problem::from_path(base, &case.overrides)?;
    let mut m = BTreeMap::new();
    let mut warnings: Vec<String> = problem.warnings.iter().map(|w| format!("key `{}`: {}", w.key, w.kind)).collect();
    match case.kind {
        CaseKind::Design => {
            admit_case(&problem, CaseKind::Design, study, budget)?;
            let o = design_report(&problem, dir, &Silent)?;
            m.insert("design_status".into(), metric(o.status));
            m.insert("verified".into(), metric(o.verified));
            // The same bands as `rotorshunt band tuned.toml` gives (0 where φ_op is unstable):
            // the smallest over the speeds.
            let width = |v: &[crate::design::evaluate::OperatingBand]| {
                v.iter().map(|b| b.band.band.map_or(0.0, |x| x.width())).fold(f64::INFINITY, f64::min)
            };
            if !o.before_bands().is_empty() {
                m.insert("band_width_before".into(), metric(width(o.before_bands())));
                m.insert("band_width_after".into(), metric(width(o.after_bands())));
                if let [only] = o.after_bands() {
                    m.insert("band_lo_after".into(), metric(only.band.band.map(|b| b.lo)));
                    m.insert("band_hi_after".into(), metric(only.band.band.map(|b| b.hi)));
                }
            }
            if let Some(spec) = problem.design.as_ref() {
                if !spec.objective.bands().is_empty() {
                    m.insert("regions_in_bands_before".into(), metric(o.before_intrusions().len()));
                    m.insert("regions_in_bands_after".into(), metric(o.after_intrusions().len()));
                }
                for (v, x) in spec.variables.iter().zip(&o.after) {
                    m.insert(format!("{} ({})", v.name(), v.parameter.unit()), metric(x));
                }
            }
            m.insert("floquet_evaluations".into(), metric(o.floquet_evaluations));
        }
        CaseKind::Regions => {
            let level = study.level.unwrap_or(study.beta_max);
            let (rotor, fs) = regions_case_system(&problem, study, budget)?;
            let range = Interval::new(study.phi[0], study.phi[1]);
            for w in super::range_warning(&problem, &fs, range, "phi", &Silent) {
                warnings.push(format!("key `{}`: {}", w.key, w.kind));
            }
            let speed = problem.model.speed;
            let full = whirl_modes_of(&rotor, &problem.settings, speed)?;
            let s = problem.regions.clone();
            let cat =
                catalogue(&fs, &full, &s, &CatalogueRequest { range, beta_max: study.beta_max, level, track: false })?;
            dir.write("regions.json", (json_pretty(&cat, "the JSON output")? + "\n").as_bytes())?;
            m.insert("regions".into(), metric(cat.regions.len()));
            let lowest = cat.regions.iter().min_by(|a, b| a.onset_beta.total_cmp(&b.onset_beta));
            m.insert("lowest_onset".into(), metric(lowest.map(|r| r.onset_beta)));
            m.insert("lowest_onset_region".into(), metric(lowest.map(|r| r.label.clone())));
            m.insert("floquet_evaluations".into(), metric(cat.evaluations));
            if let Some(p) = study.phi_op {
                // The same band as `rotorshunt band` over the study's φ range.
                let b = band(&fs, &full, &s, range, p, level)?.band;
                m.insert("band_lo".into(), metric(b.map(|b| b.lo)));
                m.insert("band_hi".into(), metric(b.map(|b| b.hi)));
                m.insert("band_width".into(), metric(b.map(|b| b.width())));
            }
        }
    }
    if !warnings.is_empty() {
        m.insert("warnings".into(), metric(warnings));
    }
    Ok(m)
}

/// A previous result of this case with the same input, if it succeeded (and the study
/// wrote it).
fn finished(dir: &OutDir, hash: &str) -> Option<CaseResult> {
    if !dir.ledger().is_some_and(|l| l.owns("result.json")) {
        return None;
    }
    let bytes = crate::problem::read_input(&dir.path("result.json")).ok()?;
    let r: CaseResult = serde_json::from_slice(&bytes).ok()?;
    (r.input_hash == hash && r.status == "ok").then_some(r)
}

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
    /// bounded by [`MAX_STUDY_CASES`] instead.
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
}

impl Run<'_> {
    /// Run case `index` (or take its finished result).
    fn case(&self, index: u64) -> Outcome {
        let case = self.plan.case(index);
        let hash = self.hasher.of(&case, &self.plan.study);
        let t = Instant::now();
        let row = |status: &str, error: Option<String>, metrics| CaseResult {
            name: case.name.clone(),
            id: case_id(&case),
            slug: case.slug.clone(),
            kind: case.kind,
            overrides: case.overrides.clone(),
            input_hash: hash.clone(),
            status: status.into(),
            error,
            metrics,
            seconds: t.elapsed().as_secs_f64(),
            task: self.task.clone(),
            tool: TOOL.into(),
        };
        let path = self.cases_dir.join(&case.slug);
        // The case lock is held until this function returns: through the commit.
        let (dir, _lock) = match folder::open_case(&path, self.study, &case.name) {
            Ok(CaseFolder::Held(ledger, lock)) => (OutDir::planned(&path, self.inputs).with_ledger(*ledger), lock),
            Ok(CaseFolder::Busy(holder)) => return Outcome::Busy(case.name.clone(), holder),
            // Not this study's folder: nothing is written into it, not even the result.
            Err(e) => return Outcome::Ran(row("failed", Some(e.to_string()), BTreeMap::new())),
        };
        if !self.force {
            if let Some(r) = finished(&dir, &hash) {
                return Outcome::Skipped(r);
            }
        }
        let r = match run_case(&self.plan.base, &case, &self.plan.study, &dir, &self.budget) {
            Ok(m) => row("ok", None, m),
            Err(e) => row("failed", Some(e.to_string()), BTreeMap::new()),
        };
        // A failure never replaces a finished result that another task committed meanwhile
        // (on a filesystem whose locks do not reach across nodes).
        if r.status != "ok" {
            if let Some(done) = finished(&dir, &hash) {
                return Outcome::Skipped(done);
            }
        }
        // result.json last, renamed into place: its presence marks the case finished.
        let written =
            json_pretty(&r, "result.json").and_then(|text| dir.write("result.json", (text + "\n").as_bytes()));
        match written {
            Ok(()) => Outcome::Ran(r),
            Err(e) => Outcome::Ran(CaseResult {
                status: "failed".into(),
                error: Some(format!("cannot write result.json: {e}")),
                ..r
            }),
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
    let base_text = crate::problem::read_input(&plan.base)?;
    // Before the folder is touched: the base with the study's overrides, each sweep value
    // on its own, and the per-case estimate of the base's cases.
    let base_name = plan.base.display().to_string();
    let base = Problem::from_bytes(&base_text, &base_name, &plan.study.set)?;
    plan.check_sweep(file, crate::problem::input::text_of(&base_text, &base_name)?, &base_name)?;
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
        return Ok((state::dry_run_text(&plan, &identity, shard), 0));
    }
    let inputs: [(&Path, &str); 2] = [(file, "the study file"), (&plan.base, "the study's base problem file")];
    // The folder is checked before anything is created in it, and again under the lock.
    let root = OutDir::planned(out, &inputs);
    let own_names: Vec<&str> = [MANIFEST, LOCK].into_iter().chain(ROOT_OUTPUTS).collect();
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
    match std::fs::create_dir(&cases_dir) {
        Ok(()) => {}
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists && cases_dir.is_dir() => {}
        Err(e) => return Err(root.error(CASES, e)),
    }
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
    let mut rows: Vec<&CaseResult> = Vec::new();
    let mut busy = Vec::new();
    let mut skipped = 0;
    for o in &outcomes {
        match o {
            Outcome::Ran(r) => rows.push(r),
            Outcome::Skipped(r) => {
                rows.push(r);
                skipped += 1;
            }
            Outcome::Busy(name, holder) => busy.push((name, holder)),
        }
    }
    if !sharded {
        write_summary(&root, &rows)?;
    }
    drop(lock);
    let failed = rows.iter().filter(|r| r.status != "ok").count();
    let mut text = match shard {
        None => format!(
            "study: {} cases ({} run, {} skipped as finished, {} failed) in {:.1} s; wrote summary.{{csv,json,md}} and cases/ to {}\n",
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
    for r in rows.iter().filter(|r| r.status != "ok") {
        text += &format!("failed: {}: {}\n", r.name, r.error.clone().unwrap_or_default());
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

pub(crate) fn write_summary(root: &OutDir, rows: &[&CaseResult]) -> Result<(), Error> {
    let keys: std::collections::BTreeSet<String> = rows.iter().flat_map(|r| r.metrics.keys().cloned()).collect();
    #[derive(Serialize)]
    struct Summary<'a> {
        tool: &'static str,
        cases: &'a [&'a CaseResult],
    }
    let json = json_pretty(&Summary { tool: TOOL, cases: rows }, "the JSON output")? + "\n";
    root.write("summary.json", json.as_bytes())?;
    let mut w = csv::Writer::from_writer(Vec::new());
    let mut header = vec!["case".to_string(), "kind".into(), "status".into(), "seconds".into()];
    header.extend(keys.iter().cloned());
    header.push("error".into());
    let csv_err = |e: csv::Error| root.error("summary.csv", e);
    w.write_record(&header).map_err(csv_err)?;
    let mut md = format!("# Study summary\n\n| {} |\n|{}\n", header.join(" | "), "---|".repeat(header.len()));
    for r in rows {
        let mut rec =
            vec![r.name.clone(), format!("{:?}", r.kind).to_lowercase(), r.status.clone(), format!("{:.2}", r.seconds)];
        rec.extend(keys.iter().map(|k| cell(r.metrics.get(k))));
        rec.push(r.error.clone().unwrap_or_default());
        w.write_record(&rec).map_err(csv_err)?;
        // Markdown is for people: numbers to 6 significant digits (the CSV keeps all).
        let short = |c: &String| match c.parse::<f64>() {
            Ok(x) if c.contains('.') || c.contains('e') => {
                format!("{}", format!("{x:.5e}").parse::<f64>().unwrap_or(x))
            }
            _ => c.replace('|', "\\|"),
        };
        md += &format!("| {} |\n", rec.iter().map(short).collect::<Vec<_>>().join(" | "));
    }
    let bytes = w.into_inner().map_err(|e| root.error("summary.csv", e))?;
    root.write("summary.csv", &bytes)?;
    root.write("summary.md", md.as_bytes())
}
