//! A region search runs to its end within the allowance of evaluations its count before
//! it gives (issue 48, "one account of cost"): `analysis/cost/regions.rs` counts a search
//! from its plan (the seeds it starts from and the guard lattice points it visits, times
//! a seed's evaluations at the default settings), and a run admitted at that count may
//! make [`Budget::allowance`] evaluations, the work limit at the count's cost per
//! evaluation. The searches report every evaluation as they make it
//! ([`Progress::evaluated`]); a search on a bundled problem that a default run would stop
//! fails here, as does a report that is not whole (its count differs from the search's).
//!
//! The requests: a catalogue over 500–3000 rad/s up to β_max = 0.6 with edges at 0.3
//! (every problem), the README's tracked catalogue (Fig. 11, 1000–1500 rad/s, β_max 0.5,
//! level 0.3, boundaries tracked), and the band at φ_op = 1230 rad/s, level 0.3, in its
//! default window (every problem). Ratios count/used are printed: the count is a plan, not
//! a bound, and the allowance, not the count, holds a search that goes further.
//!
//! The last test stops a band at half its own count.

use crate::common;

use rayon::prelude::*;
use rotorshunt::analysis::cost::{self, Estimate, PointCost};
use rotorshunt::analysis::regions::{self, seeds_for, CatalogueRequest};
use rotorshunt::analysis::{Criterion, Interval};
use rotorshunt::problem::Problem;
use rotorshunt::progress::{Deadline, Progress, Silent};
use rotorshunt::run::{Budget, Stopped};

/// The catalogue every problem is searched over: φ (rad/s), β_max and the level (−).
const RANGE: Interval = Interval::new(500.0, 3000.0);
const BETA_MAX: f64 = 0.6;
const LEVEL: f64 = 0.3;
/// The band's operating frequency (rad/s) and its default window (φ_op/20 to 20·φ_op, as
/// `rotorshunt band` takes it).
const PHI_OP: f64 = 1230.0;

/// A running bound with neither a time limit nor an allowance: it only counts.
fn watching() -> Deadline<'static> {
    Deadline::new(&Silent, f64::INFINITY)
}

/// One search's count before, its allowance at the default budget and the evaluations
/// used (and reported to `watch` while it ran): a failure when the search used more than
/// its allowance, or reported other than it used.
fn check(name: &str, what: &str, counted: &Estimate, used: usize, watch: &Deadline<'_>) -> Option<String> {
    let allowance = Budget::default().allowance(counted).unwrap_or(0);
    let c = counted.evaluations;
    println!("{name}: {what}: counted {c:.0}, used {used} ({:.2}×), allowance {allowance}", c / used.max(1) as f64);
    if watch.evaluations() != used as u64 {
        return Some(format!("{name}: {what} used {used} evaluations, reported {}", watch.evaluations()));
    }
    (used as u64 > allowance).then(|| format!("{name}: {what} used {used} evaluations, allowed {allowance}"))
}

/// The catalogue of `req` on `problem`: its count and the search's own.
fn catalogue(name: &str, problem: &Problem, req: &CatalogueRequest) -> Option<String> {
    let op = problem.operating_point().expect("the problem reduces");
    let fs = &op.floquet;
    let criterion = Criterion::of(&fs.settings);
    let seeds = seeds_for(fs, None, req.range, criterion.max_order).expect("seeds");
    let counted = cost::catalogue(&PointCost::of(fs), &op.regions, &criterion, &seeds, req);
    let watch = watching();
    let cat = regions::catalogue_with(fs, &op.modes, &op.regions, req, &watch).expect("the catalogue");
    let what = format!(
        "catalogue {}..{} rad/s, beta_max {}, level {}{}",
        req.range.lo,
        req.range.hi,
        req.beta_max,
        req.level,
        if req.track { ", tracked" } else { "" }
    );
    check(name, &what, &counted, cat.evaluations, &watch)
}

