//! The trade-off between damping and the stable band (`rotorshunt design --pareto K`):
//! K designs from the best-damped one to the one with the widest stable band around φ_op,
//! each run and verified as a design of its own.
//!
//! The front is traced by the ε-constraint method on the min-peak-response objective:
//! - the **best-damping end** is the least peak response whose band around φ_op at β_op
//!   is at least [`FLOOR_WIDTH`] wide (φ_op kept stable);
//! - the **widest-band end** is the widest-stable-band design on the same variables;
//! - the K − 2 points between are the least peak responses whose band is at least a
//!   width evenly spaced between the two ends' verified widths.
//!
//! Every other constraint of the file (operating bands kept clear, a peak limit, damping
//! floors, margins) holds at every point. The points between are run from the widest end
//! down, each with the next wider point as one more start: that design meets the narrower
//! width too, and the Nelder–Mead runs keep the best feasible design they evaluate, so a
//! point's peak is at most its wider neighbour's. A point that is still dominated (a
//! point at least as wide with a lower verified peak) is run again from the point that
//! dominates it. The figures of the front are the verifier's, not the optimiser's: each
//! band is the full catalogue's stable band around φ_op ([`crate::design::verify`]), each
//! peak the response found again on a grid ten times finer
//! (`crate::design::vibration::peak_recheck`).

use super::machine::Machine;
use super::objective::min_peak::MinPeakResponse;
use super::objective::widest_band::WidestStableBand;
use super::optimise::{run_with, RunOptions};
use super::spec::{BandWidth, DesignSpec, Response};
use super::verify::{PEAK_AGREEMENT, PEAK_GRID_FACTOR, SAME_EDGE};
use super::vibration::{peak_recheck, Baseline, PeakValue};
use super::{DesignError, DesignOutcome, Status};
use crate::analysis::Interval;
use crate::progress::Progress;
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// Fewest points of a front: its two ends.
pub const MIN_POINTS: usize = 2;
/// Most points of a front (each a whole design run).
pub const MAX_POINTS: usize = 50;
/// The band asked of the best-damping end (rad/s): φ_op stable with a band around it at
/// least this wide. A band narrower than 1 rad/s holds no operating point a machine can
/// keep, and 1 rad/s is eight steps of the band search's edge resolution (0.125 rad/s).
pub const FLOOR_WIDTH: f64 = 1.0;

/// What a front trades: the peak response at a node against the stable band around φ_op.
#[derive(Debug, Clone, PartialEq)]
pub struct TradeOff {
    /// φ_op (rad/s).
    pub phi_op: f64,
    /// The unbalance response whose peak is minimised.
    pub response: Response,
}

/// Why a design file has no trade-off for a front: the key to blame and the reason.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{reason}")]
pub struct NoTradeOff {
    /// The key path in the problem file, e.g. `design.objective`.
    pub key: String,
    /// Why, in words, with what to add.
    pub reason: String,
}

/// The trade-off of `spec`: min-peak-response with a band-width constraint (its φ_op), or
/// widest-stable-band with a `[design.response]`. Clear-bands, min-peak-response without a
/// band, widest-stable-band without a response and a design with component tolerances
/// (the points are traced at nominal values) have none.
pub fn trade_off(spec: &DesignSpec) -> Result<TradeOff, NoTradeOff> {
    let refuse = |key: &str, reason: &str| NoTradeOff { key: key.into(), reason: reason.into() };
    if spec.tolerances.is_some() {
        return Err(refuse(
            "design.tolerances",
            "a front's points are traced at nominal values: drop [design.tolerances] for the front, and design the point you choose with them afterwards",
        ));
    }
    spec.objective.trade_off(spec)
}

/// The design of one point: the least peak with a band at least `width` wide (rad/s)
/// around φ_op, or, for `None`, the widest band; the file's other constraints kept.
pub fn point_spec(spec: &DesignSpec, t: &TradeOff, width: Option<f64>) -> DesignSpec {
    let mut constraints = spec.constraints.clone();
    match width {
        Some(width) => {
            constraints.min_band_width = Some(BandWidth { phi_op: t.phi_op, width });
            DesignSpec {
                objective: MinPeakResponse { response: t.response.clone() }.into(),
                response: None,
                constraints,
                ..spec.clone()
            }
        }
        None => {
            constraints.min_band_width = None;
            DesignSpec {
                objective: WidestStableBand { phi_op: t.phi_op }.into(),
                response: Some(t.response.clone()),
                constraints,
                ..spec.clone()
            }
        }
    }
}

/// Where a point lies on the front.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Role {
    /// The least peak with φ_op stable ([`FLOOR_WIDTH`]).
    BestDamping,
    /// The least peak with a band at least a width between the ends'.
    Between,
    /// The widest stable band around φ_op.
    WidestBand,
}

