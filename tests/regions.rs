//! Instability regions as objects, checked against the charts of the Floquet analysis
//! and against theory (issue acceptance).

use crate::common;
use common::load;
use rayon::prelude::*;
use rotorshunt::analysis::floquet::FloquetSystem;
use rotorshunt::analysis::modes::whirl_modes_of;
use rotorshunt::analysis::regions::{
    catalogue, seeds, Catalogue, CatalogueRequest, Probe, RegionSettings, CENTRE_WINDOW,
};
use rotorshunt::analysis::Interval;
use rotorshunt::analysis::Rotor;
use std::sync::OnceLock;

fn prepared(name: &str, overrides: &[&str]) -> (FloquetSystem, rotorshunt::analysis::modes::ModesResult) {
    let p = load(name, overrides);
    let rotor = Rotor::new(&p.model).unwrap();
    let fs = FloquetSystem::new(&rotor, &p.settings, p.model.speed).unwrap();
    let full = whirl_modes_of(&rotor, &p.settings, p.model.speed).unwrap();
    (fs, full)
}

/// The paper's problems: open and closed circuit, Ω = 0 and 2000 rad/s, R = 0 and 50 Ω.
const PAPER_PROBLEMS: [(&str, &[&str]); 5] = [
    ("fig8-eta0.toml", &[]),                       // open, Ω = 0
    ("fig8-eta0.toml", &["circuit.state=closed"]), // closed, Ω = 0, R = 0
    ("fig9-open-2000.toml", &[]),                  // open, Ω = 2000
    ("fig11-closed-2000.toml", &[]),               // closed, Ω = 2000, R = 0
    ("fig13-r50.toml", &[]),                       // closed, Ω = 2000, R = 50 Ω
];

fn unstable(fs: &FloquetSystem, phi: f64, beta: f64) -> bool {
    !fs.point_fast(&fs.table(phi, beta), beta).summary.stable
}

/// Catalogued spans at the level, with the guard scan's unexplained intervals.
fn spans(c: &Catalogue) -> Vec<(f64, f64)> {
    let mut out: Vec<(f64, f64)> = c.regions.iter().filter_map(|r| Some((r.left?, r.right?))).collect();
    out.extend(c.unexplained.iter().map(|e| (e.lo, e.hi)));
    out
}

/// The catalogue request of these tests: φ = 100..8000 rad/s, β_max = 1, at `level`.
fn request(level: f64) -> CatalogueRequest {
    CatalogueRequest { range: Interval::new(100.0, 8000.0), beta_max: 1.0, level, track: false }
}

/// One paper problem at β_op = 0.3, shared by the tests that read it (each computed once
/// per test binary, whichever test asks first): its system, its catalogue, and the verdict
/// of every point of the 1 rad/s chart over 100..8000 rad/s.
struct AtOperatingLevel {
    fs: FloquetSystem,
    cat: Catalogue,
    /// `unstable(fs, 100 + i, 0.3)` for i = 0..=7900.
    unstable: Vec<bool>,
}

impl AtOperatingLevel {
    /// The verdict at a point of the 1 rad/s grid.
    fn unstable_at(&self, phi: f64) -> bool {
        let i = phi - 100.0;
        assert!(i.fract() == 0.0 && (0.0..=7900.0).contains(&i), "{phi} is not on the grid");
        self.unstable[i as usize]
    }
}

/// [`AtOperatingLevel`] of `PAPER_PROBLEMS[k]`.
fn at_operating_level(k: usize) -> &'static AtOperatingLevel {
    static CELLS: [OnceLock<AtOperatingLevel>; 5] = [const { OnceLock::new() }; 5];
    CELLS[k].get_or_init(|| {
        let (name, overrides) = PAPER_PROBLEMS[k];
        let (fs, full) = prepared(name, overrides);
        let cat = catalogue(&fs, &full, &RegionSettings::default(), &request(0.3)).unwrap();
        let unstable = (0..=7900).into_par_iter().map(|i| unstable(&fs, 100.0 + i as f64, 0.3)).collect();
        AtOperatingLevel { fs, cat, unstable }
    })
}

#[test]
fn undamped_starts_are_sums_of_whirl_frequencies() {
    // At zero damping every region starts on (ω_i + ω_j)/k: the located start (minimum of
    // β_c, found numerically) agrees with the prediction to 0.1 %.
    for (k, (name, overrides)) in PAPER_PROBLEMS.into_iter().enumerate().filter(|(_, (n, _))| *n != "fig13-r50.toml") {
        let c = &at_operating_level(k).cat;
        let resolved: Vec<_> = c.regions.iter().filter(|r| r.resolved).collect();
        assert!(resolved.len() >= 5, "{name}: {} resolved regions", resolved.len());
        for r in &resolved {
            assert!(
                (r.start / r.predicted - 1.0).abs() < 1e-3,
                "{name} {}: start {} vs {}",
                r.label,
                r.start,
                r.predicted
            );
        }
        // The main regions of section 5 are there, with their labels.
        let has = |l: &str| c.regions.iter().any(|r| r.label == l && r.order == 1 && r.resolved);
        match name {
            "fig8-eta0.toml" if overrides.is_empty() => {
                assert!(has("2 n1") && has("n1+n2") && has("2 n2"), "{:?}", labels(c))
            }
            "fig8-eta0.toml" => assert!(has("2 n1") && has("n1+r1") && has("2 n2"), "{:?}", labels(c)),
            "fig9-open-2000.toml" => assert!(has("f1+b1") && has("f2+b2") && has("f1+b2"), "{:?}", labels(c)),
            _ => assert!(has("f1+b1") && has("f1+r2") && has("r2+b1"), "{:?}", labels(c)),
        }
    }
}

