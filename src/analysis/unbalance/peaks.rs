//! The peaks of a probe's amplitude: each interior local maximum of the grid refined by
//! a golden-section search on the analytic response, and its API 684 half-power
//! amplification factor (the module above, section **Peaks**).

use super::{DynamicStiffness, Workspace};
use crate::analysis::AnalysisError;
use serde::{Deserialize, Serialize};

/// Relative width (of Ω_peak) of the bracket at which the golden-section search of a peak
/// stops: 1e-10 is a thousand times below [`UNBOUNDED_BANDWIDTH`], so every peak counted
/// as bounded is located well inside its half-power band, and about the f64 resolution of
/// the location of a smooth maximum (√ε ≈ 1.5e-8 of its width) for widths down to 1e-2 Ω.
pub const PEAK_SPEED_TOLERANCE: f64 = 1e-10;

/// Relative half-power bandwidth (Ω₂ − Ω₁)/Ω_peak below which a peak is reported
/// `unbounded`: an undamped mode (η = 0 and R = 0, the paper's rotor) has a pole at its
/// critical speed, and its refined "peak" is limited only by how close the search gets
/// to it (a bandwidth of ~[`PEAK_SPEED_TOLERANCE`]). 1e-7, an amplification factor of 10⁷,
/// is far beyond any damped machine (ζ = 1e-5 gives 5·10⁴) and a thousand times above
/// what the refinement resolves.
pub const UNBOUNDED_BANDWIDTH: f64 = 1e-7;

/// Bisection steps locating a half-power speed: the bracket (at most the speed range)
/// shrinks by 2⁻⁶⁰, far below [`PEAK_SPEED_TOLERANCE`] of any speed.
const HALF_POWER_STEPS: usize = 60;

/// Golden-section steps at most: a bracket of the whole admitted speed range shrinks by
/// 0.618¹²⁰ ≈ 1e-25, below [`PEAK_SPEED_TOLERANCE`] of any peak.
const GOLDEN_STEPS: usize = 120;

/// Solves of the analytic response a peak may cost at most (golden section and both
/// half-power bisections): what the cost estimate counts per peak.
pub const SOLVES_PER_PEAK: usize = GOLDEN_STEPS + 2 * HALF_POWER_STEPS;

/// Two neighbouring peaks of one curve are a **split pair** when the lower reaches the
/// higher's half-power level (at least 1/√2 of it) and their speeds lie within this share
/// of the higher's speed (−): a resonance split in two by a tuned absorber (a shunt tuned
/// to a whirl splits it by about the coupling √K², a few per cent), not two separate
/// modes. API 684's amplification factor is defined for an isolated resonance: for a
/// member of a split pair it measures one peak of the two, and is flagged as such.
pub const SPLIT_PAIR_SPACING: f64 = 0.10;

/// A peak of a probe's amplitude.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Peak {
    /// Speed of the refined maximum Ω_peak (rad/s).
    pub speed: f64,
    /// Amplitude there (m).
    pub amplitude: f64,
    /// Phase there (rad, convention of the module).
    pub phase: f64,
    /// Half-power speeds [Ω₁, Ω₂] (rad/s); absent when one lies beyond the speed range
    /// (or beyond a neighbouring higher peak).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub half_power: Option<[f64; 2]>,
    /// API 684 amplification factor Ω_peak/(Ω₂ − Ω₁) (−); absent with `half_power`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub amplification_factor: Option<f64>,
    /// The peak is a pole of the response (half-power bandwidth below
    /// [`UNBOUNDED_BANDWIDTH`]·Ω_peak): an undamped critical speed, whose amplitude is
    /// limited only by the refinement, not by the physics.
    pub unbounded: bool,
    /// The speed (rad/s) of the other peak of a split pair this one belongs to
    /// ([`SPLIT_PAIR_SPACING`]); None for an isolated peak.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub split_pair: Option<f64>,
}

impl Peak {
    /// What a reader must know of the amplification factor beside it: for a member of a
    /// split pair, ` (one peak of a split pair with the peak at X rad/s)`; else nothing.
    pub fn split_note(&self) -> String {
        split_note(self.split_pair)
    }
}

/// [`Peak::split_note`] of a peak whose pair partner is at `partner` (rad/s).
pub fn split_note(partner: Option<f64>) -> String {
    partner.map_or(String::new(), |w| format!(" (one peak of a split pair with the peak at {w:.2} rad/s)"))
}

