//! The stable band is true (issue acceptance): for `band` on every problem in problems/ at
//! φ_op = 300, 700, 1230, 1800 and 2500 rad/s and β_op = 0.1, 0.3 and 0.6,
//! 1. the Floquet point at the centre of every tongue inside the reported band of the
//!    catalogue of the band's neighbourhood at β_op (below) is stable by the declared
//!    criterion;
//! 2. no Floquet point inside the band counts by the criterion, on the points below, and
//!    the 0.05 rad/s grid finds an unstable point within 0.5 rad/s beyond each finite edge
//!    (edges at the window's limit are exempt);
//! 3. each finite edge is named by the lowest-order counted region of that catalogue whose
//!    edge facing the band is that edge (issue 27, point 7),
//!    `unlabelled` (with its exponent frequency) only when none is.
//!
//! The points of 2 inside a band (issue 30: the same check with fewer points): a scan
//! every [`SCAN`] = 0.1 rad/s over the whole band, and the 0.05 rad/s grid of the
//! acceptance where that catalogue puts a tongue: within
//! 0.1 rad/s of every catalogued tongue (each region's extent at β_op, the unexplained and
//! the ignored tongues), within the start window of every catalogued region's start (where
//! a tongue opens, thin, just above its onset), and within 0.1 rad/s inside each edge.
//! Why that still finds a counted point inside a band: the point lies in a tongue. A
//! tongue at least 0.1 rad/s wide inside the band holds a point of the scan, whether or
//! not any seed explains it (the spurious tongues this grid exists for, such as the fast
//! path's aliasing, docs/decisions.md); one that crosses an edge has points in the edge
//! strip; one thinner than 0.1 rad/s is on the 0.05 rad/s grid wherever the catalogue
//! lists it or its region's start (the thin tongues of orders 3–8, 0.1–0.2 rad/s at
//! β_op, and those thinner than the grid, printed below). What the full grid would see
//! and this does not: a tongue 0.05–0.1 rad/s wide that no catalogued tongue or region
//! start is near. The full grid over every band was 887 018 Floquet points, about 120 of
//! the binary's 210 CPU-seconds here; the points now checked are printed with that count.
//! A grid point checked at several levels is one row of the fast path, as in a chart: one
//! per-φ table, built for the highest of those levels, and a monodromy per level (the
//! same verdicts as a table per point; 246 000 tables for 451 000 points, about 7 of the
//! test's 100 CPU-seconds saved).
//!
//! The neighbourhood (issue 30, the same checks for less): the band and the whole of each
//! tongue bounding it (marched from the tongue's counted point the band reports), widened
//! by [`NEAR`](common::scan::NEAR) = 10 % on each side, as far as the centre search looks for a seed's tongue;
//! overlapping neighbourhoods of one level are merged and catalogued once. Every seed whose
//! tongue has an edge of the band, or lies inside it, is in the reach of that catalogue,
//! and the edges it reports are lattice-refined numbers that do not depend on the window
//! searched, so checks 1–3 read the same tongues as in the catalogue of the whole window
//! 100–8000 rad/s, which was half of this test's 190 CPU-seconds here.
//!
//! The reference for 2 is plain Floquet points, independent of the band's search. A
//! bounding tongue thinner than the grid spacing can fall between grid points; then the
//! tongue's own counted point (reported by the band) must lie within 0.5 rad/s beyond the
//! edge and be unstable by the reference DSTM path, and such cases are printed.
//!
//! Problems whose model and `[analysis]` settings are equal (the design problems on the
//! Fig. 11 rotor) are one input to these checks, checked once for the group.

use crate::common;

use common::scan::{band_points, catalogued_windows, grid, neighbourhood, GRID};
use rayon::prelude::*;
use rotorshunt::analysis::floquet::FloquetSystem;
use rotorshunt::analysis::modes::{whirl_modes_of, ModesResult};
use rotorshunt::analysis::regions::{
    band, catalogue, Band, Bound, Catalogue, CatalogueRequest, Level, Probe, RegionSettings,
};
use rotorshunt::analysis::{Criterion, Interval, Rotor};
use rotorshunt::problem::Problem;
use std::collections::HashMap;

/// A band the search is known to get wrong: an unstable tongue inside it that the search
/// does not look for. Each must still be found here exactly (its unstable grid points all
/// inside `tongue`), so a fix shows up as a failure that asks for its removal.
struct KnownMiss {
    /// A problem of the group (its file name).
    problem: &'static str,
    level: f64,
    phi_op: f64,
    /// Where the missed tongue lies at the level (rad/s).
    tongue: Interval,
}

