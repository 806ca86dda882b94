//! Independent verification of a design's result, and the per-speed content of its
//! report (whirls and the full region catalogue).
//!
//! A result is verified at every operating speed by three checks that share nothing with
//! the optimiser's incremental state:
//! 1. the full catalogue of the design over the design's φ range (every seed of every
//!    order up to the criterion's, and the guard lattice): its stable band around φ_op
//!    must be the band reported (the same numbers), and none of its counted tongues may
//!    reach into the band or a widened operating band;
//! 2. the Floquet point by the reference DSTM path (Eq. 26–27) at the centre of every
//!    catalogued tongue near the band: none inside the band may count as unstable;
//! 3. a grid chart at [`GRID_STEP`] over the band (or each widened operating band): no
//!    grid point may count as unstable.
//!
//! A design that fails any check is reported as not verified, never as improved.

use super::evaluate::{Candidate, OperatingBand};
use super::spec::{DesignSpec, MarginSpec, Objective};
use super::DesignError;
use crate::analysis::floquet::FloquetSystem;
use crate::analysis::modes::{whirl_modes_of, Whirl};
use crate::analysis::regions::{
    band_around, catalogue_with, margins, seeds_for, Band, Catalogue, CatalogueRequest, Counter, Level, Margins, Probe,
    RegionSettings,
};
use crate::analysis::{Criterion, Interval};
use crate::progress::Progress;
use rayon::prelude::*;
use serde::Serialize;

/// Spacing of the verification grid (rad/s): a twentieth of the 1 rad/s charts of the
/// paper's figures, fine enough to see the 0.1 rad/s tongues of order 3–5 at β = 0.3.
pub const GRID_STEP: f64 = 0.05;
/// Most grid points per window; a wider window gets a proportionally coarser grid.
pub const MAX_GRID_POINTS: usize = 40_000;
/// Tongues within this fraction of φ_op (or of a band's centre) outside the band are
/// "near": their centres are checked.
pub const NEAR: f64 = 0.1;
/// Agreement asked of two computations of the same band edge (rad/s): the lattice-refined
/// edges are the same numbers, so only round-off may separate them.
pub const SAME_EDGE: f64 = 1e-9;

/// A whirl frequency, for the report.
#[derive(Debug, Clone, Serialize)]
pub struct WhirlRow {
    /// `f1`, `b1`, `fr1`, …
    pub tag: String,
    /// Frequency (rad/s).
    pub frequency: f64,
}

/// The Floquet point at a catalogued tongue's centre by the reference path.
#[derive(Debug, Clone, Serialize)]
pub struct CentreCheck {
    /// The tongue's label (or `unlabelled`).
    pub label: String,
    /// Its centre (rad/s).
    pub phi: f64,
    /// max|μ| there by the DSTM (−).
    pub max_multiplier: f64,
    /// Whether that counts as unstable by the criterion.
    pub unstable: bool,
    /// Whether the centre lies inside the band (or a widened operating band).
    pub inside: bool,
}

/// The grid chart over one window.
#[derive(Debug, Clone, Serialize)]
pub struct GridCheck {
    /// The window (rad/s).
    pub window: Interval,
    /// Grid spacing (rad/s).
    pub step: f64,
    /// Grid points evaluated (interior points of the window).
    pub points: usize,
    /// Points that count as unstable (rad/s).
    pub unstable: Vec<f64>,
}

/// A design at one operating speed: whirls, catalogue and, for the result, its checks.
#[derive(Debug, Clone, Serialize)]
pub struct DesignAtSpeed {
    /// Ω (rad/s).
    pub speed: f64,
    /// The lowest forward and backward whirls at this speed (rad/s).
    pub whirls: Vec<WhirlRow>,
    /// Region catalogue at β_op over the design's φ range.
    pub catalogue: Catalogue,
    /// The catalogue's stable band around φ_op (widest-stable-band).
    pub catalogue_band: Option<Interval>,
    /// The band around φ_op with the seeds labelled after the full model's whirls (the
    /// optimiser's are labelled by frequency only; the numbers are the same).
    pub band: Option<Band>,
    /// Reference-path points at the centres of the catalogued tongues near the band(s).
    pub centres: Vec<CentreCheck>,
    /// Grid charts over the band or the widened operating bands.
    pub grids: Vec<GridCheck>,
    /// The margins of the band around φ_op ([`crate::analysis::regions::margins`]): load
    /// margin from this catalogue's regions (onsets up to the design's β_max), frequency
    /// margins, the largest max|μ| sampled inside and the strict-criterion band.
    pub margins: Option<Margins>,
    /// For the result with `[design.margins]`: the check at the margin level.
    pub margin_check: Option<MarginCheck>,
    /// What failed, in words (empty when verified).
    pub failures: Vec<String>,
}

