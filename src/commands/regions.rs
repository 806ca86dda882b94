//! The region commands: `regions` (catalogue, stable bands, optional tracked boundaries)
//! and `band` (the stable band around an operating frequency).

use super::bounds::{self};
use super::{files_phase, OutDir, Provenance};
use crate::commands::out::json_pretty;
use crate::commands::Error;
use rotorshunt::analysis::basis::BasisReport;
use rotorshunt::analysis::chart::ChartResult;
use rotorshunt::analysis::limits::{self, Quantity};
use rotorshunt::analysis::regions::{Band, Bound, Catalogue, CatalogueRequest, Edges, Margins, Region, RegionSettings};
use rotorshunt::analysis::Interval;
use rotorshunt::problem::{Problem, Warning};
use rotorshunt::progress::Progress;
use rotorshunt::report::chart::{Layer, RegionShape, StabilityPlot};
use rotorshunt::run::Budget;
use rotorshunt::run::{plot_grid, BandLoadMargin, BandRun, CatalogueRun, Run};
use serde::Serialize;
use std::path::Path;

fn arg(argument: &str, message: String) -> Error {
    Error::Argument { argument: argument.into(), message }
}

/// `A:B` as a φ range (rad/s), by the range rule ([`limits::phi_range`]).
fn range_of(text: &str) -> Result<Interval, Error> {
    let bad = || arg("--phi", format!("`{text}` is not of the form A:B (two numbers, rad/s)"));
    let (a, b) = text.split_once(':').ok_or_else(bad)?;
    let number = |p: &str| p.trim().parse::<f64>().map_err(|_| bad());
    bounds::flag("--phi", limits::phi_range(number(a)?, number(b)?))
}

/// The tracked regions at their true width (filled, 1 px outline, labelled) over a chart
/// of the same problem (600 × 41 grid), the `chart` phase of `progress`.
fn boundary_plot(problem: &Problem, cat: &Catalogue, c: ChartResult) -> StabilityPlot {
    let (phis, betas) = plot_grid(cat.range, cat.beta_max);
    let resolved: Vec<&Region> = cat.regions.iter().filter(|r| r.resolved).collect();
    let regions = resolved
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let own = own_levels(r, resolved.iter().enumerate().filter(|&(j, _)| j != i).map(|(_, q)| *q));
            let mut outline = vec![(r.start, r.onset_beta)];
            outline.extend(r.boundary[..own].iter().map(|e| (e.phi.lo, e.beta)));
            outline.extend(r.boundary[..own].iter().rev().map(|e| (e.phi.hi, e.beta)));
            RegionShape { label: r.label.clone(), outline }
        })
        .collect();
    let layer = Layer {
        name: format!("grid points ({} φ × {} β)", phis.len(), betas.len()),
        color: GRID_LAYER_COLOR,
        chart: c,
    };
    let mut levels = Vec::new();
    if cat.level < cat.beta_max {
        levels.push((cat.level, format!("edges and bands at β = {}", cat.level)));
    }
    StabilityPlot::new(&format!("Instability regions: {}", super::plot_title(problem)), vec![layer])
        .with_regions(regions)
        .with_levels(levels)
}

/// The number of `r`'s tracked levels (from its onset up) that are its own: up to the
/// first level where its interval meets another tracked region's at the same β after
/// being apart (the two have merged into one unstable area, whose tracked edges then
/// belong to neither), or every level. Above it the plot shows the grid alone, so
/// unrelated regions never cross. A region that meets `r` from `r`'s first level on is a
/// second tracking of the same tongue (two labels of one area), not a merge.
fn own_levels<'a>(r: &Region, others: impl Iterator<Item = &'a Region>) -> usize {
    let meets = |q: &Region, e: &Edges| interval_at(q, e.beta).is_some_and(|i| i.lo < e.phi.hi && e.phi.lo < i.hi);
    others
        .filter(|q| r.boundary.first().is_some_and(|e| !meets(q, e)))
        .filter_map(|q| r.boundary.iter().position(|e| meets(q, e)))
        .min()
        .unwrap_or(r.boundary.len())
}

/// A tracked region's φ interval at `beta` (rad/s): its edges interpolated linearly
/// between the tracked levels around `beta`, from its tip (start, onset) up; `None` below
/// its onset or above its highest level.
fn interval_at(q: &Region, beta: f64) -> Option<Interval> {
    let tip = Interval::new(q.start, q.start);
    let mut below = (q.onset_beta, tip);
    for e in &q.boundary {
        if e.beta >= beta {
            if beta < below.0 {
                return None;
            }
            let t = if e.beta > below.0 { (beta - below.0) / (e.beta - below.0) } else { 1.0 };
            let lerp = |a: f64, b: f64| a + t * (b - a);
            return Some(Interval::new(lerp(below.1.lo, e.phi.lo), lerp(below.1.hi, e.phi.hi)));
        }
        below = (e.beta, e.phi);
    }
    None
}