/// The known misses: difference-type combination tongues (|ω_i − ω_j|/k of two whirls of
/// one direction), which only a damped model has and the seeds (sum type) do not predict;
/// docs/regions.md, "What the band does not search". On the Fig. 11 rotor with η = 200
/// N·s/m at β = 0.1, a tongue at 2303.4–2306.6 rad/s with growth rate 8.4e-4 1/s (the
/// reference DSTM agrees: ln max|μ| = 2.29e-6 at 2303.6 rad/s, M = 24).
const KNOWN_MISSES: [KnownMiss; 1] = [KnownMiss {
    problem: "design-min-peak-at-speed.toml",
    level: 0.1,
    phi_op: 2500.0,
    tongue: Interval::new(2303.0, 2307.0),
}];

const PHI_OPS: [f64; 5] = [300.0, 700.0, 1230.0, 1800.0, 2500.0];
const LEVELS: [f64; 3] = [0.1, 0.3, 0.6];
/// The window of every band and catalogue: the φ range of the paper's charts (rad/s).
const WINDOW: Interval = Interval::new(100.0, 8000.0);
/// The reach beyond an edge (rad/s), from the acceptance.
const BEYOND: f64 = 0.5;
/// Two routes to the same lattice-refined edge give the same number; only round-off may
/// separate them (rad/s), as for the band's own naming.
const SAME_EDGE: f64 = 1e-9;

/// The union of `intervals` as disjoint intervals, ascending.
fn merged(intervals: impl Iterator<Item = Interval>) -> Vec<Interval> {
    let mut v: Vec<Interval> = intervals.collect();
    v.sort_by(|a, b| a.lo.total_cmp(&b.lo));
    let mut out: Vec<Interval> = Vec::new();
    for i in v {
        match out.last_mut() {
            Some(last) if i.lo <= last.hi => *last = Interval::new(last.lo, last.hi.max(i.hi)),
            _ => out.push(i),
        }
    }
    out
}

/// Every problem file of the catalogue (top level of problems/).
fn problems() -> Vec<String> {
    common::toml_names(&common::root().join("problems"))
}

/// What one problem's checks found.
#[derive(Default)]
struct Report {
    checked: usize,
    thin: Vec<String>,
    failures: Vec<String>,
    /// Points of the full 0.05 rad/s grid over the bands and beyond their edges, points
    /// checked (both counted once per band), Floquet points evaluated (a point shared by
    /// the bands of several φ_op at one level is evaluated once) and the per-φ tables
    /// they took (one for the levels that share a grid point).
    full_grid: usize,
    total_points: usize,
    evaluated: usize,
    tables: usize,
    named: usize,
    unlabelled: usize,
    /// Bands that showed a known miss ([`KNOWN_MISSES`]) as recorded.
    known: usize,
}

/// What checks 1–3 read of one stable band: the catalogue of its neighbourhood and the
/// grid points of check 2.
struct BandPoints<'a> {
    cat: &'a Catalogue,
    /// Inside the band: the scan and the grid near the catalogue's tongues.
    inside: Vec<i64>,
    /// Beyond each edge a tongue bounds.
    beyond: Vec<Beyond<'a>>,
}

/// The grid points within [`BEYOND`] of a band's edge, outside it.
struct Beyond<'a> {
    points: Vec<i64>,
    /// The edge (rad/s) and its direction (−1 below the band, +1 above).
    edge: f64,
    dir: f64,
    bound: &'a Bound,
}

impl BandPoints<'_> {
    /// Every grid point of check 2 of the band.
    fn all(&self) -> impl Iterator<Item = i64> + '_ {
        self.inside.iter().chain(self.beyond.iter().flat_map(|b| &b.points)).copied()
    }
}

/// One level's bands (one per φ_op) and the catalogues of their neighbourhoods (each
/// band widened by NEAR on both sides, overlapping ones merged): one catalogue per merged
/// neighbourhood, with the windows of check 2 it gives.
struct AtLevel {
    level: f64,
    bands: Vec<Band>,
    catalogues: Vec<(Interval, Catalogue, Vec<Interval>)>,
}

