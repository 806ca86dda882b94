//! The min-peak design as built (`[design.tolerances]`): its peak at every corner of the
//! tolerance box and at the box's Monte Carlo samples ([`crate::design::tolerance`]), each
//! on the model rebuilt with the parts' factors under the design's P_cr. The optimiser
//! minimises the worst corner's peak; the verification finds it again and adds the
//! samples, which the corners need not bound.

use super::*;
use crate::design::spec::Response;
use crate::design::tolerance::{Perturbation, Tolerances};
use crate::design::vibration::{peak_of, PeakValue};
use crate::model::Model;

/// The peak of one build of a design: a corner of the tolerance box or a sample.
#[derive(Debug, Clone, Serialize, serde::Deserialize)]
pub struct CornerPeak {
    /// The build (`L+ R-`, `sample 12`; [`Perturbation::name`]).
    pub build: String,
    /// Its largest amplitude at the response node (m).
    pub peak: PeakValue,
}

/// The tuned min-peak design over its tolerance box.
#[derive(Debug, Clone, Serialize, serde::Deserialize)]
pub struct PeakAsBuilt {
    /// The tolerances judged.
    pub tolerances: Tolerances,
    /// The peak at the box's centre (`nominal`) and every corner.
    pub corners: Vec<CornerPeak>,
    /// Monte Carlo samples judged.
    pub samples: usize,
    /// The sample with the largest peak.
    pub worst_sample: Option<CornerPeak>,
    /// The build with the largest peak, corners and samples together: the peak the
    /// designer can count on with parts inside the tolerances.
    pub worst: CornerPeak,
    /// Builds over `design.constraints.max_peak`, when there is one.
    pub over_limit: usize,
}

/// The peak of the design `model` (under P_cr = `critical_load`, N) built as `p`
/// ([`Perturbation::apply`]).
pub(crate) fn build_peak(
    model: &Model,
    critical_load: f64,
    p: &Perturbation,
    response: &Response,
) -> Result<CornerPeak, DesignError> {
    let rotor = crate::Rotor::new(&p.apply(model, critical_load))?;
    Ok(CornerPeak { build: p.name.clone(), peak: peak_of(&rotor, response)? })
}

/// The largest peak of `peaks`.
pub(crate) fn largest(peaks: &[CornerPeak]) -> Option<&CornerPeak> {
    peaks.iter().max_by(|a, b| a.peak.amplitude.total_cmp(&b.peak.amplitude))
}

/// The tuned design `tuned` over the box `t` ([`PeakAsBuilt`]), and the verification part
/// `tolerance-peaks`: it fails when the optimiser's worst corner (`optimiser`) is not found
/// again within [`PEAK_AGREEMENT`], or when a build exceeds `max_peak` (m). The samples
/// run in parallel (the outermost loop); `tick` once per build.
pub(super) fn check(
    tuned: &Candidate,
    t: &Tolerances,
    response: &Response,
    optimiser: Option<&CornerPeak>,
    max_peak: Option<f64>,
    tick: &(dyn Fn() + Sync),
) -> Result<(PeakAsBuilt, VerificationPart), DesignError> {
    let (model, load) = (&tuned.machine.model, tuned.rotor.critical_load);
    // Each build's peak, the builds in parallel (the outermost loop).
    let peaks = |builds: Vec<Perturbation>| -> Result<Vec<CornerPeak>, DesignError> {
        builds
            .par_iter()
            .map(|p| {
                let c = build_peak(model, load, p, response);
                tick();
                c
            })
            .collect()
    };
    let corners = peaks(t.corners())?;
    let samples = peaks(t.draw())?;
    let worst_corner = largest(&corners[1..]).or(corners.first()).cloned();
    let worst_sample = largest(&samples).cloned();
    let all: Vec<CornerPeak> = corners.iter().chain(&samples).cloned().collect();
    let worst = largest(&all).cloned().ok_or_else(|| DesignError::Optimiser("no build judged".into()))?;
    let over_limit = max_peak.map_or(0, |m| all.iter().filter(|b| b.peak.amplitude > m).count());
    let mut failed = over_limit;
    let mut again = String::new();
    if let (Some(o), Some(w)) = (optimiser, &worst_corner) {
        let d = (w.peak.amplitude - o.peak.amplitude).abs() / o.peak.amplitude.abs();
        if d > PEAK_AGREEMENT {
            failed += 1;
        }
        again = format!(
            "; the optimiser's worst corner `{}` {:.6e} m found again as `{}` {:.6e} m, {:.4} % apart (at most {} %)",
            o.build,
            o.peak.amplitude,
            w.build,
            w.peak.amplitude,
            100.0 * d,
            100.0 * PEAK_AGREEMENT
        );
    }
    let nominal = corners.first().map_or(f64::NAN, |c| c.peak.amplitude);
    let rise = |p: &CornerPeak| format!("{:+.1} %", 100.0 * (p.peak.amplitude / nominal - 1.0));
    let limit = match max_peak {
        Some(m) => format!("; {over_limit} build(s) over the peak limit {m:e} m"),
        None => String::new(),
    };
    let summary = format!(
        "the tuned design's peak at node {} at every build of the tolerance box ({}): its centre, {} corners and {} Monte Carlo samples; nominal {nominal:.6e} m; worst corner `{}` {:.6e} m ({}); worst sample {}; worst build {:.6e} m ({}){again}{limit}",
        response.node,
        t.text(),
        corners.len() - 1,
        samples.len(),
        worst_corner.as_ref().map_or("–".into(), |w| w.build.clone()),
        worst_corner.as_ref().map_or(f64::NAN, |w| w.peak.amplitude),
        worst_corner.as_ref().map_or("–".into(), rise),
        worst_sample.as_ref().map_or("none".into(), |w| format!("`{}` {:.6e} m ({})", w.build, w.peak.amplitude, rise(w))),
        worst.peak.amplitude,
        rise(&worst),
    );
    let part = VerificationPart::of("tolerance-peaks", all.len(), failed, summary, "");
    let as_built = PeakAsBuilt { tolerances: *t, corners, samples: samples.len(), worst_sample, worst, over_limit };
    Ok((as_built, part))
}