/// One point of the front, with the verifier's figures.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct FrontPoint {
    /// 1 (best damping) to K (widest band).
    pub index: usize,
    /// Where it lies on the front.
    pub role: Role,
    /// The band width asked of the point (rad/s); none for the widest-band end.
    pub asked_width: Option<f64>,
    /// The variable values (SI units, as in the problem file).
    pub values: Vec<f64>,
    /// The run's status (improved and unchanged are results; see [`Status`]).
    pub status: Status,
    /// Whether the run's design passed its verification.
    pub verified: bool,
    /// The verification's verdict in words.
    pub verdict: String,
    /// The full catalogue's stable band around φ_op at β_op, at the speed where it is
    /// narrowest (rad/s); none when φ_op is unstable there.
    pub band: Option<Interval>,
    /// Its width (rad/s): the smallest over the speeds; 0 when φ_op is unstable.
    pub width: f64,
    /// The peak response found again on a grid [`PEAK_GRID_FACTOR`] times finer than the
    /// optimiser's, refined.
    pub peak: PeakValue,
    /// The API 684 amplification factor of the peak on the response grid (−), when the
    /// half-power speeds lie inside the range.
    pub amplification_factor: Option<f64>,
    /// The point (index) that is at least as wide with a lower peak, if any: then this one
    /// is not on the front.
    pub dominated_by: Option<usize>,
    /// How many times the point was run again from a point that dominated it.
    pub reruns: usize,
    /// The whole run: starts, history, verification part by part.
    pub outcome: DesignOutcome,
}

/// A traced front.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Front {
    /// φ_op (rad/s).
    pub phi_op: f64,
    /// β_op (−).
    pub level: f64,
    /// The response whose peak is traded.
    pub response: Response,
    /// The points, from the best damping to the widest band.
    pub points: Vec<FrontPoint>,
    /// The best-damped design's band is already as wide as the widest band found: the
    /// front is its two ends.
    pub collapsed: bool,
    /// Whether the verified figures rise together: widths non-decreasing (within
    /// [`SAME_EDGE`]) and peaks non-decreasing (within [`PEAK_AGREEMENT`]) from point 1 to K.
    pub monotone: bool,
    /// Whether the ends are ends: the widest-band end at least as wide as every point
    /// (within [`SAME_EDGE`]) and the best-damping end at least as damped (a peak no
    /// higher, within [`PEAK_AGREEMENT`]).
    #[serde(default)]
    pub ends_consistent: bool,
    /// The band width the file itself asks (`constraints.min_band_width`, rad/s), if any.
    pub file_min_width: Option<f64>,
    /// Design runs made (K, plus the reruns).
    pub runs: usize,
    /// Candidate designs analysed over all runs.
    pub candidates: usize,
    /// Monodromy evaluations over all runs, optimisation and verification.
    pub evaluations: usize,
    /// Wall time (s).
    pub seconds: f64,
}

impl Front {
    /// Whether every point is a verified result.
    pub fn verified(&self) -> bool {
        self.points.iter().all(|p| p.verified && p.status.is_result())
    }
}

/// Passes the runs' phases on as more steps of the one phase of the front.
struct Relay<'a>(&'a dyn Progress);

impl Progress for Relay<'_> {
    fn phase(&self, _name: &str, steps: u64) {
        self.0.extend(steps);
    }
    fn extend(&self, steps: u64) {
        self.0.extend(steps);
    }
    fn advance(&self, steps: u64) {
        self.0.advance(steps);
    }
    fn warning(&self, w: &dyn std::fmt::Display) {
        self.0.warning(w);
    }
    fn notice(&self, line: &str) {
        self.0.notice(line);
    }
    fn evaluated(&self, count: u64) {
        self.0.evaluated(count);
    }
    fn cancelled(&self) -> bool {
        self.0.cancelled()
    }
}

/// Run one point: the design of [`point_spec`] with the caller's `options`, and its
/// verified figures.
fn point(
    base: &Machine,
    spec: &DesignSpec,
    t: &TradeOff,
    width: Option<f64>,
    options: RunOptions,
    progress: &dyn Progress,
) -> Result<FrontPoint, DesignError> {
    let spec = point_spec(spec, t, width);
    let outcome = run_with(base, &spec, &options, progress)?;
    // The band: the full catalogue's, at the speed where it is narrowest.
    let mut band: Option<Interval> = None;
    let mut width_found = f64::INFINITY;
    for d in &outcome.after_speeds {
        let w = d.catalogue_band.map_or(0.0, |b| b.width());
        if w < width_found {
            width_found = w;
            band = d.catalogue_band;
        }
    }
    // The peak: the verification's recheck, or (widest band) the same recheck here.
    let peak = match outcome.verification.peak {
        Some(p) => p.recheck,
        None => {
            let (_, rotor) = super::vibration::rotor_at(base, &spec, &outcome.after)?;
            peak_recheck(&rotor, &t.response, PEAK_GRID_FACTOR)?.0
        }
    };
    let amplification_factor =
        outcome.vibration.as_ref().and_then(|v| Baseline::of("point", &v.after).amplification_factor);
    Ok(FrontPoint {
        index: 0,
        role: match width {
            None => Role::WidestBand,
            Some(_) => Role::Between,
        },
        asked_width: width,
        values: outcome.after.clone(),
        status: outcome.status,
        verified: outcome.verified(),
        verdict: outcome.verification.verdict.clone(),
        band,
        width: if width_found.is_finite() { width_found } else { 0.0 },
        peak,
        amplification_factor,
        dominated_by: None,
        reruns: 0,
        outcome,
    })
}