impl AtLevel {
    fn new(fs: &FloquetSystem, full: &ModesResult, s: &RegionSettings, criterion: Criterion, level: f64) -> AtLevel {
        let bands: Vec<Band> =
            PHI_OPS.iter().map(|&phi_op| band(fs, full, s, WINDOW, phi_op, level).unwrap()).collect();
        let probe = Probe::new(fs, s);
        let at_level = Level::new(&probe, criterion, level, WINDOW);
        let near: Vec<Interval> = merged(bands.iter().filter_map(|b| {
            let f = b.band?;
            // The band and the whole of each bounding tongue: every seed whose tongue has
            // the band's edge is then in the catalogue's reach.
            let (mut lo, mut hi) = (f.lo, f.hi);
            for bound in [&b.left, &b.right] {
                if let Some(Bound::Tongue { inside, .. }) = bound {
                    if let Some(t) = at_level.extent(*inside) {
                        (lo, hi) = (lo.min(t.lo), hi.max(t.hi));
                    }
                }
            }
            Some(neighbourhood(lo, hi, WINDOW))
        }));
        let catalogues = near
            .par_iter()
            .map(|&range| {
                let req = CatalogueRequest { range, beta_max: level, level, track: false };
                let cat = catalogue(fs, full, s, &req).unwrap();
                let windows = catalogued_windows(&cat);
                (range, cat, windows)
            })
            .collect();
        AtLevel { level, bands, catalogues }
    }

    /// What checks 1–3 read of each band, in the order of `bands` (None where φ_op is
    /// unstable): the catalogue whose neighbourhood holds the band, and its points.
    fn points(&self) -> Vec<Option<BandPoints<'_>>> {
        self.bands
            .iter()
            .map(|b| {
                let found = b.band?;
                let (_, cat, windows) =
                    self.catalogues.iter().find(|(range, _, _)| range.lo <= found.lo && found.hi <= range.hi).unwrap();
                let beyond = [(&b.left, found.lo, -1.0), (&b.right, found.hi, 1.0)]
                    .into_iter()
                    .filter_map(|(bound, edge, dir)| {
                        let bound = bound.as_ref().filter(|b| matches!(b, Bound::Tongue { .. }))?;
                        let (lo, hi) =
                            if dir < 0.0 { (edge - BEYOND, edge + 1e-9) } else { (edge - 1e-9, edge + BEYOND) };
                        Some(Beyond { points: grid(lo, hi), edge, dir, bound })
                    })
                    .collect();
                Some(BandPoints { cat, inside: band_points(found.lo, found.hi, windows), beyond })
            })
            .collect()
    }
}

/// Whether each grid point counts at each level that checks it, evaluated once per point
/// and level, and with one per-φ table for the levels that share a point (a row of the
/// fast path, as a chart's: the same point as alone, up to the interpolant's 1e-11).
fn verdicts(fs: &FloquetSystem, criterion: Criterion, wanted: &[Vec<i64>]) -> (HashMap<(i64, usize), bool>, usize) {
    let mut levels_of: HashMap<i64, Vec<usize>> = HashMap::new();
    for (i, ks) in wanted.iter().enumerate() {
        for &k in ks {
            let at = levels_of.entry(k).or_default();
            if !at.contains(&i) {
                at.push(i);
            }
        }
    }
    let rows: Vec<(i64, Vec<usize>)> = levels_of.into_iter().collect();
    let found: Vec<Vec<((i64, usize), bool)>> = rows
        .par_iter()
        .map(|(k, at)| {
            let phi = *k as f64 * GRID;
            let top = at.iter().map(|&i| LEVELS[i]).fold(0.0, f64::max);
            let table = fs.table(phi, top);
            at.iter().map(|&i| ((*k, i), criterion.counts(&fs.point_fast(&table, LEVELS[i]).summary))).collect()
        })
        .collect();
    (found.into_iter().flatten().collect(), rows.len())
}

