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

use super::evaluate::{
    band_of_system, margin_shortfall, operating_bands, operating_bands_at, Candidate, EvalContext, OperatingBand,
};
use super::spec::DesignSpec;
use super::tolerance::{Perturbation, Tolerances};
use super::DesignError;
use crate::analysis::floquet::FloquetSystem;
use crate::analysis::regions::{Counter, RegionSettings};
use crate::analysis::Interval;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// One build of the tuned design, judged.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Build {
    /// The factors on the components.
    pub perturbation: Perturbation,
    /// The speeds it was judged at (rad/s): every operating speed, or, for a Monte Carlo
    /// sample over a speed range, the one where the box's corners leave the narrowest
    /// guaranteed band (`check`).
    pub speeds: Vec<f64>,
    /// The band around φ_op at each of those speeds (rad/s); None where φ_op is unstable.
    pub bands: Vec<Option<Interval>>,
    /// The smallest signed band width over the speeds (rad/s).
    pub width: f64,
    /// Why it does not hold; None when it holds.
    pub failure: Option<String>,
}

/// The tuned design over its tolerance box.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Robustness {
    /// The tolerances judged.
    pub tolerances: Tolerances,
    /// Over a speed range, the one speed the samples were judged at (rad/s): where the
    /// corners leave the narrowest guaranteed band; None: the samples were judged at every
    /// operating speed.
    pub sample_speed: Option<f64>,
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

/// What the optimiser steers by for one build of a candidate, on the speed grid.
#[derive(Debug, Clone)]
pub struct Judged {
    /// The smallest signed band width over the grid's speeds (rad/s).
    pub smallest: f64,
    /// The margin penalty (rad/s of width): `penalty` per rad/s of frequency-margin
    /// shortfall at the margin level; 0 without `[design.margins]`.
    pub penalty: f64,
    /// The band around φ_op at each speed of the grid.
    pub bands: Vec<OperatingBand>,
}

impl Judged {
    /// The value on the grid: the smallest width less the penalty (rad/s).
    pub fn value(&self) -> f64 {
        self.smallest - self.penalty
    }
}

/// One build of a candidate judged on the speed grid ([`Judged`]), with `penalty` per
/// rad/s of margin shortfall.
pub fn judged(c: &Candidate, ev: &EvalContext<'_>, phi_op: f64, penalty: f64) -> Result<Judged, DesignError> {
    let spec = ev.spec;
    let bands = operating_bands(c, ev, phi_op)?;
    let penalty = match spec.constraints.margins {
        Some(m) => penalty * margin_shortfall(&operating_bands_at(c, ev, phi_op, m.level(spec.level))?, &m),
        None => 0.0,
    };
    Ok(Judged { smallest: smallest_counted(&bands), penalty, bands })
}

/// One build of a candidate judged at one speed `w` (rad/s) outside its grid: the signed
/// width of its band around φ_op there, less `penalty` per rad/s of margin shortfall at
/// the margin level there.
pub fn judged_at(c: &Candidate, ev: &EvalContext<'_>, phi_op: f64, w: f64, penalty: f64) -> Result<f64, DesignError> {
    let spec = ev.spec;
    let fs = FloquetSystem::new(&c.rotor, &c.machine.settings, w)?;
    let band = OperatingBand { speed: w, band: band_of_system(c, ev, &fs, phi_op, spec.level)? };
    let penalty = match spec.constraints.margins {
        Some(m) => {
            let at = OperatingBand { speed: w, band: band_of_system(c, ev, &fs, phi_op, m.level(spec.level))? };
            penalty * margin_shortfall(&[at], &m)
        }
        None => 0.0,
    };
    Ok(band.band.counted_width() - penalty)
}

/// Golden-section steps refining the worst speed of a speed range's grid.
pub const SPEED_REFINEMENTS: usize = 4;

/// The worst speed of a speed range refined (speed in rad/s, signed band width in rad/s):
/// golden-section steps ([`SPEED_REFINEMENTS`]) minimising the signed width between the
/// grid neighbours of the grid's worst speed, each at a reduced system built at that
/// speed. Region starts move with speed, so the worst speed need not be an end or a grid
/// speed; the fine verification grid checks what the refinement cannot promise.
pub fn refined_worst(
    c: &Candidate,
    ev: &EvalContext<'_>,
    phi_op: f64,
    bands: &[OperatingBand],
) -> Result<(f64, f64), DesignError> {
    let (k, worst) = bands
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.band.counted_width().total_cmp(&b.1.band.counted_width()))
        .map(|(k, b)| (k, b.band.counted_width()))
        .ok_or_else(|| DesignError::Optimiser("no operating speed".into()))?;
    let at = |w: f64| -> Result<f64, DesignError> {
        let fs = FloquetSystem::new(&c.rotor, &c.machine.settings, w)?;
        Ok(band_of_system(c, ev, &fs, phi_op, ev.spec.level)?.counted_width())
    };
    let speeds: Vec<f64> = bands.iter().map(|b| b.speed).collect();
    let (mut a, mut b) = (speeds[k.saturating_sub(1)], speeds[(k + 1).min(speeds.len() - 1)]);
    let mut best = (speeds[k], worst);
    let g = (5f64.sqrt() - 1.0) / 2.0;
    let (mut x1, mut x2) = (b - g * (b - a), a + g * (b - a));
    let (mut f1, mut f2) = (at(x1)?, at(x2)?);
    for _ in 2..SPEED_REFINEMENTS {
        if f1 < f2 {
            b = x2;
            (x2, f2) = (x1, f1);
            x1 = b - g * (b - a);
            f1 = at(x1)?;
        } else {
            a = x1;
            (x1, f1) = (x2, f2);
            x2 = a + g * (b - a);
            f2 = at(x2)?;
        }
    }
    for (w, f) in [(x1, f1), (x2, f2)] {
        if f < best.1 {
            best = (w, f);
        }
    }
    Ok(best)
}