/// Marks the split pairs of `peaks` (sorted by speed; [`SPLIT_PAIR_SPACING`]).
fn mark_split_pairs(peaks: &mut [Peak]) {
    for i in 1..peaks.len() {
        let (a, b) = (&peaks[i - 1], &peaks[i]);
        let (high, low) = if a.amplitude >= b.amplitude { (a, b) } else { (b, a) };
        let close = (b.speed - a.speed).abs() <= SPLIT_PAIR_SPACING * high.speed;
        if close && low.amplitude >= high.amplitude / std::f64::consts::SQRT_2 && !a.unbounded && !b.unbounded {
            let (wa, wb) = (a.speed, b.speed);
            peaks[i - 1].split_pair = Some(wb);
            peaks[i].split_pair = Some(wa);
        }
    }
}

/// The response at one DOF and its samples on the speed grid: what the refinement of a
/// peak asks.
struct Curve<'a> {
    a: &'a DynamicStiffness,
    dof: usize,
    /// The grid speeds (rad/s).
    speeds: &'a [f64],
    /// |U_dof| at each grid speed (m).
    amp: &'a [f64],
    /// Every (Ω, |U|, arg U) the refinement solved, for the drawn curve.
    samples: std::cell::RefCell<Vec<[f64; 3]>>,
}

impl Curve<'_> {
    /// The amplitude and phase at DOF `dof` at speed Ω ([`DynamicStiffness::amplitude`]).
    fn at(&self, speed: f64, work: &mut Workspace) -> Result<(f64, f64), AnalysisError> {
        let (amplitude, phase) = self.a.amplitude(&self.a.solve(speed, work)?, self.dof);
        self.samples.borrow_mut().push([speed, amplitude, phase]);
        Ok((amplitude, phase))
    }
}

/// The interior local maxima of `amp` over `speeds`, refined, and every sample of the
/// analytic response the refinement solved (Ω, |U|, arg U), sorted by speed: points of the
/// same response as the grid, dense near each peak (the golden section closes in on it,
/// the half-power bisections sample both flanks), so a curve drawn through the grid and
/// them passes through every refined peak.
pub(super) fn refine_peaks(
    a: &DynamicStiffness,
    dof: usize,
    speeds: &[f64],
    amp: &[f64],
    work: &mut Workspace,
) -> Result<(Vec<Peak>, Vec<[f64; 3]>), AnalysisError> {
    let curve = Curve { a, dof, speeds, amp, samples: Default::default() };
    let mut peaks = Vec::new();
    for i in 1..amp.len().saturating_sub(1) {
        // Strict on the left, not on the right: a flat top counts once.
        if !(amp[i] > amp[i - 1] && amp[i] >= amp[i + 1]) {
            continue;
        }
        let (speed, value) = golden_max(&curve, speeds[i - 1], speeds[i + 1], (speeds[i], amp[i]), work)?;
        let amplitude = value.0;
        let half = amplitude / std::f64::consts::SQRT_2;
        let left = half_power(&curve, speed, half, Side::Below, work)?;
        let right = half_power(&curve, speed, half, Side::Above, work)?;
        let half_power = left.zip(right).map(|(l, r)| [l, r]);
        let width = half_power.map(|[l, r]| r - l);
        let unbounded = width.is_some_and(|w| w < UNBOUNDED_BANDWIDTH * speed);
        peaks.push(Peak {
            speed,
            amplitude,
            phase: value.1,
            half_power,
            amplification_factor: width.filter(|w| *w > 0.0).map(|w| speed / w),
            unbounded,
            split_pair: None,
        });
    }
    mark_split_pairs(&mut peaks);
    let mut samples = curve.samples.into_inner();
    samples.sort_by(|x, y| x[0].total_cmp(&y[0]));
    samples.dedup_by(|x, y| x[0] == y[0]);
    Ok((peaks, samples))
}