/// The checks of the module's doc on one problem, every φ_op and level (`name` names it
/// in the messages: the problems of the group that share its model and settings).
fn check_problem(name: &str, p: &Problem) -> Report {
    let s = RegionSettings::default();
    let mut r = Report::default();
    let rotor = Rotor::new(&p.model).unwrap();
    let fs = FloquetSystem::new(&rotor, &p.settings, p.model.speed).unwrap();
    let full = whirl_modes_of(&rotor, &p.settings, p.model.speed).unwrap();
    let criterion = Criterion::of(&p.settings);
    let counts = |phi: f64, beta: f64| criterion.counts(&fs.point_fast(&fs.table(phi, beta), beta).summary);
    let at_levels: Vec<AtLevel> = LEVELS.iter().map(|&level| AtLevel::new(&fs, &full, &s, criterion, level)).collect();
    // The grid points of every band at every level, each evaluated once per level.
    let points: Vec<_> = at_levels.iter().map(AtLevel::points).collect();
    let wanted: Vec<Vec<i64>> =
        points.iter().map(|bands| bands.iter().flatten().flat_map(BandPoints::all).collect()).collect();
    let (verdict, tables) = verdicts(&fs, criterion, &wanted);
    r.evaluated = verdict.len();
    r.tables = tables;
    for (i, (at, band_points)) in at_levels.iter().zip(&points).enumerate() {
        let level = at.level;
        let counted = |ks: &[i64]| -> Vec<i64> { ks.iter().copied().filter(|&k| verdict[&(k, i)]).collect() };
        for ((&phi_op, b), band_points) in PHI_OPS.iter().zip(&at.bands).zip(band_points) {
            let (Some(found), Some(BandPoints { cat, inside, beyond })) = (b.band, band_points) else {
                // φ_op unstable: it must count, and lie in the reported tongue.
                let t = b.containing.unwrap();
                if !counts(phi_op, level) || !t.contains(phi_op) {
                    r.failures.push(format!("{name} β {level} φ_op {phi_op}: unstable claim {t:?} wrong"));
                }
                continue;
            };
            r.checked += 1;
            // 1. Centres of catalogued tongues inside the band.
            let mut tongues: Vec<Interval> =
                cat.regions.iter().filter_map(|r| Some(Interval::new(r.left?, r.right?))).collect();
            tongues.extend(cat.unexplained.iter().copied());
            for t in tongues.iter().filter(|t| found.lo < t.centre() && t.centre() < found.hi) {
                if counts(t.centre(), level) {
                    r.failures
                        .push(format!("{name} β {level} φ_op {phi_op}: catalogued tongue {t:?} inside {found:?}"));
                }
            }
            // 3. Each finite edge named by the lowest-order counted region of this
            //    catalogue whose facing edge is the band's edge (issue 27, point 7).
            for (bound, below) in [(&b.left, true), (&b.right, false)] {
                let Some(Bound::Tongue { edge, label, unexplained, .. }) = bound else { continue };
                r.named += 1;
                let want = cat
                    .regions
                    .iter()
                    .filter(|r| r.counted)
                    .filter(|r| {
                        let facing = if below { r.right } else { r.left };
                        facing.is_some_and(|f| (f - edge).abs() <= SAME_EDGE)
                    })
                    .min_by(|a, b| a.order.cmp(&b.order).then_with(|| a.label.cmp(&b.label)))
                    .map(|r| format!("{} (k = {})", r.label, r.order));
                let case = format!("{name} β {level} φ_op {phi_op} edge {edge}");
                match want {
                    Some(w) if &w == label => {}
                    Some(w) => r.failures.push(format!("{case}: named {label}, the catalogue's lowest order is {w}")),
                    None if label == "unlabelled" && unexplained.is_some() => r.unlabelled += 1,
                    None => r.failures.push(format!("{case}: named {label}, no catalogued tongue has the edge")),
                }
            }
            // 2. The scan and the grid near catalogued tongues over the band, and the grid
            //    BEYOND on each side.
            r.full_grid += grid(found.lo, found.hi).len();
            r.total_points += inside.len();
            let bad: Vec<f64> = counted(inside).into_iter().map(|k| k as f64 * GRID).collect();
            let known =
                KNOWN_MISSES.iter().find(|m| name.contains(m.problem) && m.level == level && m.phi_op == phi_op);
            match known {
                Some(m) if !bad.is_empty() && bad.iter().all(|&x| m.tongue.contains(x)) => {
                    eprintln!(
                        "KNOWN MISS {name} β {level} φ_op {phi_op}: {} unstable grid points in [{}, {}] inside {found:?} (a difference-type tongue, docs/regions.md)",
                        bad.len(),
                        m.tongue.lo,
                        m.tongue.hi
                    );
                    r.known += 1;
                }
                Some(_) => r.failures.push(format!(
                    "{name} β {level} φ_op {phi_op}: the known miss is not as recorded (band {found:?}, unstable grid points {:?}): update KNOWN_MISSES",
                    &bad[..bad.len().min(5)]
                )),
                None => {}
            }
            if !bad.is_empty() && known.is_none() {
                r.failures.push(format!(
                    "{name} β {level} φ_op {phi_op}: band {found:?} has {} unstable grid points, first {:?}",
                    bad.len(),
                    &bad[..bad.len().min(5)]
                ));
            }
            for Beyond { points: ks, edge, dir, bound } in beyond {
                let Bound::Tongue { inside: point, label, .. } = bound else { continue };
                r.full_grid += ks.len();
                r.total_points += ks.len();
                if !counted(ks).is_empty() {
                    continue;
                }
                // A tongue thinner than the grid: its own point, by the reference path.
                let dstm = fs.point_dstm(*point, level, p.settings.reference_steps).summary;
                let close = (point - edge) * dir >= 0.0 && (point - edge).abs() <= BEYOND;
                if close && criterion.counts(&dstm) {
                    r.thin.push(format!("{name} β {level} φ_op {phi_op}: {label} at {point:.4} (edge {edge:.4})"));
                } else {
                    r.failures.push(format!(
                        "{name} β {level} φ_op {phi_op}: no unstable point within {BEYOND} rad/s beyond edge {edge} ({label}, point {point}, DSTM max|mu| {})",
                        dstm.max_multiplier
                    ));
                }
            }
        }
    }
    r
}