/// `[design.margins]` checked on the result at one speed, by routes the optimiser does
/// not take: the full catalogue at the margin level (its stable band containing φ_op and
/// its counted tongues), and a grid at that level over the catalogue's band.
#[derive(Debug, Clone, Serialize)]
pub struct MarginCheck {
    /// The margin level (1 + beta)·β_op (−).
    pub level: f64,
    /// The catalogue's stable band containing φ_op at that level (rad/s).
    pub band: Option<Interval>,
    /// φ_op − lo (rad/s).
    pub phi_below: Option<f64>,
    /// hi − φ_op (rad/s).
    pub phi_above: Option<f64>,
    /// Counted tongues of that catalogue with an onset below the margin level that reach
    /// within the frequency margin of φ_op: (label, extent at the margin level).
    pub intruders: Vec<(String, Interval)>,
    /// The grid at the margin level over the catalogue's band.
    pub grid: Option<GridCheck>,
    /// Monodromy evaluations of the check.
    pub evaluations: usize,
}

/// Whirls per direction listed in the report.
const REPORT_WHIRLS: usize = 6;

/// Whirls and catalogue of a design at each operating speed (no checks); the searches
/// report their steps to `progress` ([`catalogue_with`]).
pub fn describe(
    c: &Candidate,
    spec: &DesignSpec,
    s: &RegionSettings,
    progress: &dyn Progress,
) -> Result<Vec<DesignAtSpeed>, DesignError> {
    c.systems
        .iter()
        .map(|(w, fs)| {
            let full = whirl_modes_of(&c.rotor, &c.problem.settings, *w)?;
            let req =
                CatalogueRequest { range: spec.range(), beta_max: spec.beta_max, level: spec.level, track: false };
            let cat = catalogue_with(fs, &full, s, &req, progress)?;
            let mut whirls = Vec::new();
            for dir in [Whirl::Forward, Whirl::Backward] {
                whirls.extend(
                    full.modes
                        .iter()
                        .filter(|m| m.whirl == dir)
                        .take(REPORT_WHIRLS)
                        .map(|m| WhirlRow { tag: m.tag(), frequency: m.frequency }),
                );
            }
            let catalogue_band = spec.phi_op().and_then(|p| cat.band_containing(p));
            let (band, margins) = match spec.phi_op() {
                Some(p) => {
                    let seeds = seeds_for(fs, Some(&full), spec.range(), c.criterion().max_order)?;
                    let probe = Probe::reporting(fs, s, progress);
                    let band = band_around(&Level::new(&probe, c.criterion(), spec.level, spec.range()), &seeds, p);
                    let strict = margins::strict_band(fs, s, &seeds, &band, spec.range());
                    let tolerance = c.criterion().strict().instability_tolerance;
                    let m = margins::assemble(&band, strict, &cat.regions, spec.beta_max, tolerance);
                    (Some(band), m)
                }
                None => (None, None),
            };
            Ok(DesignAtSpeed {
                speed: *w,
                whirls,
                catalogue: cat,
                catalogue_band,
                band,
                centres: Vec::new(),
                grids: Vec::new(),
                margins,
                margin_check: None,
                failures: Vec::new(),
            })
        })
        .collect()
}

/// Every catalogued tongue at the level: (label, extent, counted).
fn tongues(cat: &Catalogue) -> Vec<(String, Interval, bool)> {
    let mut out: Vec<(String, Interval, bool)> = cat
        .regions
        .iter()
        .filter_map(|r| Some((format!("{}/{}", r.label, r.order), Interval::new(r.left?, r.right?), r.counted)))
        .collect();
    out.extend(cat.unexplained.iter().map(|e| ("unlabelled".to_string(), *e, true)));
    out.extend(cat.ignored.iter().map(|t| (t.label(), t.extent, false)));
    out
}

