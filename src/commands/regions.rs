//! The region commands: `regions` (catalogue, stable bands, optional tracked boundaries)
//! and `band` (the stable band around an operating frequency).

use super::{parse_range, OutDir, Provenance};
use crate::analysis::chart::chart;
use crate::analysis::floquet::FloquetSystem;
use crate::analysis::modes::whirl_modes_of;
use crate::analysis::regions::{band_at, catalogue, Catalogue, Edges, RegionSettings};
use crate::analysis::Rotor;
use crate::problem::Problem;
use crate::report::chart::{Layer, StabilityPlot};
use crate::report::plot::Series;
use crate::Error;
use serde::Serialize;
use std::path::Path;
use std::time::Instant;

fn arg(argument: &str, message: String) -> Error {
    Error::Argument { argument: argument.into(), message }
}

fn range_of(text: &str) -> Result<(f64, f64), Error> {
    let parts: Vec<&str> = text.split(':').collect();
    let v =
        if parts.len() == 2 { parse_range(&format!("{}:{}:{}", parts[0], parts[1], 1e9), "--phi")? } else { vec![] };
    let lo = v.first().copied();
    let hi = parts.get(1).and_then(|p| p.trim().parse::<f64>().ok());
    match (lo, hi) {
        (Some(lo), Some(hi)) if lo > 0.0 && hi > lo && hi.is_finite() => Ok((lo, hi)),
        _ => Err(arg("--phi", format!("`{text}` must be A:B with 0 < A < B (rad/s)"))),
    }
}

fn prepare(problem: &Problem) -> Result<(Rotor, FloquetSystem), Error> {
    let rotor = Rotor::new(&problem.model)?;
    let fs = FloquetSystem::new(&rotor, &problem.settings, problem.model.speed)?;
    Ok((rotor, fs))
}

/// The tracked boundaries (black) over a chart of the same problem (600 × 41 grid).
fn boundary_plot(dir: &OutDir, problem: &Problem, fs: &FloquetSystem, cat: &Catalogue) -> Result<(), Error> {
    let (lo, hi) = (cat.range[0], cat.range[1]);
    let phis: Vec<f64> = (0..600).map(|i| lo + (hi - lo) * i as f64 / 599.0).collect();
    let betas: Vec<f64> = (0..41).map(|i| cat.beta_max * i as f64 / 40.0).collect();
    let c = chart(fs, &phis, &betas, &|| {});
    let mut lines = Vec::new();
    for r in cat.regions.iter().filter(|r| r.resolved) {
        let side = |f: &dyn Fn(&Edges) -> f64| -> Series {
            let mut points = vec![(r.start, r.onset_beta)];
            points.extend(r.boundary.iter().map(|e| (f(e), e.beta)));
            Series { name: String::new(), color: (0, 0, 0), dashed: false, points }
        };
        lines.push(side(&|e| e.left));
        lines.push(side(&|e| e.right));
    }
    let layer = Layer { name: format!("{} circuit", problem.model.circuit.state), color: (31, 119, 180), chart: c };
    let plot = StabilityPlot::new(&format!("Tracked region boundaries: {}", super::title(problem)), vec![layer])
        .with_lines(lines);
    dir.write("regions.svg", plot.svg().map_err(|e| dir.error("regions.svg", e))?.as_bytes())?;
    dir.write("regions.png", &plot.png().map_err(|e| dir.error("regions.png", e))?)
}

#[derive(Serialize)]
struct RegionsJson<'a> {
    #[serde(flatten)]
    provenance: Provenance,
    speed: f64,
    region_settings: &'a RegionSettings,
    seconds: f64,
    #[serde(flatten)]
    catalogue: &'a Catalogue,
}