/// Whether `a` dominates `b`: at least as wide, and a lower peak by more than the
/// recheck's agreement.
fn dominates(a: &FrontPoint, b: &FrontPoint) -> bool {
    a.width >= b.width - SAME_EDGE && a.peak.amplitude < b.peak.amplitude * (1.0 - PEAK_AGREEMENT)
}

/// The point (index) that dominates point `j`, if any.
fn dominator(points: &[FrontPoint], j: usize) -> Option<usize> {
    (0..points.len()).find(|&i| i != j && dominates(&points[i], &points[j]))
}

/// The first dominated point that may be run again (not yet run again, and not the
/// widest-band end, which no band constraint describes), with the one that dominates it.
fn first_to_rerun(points: &[FrontPoint]) -> Option<(usize, usize)> {
    (0..points.len())
        .filter(|&j| points[j].reruns == 0 && points[j].role != Role::WidestBand)
        .find_map(|j| dominator(points, j).map(|i| (j, i)))
}

/// Whether the first point is the best damped and the last the widest ([`Front::ends_consistent`]).
fn ends_consistent(points: &[FrontPoint]) -> bool {
    let (Some(first), Some(last)) = (points.first(), points.last()) else { return false };
    points
        .iter()
        .all(|p| p.width <= last.width + SAME_EDGE && p.peak.amplitude >= first.peak.amplitude * (1.0 - PEAK_AGREEMENT))
}