/// Golden-section maximisation of |U_dof| on [lo, hi], which holds the grid maximum
/// `best` (speed, amplitude): the refined (speed, U). The grid point is kept if the search
/// finds nothing higher (a maximum at a bracket end).
fn golden_max(
    curve: &Curve<'_>,
    lo: f64,
    hi: f64,
    best: (f64, f64),
    work: &mut Workspace,
) -> Result<(f64, (f64, f64)), AnalysisError> {
    const INV_PHI: f64 = 0.618_033_988_749_894_9;
    let (mut lo, mut hi) = (lo, hi);
    let mut x1 = hi - INV_PHI * (hi - lo);
    let mut x2 = lo + INV_PHI * (hi - lo);
    let mut f1 = curve.at(x1, work)?;
    let mut f2 = curve.at(x2, work)?;
    for _ in 0..GOLDEN_STEPS {
        if hi - lo <= PEAK_SPEED_TOLERANCE * best.0.max(f64::MIN_POSITIVE) {
            break;
        }
        if f1.0 >= f2.0 {
            hi = x2;
            (x2, f2) = (x1, f1);
            x1 = hi - INV_PHI * (hi - lo);
            f1 = curve.at(x1, work)?;
        } else {
            lo = x1;
            (x1, f1) = (x2, f2);
            x2 = lo + INV_PHI * (hi - lo);
            f2 = curve.at(x2, work)?;
        }
    }
    let (x, f) = if f1.0 >= f2.0 { (x1, f1) } else { (x2, f2) };
    if f.0 >= best.1 {
        Ok((x, f))
    } else {
        Ok((best.0, curve.at(best.0, work)?))
    }
}

#[derive(Clone, Copy, PartialEq)]
enum Side {
    Below,
    Above,
}

/// The nearest speed on `side` of the peak at `peak` where the amplitude falls to `half`:
/// the first grid speed beyond the peak below `half`, then bisection between it and the
/// last speed at or above `half`. None when the grid ends first, or rises above the peak
/// amplitude (√2·half) first (a higher neighbouring peak).
fn half_power(
    curve: &Curve<'_>,
    peak: f64,
    half: f64,
    side: Side,
    work: &mut Workspace,
) -> Result<Option<f64>, AnalysisError> {
    let (speeds, amp) = (curve.speeds, curve.amp);
    let top = half * std::f64::consts::SQRT_2;
    let order: Box<dyn Iterator<Item = usize>> = match side {
        Side::Above => Box::new((0..speeds.len()).filter(|&i| speeds[i] > peak)),
        Side::Below => Box::new((0..speeds.len()).rev().filter(|&i| speeds[i] < peak)),
    };
    let mut inside = peak;
    for i in order {
        if amp[i] > top {
            return Ok(None);
        }
        if amp[i] < half {
            let mut outside = speeds[i];
            for _ in 0..HALF_POWER_STEPS {
                let mid = 0.5 * (inside + outside);
                if mid == inside || mid == outside {
                    break;
                }
                if curve.at(mid, work)?.0 >= half {
                    inside = mid;
                } else {
                    outside = mid;
                }
            }
            return Ok(Some(0.5 * (inside + outside)));
        }
        inside = speeds[i];
    }
    Ok(None)
}

#[cfg(test)]
mod split_pair_tests {
    use super::*;

    fn peak(speed: f64, amplitude: f64) -> Peak {
        Peak {
            speed,
            amplitude,
            phase: 0.0,
            half_power: None,
            amplification_factor: None,
            unbounded: false,
            split_pair: None,
        }
    }

    fn pairs(p: &[(f64, f64)]) -> Vec<Option<f64>> {
        let mut peaks: Vec<Peak> = p.iter().map(|&(w, a)| peak(w, a)).collect();
        mark_split_pairs(&mut peaks);
        peaks.iter().map(|k| k.split_pair).collect()
    }

    #[test]
    fn two_close_peaks_of_like_height_are_a_split_pair_and_others_are_not() {
        // The tuned shunt's pair on the paper's rotor: 354.9 and 364.3 rad/s, 2.258e-2 and
        // 2.260e-2 m.
        assert_eq!(pairs(&[(354.9, 2.258e-2), (364.3, 2.260e-2)]), [Some(364.3), Some(354.9)]);
        // The lower under the higher's half-power level (1/√2 = 0.7071): separate peaks.
        assert_eq!(pairs(&[(354.9, 1.0), (364.3, 0.70)]), [None, None]);
        assert_eq!(pairs(&[(354.9, 1.0), (364.3, 0.71)]), [Some(364.3), Some(354.9)]);
        // Like heights far apart (more than 10 % of the higher's speed): two modes.
        assert_eq!(pairs(&[(360.0, 1.0), (400.0, 1.0)]), [None, None]);
        assert_eq!(pairs(&[(360.0, 1.0), (395.0, 1.0), (2000.0, 1.0)]), [Some(395.0), Some(360.0), None]);
    }
}