/// `rotorshunt regions FILE --phi A:B --beta-max BMAX [--level BOP] [--json] [--out DIR]`.
pub fn regions_cmd(
    problem: &Problem,
    phi: &str,
    beta_max: f64,
    level: Option<f64>,
    json: bool,
    out: Option<&Path>,
) -> Result<String, Error> {
    let range = range_of(phi)?;
    if !(beta_max.is_finite() && beta_max > 0.0) {
        return Err(arg("--beta-max", format!("must be a positive load coefficient, found {beta_max}")));
    }
    let level = level.unwrap_or(beta_max);
    if !(level.is_finite() && level > 0.0 && level <= beta_max) {
        return Err(arg("--level", format!("must be in (0, beta-max = {beta_max}], found {level}")));
    }
    let (rotor, fs) = prepare(problem)?;
    let full = whirl_modes_of(&rotor, &problem.settings, problem.model.speed)?;
    let settings = RegionSettings::default();
    let start = Instant::now();
    let cat = catalogue(&fs, &full, &settings, range, beta_max, level, out.is_some())?;
    let seconds = start.elapsed().as_secs_f64();
    let doc = RegionsJson {
        provenance: Provenance::of(problem),
        speed: problem.model.speed,
        region_settings: &settings,
        seconds,
        catalogue: &cat,
    };
    let json_text = serde_json::to_string_pretty(&doc).expect("plain data serialises") + "\n";
    if let Some(dir) = out {
        let dir = OutDir::create(dir, &problem.file)?;
        dir.write("regions.json", json_text.as_bytes())?;
        boundary_plot(&dir, problem, &fs, &cat)?;
    }
    if json {
        return Ok(json_text);
    }
    let mut s = format!(
        "{} regions with onset below beta = {beta_max} in phi = {}..{} rad/s (speed {} rad/s), edges at beta = {level}; {} monodromy evaluations in {seconds:.2} s\n",
        cat.regions.len(),
        range.0,
        range.1,
        problem.model.speed,
        cat.evaluations
    );
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
            if r.resolved { "" } else { "tip not located: start and onset are a point of the region and beta_c there" }
        );
    }
    for u in &cat.unexplained {
        s += &format!(
            "unexplained: unstable at the level in [{:.2}, {:.2}] rad/s (guard scan; no region of order <= {} found there)\n",
            u.left, u.right, settings.search_order
        );
    }
    s += "stable bands at the level (rad/s):";
    for b in &cat.stable_bands {
        s += &format!(" [{:.1}, {:.1}]", b[0], b[1]);
    }
    Ok(s + "\n")
}

/// JSON of `band`.
#[derive(Debug, Serialize)]
pub struct BandOutput {
    /// Tool, input hash and settings.
    #[serde(flatten)]
    pub provenance: Provenance,
    /// Operating frequency (rad/s).
    pub phi_op: f64,
    /// Load level β_op.
    pub level: f64,
    /// The stable band [lo, hi] containing φ_op, or null when φ_op is unstable.
    pub band: Option<[f64; 2]>,
    /// Width (rad/s).
    pub width: Option<f64>,
    /// Monodromy evaluations used.
    pub evaluations: usize,
    /// Wall time (s).
    pub seconds: f64,
}

/// `rotorshunt band FILE --phi-op P --level BOP [--json]`.
pub fn band_cmd(problem: &Problem, phi_op: f64, level: f64, json: bool) -> Result<String, Error> {
    if !(phi_op.is_finite() && phi_op > 0.0) {
        return Err(arg("--phi-op", format!("must be a positive frequency in rad/s, found {phi_op}")));
    }
    if !(level.is_finite() && level >= 0.0) {
        return Err(arg("--level", format!("must be a load coefficient >= 0, found {level}")));
    }
    let (_, fs) = prepare(problem)?;
    let start = Instant::now();
    let mut count = 0;
    let band = band_at(&fs, &RegionSettings::default(), phi_op, level, (phi_op * 0.05, phi_op * 20.0), &mut count);
    let out = BandOutput {
        provenance: Provenance::of(problem),
        phi_op,
        level,
        band,
        width: band.map(|b| b[1] - b[0]),
        evaluations: count,
        seconds: start.elapsed().as_secs_f64(),
    };
    if json {
        return Ok(serde_json::to_string_pretty(&out).expect("plain data serialises") + "\n");
    }
    Ok(match band {
        Some(b) => format!(
            "stable band at beta = {level} around phi = {phi_op} rad/s: [{:.2}, {:.2}] rad/s, width {:.2} rad/s ({} evaluations, {:.3} s)\n",
            b[0],
            b[1],
            b[1] - b[0],
            count,
            out.seconds
        ),
        None => format!("phi = {phi_op} rad/s is unstable at beta = {level}: no stable band contains it ({count} evaluations)\n"),
    })
}