/// Colour of the grid chart under the tracked regions: light, so the tracked outlines
/// (the true widths) stand out from the grid's cells.
const GRID_LAYER_COLOR: (u8, u8, u8) = (160, 190, 225);

/// JSON of `regions` (`--json`, regions.json).
#[derive(Serialize)]
pub struct RegionsJson {
    /// Tool, input hash and settings, and the φ range's warning.
    #[serde(flatten)]
    pub provenance: Provenance,
    /// Speed Ω (rad/s).
    pub speed: f64,
    /// The region search's settings.
    pub region_settings: RegionSettings,
    /// Wall time of the search (s).
    pub seconds: f64,
    /// The reduced basis the catalogue was computed on, and its convergence.
    pub basis: BasisReport,
    /// The regions, the stable bands at the level and what the search asked.
    #[serde(flatten)]
    pub catalogue: Catalogue,
    /// The load margin of each stable band at the level (same order as `stable_bands`).
    pub band_margins: Vec<BandLoadMargin>,
}

/// What a catalogue is asked on the command line.
pub struct RegionsArgs<'a> {
    /// `--phi A:B` (rad/s).
    pub phi: &'a str,
    /// `--beta-max` (−).
    pub beta_max: f64,
    /// `--level` (−; default β_max).
    pub level: Option<f64>,
    /// `--json`: print JSON instead of the table.
    pub json: bool,
    /// `--out DIR`: also track boundaries and write regions.{json,svg,png} there.
    pub out: Option<&'a Path>,
}

/// The catalogue `regions` asks: `--phi A:B` (rad/s), `--beta-max` and `--level` checked
/// by their rules, with tracked boundaries when `track`.
pub fn regions_request(phi: &str, beta_max: f64, level: Option<f64>, track: bool) -> Result<CatalogueRequest, Error> {
    let range = range_of(phi)?;
    let beta_max = bounds::flag("--beta-max", limits::beta_max(beta_max))?;
    let level = bounds::flag("--level", limits::level(level.unwrap_or(beta_max), beta_max))?;
    let req = CatalogueRequest::builder().range(range).beta_max(beta_max).level(level).track(track).build();
    Ok(req.map_err(rotorshunt::analysis::AnalysisError::from)?)
}

/// The JSON document of `regions` from the catalogue a run computed on `problem` (its
/// boundary plot's chart aside) and the range's `warnings`. Written and rendered by
/// `regions`, converted by the Python bindings' `regions`.
pub fn regions_output(problem: &Problem, warnings: &[Warning], r: CatalogueRun) -> RegionsJson {
    let CatalogueRun { sized, seconds, grid: _, band_margins } = r;
    RegionsJson {
        provenance: Provenance::of(problem).with(warnings),
        speed: problem.model.speed,
        region_settings: problem.regions.clone(),
        seconds,
        basis: sized.basis,
        catalogue: sized.answer,
        band_margins,
    }
}

