//! `rotorshunt study STUDY.toml --out DIR [--force]`: a batch of analysis or design cases
//! built from one base problem by `--set`-style overrides (a list and/or a cartesian
//! sweep), run in parallel across cases. Each case writes its files under
//! `DIR/cases/<name>/` and, last, `result.json` (atomically): a case whose `result.json`
//! records the same input hash and success is skipped on a re-run unless `--force`.
//! A failing case is recorded with its error and the others go on.

use super::design::design_report;
use super::{OutDir, Progress, Quiet, TOOL};
use crate::analysis::floquet::FloquetSystem;
use crate::analysis::modes::whirl_modes_of;
use crate::analysis::regions::{band, catalogue, CatalogueRequest, RegionSettings};
use crate::analysis::Interval;
use crate::analysis::Rotor;
use crate::problem::Problem;
use crate::Error;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What a case runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
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
struct StudyFile {
    /// Base problem file, relative to the study file.
    base: String,
    /// Default kind of the cases.
    #[serde(default = "default_kind")]
    kind: CaseKind,
    /// φ range of regions cases (rad/s).
    #[serde(default = "default_phi")]
    phi: [f64; 2],
    /// β_max of regions cases.
    #[serde(default = "default_beta_max")]
    beta_max: f64,
    /// Level β_op of regions cases (default β_max).
    #[serde(default)]
    level: Option<f64>,
    /// Operating frequency of regions cases: also report its stable band (rad/s).
    #[serde(default)]
    phi_op: Option<f64>,
    /// Overrides for every case.
    #[serde(default)]
    set: Vec<String>,
    /// Listed cases.
    #[serde(default)]
    cases: Vec<CaseFile>,
    /// Cartesian sweep: key path → list of values.
    #[serde(default)]
    sweep: BTreeMap<String, Vec<toml::Value>>,
}