fn labels(c: &Catalogue) -> Vec<String> {
    c.regions.iter().map(|r| format!("{}/{}", r.label, r.order)).collect()
}

#[test]
fn catalogue_covers_the_floquet_chart_on_every_paper_problem() {
    // The chart of the Floquet analysis (φ step 25 rad/s, as Figs. 8-13 are computed) at
    // four levels up to β_max = 1: every unstable chart point lies in a catalogued region
    // (to within the 1 rad/s edge check), on each of the paper's five problems.
    // The five problems in parallel, and the chart's points (the machine's cores).
    PAPER_PROBLEMS.par_iter().for_each(|&(name, overrides)| {
        let (fs, full) = prepared(name, overrides);
        for level in [0.25, 0.5, 0.75, 1.0] {
            let c = catalogue(&fs, &full, &RegionSettings::default(), &request(level)).unwrap();
            let spans = spans(&c);
            let missed: Vec<f64> = (0..=316)
                .into_par_iter()
                .map(|i| 100.0 + 25.0 * i as f64)
                .filter(|&phi| unstable(&fs, phi, level))
                .filter(|&phi| !spans.iter().any(|(l, r)| phi >= l - 1.0 && phi <= r + 1.0))
                .collect();
            assert!(
                missed.is_empty(),
                "{name} {overrides:?} β = {level}: chart points outside every region: {missed:?}"
            );
        }
    });
}

#[test]
fn catalogue_covers_a_fine_chart_at_the_operating_level() {
    // A 1 rad/s chart at β_op = 0.3 on each paper problem: every unstable grid point lies
    // in a catalogued region, unless its unstable interval is narrower than the catalogue's
    // φ resolution (`phi_tolerance`, 0.2 rad/s), measured with tight settings. Regions of
    // every order are there, labelled with their pair and order, each found within the
    // centre search's window of its predicted start (ω_i + ω_j)/k.
    let s = RegionSettings::default();
    let precise = RegionSettings::precise();
    let mut orders = std::collections::BTreeSet::new();
    for (k, (name, overrides)) in PAPER_PROBLEMS.into_iter().enumerate() {
        let at = at_operating_level(k);
        let (fs, c) = (&at.fs, &at.cat);
        let spans = spans(c);
        let mut below_resolution = Vec::new();
        for phi in (0..=7900).map(|i| 100.0 + i as f64) {
            if !at.unstable_at(phi) || spans.iter().any(|(l, r)| phi >= l - 1.0 && phi <= r + 1.0) {
                continue;
            }
            let e = Probe::new(fs, &precise).edges(phi, 0.3);
            assert!(
                e.hi - e.lo < s.phi_tolerance,
                "{name} {overrides:?}: unstable [{}, {}] outside every region",
                e.lo,
                e.hi
            );
            below_resolution.push((phi, e.hi - e.lo));
        }
        let (f, b) = fs.whirls().unwrap();
        for r in &c.regions {
            let sums: Vec<f64> = f.iter().flat_map(|x| b.iter().map(move |y| (x + y) / r.order as f64)).collect();
            assert!(
                !r.label.is_empty() && sums.iter().any(|&p| (p - r.predicted).abs() < 1e-9 * p),
                "{name}: {} / {} predicted {}",
                r.label,
                r.order,
                r.predicted
            );
            if let (Some(l), Some(h)) = (r.left, r.right) {
                let window = CENTRE_WINDOW * r.predicted;
                assert!(
                    l <= r.predicted + window && h >= r.predicted - window,
                    "{name}: {} far from its seed",
                    r.label
                );
            }
            orders.insert(r.order);
        }
        eprintln!("{name} {overrides:?}: {} regions; below resolution: {below_resolution:?}", c.regions.len());
    }
    assert!(orders.iter().any(|&k| k >= 5), "orders found: {orders:?}");
}