/// The band at [`PHI_OP`] on `problem`: its count and the search's own.
fn band(name: &str, problem: &Problem) -> Option<String> {
    let op = problem.operating_point().expect("the problem reduces");
    let fs = &op.floquet;
    let criterion = Criterion::of(&fs.settings);
    let window = Interval::new(PHI_OP / 20.0, PHI_OP * 20.0);
    let seeds = seeds_for(fs, None, window, criterion.max_order).expect("seeds");
    let counted = cost::band(&PointCost::of(fs), &op.regions, &criterion, &seeds, window, LEVEL);
    let watch = watching();
    let b = regions::band_with(fs, &op.modes, &op.regions, window, PHI_OP, LEVEL, &watch).expect("the band");
    let what = format!("band at phi_op = {PHI_OP} rad/s, level {LEVEL}");
    let failure = check(name, &what, &counted, b.evaluations, &watch);
    // The `band` command's work under one running bound: the band, then its margins (the
    // strict band, not reported, and the load margin's catalogue), within their allowance.
    let pc = PointCost::of(fs);
    let counted = cost::band_and_margins(&pc, &op.regions, &criterion, &seeds, window, LEVEL);
    let labelled = seeds_for(fs, Some(&op.modes), window, criterion.max_order).expect("seeds");
    regions::margins::band_margins(fs, &op.modes, &op.regions, &labelled, &b, window, &watch).expect("margins");
    let reported = watch.evaluations();
    let allowance = Budget::default().allowance(&counted).unwrap_or(0);
    println!(
        "{name}: {what} and its margins: counted {:.0}, reported {reported}, allowance {allowance}",
        counted.evaluations
    );
    failure.or_else(|| {
        (reported > allowance)
            .then(|| format!("{name}: {what} and its margins reported {reported}, allowed {allowance}"))
    })
}

#[test]
fn region_searches_run_to_their_end_within_their_allowance() {
    let names = common::toml_names(&common::root().join("problems"));
    assert!(names.len() >= 20, "the catalogue's problems: {names:?}");
    let req = CatalogueRequest::builder().range(RANGE).beta_max(BETA_MAX).level(LEVEL).build().expect("request");
    // Problems whose model and settings are equal (the design problems on the Fig. 11
    // rotor) are one input: checked once, under the first name.
    let mut distinct: Vec<(String, Problem)> = Vec::new();
    for name in names {
        let p = Problem::from_path(common::root().join("problems").join(&name), &[]).expect("loads");
        if !distinct.iter().any(|(_, q)| q.model == p.model && q.settings == p.settings && q.regions == p.regions) {
            distinct.push((name, p));
        }
    }
    assert!(distinct.len() >= 10, "{} distinct problems", distinct.len());
    let mut failures: Vec<String> = distinct
        .par_iter()
        .flat_map(|(name, problem)| [catalogue(name, problem, &req), band(name, problem)])
        .flatten()
        .collect();
    let fig11 = Problem::from_path(common::root().join("problems/fig11-closed-2000.toml"), &[]).expect("loads");
    let tracked = CatalogueRequest::builder()
        .range(Interval::new(1000.0, 1500.0))
        .beta_max(0.5)
        .level(0.3)
        .track(true)
        .build()
        .expect("request");
    failures.extend(catalogue("fig11-closed-2000.toml", &fig11, &tracked));
    assert!(failures.is_empty(), "searches beyond their allowance:\n{}", failures.join("\n"));
}

#[test]
fn a_search_past_its_allowance_stops_on_its_own_count() {
    let problem = Problem::from_path(common::root().join("problems/fig11-closed-2000.toml"), &[]).expect("loads");
    let op = problem.operating_point().expect("the problem reduces");
    let (fs, window) = (&op.floquet, Interval::new(PHI_OP / 20.0, PHI_OP * 20.0));
    let band =
        |progress: &dyn Progress| regions::band_with(fs, &op.modes, &op.regions, window, PHI_OP, LEVEL, progress);
    let used = band(&Silent).expect("the band").evaluations as u64;
    assert!(used > 20, "a band of {used} evaluations");
    // An allowance of its own count: not stopped.
    let whole = watching().with_allowance(Some(used));
    let again = band(&whole);
    assert!(!whole.tripped(), "stopped at its own count: {whole:?}");
    assert_eq!(again.expect("the band").evaluations as u64, used);
    // Half of it: stopped by the count, before the search's end, and the command's error says so.
    let half = watching().with_allowance(Some(used / 2));
    let _incomplete = band(&half);
    assert!(half.tripped() && half.counted_out(), "{half:?}");
    assert!(half.evaluations() > used / 2 && half.evaluations() < used, "{} of {used}", half.evaluations());
    match Budget::default().stopped(&half, "the band search") {
        Err(Stopped::Count(e)) => {
            assert_eq!((e.allowed, e.used), (used / 2, half.evaluations()));
            let text = e.to_string();
            assert!(
                text.starts_with(&format!("the band search was stopped at its allowance of {} monodromy", used / 2)),
                "{text}"
            );
        }
        other => panic!("not a count stop: {other:?}"),
    }
}