/// The grid over `window` at [`GRID_STEP`] (coarser beyond [`MAX_GRID_POINTS`]), interior
/// points only, in parallel; a step of `progress` per point.
fn grid(
    fs: &FloquetSystem,
    criterion: &Criterion,
    window: Interval,
    level: f64,
    count: &Counter,
    progress: &dyn Progress,
) -> GridCheck {
    let step = GRID_STEP.max(window.width() / MAX_GRID_POINTS as f64);
    let n = (window.width() / step).floor() as usize;
    let points: Vec<f64> = (1..n).map(|i| window.lo + step * i as f64).filter(|&p| p < window.hi).collect();
    count.add(points.len());
    progress.extend(points.len() as u64);
    let unstable: Vec<f64> = points
        .par_iter()
        .copied()
        .filter(|&phi| {
            let counted = criterion.counts(&fs.point_fast(&fs.table(phi, level), level).summary);
            progress.advance(1);
            counted
        })
        .collect();
    GridCheck { window, step, points: points.len(), unstable }
}

/// Verify a design's result (module docs): `bands` are the design's operating bands at
/// each speed (widest-stable-band), or empty (clear-bands). Fills the checks of `at`;
/// a step of `progress` per reference point and grid point.
pub fn verify(
    c: &Candidate,
    spec: &DesignSpec,
    bands: &[OperatingBand],
    at: &mut [DesignAtSpeed],
    count: &Counter,
    progress: &dyn Progress,
) -> bool {
    let criterion = c.criterion();
    let mut passed = true;
    for (k, d) in at.iter_mut().enumerate() {
        let fs = &c.systems[k].1;
        // The windows that must be free of instability, and the reach of "near".
        let windows: Vec<Interval> = match spec.objective {
            Objective::WidestStableBand { .. } => {
                let b = bands.get(k).and_then(|b| b.band.band);
                if d.band.as_ref().map(|x| x.band) != Some(b) {
                    d.failures.push(format!(
                        "the band with labelled seeds ({:?}) differs from the optimiser's ({b:?})",
                        d.band.as_ref().and_then(|x| x.band)
                    ));
                }
                if let (Some(b), Some(cb)) = (b, d.catalogue_band) {
                    if (b.lo - cb.lo).abs() > SAME_EDGE || (b.hi - cb.hi).abs() > SAME_EDGE {
                        d.failures.push(format!("the catalogue's stable band {cb:.3} differs from the band {b:.3}"));
                    }
                } else if b.is_some() != d.catalogue_band.is_some() {
                    d.failures.push(format!(
                        "the catalogue's stable band ({:?}) and the band ({:?}) disagree on whether phi_op is stable",
                        d.catalogue_band, b
                    ));
                }
                let mut w: Vec<Interval> = b.into_iter().collect();
                w.extend(spec.constraints.bands.iter().map(|b| b.guarded()));
                w
            }
            Objective::ClearBands { .. } => spec.kept_clear().iter().map(|b| b.guarded()).collect(),
            Objective::MinPeakResponse { .. } => {
                let mut w: Vec<Interval> = spec.kept_clear().iter().map(|b| b.guarded()).collect();
                if let Some(min) = spec.constraints.min_band_width {
                    match d.catalogue_band {
                        Some(cb) if cb.width() >= min.width => w.push(cb),
                        other => d.failures.push(format!(
                            "the catalogue's stable band around {} rad/s ({other:?}) is not {} rad/s wide",
                            min.phi_op, min.width
                        )),
                    }
                }
                w
            }
        };
        let all = tongues(&d.catalogue);
        for w in &windows {
            for (label, e, counted) in &all {
                if *counted && e.hi > w.lo + SAME_EDGE && e.lo < w.hi - SAME_EDGE {
                    d.failures.push(format!("catalogued tongue {label} at {e:.3} reaches into {w:.3}"));
                }
            }
        }
        let reach = |w: &Interval| NEAR * w.centre().max(spec.objective.phi_op().unwrap_or(0.0));
        let near: Vec<&(String, Interval, bool)> = all
            .iter()
            .filter(|(_, e, _)| windows.iter().any(|w| e.overlaps(&Interval::new(w.lo - reach(w), w.hi + reach(w)))))
            .collect();
        count.add(near.len());
        progress.extend(near.len() as u64);
        d.centres = near
            .par_iter()
            .map(|(label, e, _)| {
                let phi = e.centre();
                let p = fs.point_dstm(phi, spec.level, fs.settings.reference_steps).summary;
                progress.advance(1);
                CentreCheck {
                    label: label.clone(),
                    phi,
                    max_multiplier: p.max_multiplier,
                    unstable: criterion.counts(&p),
                    inside: windows.iter().any(|w| w.lo < phi && phi < w.hi),
                }
            })
            .collect();
        for cc in d.centres.iter().filter(|cc| cc.inside && cc.unstable) {
            d.failures.push(format!(
                "the reference (DSTM) point at the centre of {} ({:.3} rad/s) is unstable, max|mu| = {:.6}",
                cc.label, cc.phi, cc.max_multiplier
            ));
        }
        d.grids = windows.iter().map(|w| grid(fs, &criterion, *w, spec.level, count, progress)).collect();
        for g in &d.grids {
            if let Some(p) = g.unstable.first() {
                d.failures.push(format!(
                    "{} point(s) of the {} rad/s grid over {:.3} are unstable, the first at {p:.3} rad/s",
                    g.unstable.len(),
                    g.step,
                    g.window
                ));
            }
        }
        if let (Some(m), Some(phi_op)) = (spec.constraints.margins, spec.phi_op()) {
            let check = margin_check(c, k, spec, &m, phi_op, progress);
            match check {
                Ok(mc) => {
                    count.add(mc.evaluations);
                    d.failures.extend(margin_failures(&mc, &m, phi_op));
                    d.margin_check = Some(mc);
                }
                Err(e) => d.failures.push(format!("the margin check's catalogue failed: {e}")),
            }
        }
        passed &= d.failures.is_empty();
    }
    passed
}

