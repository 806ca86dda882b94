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

mod folder;
mod plan;

use super::bounds::{self, Names};
use super::design::{design_estimate, design_report, DESIGN};
use super::{OutDir, Progress, Quiet, TOOL};
use crate::analysis::cost::{self, Budget, CatalogueWork, Dense, PointCost};
use crate::analysis::floquet::FloquetSystem;
use crate::analysis::modes::whirl_modes_of;
use crate::analysis::regions::seeds_for;
use crate::analysis::regions::{band, catalogue, CatalogueRequest, RegionSettings};
use crate::analysis::Criterion;
use crate::analysis::Interval;
use crate::analysis::Rotor;
use crate::problem::Problem;
use crate::Error;
pub(crate) use folder::Ledger;
use folder::{Identity, StudyLock, CASES, LOCK, MANIFEST, ROOT_OUTPUTS};
pub use folder::{Manifest, Role};
pub use plan::{Case, MAX_STUDY_CASES};
use plan::{Plan, StudyFile};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
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
    /// Tool and version.
    pub tool: String,
}

fn input_hash(base_text: &[u8], case: &Case, study: &StudyFile) -> String {
    let mut h = Sha256::new();
    h.update(base_text);
    h.update(format!(
        "\n{:?}\n{:?}\n{:?} {:?} {:?} {:?}\n",
        case.kind, case.overrides, study.phi, study.beta_max, study.level, study.phi_op
    ));
    h.update(TOOL.as_bytes());
    format!("{:x}", h.finalize())
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
    let (s, criterion, pc) = (RegionSettings::default(), Criterion::of(&fs.settings), PointCost::of(&fs));
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
    match case.kind {
        CaseKind::Design => {
            admit_case(&problem, CaseKind::Design, study, budget)?;
            let o = design_report(&problem, dir, &Quiet)?;
            m.insert("design_status".into(), metric(o.status));
            m.insert("verified".into(), metric(o.verified));
            // The same bands as `rotorshunt band tuned.toml` gives (0 where φ_op is unstable):
            // the smallest over the speeds.
            let width = |v: &[crate::design::evaluate::OperatingBand]| {
                v.iter().map(|b| b.band.band.map_or(0.0, |x| x.width())).fold(f64::INFINITY, f64::min)
            };
            if !o.before_bands.is_empty() {
                m.insert("band_width_before".into(), metric(width(&o.before_bands)));
                m.insert("band_width_after".into(), metric(width(&o.after_bands)));
                if let [only] = o.after_bands.as_slice() {
                    m.insert("band_lo_after".into(), metric(only.band.band.map(|b| b.lo)));
                    m.insert("band_hi_after".into(), metric(only.band.band.map(|b| b.hi)));
                }
            }
            if let Some(spec) = problem.design.as_ref() {
                if !spec.bands.is_empty() {
                    m.insert("regions_in_bands_before".into(), metric(o.before_intrusions.len()));
                    m.insert("regions_in_bands_after".into(), metric(o.after_intrusions.len()));
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
            let speed = problem.model.speed;
            let full = whirl_modes_of(&rotor, &problem.settings, speed)?;
            let s = RegionSettings::default();
            let range = Interval::new(study.phi[0], study.phi[1]);
            let cat =
                catalogue(&fs, &full, &s, &CatalogueRequest { range, beta_max: study.beta_max, level, track: false })?;
            dir.write(
                "regions.json",
                (serde_json::to_string_pretty(&cat).expect("plain data serialises") + "\n").as_bytes(),
            )?;
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

/// How `study` treats finished cases and the `--out` folder.
#[derive(Debug, Clone, Copy, Default)]
pub struct StudyOptions {
    /// Recompute cases that are already finished (`--force`).
    pub force: bool,
    /// Write into a `--out` folder that holds entries the study did not create
    /// (`--allow-non-empty`); they are never changed.
    pub allow_non_empty: bool,
    /// The limits of each case's estimated cost (`--max-cost`); the number of cases is
    /// bounded by [`MAX_STUDY_CASES`] instead.
    pub budget: Budget,
}

/// Everything a case needs from its study.
struct Run<'a> {
    plan: &'a Plan,
    base_text: &'a [u8],
    cases_dir: std::path::PathBuf,
    study: &'a str,
    inputs: &'a [(&'a Path, &'a str)],
    force: bool,
    budget: Budget,
}

impl Run<'_> {
    /// Run case `index` (or take its finished result); its row and whether it was skipped.
    fn case(&self, index: u64) -> (CaseResult, bool) {
        let case = self.plan.case(index);
        let hash = input_hash(self.base_text, &case, &self.plan.study);
        let t = Instant::now();
        let row = |status: &str, error: Option<String>, metrics| CaseResult {
            name: case.name.clone(),
            slug: case.slug.clone(),
            kind: case.kind,
            overrides: case.overrides.clone(),
            input_hash: hash.clone(),
            status: status.into(),
            error,
            metrics,
            seconds: t.elapsed().as_secs_f64(),
            tool: TOOL.into(),
        };
        let path = self.cases_dir.join(&case.slug);
        let dir = match folder::open_case(&path, self.study, &case.name) {
            Ok(ledger) => OutDir::planned(&path, self.inputs).with_ledger(ledger),
            // Not this study's folder: nothing is written into it, not even the result.
            Err(e) => return (row("failed", Some(e.to_string()), BTreeMap::new()), false),
        };
        if !self.force {
            if let Some(r) = finished(&dir, &hash) {
                return (r, true);
            }
        }
        let r = match run_case(&self.plan.base, &case, &self.plan.study, &dir, &self.budget) {
            Ok(m) => row("ok", None, m),
            Err(e) => row("failed", Some(e.to_string()), BTreeMap::new()),
        };
        // result.json last: its presence marks the case finished.
        let text = serde_json::to_string_pretty(&r).expect("plain data serialises") + "\n";
        match dir.write("result.json", text.as_bytes()) {
            Ok(()) => (r, false),
            Err(e) => (
                CaseResult { status: "failed".into(), error: Some(format!("cannot write result.json: {e}")), ..r },
                false,
            ),
        }
    }
}

/// `rotorshunt study STUDY.toml --out DIR [--force] [--allow-non-empty]`: the summary
/// text and the number of failed cases.
pub fn study_cmd(
    file: &Path,
    out: &Path,
    options: StudyOptions,
    progress: &dyn Progress,
) -> Result<(String, usize), Error> {
    let plan = Plan::read(file)?;
    let base_text = crate::problem::read_input(&plan.base)?;
    // Before the folder is touched: the base with the study's overrides, each sweep value
    // on its own, and the per-case estimate of the base's cases.
    let base_name = plan.base.display().to_string();
    let base = Problem::from_bytes(&base_text, &base_name, &plan.study.set)?;
    plan.check_sweep(file, crate::problem::input::text_of(&base_text, &base_name)?, &base_name)?;
    let budget = case_budget(&options.budget);
    let kinds: std::collections::BTreeSet<CaseKind> = plan.kinds();
    for kind in kinds {
        admit_case(&base, kind, &plan.study, &budget)?;
    }
    let identity = Identity {
        study: std::fs::canonicalize(file).unwrap_or_else(|_| file.to_path_buf()).display().to_string(),
        plan: plan.survey(file, &base_text)?,
        cases: plan.len(),
    };
    let inputs: [(&Path, &str); 2] = [(file, "the study file"), (&plan.base, "the study's base problem file")];
    // The folder is checked before anything is created in it, and again under the lock.
    let root = OutDir::planned(out, &inputs);
    let own_names: Vec<&str> = [MANIFEST, LOCK].into_iter().chain(ROOT_OUTPUTS).collect();
    root.check_outputs(&own_names)?;
    folder::inspect(out, &identity, options.allow_non_empty)?;
    std::fs::create_dir_all(out)
        .map_err(|e| Error::Output { path: out.display().to_string(), message: e.to_string() })?;
    let lock = StudyLock::acquire(out, &identity.study)?;
    let found = folder::inspect(out, &identity, options.allow_non_empty)?;
    let (ledger, mut notes) = folder::open_root(out, &identity, found)?;
    notes.extend(lock.taken_over.clone());
    ledger.claim(CASES, &out.join(CASES))?;
    let root = root.with_ledger(ledger);
    let cases_dir = out.join(CASES);
    match std::fs::create_dir(&cases_dir) {
        Ok(()) => {}
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists && cases_dir.is_dir() => {}
        Err(e) => return Err(root.error(CASES, e)),
    }
    let started = Instant::now();
    progress.start(plan.len(), "study");
    let run = Run {
        plan: &plan,
        base_text: &base_text,
        cases_dir,
        study: &identity.study,
        inputs: &inputs,
        force: options.force,
        budget,
    };
    // Cases in parallel (the outermost loop), each built from its index when it runs;
    // results in case order.
    let results: Vec<(CaseResult, bool)> = (0..plan.len() as usize)
        .into_par_iter()
        .map(|i| {
            let r = run.case(i as u64);
            progress.tick();
            r
        })
        .collect();
    progress.finish();
    let rows: Vec<&CaseResult> = results.iter().map(|(r, _)| r).collect();
    write_summary(&root, &rows)?;
    drop(lock);
    let skipped = results.iter().filter(|(_, s)| *s).count();
    let failed = rows.iter().filter(|r| r.status != "ok").count();
    let mut text = format!(
        "study: {} cases ({} run, {} skipped as finished, {} failed) in {:.1} s; wrote summary.{{csv,json,md}} and cases/ to {}\n",
        rows.len(),
        rows.len() - skipped,
        skipped,
        failed,
        started.elapsed().as_secs_f64(),
        out.display()
    );
    for r in rows.iter().filter(|r| r.status != "ok") {
        text += &format!("failed: {}: {}\n", r.name, r.error.clone().unwrap_or_default());
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

fn write_summary(root: &OutDir, rows: &[&CaseResult]) -> Result<(), Error> {
    let keys: std::collections::BTreeSet<String> = rows.iter().flat_map(|r| r.metrics.keys().cloned()).collect();
    #[derive(Serialize)]
    struct Summary<'a> {
        tool: &'static str,
        cases: &'a [&'a CaseResult],
    }
    let json =
        serde_json::to_string_pretty(&Summary { tool: TOOL, cases: rows }).expect("plain data serialises") + "\n";
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