/// The smallest signed band width over the speeds (rad/s).
pub fn smallest(bands: &[OperatingBand]) -> f64 {
    bands.iter().map(OperatingBand::signed_width).fold(f64::INFINITY, f64::min)
}

/// The smallest width over the speeds that the widest-band objective counts (rad/s):
/// none of what the window supplies ([`crate::analysis::regions::Band::counted_width`]).
pub fn smallest_counted(bands: &[OperatingBand]) -> f64 {
    bands.iter().map(|b| b.band.counted_width()).fold(f64::INFINITY, f64::min)
}

/// One build judged ([`Build`]) at the speeds of `built`'s reduced systems.
fn build(built: &Candidate, ev: &EvalContext<'_>, phi_op: f64, p: &Perturbation) -> Result<Build, DesignError> {
    let spec = ev.spec;
    let bands = operating_bands(built, ev, phi_op)?;
    let mut failure = None;
    if let Some(b) = bands.iter().find(|b| b.band.band.is_none()) {
        failure = Some(format!("phi_op = {phi_op} rad/s is unstable at Omega = {} rad/s", b.speed));
    }
    if let (None, Some(m)) = (&failure, spec.constraints.margins) {
        let at = operating_bands_at(built, ev, phi_op, m.level(spec.level))?;
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
        speeds: bands.iter().map(|b| b.speed).collect(),
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
    let ev = EvalContext { spec, regions: s, count: &count };
    let corners: Vec<Build> = t
        .corners()
        .par_iter()
        .map(|p| {
            let b = build(&c.perturbed(spec, p)?, &ev, phi_op, p);
            tick();
            b
        })
        .collect::<Result<_, _>>()?;
    let guaranteed = |builds: &[&Build]| -> Vec<Option<Interval>> {
        spec.speeds
            .iter()
            .map(|&w| {
                builds
                    .iter()
                    .filter_map(|b| b.speeds.iter().position(|&x| x == w).map(|i| b.bands[i]))
                    .try_fold(None::<Interval>, |acc, band| {
                        let band = band?;
                        Some(Some(match acc {
                            None => band,
                            Some(a) => Interval::new(a.lo.max(band.lo), a.hi.min(band.hi)),
                        }))
                    })
                    .flatten()
            })
            .collect()
    };
    // Over a speed range the samples are judged where the corners leave the narrowest
    // guaranteed band (an unstable φ_op first): the corners bound the box at every speed,
    // and the samples check, where it is tightest, that no build inside does worse.
    let sample_speed = spec.speed_range.map(|_| {
        let by_corners = guaranteed(&corners.iter().collect::<Vec<_>>());
        let width = |k: usize| by_corners[k].map_or(f64::NEG_INFINITY, |b| b.width());
        let k = (0..spec.speeds.len()).min_by(|&a, &b| width(a).total_cmp(&width(b))).unwrap_or(0);
        spec.speeds[k]
    });
    let samples: Vec<Build> = t
        .draw()
        .par_iter()
        .map(|p| {
            let built = match sample_speed {
                Some(w) => {
                    let mut b = c.perturbed_rotor(p)?;
                    b.systems = vec![(w, FloquetSystem::new(&b.rotor, &b.machine.settings, w)?)];
                    b
                }
                None => c.perturbed(spec, p)?,
            };
            let b = build(&built, &ev, phi_op, p);
            tick();
            b
        })
        .collect::<Result<_, _>>()?;
    let all = || corners.iter().chain(&samples);
    let worst = all().min_by(|a, b| a.width.total_cmp(&b.width)).cloned().unwrap_or_else(|| corners[0].clone());
    let failing = all().find(|b| b.failure.is_some()).cloned();
    let guaranteed = guaranteed(&all().collect::<Vec<_>>());
    Ok(Robustness {
        sample_speed,
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
        "the band around phi_op = {phi_op} rad/s at every build of the tolerance box ({}): its centre and {} corners at every speed, and {} Monte Carlo samples{}, {} of {} builds failing; worst build `{}`: band {} (smallest width {:.2} rad/s); guaranteed band (the intersection over every build) {}",
        r.tolerances.text(),
        r.corners.len() - 1,
        r.samples,
        sample_speed_text(r),
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

/// Where the samples were judged, in words: empty when at every speed.
fn sample_speed_text(r: &Robustness) -> String {
    r.sample_speed.map_or(String::new(), |w| {
        format!(" at Omega = {w} rad/s (where the corners leave the narrowest guaranteed band)")
    })
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
        "guaranteed band {} over {} builds (centre, {} corners, {} samples{}), worst build `{}`{}",
        bands.join(", "),
        r.checked(),
        r.corners.len() - 1,
        r.samples,
        sample_speed_text(r),
        r.worst.perturbation.name,
        if r.holds() { String::new() } else { format!(", {} build(s) failing: NOT ROBUST", r.failed()) }
    )
}

/// The tuned design over its speed range, on the verification's fine grid.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SpeedCheck {
    /// The range (rad/s).
    pub range: Interval,
    /// (speed in rad/s, band around φ_op in rad/s or None where φ_op is unstable) at each
    /// speed of the grid ([`crate::design::spec::VERIFY_SPEEDS`]).
    pub bands: Vec<(f64, Option<Interval>)>,
    /// The speeds where the design does not hold, with why.
    pub failing: Vec<(f64, String)>,
    /// The speed of the narrowest band (rad/s) and its signed width (rad/s).
    pub narrowest: (f64, f64),
    /// Monodromy evaluations of the check.
    pub evaluations: usize,
}

/// The tuned design `c` at every speed of the fine grid over its speed range: φ_op stable,
/// the band at least the band-width constraint's width, the margins met; `tick` per speed.
pub fn speed_check(
    c: &Candidate,
    spec: &DesignSpec,
    range: Interval,
    phi_op: f64,
    s: &RegionSettings,
    tick: &(dyn Fn() + Sync),
) -> Result<SpeedCheck, DesignError> {
    let count = Counter::default();
    let ev = EvalContext { spec, regions: s, count: &count };
    let grid = crate::design::spec::speed_grid(range, crate::design::spec::VERIFY_SPEEDS);
    let judged: Vec<(f64, crate::analysis::regions::Band, Option<String>)> = grid
        .par_iter()
        .map(|&w| {
            let fs = FloquetSystem::new(&c.rotor, &c.machine.settings, w)?;
            let band = band_of_system(c, &ev, &fs, phi_op, spec.level)?;
            let mut why = None;
            if band.band.is_none() {
                why = Some(format!("phi_op = {phi_op} rad/s is unstable"));
            } else if let Some(min) = spec.constraints.min_band_width.filter(|m| band.signed_width() < m.width) {
                why = Some(format!("the band is {:.3} rad/s wide, below {} rad/s", band.signed_width(), min.width));
            } else if let Some(m) = spec.constraints.margins {
                let at = band_of_system(c, &ev, &fs, phi_op, m.level(spec.level))?;
                let short = margin_shortfall(&[OperatingBand { speed: w, band: at }], &m);
                if short > 0.0 {
                    why = Some(format!("the frequency margin at the margin level is short by {short:.3} rad/s"));
                }
            }
            tick();
            Ok((w, band, why))
        })
        .collect::<Result<_, DesignError>>()?;
    let narrowest = judged
        .iter()
        .map(|(w, b, _)| (*w, b.signed_width()))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap_or((range.lo, f64::NAN));
    Ok(SpeedCheck {
        range,
        bands: judged.iter().map(|(w, b, _)| (*w, b.band)).collect(),
        failing: judged.iter().filter_map(|(w, _, why)| why.clone().map(|y| (*w, y))).collect(),
        narrowest,
        evaluations: count.get(),
    })
}

/// The speed part's sentence.
pub fn speed_summary(r: &SpeedCheck, phi_op: f64) -> String {
    let mut s = format!(
        "the band around phi_op = {phi_op} rad/s at {} speeds over Omega = {}..{} rad/s, {} failing; narrowest at Omega = {:.2} rad/s: signed width {:.2} rad/s",
        r.bands.len(),
        r.range.lo,
        r.range.hi,
        r.failing.len(),
        r.narrowest.0,
        r.narrowest.1
    );
    if let Some((w, why)) = r.failing.first() {
        s += &format!("; first failing speed {w:.2} rad/s: {why}");
    }
    s
}

/// Over the speed range, before and after, in words: how many of the grid's speeds fail.
pub fn speed_range_text(before: Option<&SpeedCheck>, after: &SpeedCheck) -> String {
    let one = |r: &SpeedCheck| match r.failing.first() {
        Some((w, why)) => {
            format!("fails at {} of {} speeds (first Omega = {w:.2} rad/s: {why})", r.failing.len(), r.bands.len())
        }
        None => format!(
            "holds at all {} speeds (narrowest band at Omega = {:.2} rad/s, {:.2} rad/s)",
            r.bands.len(),
            r.narrowest.0,
            r.narrowest.1
        ),
    };
    let mut s = format!("over Omega = {}..{} rad/s", after.range.lo, after.range.hi);
    if let Some(b) = before {
        s += &format!(": the reference {}", one(b));
    }
    s + &format!("; the tuned design {}", one(after))
}