/// Trace the front of `base`'s design with `k` points ([`MIN_POINTS`]..=[`MAX_POINTS`]):
/// see the module docs. `progress` sees one phase, `front`, whose steps are the runs'
/// candidates and verification points, known as each run begins.
pub fn front(base: &Machine, spec: &DesignSpec, k: usize, progress: &dyn Progress) -> Result<Front, DesignError> {
    let t = trade_off(spec).map_err(DesignError::NoTradeOff)?;
    if !(MIN_POINTS..=MAX_POINTS).contains(&k) {
        return Err(DesignError::FrontPoints(k));
    }
    let started = Instant::now();
    progress.phase("front", 0);
    let relay = Relay(progress);
    let mut runs = 2;
    let (damping, widest) = rayon::join(
        || point(base, spec, &t, Some(FLOOR_WIDTH), RunOptions::default(), &relay),
        || point(base, spec, &t, None, RunOptions::default(), &relay),
    );
    let (mut damping, widest) = (damping?, widest?);
    damping.role = Role::BestDamping;
    // The unconstrained optimum does not depend on the band asked: found once.
    let unconstrained = damping.outcome.peak_findings().map(|f| f.unconstrained.values.clone());
    let options = |name: String, start: &[f64]| RunOptions {
        extra_starts: vec![(name, start.to_vec())],
        unconstrained: unconstrained.clone(),
        observer: None,
    };
    let (lo, hi) = (damping.width.max(FLOOR_WIDTH), widest.width);
    let collapsed = hi <= lo + SAME_EDGE;
    let mut points = vec![damping];
    if !collapsed {
        // From the widest end down, each point started from its wider neighbour.
        let mut between = Vec::new();
        let mut wider = widest.values.clone();
        for i in (1..k - 1).rev() {
            let width = lo + (hi - lo) * i as f64 / (k - 1) as f64;
            let p = point(base, spec, &t, Some(width), options("the next wider point".into(), &wider), &relay)?;
            runs += 1;
            wider = p.values.clone();
            between.push(p);
        }
        between.reverse();
        points.extend(between);
    }
    points.push(widest);
    // A dominated point run again from the point that dominates it (whose band is wide
    // enough for it): at most once per point.
    while let Some((j, i)) = first_to_rerun(&points) {
        let start = options(format!("front point {}", i + 1), &points[i].values);
        let mut again = point(base, spec, &t, points[j].asked_width, start, &relay)?;
        runs += 1;
        again.role = points[j].role;
        again.reruns = points[j].reruns + 1;
        points[j] = again;
    }
    // The widest-band end at least as wide as every other point: when a point between is
    // wider, the widest-band design is run again with it as one more start (once), and
    // kept when it is wider than before.
    let last = points.len() - 1;
    let wider = (0..last)
        .filter(|&i| points[i].width > points[last].width + SAME_EDGE)
        .max_by(|&a, &b| points[a].width.total_cmp(&points[b].width));
    if let Some(i) = wider {
        let start = options(format!("front point {}", i + 1), &points[i].values);
        let mut again = point(base, spec, &t, None, start, &relay)?;
        runs += 1;
        again.reruns = points[last].reruns + 1;
        if again.width > points[last].width {
            points[last] = again;
        }
    }
    let ends_consistent = ends_consistent(&points);
    for (n, p) in points.iter_mut().enumerate() {
        p.index = n + 1;
    }
    let dominated: Vec<Option<usize>> = (0..points.len()).map(|j| dominator(&points, j).map(|i| i + 1)).collect();
    for (p, d) in points.iter_mut().zip(dominated) {
        p.dominated_by = d;
    }
    let monotone = points.windows(2).all(|w| {
        w[1].width >= w[0].width - SAME_EDGE && w[1].peak.amplitude >= w[0].peak.amplitude * (1.0 - PEAK_AGREEMENT)
    });
    let candidates = points.iter().map(|p| p.outcome.candidates).sum();
    let evaluations =
        points.iter().map(|p| p.outcome.floquet_evaluations + p.outcome.verification_cost.evaluations).sum();
    Ok(Front {
        phi_op: t.phi_op,
        level: spec.level,
        response: t.response,
        points,
        collapsed,
        monotone,
        ends_consistent,
        file_min_width: spec.constraints.min_band_width.map(|b| b.width),
        runs,
        candidates,
        evaluations,
        seconds: started.elapsed().as_secs_f64(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::design::objective::clear_bands::ClearBands;
    use crate::design::objective::AnyObjective;
    use crate::design::spec::{Band, Constraints};

    fn spec(objective: AnyObjective, constraints: Constraints, response: Option<Response>) -> DesignSpec {
        DesignSpec {
            objective,
            level: 0.3,
            phi_range: (100.0, 8000.0),
            beta_max: 0.6,
            speeds: vec![2000.0],
            variables: Vec::new(),
            starts: 3,
            max_iterations: 20,
            response,
            constraints,
            speed_range: None,
            tolerances: None,
            speed_unit: Default::default(),
            chart_grid: crate::design::spec::CHART_GRID,
            refined_check: true,
            map: true,
            warnings: Default::default(),
        }
    }

    fn response() -> Response {
        Response { node: 16, speeds: Interval::new(250.0, 500.0), points: 201 }
    }

    #[test]
    fn only_a_peak_against_a_band_is_a_trade_off() {
        let width =
            Constraints { min_band_width: Some(BandWidth { phi_op: 370.0, width: 225.0 }), ..Default::default() };
        let min_peak = AnyObjective::new(MinPeakResponse { response: response() });
        let t = trade_off(&spec(min_peak.clone(), width.clone(), None)).unwrap();
        assert_eq!((t.phi_op, t.response.node), (370.0, 16));
        let e = trade_off(&spec(min_peak, Constraints::default(), None)).unwrap_err();
        assert_eq!(e.key, "design.objective");
        let widest = AnyObjective::new(WidestStableBand { phi_op: 1230.0 });
        assert_eq!(trade_off(&spec(widest.clone(), Constraints::default(), Some(response()))).unwrap().phi_op, 1230.0);
        assert!(trade_off(&spec(widest, Constraints::default(), None)).is_err());
        let clear = AnyObjective::new(ClearBands { bands: vec![Band { lo: 1.0, hi: 2.0, clearance: 0.0 }] });
        assert!(trade_off(&spec(clear, width, Some(response()))).unwrap_err().reason.contains("single objective"));
    }

    #[test]
    fn a_point_keeps_the_other_constraints_and_sets_its_own_width() {
        let c = Constraints {
            min_band_width: Some(BandWidth { phi_op: 370.0, width: 225.0 }),
            max_peak: Some(1e-2),
            ..Default::default()
        };
        let s = spec(MinPeakResponse { response: response() }.into(), c, None);
        let t = trade_off(&s).unwrap();
        let p = point_spec(&s, &t, Some(100.0));
        assert_eq!(p.constraints.min_band_width.map(|b| b.width), Some(100.0));
        assert_eq!(p.constraints.max_peak, Some(1e-2));
        let w = point_spec(&s, &t, None);
        assert_eq!(w.objective.phi_op(), Some(370.0));
        assert!(w.constraints.min_band_width.is_none());
        assert_eq!(w.response().map(|r| r.node), Some(16));
    }
}
