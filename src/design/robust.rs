//! The tuned design judged as built (`[design.tolerances]`): its band around φ_op at
//! every corner and the centre of the tolerance box, and at Monte Carlo samples drawn
//! from it ([`crate::design::tolerance`]), each by the same band function as
//! `rotorshunt band` on the perturbed design, at every operating speed.
//!
//! A build **holds** when φ_op is stable at every speed and, with `[design.margins]`, the
//! band at the margin level keeps the frequency margin; with a band-width constraint, the
//! band is at least that wide. The **guaranteed band** at a speed is the intersection of
//! the bands of every build checked: what the designer can count on with parts inside
//! the tolerances. A design whose builds do not all hold is `not-robust`, with the first
//! failing build named (a corner before a sample).

use super::evaluate::{margin_shortfall, operating_bands, operating_bands_at, Candidate, OperatingBand};
use super::spec::DesignSpec;
use super::tolerance::{Perturbation, Tolerances};
use super::DesignError;
use crate::analysis::regions::{Counter, RegionSettings};
use crate::analysis::Interval;
use rayon::prelude::*;
use serde::Serialize;

/// One build of the tuned design, judged.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Build {
    /// The factors on the components.
    pub perturbation: Perturbation,
    /// The band around φ_op at each operating speed (rad/s); None where φ_op is unstable.
    pub bands: Vec<Option<Interval>>,
    /// The smallest signed band width over the speeds (rad/s).
    pub width: f64,
    /// Why it does not hold; None when it holds.
    pub failure: Option<String>,
}

/// The tuned design over its tolerance box.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Robustness {
    /// The tolerances judged.
    pub tolerances: Tolerances,
    /// The centre and corners of the box, judged.
    pub corners: Vec<Build>,
    /// Monte Carlo samples judged.
    pub samples: usize,
    /// Of those, the ones that do not hold.
    pub samples_failed: usize,
    /// The build with the smallest band width among corners and samples.
    pub worst: Build,
    /// The first build that does not hold (a corner before a sample); None when all hold.
    pub failing: Option<Build>,
    /// The guaranteed band at each speed (rad/s): the intersection of every build's band;
    /// None where some build has φ_op unstable.
    pub guaranteed: Vec<Option<Interval>>,
    /// Monodromy evaluations of the check.
    pub evaluations: usize,
}

impl Robustness {
    /// Whether every build checked holds.
    pub fn holds(&self) -> bool {
        self.failing.is_none()
    }

    /// Builds checked: the box's centre and corners, and the samples.
    pub fn checked(&self) -> usize {
        self.corners.len() + self.samples
    }

    /// Builds that do not hold.
    pub fn failed(&self) -> usize {
        self.corners.iter().filter(|b| b.failure.is_some()).count() + self.samples_failed
    }
}

/// The value the optimiser steers by for one build of a candidate (rad/s): its smallest
/// signed band width over the speeds, less `penalty` per rad/s of margin shortfall at the
/// margin level; with the bands.
pub fn judged(
    c: &Candidate,
    spec: &DesignSpec,
    phi_op: f64,
    s: &RegionSettings,
    count: &Counter,
    penalty: f64,
) -> Result<(f64, Vec<OperatingBand>), DesignError> {
    let bands = operating_bands(c, spec, phi_op, s, count)?;
    let mut value = smallest(&bands);
    if let Some(m) = spec.constraints.margins {
        let at = operating_bands_at(c, spec, phi_op, m.level(spec.level), s, count)?;
        value -= penalty * margin_shortfall(&at, &m);
    }
    Ok((value, bands))
}

/// The smallest signed band width over the speeds (rad/s).
pub fn smallest(bands: &[OperatingBand]) -> f64 {
    bands.iter().map(OperatingBand::signed_width).fold(f64::INFINITY, f64::min)
}

/// One build judged ([`Build`]).
fn build(
    c: &Candidate,
    spec: &DesignSpec,
    phi_op: f64,
    p: &Perturbation,
    s: &RegionSettings,
    count: &Counter,
) -> Result<Build, DesignError> {
    let built = c.perturbed(spec, p)?;
    let bands = operating_bands(&built, spec, phi_op, s, count)?;
    let mut failure = None;
    if let Some(b) = bands.iter().find(|b| b.band.band.is_none()) {
        failure = Some(format!("phi_op = {phi_op} rad/s is unstable at Omega = {} rad/s", b.speed));
    }
    if let (None, Some(m)) = (&failure, spec.constraints.margins) {
        let at = operating_bands_at(&built, spec, phi_op, m.level(spec.level), s, count)?;
        let short = margin_shortfall(&at, &m);
        if short > 0.0 {
            failure = Some(format!(
                "the band at the margin level beta = {:.4} misses the frequency margin of {} rad/s by {short:.3} rad/s",
                m.level(spec.level),
                m.phi
            ));
        }
    }
    if let (None, Some(w)) = (&failure, spec.constraints.min_band_width) {
        let width = smallest(&bands);
        if width < w.width {
            failure = Some(format!("the band is {width:.3} rad/s wide, below the {} rad/s asked", w.width));
        }
    }
    Ok(Build {
        perturbation: p.clone(),
        bands: bands.iter().map(|b| b.band.band).collect(),
        width: smallest(&bands),
        failure,
    })
}