/// The margin check at speed index `k` ([`MarginCheck`]).
fn margin_check(
    c: &Candidate,
    k: usize,
    spec: &DesignSpec,
    m: &MarginSpec,
    phi_op: f64,
    progress: &dyn Progress,
) -> Result<MarginCheck, DesignError> {
    let (w, fs) = (&c.systems[k].0, &c.systems[k].1);
    let level = m.level(spec.level);
    let full = whirl_modes_of(&c.rotor, &c.problem.settings, *w)?;
    let req = CatalogueRequest { range: spec.range(), beta_max: spec.beta_max.max(level), level, track: false };
    let cat = catalogue_with(fs, &full, &c.problem.regions, &req, progress)?;
    let band = cat.band_containing(phi_op);
    let guarded = Interval::new(phi_op - m.phi, phi_op + m.phi);
    let intruders = tongues(&cat)
        .into_iter()
        .filter(|(_, e, counted)| *counted && e.hi > guarded.lo + SAME_EDGE && e.lo < guarded.hi - SAME_EDGE)
        .map(|(label, e, _)| (label, e))
        .collect();
    let count = Counter::default();
    let grid = band.map(|b| grid(fs, &c.criterion(), b, level, &count, progress));
    Ok(MarginCheck {
        level,
        band,
        phi_below: band.map(|b| phi_op - b.lo),
        phi_above: band.map(|b| b.hi - phi_op),
        intruders,
        grid,
        evaluations: cat.evaluations + count.get(),
    })
}

/// What a margin check found wrong, in words.
fn margin_failures(mc: &MarginCheck, m: &MarginSpec, phi_op: f64) -> Vec<String> {
    let mut out = Vec::new();
    match (mc.phi_below, mc.phi_above) {
        (Some(below), Some(above)) => {
            if below < m.phi - SAME_EDGE || above < m.phi - SAME_EDGE {
                out.push(format!(
                    "margins: at beta = {:.6} phi_op - lo = {below:.3} and hi - phi_op = {above:.3} rad/s, less than the {} rad/s asked",
                    mc.level, m.phi
                ));
            }
        }
        _ => out.push(format!("margins: phi_op = {phi_op} rad/s is unstable at beta = {:.6}", mc.level)),
    }
    for (label, e) in &mc.intruders {
        out.push(format!(
            "margins: catalogued tongue {label} at {e:.3} (beta = {:.6}) reaches within {} rad/s of phi_op",
            mc.level, m.phi
        ));
    }
    if let Some(g) = mc.grid.as_ref().filter(|g| !g.unstable.is_empty()) {
        out.push(format!(
            "margins: {} point(s) of the {} rad/s grid over {:.3} at beta = {:.6} are unstable",
            g.unstable.len(),
            g.step,
            g.window,
            mc.level
        ));
    }
    out
}
