//! Campbell diagram: whirl frequencies over a speed range, modes tracked from speed to
//! speed by the modal assurance criterion (Figs. 6 and 7).

use super::modes::{whirl_modes_of, ModeKind, ModesResult, Whirl};
use super::{AnalysisError, Rotor, Settings};
use crate::progress::Progress;
use faer::{c64, ColRef};
use rayon::prelude::*;
use serde::Serialize;

/// One point of a tracked mode.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TrackPoint {
    /// Speed Ω (rad/s).
    pub speed: f64,
    /// Whirl frequency (rad/s).
    pub frequency: f64,
    /// Damping ratio (−).
    pub damping_ratio: f64,
    /// MAC with the previous point of the track (1 at the first speed).
    pub mac: f64,
    /// True when `mac` is below the threshold: a possible crossing or swap.
    pub flagged: bool,
}

/// One mode followed over the speed range.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Track {
    /// Tag at the first speed (e.g. `f1`, `br2`).
    pub tag: String,
    /// Forward or backward whirl.
    pub whirl: Whirl,
    /// Mechanical or electrical at the first speed.
    pub kind: ModeKind,
    /// The points, one per speed.
    pub points: Vec<TrackPoint>,
}

/// A Campbell diagram.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CampbellResult {
    /// Speeds Ω (rad/s).
    pub speeds: Vec<f64>,
    /// Tracked modes: the lowest `count` forward and backward at the first speed.
    pub tracks: Vec<Track>,
    /// MAC threshold used (−).
    pub mac_threshold: f64,
    /// Number of flagged steps.
    pub flagged: usize,
}

/// Modal assurance criterion |xᴴy|²/(xᴴx·yᴴy) of two complex shapes.
pub fn mac(x: ColRef<'_, c64>, y: ColRef<'_, c64>) -> f64 {
    let mut xy = c64::new(0.0, 0.0);
    let (mut xx, mut yy) = (0.0, 0.0);
    for i in 0..x.nrows() {
        xy += x[i].conj() * y[i];
        xx += x[i].norm_sqr();
        yy += y[i].norm_sqr();
    }
    xy.norm_sqr() / (xx * yy)
}

/// Extra candidates per whirl direction considered at each new speed, so that a mode
/// entering the lowest `count` from above can still be matched.
const TRACKING_MARGIN: usize = 3;

/// Campbell diagram of the lowest `count` forward and backward whirls over `speeds`
/// (rad/s). Eigen-solutions run in parallel over speeds (`progress` advances one step per
/// speed); tracking is sequential and deterministic.
pub fn campbell(
    rotor: &Rotor,
    settings: &Settings,
    speeds: &[f64],
    count: usize,
    progress: &dyn Progress,
) -> Result<CampbellResult, AnalysisError> {
    let solved: Vec<ModesResult> = speeds
        .par_iter()
        .map(|&w| {
            let r = whirl_modes_of(rotor, settings, w);
            progress.advance(1);
            r
        })
        .collect::<Result<_, _>>()?;
    let mut tracks = Vec::new();
    let mut flagged = 0;
    for whirl in [Whirl::Forward, Whirl::Backward] {
        let pick = |r: &ModesResult, n: usize| -> Vec<usize> {
            (0..r.modes.len()).filter(|&i| r.modes[i].whirl == whirl).take(n).collect()
        };
        let Some(first) = solved.first() else { break };
        // (track, column of its shape in the current speed's result)
        // A track whose mode has no partner left (e.g. it became overdamped) ends there.
        let mut current: Vec<(Track, Option<usize>)> = pick(first, count)
            .into_iter()
            .map(|i| {
                let m = &first.modes[i];
                let p = TrackPoint {
                    speed: first.speed,
                    frequency: m.frequency,
                    damping_ratio: m.damping_ratio,
                    mac: 1.0,
                    flagged: false,
                };
                (Track { tag: m.tag(), whirl, kind: m.kind, points: vec![p] }, Some(i))
            })
            .collect();
        for pair in solved.windows(2) {
            let (prev, next) = (&pair[0], &pair[1]);
            let candidates = pick(next, count + TRACKING_MARGIN);
            let mut scores = Vec::new();
            for (t, (_, pc)) in current.iter().enumerate() {
                let Some(pc) = *pc else { continue };
                for &c in &candidates {
                    scores.push((mac(prev.shapes.col(pc), next.shapes.col(c)), t, c));
                }
            }
            // Greedy assignment by descending MAC, ties broken by index: deterministic.
            scores.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
            let mut taken_t = vec![false; current.len()];
            let mut taken_c = vec![false; next.modes.len()];
            let mut assigned = vec![None; current.len()];
            for (score, t, c) in scores {
                if !taken_t[t] && !taken_c[c] {
                    taken_t[t] = true;
                    taken_c[c] = true;
                    assigned[t] = Some((score, c));
                }
            }
            for (t, (track, col)) in current.iter_mut().enumerate() {
                let Some((score, c)) = assigned[t] else {
                    *col = None;
                    continue;
                };
                let m = &next.modes[c];
                let bad = score < settings.mac_threshold;
                flagged += usize::from(bad);
                track.points.push(TrackPoint {
                    speed: next.speed,
                    frequency: m.frequency,
                    damping_ratio: m.damping_ratio,
                    mac: score,
                    flagged: bad,
                });
                *col = Some(c);
            }
        }
        tracks.extend(current.into_iter().map(|(t, _)| t));
    }
    tracks.sort_by(|a, b| a.points[0].frequency.total_cmp(&b.points[0].frequency));
    Ok(CampbellResult { speeds: speeds.to_vec(), tracks, mac_threshold: settings.mac_threshold, flagged })
}