/// The tuned design `c` over the tolerance box `t` ([`Robustness`]); `tick` once per
/// build judged.
pub fn check(
    c: &Candidate,
    spec: &DesignSpec,
    t: &Tolerances,
    phi_op: f64,
    s: &RegionSettings,
    tick: &(dyn Fn() + Sync),
) -> Result<Robustness, DesignError> {
    let count = Counter::default();
    let judge = |p: &Perturbation| {
        let b = build(c, spec, phi_op, p, s, &count);
        tick();
        b
    };
    let corners: Vec<Build> = t.corners().par_iter().map(judge).collect::<Result<_, _>>()?;
    let samples: Vec<Build> = t.draw().par_iter().map(judge).collect::<Result<_, _>>()?;
    let all = || corners.iter().chain(&samples);
    let worst = all().min_by(|a, b| a.width.total_cmp(&b.width)).cloned().unwrap_or_else(|| corners[0].clone());
    let failing = all().find(|b| b.failure.is_some()).cloned();
    let guaranteed = (0..spec.speeds.len())
        .map(|k| {
            all()
                .try_fold(None::<Interval>, |acc, b| {
                    let band = b.bands.get(k).copied().flatten()?;
                    Some(Some(match acc {
                        None => band,
                        Some(a) => Interval::new(a.lo.max(band.lo), a.hi.min(band.hi)),
                    }))
                })
                .flatten()
        })
        .collect();
    Ok(Robustness {
        tolerances: *t,
        samples_failed: samples.iter().filter(|b| b.failure.is_some()).count(),
        samples: samples.len(),
        corners,
        worst,
        failing,
        guaranteed,
        evaluations: count.get(),
    })
}

/// The tolerance part's sentence: what was checked, the worst build, the guaranteed band
/// and the first failing build.
pub fn summary(r: &Robustness, phi_op: f64) -> String {
    let band = |b: &Option<Interval>| {
        b.map_or("none (phi_op unstable)".to_string(), |x| format!("[{:.2}, {:.2}]", x.lo, x.hi))
    };
    let bands = |v: &[Option<Interval>]| v.iter().map(band).collect::<Vec<_>>().join(", ");
    let mut s = format!(
        "the band around phi_op = {phi_op} rad/s at every build of the tolerance box ({}): its centre and {} corners, and {} Monte Carlo samples, {} of {} builds failing; worst build `{}`: band {} (smallest width {:.2} rad/s); guaranteed band (the intersection over every build) {}",
        r.tolerances.text(),
        r.corners.len() - 1,
        r.samples,
        r.failed(),
        r.checked(),
        r.worst.perturbation.name,
        bands(&r.worst.bands),
        r.worst.width,
        bands(&r.guaranteed)
    );
    if let Some(f) = &r.failing {
        s += &format!(
            "; first failing build `{}` (L x{:.4}, R x{:.4}, C_f x{:.4}, C_p x{:.4}): {}",
            f.perturbation.name,
            f.perturbation.inductance,
            f.perturbation.resistance,
            f.perturbation.c_f,
            f.perturbation.cp_t,
            f.failure.as_deref().unwrap_or("")
        );
    }
    s
}

/// The guaranteed band in words: at each speed `[lo, hi] (width) rad/s` or that φ_op is
/// unstable at some build, with the number of builds and the worst one.
pub fn guaranteed_text(r: &Robustness) -> String {
    let bands: Vec<String> = r
        .guaranteed
        .iter()
        .map(|b| match b {
            Some(x) => format!("[{:.2}, {:.2}] ({:.2} rad/s)", x.lo, x.hi, x.width()),
            None => "none: phi_op is unstable at some build".to_string(),
        })
        .collect();
    format!(
        "guaranteed band {} over {} builds (centre, {} corners, {} samples), worst build `{}`{}",
        bands.join(", "),
        r.checked(),
        r.corners.len() - 1,
        r.samples,
        r.worst.perturbation.name,
        if r.holds() { String::new() } else { format!(", {} build(s) failing: NOT ROBUST", r.failed()) }
    )
}