#[test]
#[ignore = "a sweep over problems/ (every problem x 5 phi_op x 3 levels, about 80 s on 2 cores); tests/held_out_band.rs checks the same rule in CI on held-out rotors; run by hand: cargo test --release --test suite -- --ignored band_is_true_on_every_problem"]
fn band_is_true_on_every_problem() {
    // What the checks read of a problem is its model and its `[analysis]` settings (the
    // band and the catalogue run with the default region settings): problems equal in
    // both (the design problems built on the Fig. 11 rotor, for instance, which differ
    // only in their `[design]` tables) are checked once, as one group, since the same
    // computation on the same input gives the same result bit for bit
    // (tests/reproducibility.rs).
    let mut groups: Vec<(Vec<String>, Problem)> = Vec::new();
    for name in problems() {
        let p = common::load(&name, &[]);
        match groups.iter_mut().find(|(_, q)| q.model == p.model && q.settings == p.settings) {
            Some((names, _)) => names.push(name),
            None => groups.push((vec![name], p)),
        }
    }
    let files: usize = groups.iter().map(|(names, _)| names.len()).sum();
    eprintln!("{files} problems, {} distinct models and settings:", groups.len());
    // The groups in parallel (each band and catalogue search is sequential), the grid
    // points of each band too.
    let reports: Vec<Report> = groups
        .par_iter()
        .map(|(names, p)| {
            let r = check_problem(&names.join(" = "), p);
            eprintln!(
                "  {}: {} bands, {} grid points evaluated on {} per-phi tables",
                names.join(", "),
                r.checked,
                r.evaluated,
                r.tables
            );
            r
        })
        .collect();
    let mut all = Report::default();
    for r in reports {
        all.checked += r.checked;
        all.thin.extend(r.thin);
        all.failures.extend(r.failures);
        all.full_grid += r.full_grid;
        all.total_points += r.total_points;
        all.evaluated += r.evaluated;
        all.tables += r.tables;
        all.named += r.named;
        all.unlabelled += r.unlabelled;
        all.known += r.known;
    }
    let Report { checked, thin, failures, full_grid, total_points, evaluated, tables, named, unlabelled, known } = all;
    eprintln!(
        "{checked} bands checked, {total_points} points ({evaluated} evaluated, on {tables} per-phi tables) where the full 0.05 rad/s grid has {full_grid}; bounded by tongues thinner than the grid: {thin:#?}"
    );
    eprintln!("{named} finite edges named, {unlabelled} of them unlabelled (no catalogued tongue with the edge)");
    assert!(failures.is_empty(), "{} failures:\n{}", failures.len(), failures.join("\n"));
    // Every known miss was seen as recorded: one that no longer shows was fixed.
    assert_eq!(known, KNOWN_MISSES.len(), "a known miss no longer shows: remove it from KNOWN_MISSES");
    assert!(checked >= 60, "only {checked} stable bands checked");
    assert!(groups.len() >= 10, "only {} distinct problems", groups.len());
}