/// `rotorshunt regions FILE --phi A:B --beta-max BMAX [--level BOP] [--json] [--out DIR]`.
/// Progress: `catalogue` (a step per search, [`rotorshunt::analysis::regions::catalogue_with`]), and with `--out` the
/// boundary plot's `chart` and the `files`.
pub fn regions_cmd(
    problem: &Problem,
    args: RegionsArgs<'_>,
    progress: &dyn Progress,
    budget: Budget,
) -> Result<String, Error> {
    let RegionsArgs { phi, beta_max, level, json, out } = args;
    let req = regions_request(phi, beta_max, level, out.is_some())?;
    let (range, beta_max, level) = (req.range, req.beta_max, req.level);
    let run = Run::new(progress).with_budget(budget);
    let job = run.catalogue(problem, &req)?;
    let warnings = job.warnings.clone();
    // The staging folder is made before the search: an --out that cannot be written
    // fails at once, and nothing of the folder changes until the last file is written.
    let dir = out.map(|d| OutDir::create(d, &problem.file)).transpose()?;
    let mut r = job.run()?;
    let grid = r.grid.take();
    let doc = regions_output(problem, &warnings, r);
    let (cat, seconds) = (&doc.catalogue, doc.seconds);
    let json_text = json_pretty(&doc, "the JSON output")? + "\n";
    if let (Some(dir), Some(grid)) = (dir, grid) {
        let plot = boundary_plot(problem, cat, grid);
        let written = files_phase(progress, 3);
        dir.write("regions.json", json_text.as_bytes())?;
        written();
        dir.figure("regions", &plot)?;
        written();
        written();
        dir.commit("regions", progress)?;
    }
    if json {
        return Ok(json_text);
    }
    let mut s = format!(
        "{} regions with onset below beta = {beta_max} in phi = {}..{} rad/s (speed {} rad/s), edges at beta = {level}; {} monodromy evaluations in {seconds:.2} s\n",
        cat.regions.len(),
        range.lo,
        range.hi,
        problem.model.speed,
        cat.evaluations
    );
    s += &format!("basis: {}\n", doc.basis.text());
    s += &format!(
        "{:>10} {:>5} {:>11} {:>10} {:>10} {:>8} {:>10} {:>10} {:>8}  note\n",
        "label", "k", "kind", "predicted", "start", "onset", "left", "right", "width"
    );
    let f = |x: Option<f64>| x.map(|v| format!("{v:.2}")).unwrap_or_else(|| "-".into());
    for r in &cat.regions {
        s += &format!(
            "{:>10} {:>5} {:>11} {:>10.2} {:>10.2} {:>8.4} {:>10} {:>10} {:>8}  {}\n",
            r.label,
            r.order,
            format!("{:?}", r.kind).to_lowercase(),
            r.predicted,
            r.start,
            r.onset_beta,
            f(r.left),
            f(r.right),
            f(r.width),
            if r.resolved { "" } else { "onset is an upper bound (the tongue's tip merges with a neighbour's)" }
        );
    }
    for u in &cat.unexplained {
        s += &format!(
            "unexplained: unstable at the level in [{:.2}, {:.2}] rad/s (guard lattice; no seed of order <= {} identified there)\n",
            u.lo, u.hi, cat.criterion.max_order
        );
    }
    s += "stable bands at the level (rad/s):";
    for b in &cat.stable_bands {
        s += &format!(" [{:.1}, {:.1}]", b.lo, b.hi);
    }
    s +=
        "\nload margins of the stable bands (lowest onset above the level of a region born inside, onset/level - 1):\n";
    for m in &doc.band_margins {
        s += &match &m.load {
            Some(l) => format!(
                "  [{:.1}, {:.1}]: {:+.2} % ({} (k = {}) at {:.2} rad/s, onset {:.4})\n",
                m.band.lo,
                m.band.hi,
                100.0 * l.margin,
                l.label,
                l.order,
                l.start,
                l.onset
            ),
            None => format!(
                "  [{:.1}, {:.1}]: more than {:.1} % (none born inside up to beta_max = {beta_max})\n",
                m.band.lo,
                m.band.hi,
                100.0 * (beta_max / level - 1.0)
            ),
        };
    }
    Ok(s)
}

/// JSON of `band`.
#[derive(Debug, Serialize)]
pub struct BandOutput {
    /// Tool, input hash and settings (the criterion among them).
    #[serde(flatten)]
    pub provenance: Provenance,
    /// Speed Ω (rad/s).
    pub speed: f64,
    /// The φ window searched (rad/s).
    pub window: Interval,
    /// The band and what bounds it.
    #[serde(flatten)]
    pub band: Band,
    /// Width (rad/s), when φ_op is stable: at least this much when `clipped`.
    pub width: Option<f64>,
    /// Whether the band ends at an end of the window rather than at a tongue: its true
    /// extent is at least the band's ([`Band::clipped`]).
    pub clipped: bool,
    /// The reduced basis the band was computed on, and its convergence.
    pub basis: BasisReport,
    /// The band's margins: load margin (onset/β_op − 1 of the lowest counted tongue born
    /// inside it, searched up to 2·β_op), frequency margins φ_op − lo and hi − φ_op
    /// (rad/s), the largest max|μ| sampled inside it and the band by the strict
    /// criterion; null when φ_op is unstable.
    pub margins: Option<Margins>,
    /// Wall time (s).
    pub seconds: f64,
}

/// The default φ window of `band` around φ_op (rad/s): a twentieth to twenty times φ_op
/// (at most the largest frequency, [`limits::MAX_PHI`]).
pub fn default_window(phi_op: f64) -> Interval {
    Interval::new(phi_op / 20.0, (phi_op * 20.0).min(limits::MAX_PHI))
}

fn bound_text(b: &Option<Bound>) -> String {
    match b {
        Some(Bound::Tongue { edge, label, inside, unexplained }) => {
            let why = unexplained.as_ref().map_or_else(String::new, |u| {
                format!(
                    "; no catalogued tongue has this edge: unstable Floquet exponent at {:.3} rad/s, nearest whirl combination {} = {:.3} rad/s",
                    u.exponent_frequency, u.nearest, u.nearest_frequency
                )
            });
            format!("{label} (edge {edge:.3} rad/s, unstable at {inside:.3} rad/s{why})")
        }
        _ => "the end of the search window (the band is clipped: widen --phi to see its edge)".into(),
    }
}

