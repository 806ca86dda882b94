//! Campbell diagram: whirl frequencies over a speed range, modes tracked from speed to
//! speed by the modal assurance criterion (Figs. 6 and 7).

use super::modes::{whirls_at_least, ModeKind, ModesResult, Whirl, WhirlMode, WHIRL_WINDOW};
use super::{AnalysisError, Rotor, Settings};
use crate::progress::Progress;
use faer::{c64, ColRef};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// One point of a tracked mode.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
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
    /// Real coordinates only: the whirl direction at this speed, which may change along a
    /// track (a planar mode at rest becoming a backward ellipse with speed).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub whirl: Option<Whirl>,
}

/// One mode followed over the speed range.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Track {
    /// Tag at the track's first point (e.g. `f1`, `br2`): the mode's identity, which the
    /// track keeps over the whole range whatever its rank among the whirls.
    pub tag: String,
    /// Forward or backward whirl (real coordinates: also mixed) at the track's first
    /// point.
    pub whirl: Whirl,
    /// Mechanical or electrical at the first point.
    pub kind: ModeKind,
    /// Tag of the mode at the track's last point: differs from `tag` where the mode
    /// changes character along the range (a veering, e.g. `bs1` becoming `b3`).
    pub last_tag: String,
    /// Speed Ω (rad/s) at which the mode first counts among the lowest `count` whirls of
    /// its direction, when that is not the first speed (a mode entering the window from
    /// above, tracked back to the first speed); absent for the modes tracked from the
    /// first speed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub enters: Option<f64>,
    /// The points, one per speed from the first speed the mode could be followed to.
    pub points: Vec<TrackPoint>,
}

/// A Campbell diagram.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CampbellResult {
    /// Speeds Ω (rad/s).
    pub speeds: Vec<f64>,
    /// Tracked modes: the lowest `count` forward and backward at the first speed, then
    /// every mode that enters the lowest `count` of its direction at a later speed
    /// ([`Track::enters`]), sorted by their first frequency. In real coordinates the
    /// whirls of [`ModesResult::lowest`] (forward, backward and mixed, from a window),
    /// followed whatever their direction.
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
///
/// In real coordinates (an anisotropic model) a whirl's direction comes from its orbits
/// and may change with speed (planar at rest, then backward or forward), so the whirls
/// [`ModesResult::lowest`] lists are tracked in one pool whatever their direction, each
/// point keeping its own ([`TrackPoint::whirl`]); the modes at each speed are those of
/// the window of `count` + `TRACKING_MARGIN` (the shift-invert solve on a large model,
/// [`super::modes::lowest_whirls_of`]).
///
/// A speed not begun when [`Progress::cancelled`] turns true is skipped and the diagram
/// comes back empty, to be discarded (as a chart's rows).
pub fn campbell(
    rotor: &Rotor,
    settings: &Settings,
    speeds: &[f64],
    count: usize,
    progress: &dyn Progress,
) -> Result<CampbellResult, AnalysisError> {
    let wanted = WHIRL_WINDOW * (count + TRACKING_MARGIN);
    let solved: Vec<Option<ModesResult>> = speeds
        .par_iter()
        .map(|&w| {
            // A speed not begun when the caller asks to stop is skipped.
            if progress.cancelled() {
                return Ok(None);
            }
            let r = whirls_at_least(rotor, settings, w, wanted)?;
            progress.advance(1);
            Ok(Some(r))
        })
        .collect::<Result<_, AnalysisError>>()?;
    // Stopped: an empty diagram, which the caller that asked to stop discards.
    let Some(solved) = solved.into_iter().collect::<Option<Vec<ModesResult>>>() else {
        return Ok(CampbellResult {
            speeds: Vec::new(),
            tracks: Vec::new(),
            mac_threshold: settings.mac_threshold,
            flagged: 0,
        });
    };
    let mut tracks = Vec::new();
    let mut flagged = 0;
    if rotor.real {
        let listed: Vec<Vec<usize>> = solved.iter().map(|r| r.lowest_indices(count)).collect();
        let candidates: Vec<Vec<usize>> = solved
            .iter()
            .zip(&listed)
            .map(|(r, l)| {
                let mut c = l.clone();
                c.extend(r.window(count + TRACKING_MARGIN).into_iter().filter(|i| !l.contains(i)));
                c
            })
            .collect();
        let (found, steps) = track(&solved, &listed, &candidates, settings.mac_threshold, true);
        tracks.extend(found);
        flagged += steps;
    } else {
        for whirl in [Whirl::Forward, Whirl::Backward] {
            let of_whirl: Vec<Vec<usize>> =
                solved.iter().map(|r| (0..r.modes.len()).filter(|&i| r.modes[i].whirl == whirl).collect()).collect();
            let listed: Vec<Vec<usize>> = of_whirl.iter().map(|o| o.iter().copied().take(count).collect()).collect();
            let candidates: Vec<Vec<usize>> =
                of_whirl.iter().map(|o| o.iter().copied().take(count + TRACKING_MARGIN).collect()).collect();
            let (found, steps) = track(&solved, &listed, &candidates, settings.mac_threshold, false);
            tracks.extend(found);
            flagged += steps;
        }
    }
    tracks.sort_by(|a, b| {
        let first = |t: &Track| t.points.first().map_or((f64::INFINITY, f64::INFINITY), |p| (p.speed, p.frequency));
        let (fa, fb) = (first(a), first(b));
        fa.1.total_cmp(&fb.1).then(fa.0.total_cmp(&fb.0))
    });
    Ok(CampbellResult { speeds: speeds.to_vec(), tracks, mac_threshold: settings.mac_threshold, flagged })
}