#[test]
fn catalogued_edges_match_a_fine_chart_at_the_level() {
    // Fine grid along φ (step 1 rad/s) at β_op = 0.3 on each paper problem: every grid
    // point more than one step inside a region's [left, right] is unstable, and each region
    // edge has a stable grid point within one step outside it unless another region
    // continues there.
    for (k, (name, overrides)) in PAPER_PROBLEMS.into_iter().enumerate() {
        let at = at_operating_level(k);
        let (fs, c) = (&at.fs, &at.cat);
        let spans: Vec<(f64, f64)> = c.regions.iter().filter_map(|r| Some((r.left?, r.right?))).collect();
        let wrong: Vec<f64> = (0..=7900)
            .map(|i| 100.0 + i as f64)
            .filter(|&phi| spans.iter().any(|(l, r)| phi > l + 1.0 && phi < r - 1.0))
            .filter(|&phi| !at.unstable_at(phi))
            .collect();
        assert!(wrong.is_empty(), "{name} {overrides:?}: stable grid points inside a region: {wrong:?}");
        for (l, r) in &spans {
            for (outside, what) in [(l - 1.0, "left"), (r + 1.0, "right")] {
                let covered = spans.iter().any(|(a, b)| outside >= a - 0.5 && outside <= b + 0.5);
                if !covered && outside > 100.0 && outside < 8000.0 {
                    assert!(!unstable(fs, outside, 0.3), "{name}: {what} edge of [{l}, {r}]: {outside} unstable");
                }
            }
        }
        // The stable bands are the complement: a point in a band's interior is stable.
        for b in &c.stable_bands {
            if b.width() > 4.0 {
                assert!(!unstable(fs, b.centre(), 0.3), "{name}: band {b:?}");
            }
        }
    }
}

#[test]
fn tracked_edges_agree_with_the_grid_within_one_step() {
    // Continuation from the start upward: at every tracked level the points one grid
    // step (1 rad/s) outside each edge are stable and one step inside are unstable.
    let (fs, full) = prepared("fig9-open-2000.toml", &[]);
    let s = RegionSettings::default();
    let seeds = seeds(&fs, Some(&full), Interval::new(100.0, 8000.0), 1).unwrap();
    let mut checked = 0;
    for label in ["f1+b2", "f2+b1", "f2+b2"] {
        let seed = seeds.iter().find(|x| x.label == label).unwrap();
        let probe = Probe::new(&fs, &s);
        let st = probe.locate_start(seed.phi, 0.003 * seed.phi, 1.0, 1.0).unwrap();
        assert!(st.resolved);
        let boundary = probe.track(st.phi, st.onset, 0.6);
        assert!(boundary.len() >= 4, "{label}: {} levels", boundary.len());
        for e in &boundary {
            let u = |phi: f64| !fs.point_fast(&fs.table(phi, e.beta), e.beta).summary.stable;
            assert!(!u(e.phi.lo - 1.0) && u(e.phi.lo + 1.0), "{label} left edge {} at β = {}", e.phi.lo, e.beta);
            assert!(u(e.phi.hi - 1.0) && !u(e.phi.hi + 1.0), "{label} right edge {} at β = {}", e.phi.hi, e.beta);
            checked += 1;
        }
        eprintln!("{label}: {} levels tracked with {} monodromy evaluations", boundary.len(), probe.evaluations());
    }
    assert!(checked >= 12);
}

#[test]
fn critical_load_by_bisection_matches_a_dense_scan() {
    // β_c(φ) from bracketing + bisection (tolerance 1e-4) against a dense scan of β at
    // step 0.001: they agree to the scan step plus the tolerance.
    let (fs, _) = prepared("fig11-closed-2000.toml", &[]);
    let s = RegionSettings::default();
    for phi in [600.0, 703.0, 1185.0, 2060.0, 2500.0, 3550.0, 5241.79] {
        let c = Probe::new(&fs, &s).critical_load(phi, 1.0);
        let table = fs.table(phi, 1.0);
        let dense = (0..=1000).map(|i| i as f64 * 0.001).find(|&b| !fs.point_fast(&table, b).summary.stable);
        match (c.beta, dense) {
            (Some(a), Some(b)) => {
                assert!((a - b).abs() <= 0.001 + s.beta_tolerance, "φ = {phi}: bisection {a}, scan {b}")
            }
            (None, None) => {}
            other => panic!("φ = {phi}: {other:?}"),
        }
    }
}

#[test]
fn damping_and_resistance_lift_the_onsets() {
    // Figs. 8 and 13: the onset of the n1+n2 region rises with η = 0, 200, 4000 N·s/m, and
    // that of the f1+r2 region with R = 0, 10, 50 Ω.
    let s = RegionSettings::default();
    let onset = |name: &str, label: &str| {
        let (fs, full) = prepared(name, &[]);
        let seed = seeds(&fs, Some(&full), Interval::new(100.0, 8000.0), 1)
            .unwrap()
            .into_iter()
            .find(|x| x.label == label)
            .unwrap();
        Probe::new(&fs, &s).locate_start(seed.phi, 0.003 * seed.phi, 1.0, 1.0).unwrap().onset
    };
    let eta: Vec<f64> =
        ["fig8-eta0.toml", "fig8-eta200.toml", "fig8-eta4000.toml"].iter().map(|n| onset(n, "n1+n2")).collect();
    assert!(eta[0] < eta[1] && eta[1] < eta[2], "onsets over η: {eta:?}");
    let r: Vec<f64> =
        ["fig11-closed-2000.toml", "fig13-r10.toml", "fig13-r50.toml"].iter().map(|n| onset(n, "f1+r2")).collect();
    assert!(r[0] < r[1] && r[1] < r[2], "onsets over R: {r:?}");
    eprintln!("onsets: η {eta:?}, R {r:?}");
}