/// What `band` asks, checked by the rules: the operating frequency φ_op (rad/s), the load
/// level and the φ window (rad/s), with the flag that set the window (`--phi`, or
/// `--phi-op` for the default window around it).
#[derive(Debug, Clone, Copy)]
pub struct BandRequest {
    /// `--phi-op` (rad/s).
    pub phi_op: f64,
    /// `--level` (−).
    pub level: f64,
    /// The window searched (rad/s): `--phi`, or [`default_window`].
    pub window: Interval,
    /// The flag the window's warnings name.
    pub key: &'static str,
}

/// The band `band` asks around `phi_op` (rad/s) at `level`, in the window `A:B` (rad/s)
/// or the default one, each checked by its rule.
pub fn band_request(phi_op: f64, level: f64, window: Option<&str>) -> Result<BandRequest, Error> {
    let phi_op = bounds::flag("--phi-op", limits::frequency(Quantity::OperatingFrequency, phi_op))?;
    let level = bounds::flag("--level", limits::level(level, limits::MAX_BETA))?;
    let (window, key) = match window {
        Some(text) => (range_of(text)?, "--phi"),
        None => (default_window(phi_op), "--phi-op"),
    };
    bounds::flag("--phi-op", limits::phi_op(phi_op, window))?;
    Ok(BandRequest { phi_op, level, window, key })
}

/// The JSON document of `band` from the band a run found on `problem` in `window` (rad/s)
/// and the window's `warnings`. Rendered by `band`, converted by the Python bindings'
/// `band`.
pub fn band_output(problem: &Problem, window: Interval, warnings: &[Warning], r: BandRun) -> BandOutput {
    let BandRun { sized, margins, seconds } = r;
    let b = sized.answer;
    BandOutput {
        basis: sized.basis,
        margins,
        provenance: Provenance::of(problem).with(warnings),
        speed: problem.model.speed,
        window,
        width: b.band.map(|x| x.width()),
        clipped: b.clipped(),
        band: b,
        seconds,
    }
}

/// `rotorshunt band FILE --phi-op P --level BOP [--phi A:B] [--json]`. Progress: `band`
/// (a step per search, [`rotorshunt::analysis::regions::band_with`]), then `margins`.
pub fn band_cmd(
    problem: &Problem,
    phi_op: f64,
    level: f64,
    window: Option<&str>,
    json: bool,
    progress: &dyn Progress,
    budget: Budget,
) -> Result<String, Error> {
    let BandRequest { phi_op, level, window, key } = band_request(phi_op, level, window)?;
    let run = Run::new(progress).with_budget(budget);
    let job = run.band(problem, phi_op, level, window, key)?;
    let warnings = job.warnings.clone();
    let out = band_output(problem, window, &warnings, job.run()?);
    if json {
        return Ok(json_pretty(&out, "the JSON output")? + "\n");
    }
    let b = &out.band;
    let mut text = match b.band {
        Some(x) => format!(
            "stable band at beta = {level} around phi = {phi_op} rad/s: [{:.2}, {:.2}] rad/s, width {}{:.2} rad/s ({} evaluations, {:.3} s)\n  guarantee: {}\n  below: {}\n  above: {}\n",
            x.lo,
            x.hi,
            if out.clipped { "at least " } else { "" },
            x.width(),
            b.evaluations,
            out.seconds,
            b.guarantee,
            bound_text(&b.left),
            bound_text(&b.right),
        ),
        None => {
            let t = b.containing.unwrap_or(Interval::new(phi_op, phi_op));
            format!(
                "phi = {phi_op} rad/s is unstable at beta = {level}: it lies in the tongue [{:.2}, {:.2}] rad/s, so no stable band contains it ({} evaluations)\n",
                t.lo, t.hi, b.evaluations
            )
        }
    };
    text += &format!("  basis: {}\n", out.basis.text());
    if let Some(m) = &out.margins {
        text += &m.text("  ");
    }
    for t in &b.ignored {
        let why = match t.ignored {
            Some(rotorshunt::analysis::regions::Ignored::SlowGrowth) => "growth below min_growth_rate",
            _ => "narrower than min_tongue_width",
        };
        text += &format!(
            "  ignored by the criterion ({why}): {} at [{:.3}, {:.3}] rad/s ({:.3} rad/s wide)\n",
            t.label(),
            t.extent.lo,
            t.extent.hi,
            t.extent.width()
        );
    }
    Ok(text)
}