fn default_kind() -> CaseKind {
    CaseKind::Regions
}
fn default_phi() -> [f64; 2] {
    [100.0, 8000.0]
}
fn default_beta_max() -> f64 {
    1.0
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct CaseFile {
    name: String,
    #[serde(default)]
    kind: Option<CaseKind>,
    #[serde(default)]
    set: Vec<String>,
}

/// One case to run.
#[derive(Debug, Clone, Serialize)]
pub struct Case {
    /// Name (listed) or the sweep's key=value pairs.
    pub name: String,
    /// Directory name under `cases/`.
    pub slug: String,
    /// Kind.
    pub kind: CaseKind,
    /// Overrides on the base problem.
    pub overrides: Vec<String>,
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

fn slug(text: &str) -> String {
    let s: String =
        text.chars().map(|c| if c.is_ascii_alphanumeric() || c == '.' || c == '-' { c } else { '_' }).collect();
    s.trim_matches('_').chars().take(120).collect()
}

fn study_error(file: &Path, message: impl Into<String>) -> Error {
    Error::Study { file: file.display().to_string(), message: message.into() }
}

/// Read a study file: the base problem path and the cases.
fn read(file: &Path) -> Result<(StudyFile, PathBuf, Vec<Case>), Error> {
    let text = crate::problem::read_toml(file)?;
    let de = toml::Deserializer::parse(&text).map_err(|e| study_error(file, e.to_string()))?;
    let study: StudyFile = serde_path_to_error::deserialize(de)
        .map_err(|e| study_error(file, format!("key `{}`: {}", e.path(), e.inner().message().trim())))?;
    let base = file.parent().unwrap_or(Path::new(".")).join(&study.base);
    let mut cases: Vec<Case> = study
        .cases
        .iter()
        .map(|c| Case {
            name: c.name.clone(),
            slug: slug(&c.name),
            kind: c.kind.unwrap_or(study.kind),
            overrides: study.set.iter().chain(&c.set).cloned().collect(),
        })
        .collect();
    // The sweep: every combination, keys in sorted order.
    let mut combos: Vec<Vec<String>> = vec![Vec::new()];
    for (key, values) in &study.sweep {
        if values.is_empty() {
            return Err(study_error(file, format!("key `sweep.{key}`: needs at least one value")));
        }
        combos = combos
            .into_iter()
            .flat_map(|c| {
                values.iter().map(move |v| {
                    let mut c = c.clone();
                    c.push(format!("{key}={v}"));
                    c
                })
            })
            .collect();
    }
    if !study.sweep.is_empty() {
        for c in combos {
            let name = c.join(",");
            cases.push(Case {
                slug: slug(&name),
                name,
                kind: study.kind,
                overrides: study.set.iter().chain(&c).cloned().collect(),
            });
        }
    }
    if cases.is_empty() {
        return Err(study_error(file, "no cases: give [[cases]] and/or a [sweep] table"));
    }
    let mut seen = std::collections::BTreeSet::new();
    for c in &cases {
        if !seen.insert(c.slug.clone()) {
            return Err(study_error(file, format!("two cases share the name `{}`", c.slug)));
        }
    }
    Ok((study, base, cases))
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

/// Run one case into `dir`; its metrics.
fn run_case(
    base: &Path,
    case: &Case,
    study: &StudyFile,
    dir: &Path,
) -> Result<BTreeMap<String, serde_json::Value>, Error> {
    let problem = Problem::from_path(base, &case.overrides)?;
    let mut m = BTreeMap::new();
    match case.kind {
        CaseKind::Design => {
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
            let rotor = Rotor::new(&problem.model)?;
            let speed = problem.model.speed;
            let fs = FloquetSystem::new(&rotor, &problem.settings, speed)?;
            let full = whirl_modes_of(&rotor, &problem.settings, speed)?;
            let s = RegionSettings::default();
            let range = Interval::new(study.phi[0], study.phi[1]);
            let cat =
                catalogue(&fs, &full, &s, &CatalogueRequest { range, beta_max: study.beta_max, level, track: false })?;
            let out = OutDir::create(dir, base.to_str().unwrap_or_default())?;
            out.write(
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

/// A previous result of this case with the same input, if it succeeded.
fn finished(dir: &Path, hash: &str) -> Option<CaseResult> {
    let bytes = crate::problem::read_input(&dir.join("result.json")).ok()?;
    let r: CaseResult = serde_json::from_slice(&bytes).ok()?;
    (r.input_hash == hash && r.status == "ok").then_some(r)
}

/// `rotorshunt study STUDY.toml --out DIR [--force]`.
/// The summary text and the number of failed cases.
pub fn study_cmd(file: &Path, out: &Path, force: bool, progress: &dyn Progress) -> Result<(String, usize), Error> {
    let (study, base, cases) = read(file)?;
    let base_text = crate::problem::read_input(&base)?;
    let root = OutDir::create(out, file.to_str().unwrap_or_default())?;
    // A killed run can leave write_atomic's temporaries (never a partial result file).
    crate::report::remove_temporaries(out).map_err(|e| root.error("(temporaries)", e))?;
    let started = Instant::now();
    progress.start(cases.len() as u64, "study");
    // Cases in parallel (the outermost loop); results in case order.
    let results: Vec<(CaseResult, bool)> = cases
        .par_iter()
        .map(|case| {
            let dir = out.join("cases").join(&case.slug);
            let hash = input_hash(&base_text, case, &study);
            if !force {
                if let Some(r) = finished(&dir, &hash) {
                    progress.tick();
                    return (r, true);
                }
            }
            let t = Instant::now();
            let outcome = std::fs::create_dir_all(&dir)
                .map_err(|e| Error::Output { path: dir.display().to_string(), message: e.to_string() })
                .and_then(|_| run_case(&base, case, &study, &dir));
            let (status, error, metrics) = match outcome {
                Ok(m) => ("ok", None, m),
                Err(e) => ("failed", Some(e.to_string()), BTreeMap::new()),
            };
            let r = CaseResult {
                name: case.name.clone(),
                slug: case.slug.clone(),
                kind: case.kind,
                overrides: case.overrides.clone(),
                input_hash: hash,
                status: status.into(),
                error,
                metrics,
                seconds: t.elapsed().as_secs_f64(),
                tool: TOOL.into(),
            };
            // result.json last: its presence marks the case finished.
            let text = serde_json::to_string_pretty(&r).expect("plain data serialises") + "\n";
            let written = crate::report::write_atomic(&dir.join("result.json"), text.as_bytes());
            progress.tick();
            match written {
                Ok(()) => (r, false),
                Err(e) => (
                    CaseResult { status: "failed".into(), error: Some(format!("cannot write result.json: {e}")), ..r },
                    false,
                ),
            }
        })
        .collect();
    progress.finish();
    let rows: Vec<&CaseResult> = results.iter().map(|(r, _)| r).collect();
    write_summary(&root, &rows)?;
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
