//! Running one case of a study: its cost admitted against the study's budget, then the
//! catalogue (and band) or the design, and the key results recorded as metrics.

use super::*;

fn metric(v: impl Serialize) -> serde_json::Value {
    serde_json::to_value(v).unwrap_or(serde_json::Value::Null)
}

/// A case's budget: the cases run in parallel, so each may hold a share of the memory.
pub(super) fn case_budget(budget: &Budget) -> Budget {
    budget.share(rayon::current_num_threads() as f64)
}

/// The catalogue a regions case asks for: the study's range, β_max and level.
fn case_request(study: &StudyFile) -> CatalogueRequest {
    let range = Interval::new(study.phi[0], study.phi[1]);
    CatalogueRequest { range, beta_max: study.beta_max, level: study.level.unwrap_or(study.beta_max), track: false }
}

/// Admit a case of `kind` on `problem` (the study's per-case estimate) within `budget`.
pub(super) fn admit_case(problem: &Problem, kind: CaseKind, study: &StudyFile, budget: &Budget) -> Result<(), Error> {
    let run = rotorshunt::run::Run::new(&Silent).with_budget(*budget);
    match kind {
        CaseKind::Regions => run.regions_case(problem, &case_request(study), study.phi_op).map(|_| ())?,
        // A design case without a design is reported by the case itself (NoDesign).
        CaseKind::Design if problem.design.is_none() => {}
        CaseKind::Design => run.design(problem, "a design case").map(|_| ())?,
    }
    Ok(())
}

/// Run one case into its folder; its metrics. Its estimated work is admitted within
/// `budget` first (a case beyond it fails with the cost error).
pub(super) fn run_case(
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
            let run = rotorshunt::run::Run::new(&Silent).with_budget(*budget);
            let job = run.design(&problem, "a design case")?;
            // A case stopped by its limit fails, as any stopped case does (its record
            // says why; the study keeps no half-done design).
            let o = match design_report(&problem, dir, job, &Silent)? {
                rotorshunt::run::Outcome { stop: Some(stop), .. } => return Err(stop.into()),
                rotorshunt::run::Outcome { value, .. } => value,
            };
            m.insert("design_status".into(), metric(o.status));
            m.insert("verified".into(), metric(o.verified()));
            if let Some(b) = &o.basis {
                m.insert("basis_modes".into(), metric(b.modes));
                m.insert("basis_converged".into(), metric(b.converged()));
            }
            // The same bands as `rotorshunt band tuned.toml` gives (0 where φ_op is unstable):
            // the smallest over the speeds.
            let width = |v: &[rotorshunt::design::evaluate::OperatingBand]| {
                v.iter().map(|b| b.band.band.map_or(0.0, |x| x.width())).fold(f64::INFINITY, f64::min)
            };
            if !o.before_bands().is_empty() {
                m.insert("band_width_before".into(), metric(width(o.before_bands())));
                m.insert("band_width_after".into(), metric(width(o.after_bands())));
                if let [only] = o.after_bands() {
                    m.insert("band_lo_after".into(), metric(only.band.band.map(|b| b.lo)));
                    m.insert("band_hi_after".into(), metric(only.band.band.map(|b| b.hi)));
                    m.insert("clipped_after".into(), metric(only.band.clipped()));
                }
                // The tuned band's margins (the smallest over the speeds; docs/studies.md).
                let after: Vec<&rotorshunt::analysis::regions::Margins> =
                    o.after_speeds.iter().filter_map(|d| d.margins.as_ref()).collect();
                if !after.is_empty() {
                    let least = |f: &dyn Fn(&rotorshunt::analysis::regions::Margins) -> f64| {
                        after.iter().map(|x| f(x)).fold(f64::INFINITY, f64::min)
                    };
                    m.insert("load_margin_after".into(), metric(least(&|x| x.load_margin())));
                    m.insert("phi_margin_below_after".into(), metric(least(&|x| x.phi_below)));
                    m.insert("phi_margin_above_after".into(), metric(least(&|x| x.phi_above)));
                    let width = least(&|x| x.strict_band.map_or(0.0, |b| b.width()));
                    m.insert("strict_band_width_after".into(), metric(width));
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
            let run = rotorshunt::run::Run::new(&Silent).with_budget(*budget);
            let job = run.regions_case(&problem, &case_request(study), study.phi_op)?;
            warnings.extend(job.warnings.iter().map(|w| format!("key `{}`: {}", w.key, w.kind)));
            let (sized, found) = job.run()?;
            let cat = sized.answer;
            m.insert("basis_modes".into(), metric(sized.basis.modes));
            m.insert("basis_converged".into(), metric(sized.basis.converged()));
            dir.write("regions.json", (json_pretty(&cat, "the JSON output")? + "\n").as_bytes())?;
            m.insert("regions".into(), metric(cat.regions.len()));
            let lowest = cat.regions.iter().min_by(|a, b| a.onset_beta.total_cmp(&b.onset_beta));
            m.insert("lowest_onset".into(), metric(lowest.map(|r| r.onset_beta)));
            m.insert("lowest_onset_region".into(), metric(lowest.map(|r| r.label.clone())));
            m.insert("floquet_evaluations".into(), metric(cat.evaluations));
            // The same band as `rotorshunt band` over the study's φ range.
            if let Some(found) = found {
                let b = found.band;
                m.insert("band_lo".into(), metric(b.map(|b| b.lo)));
                m.insert("band_hi".into(), metric(b.map(|b| b.hi)));
                m.insert("band_width".into(), metric(b.map(|b| b.width())));
                m.insert("clipped".into(), metric(found.clipped()));
            }
        }
    }
    if !warnings.is_empty() {
        m.insert("warnings".into(), metric(warnings));
    }
    Ok(m)
}

/// A previous result of this case with the same input, if it succeeded, the study wrote
/// it and it is a valid record of this case ([`CaseResult::check`]; an invalid one is
/// recomputed).
pub(super) fn finished(dir: &OutDir, case: &Case, hash: &str) -> Option<CaseResult> {
    if !dir.ledger().is_some_and(|l| l.owns("result.json")) {
        return None;
    }
    let r = super::case::read_result(&dir.path(""), case)?.ok()?;
    (r.input_hash == hash && r.status == CaseStatus::Ok).then_some(r)
}