/// A track being built: the column of its mode at each speed (`None` where it is not
/// followed) and the MAC of each point with the previous one.
struct Chain {
    cols: Vec<Option<usize>>,
    macs: Vec<f64>,
    enters: Option<usize>,
}

/// Greedy MAC assignment of `sources` (chain, column at `from`) to the `free` columns of
/// `to`, by descending MAC, ties broken by index: deterministic.
fn assign(
    from: &ModesResult,
    to: &ModesResult,
    sources: &[(usize, usize)],
    free: &[usize],
) -> Vec<(usize, usize, f64)> {
    let mut scores = Vec::new();
    for &(t, pc) in sources {
        for &c in free {
            scores.push((mac(from.shapes.col(pc), to.shapes.col(c)), t, c));
        }
    }
    scores.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
    let mut taken_t = std::collections::BTreeSet::new();
    let mut taken_c = std::collections::BTreeSet::new();
    let mut out = Vec::new();
    for (score, t, c) in scores {
        if !taken_t.contains(&t) && !taken_c.contains(&c) {
            taken_t.insert(t);
            taken_c.insert(c);
            out.push((t, c, score));
        }
    }
    out
}

/// The tracks of one pool of whirls and their number of flagged steps: `listed[s]` the
/// modes (indices into `solved[s].modes`, by frequency) to be tracked at speed `s`,
/// `candidates[s]` those a track may continue to (the listed first, then a few more).
/// First the listed modes at the first speed, followed speed by speed among the
/// candidates; then, while a listed mode at some speed belongs to no track, a new track
/// from it, followed back towards the first speed (as long as the MAC stays above
/// `threshold`) and on to the last among the candidates no track holds, so that a mode
/// entering the window gets its own track and label instead of continuing another's.
/// `per_point`: record each point's direction (real coordinates).
fn track(
    solved: &[ModesResult],
    listed: &[Vec<usize>],
    candidates: &[Vec<usize>],
    threshold: f64,
    per_point: bool,
) -> (Vec<Track>, usize) {
    if solved.is_empty() {
        return (Vec::new(), 0);
    }
    let n = solved.len();
    let mut owner: Vec<Vec<bool>> = solved.iter().map(|r| vec![false; r.modes.len()]).collect();
    let mut chains: Vec<Chain> = listed[0]
        .iter()
        .map(|&c| {
            owner[0][c] = true;
            let mut cols = vec![None; n];
            cols[0] = Some(c);
            Chain { cols, macs: vec![1.0; n], enters: None }
        })
        .collect();
    for s in 0..n.saturating_sub(1) {
        let sources: Vec<(usize, usize)> =
            chains.iter().enumerate().filter_map(|(t, ch)| ch.cols[s].map(|c| (t, c))).collect();
        let free: Vec<usize> = candidates[s + 1].clone();
        for (t, c, score) in assign(&solved[s], &solved[s + 1], &sources, &free) {
            chains[t].cols[s + 1] = Some(c);
            chains[t].macs[s + 1] = score;
            owner[s + 1][c] = true;
        }
    }
    // Modes entering the window that no track holds: a track of their own each.
    loop {
        let unowned = (0..n).find_map(|s| listed[s].iter().find(|&&c| !owner[s][c]).map(|&c| (s, c)));
        let Some((s0, c0)) = unowned else { break };
        owner[s0][c0] = true;
        let mut cols = vec![None; n];
        cols[s0] = Some(c0);
        let mut macs = vec![1.0; n];
        let free_at = |s: usize, owner: &Vec<Vec<bool>>| -> Vec<usize> {
            candidates[s].iter().copied().filter(|&c| !owner[s][c]).collect()
        };
        for s in (0..s0).rev() {
            let Some(from) = cols[s + 1] else { break };
            let Some(&(_, c, score)) = assign(&solved[s + 1], &solved[s], &[(0, from)], &free_at(s, &owner)).first()
            else {
                break;
            };
            // No credible predecessor: the mode starts here (e.g. an overdamped pair
            // becoming a whirl), rather than continuing an unrelated mode.
            if score < threshold {
                break;
            }
            cols[s] = Some(c);
            macs[s + 1] = score;
            owner[s][c] = true;
        }
        for s in s0..n.saturating_sub(1) {
            let Some(from) = cols[s] else { break };
            let Some(&(_, c, score)) =
                assign(&solved[s], &solved[s + 1], &[(0, from)], &free_at(s + 1, &owner)).first()
            else {
                break;
            };
            cols[s + 1] = Some(c);
            macs[s + 1] = score;
            owner[s + 1][c] = true;
        }
        if let Some(start) = cols.iter().position(Option::is_some) {
            macs[start] = 1.0;
        }
        chains.push(Chain { cols, macs, enters: Some(s0) });
    }
    let mut flagged = 0;
    let tracks = chains
        .into_iter()
        .filter_map(|ch| {
            let mut points = Vec::new();
            let mut ends = None;
            for (s, col) in ch.cols.iter().enumerate() {
                let Some(c) = *col else { continue };
                let m = &solved[s].modes[c];
                let first_point = points.is_empty();
                let bad = !first_point && ch.macs[s] < threshold;
                flagged += usize::from(bad);
                points.push(TrackPoint {
                    speed: solved[s].speed,
                    frequency: m.frequency,
                    damping_ratio: m.damping_ratio,
                    mac: if first_point { 1.0 } else { ch.macs[s] },
                    flagged: bad,
                    whirl: per_point.then_some(m.whirl),
                });
                let first_mode = ends.map_or(m, |(f, _): (&WhirlMode, &WhirlMode)| f);
                ends = Some((first_mode, m));
            }
            let (head, tail) = ends?;
            Some(Track {
                tag: head.tag(),
                whirl: head.whirl,
                kind: head.kind,
                last_tag: tail.tag(),
                enters: ch.enters.map(|s| solved[s].speed),
                points,
            })
        })
        .collect();
    (tracks, flagged)
}
