//! Damping ratios of labelled whirl modes over a speed range (issue 17): the modal damping
//! ratio ζ = −Re λ/|λ| of each mode ([`super::modes`]), followed from speed to speed by
//! the Campbell tracking of [`super::campbell`] (MAC), so that a mode keeps its tag at
//! the first speed (`f1`, `b2`, `fr1`, …) however its frequency moves. What a constraint
//! "ζ of mode X ≥ limit" over the operating speeds evaluates.

use super::campbell::{campbell, Track};
use super::modes::{whirl_modes_of, Whirl};
use super::unbalance::check_speeds;
use super::{AnalysisError, Rotor, Settings};
use serde::{Deserialize, Serialize};

/// ζ of one tracked mode over the speeds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModeDamping {
    /// The mode's tag at the first speed, e.g. `f1`, `br1`.
    pub tag: String,
    /// The tracked points (speed, frequency, ζ, MAC, flag), one per speed.
    pub track: Track,
    /// The smallest ζ over the speeds (−).
    pub min_damping_ratio: f64,
    /// The speed of the smallest ζ (rad/s).
    pub min_speed: f64,
}

impl ModeDamping {
    fn of(track: Track) -> ModeDamping {
        let (min_speed, min_damping_ratio) = track
            .points
            .iter()
            .map(|p| (p.speed, p.damping_ratio))
            .fold((f64::NAN, f64::INFINITY), |a, b| if b.1 < a.1 { b } else { a });
        ModeDamping { tag: track.tag.clone(), track, min_damping_ratio, min_speed }
    }
}

/// The tags of the whirls at speed `speed`, lowest first per direction (forward, then
/// backward).
fn tags_at(rotor: &Rotor, settings: &Settings, speed: f64) -> Result<Vec<(String, Whirl, usize)>, AnalysisError> {
    let modes = whirl_modes_of(rotor, settings, speed)?;
    let mut out = Vec::new();
    for whirl in [Whirl::Forward, Whirl::Backward] {
        out.extend(modes.modes.iter().filter(|m| m.whirl == whirl).enumerate().map(|(rank, m)| (m.tag(), whirl, rank)));
    }
    Ok(out)
}

/// ζ of the whirl modes tagged `tags` at the first speed (e.g. `["f1", "fr1"]`), tracked
/// over `speeds` (rad/s, ascending). A tag the model does not have at the first speed is
/// [`AnalysisError::UnknownMode`], listing the tags it has. `progress` advances per speed.
pub fn mode_damping(
    rotor: &Rotor,
    settings: &Settings,
    speeds: &[f64],
    tags: &[String],
    progress: &dyn crate::progress::Progress,
) -> Result<Vec<ModeDamping>, AnalysisError> {
    check_speeds(speeds)?;
    let known = tags_at(rotor, settings, speeds[0])?;
    let mut count = 1;
    for tag in tags {
        match known.iter().find(|(t, _, _)| t == tag) {
            Some((_, _, rank)) => count = count.max(rank + 1),
            None => {
                return Err(AnalysisError::UnknownMode {
                    label: tag.clone(),
                    speed: speeds[0],
                    available: known.iter().map(|(t, _, _)| t.clone()).collect(),
                })
            }
        }
    }
    let diagram = campbell(rotor, settings, speeds, count, progress)?;
    let mut out = Vec::with_capacity(tags.len());
    for tag in tags {
        let track =
            diagram.tracks.iter().filter(|t| t.enters.is_none()).find(|t| &t.tag == tag).cloned().ok_or_else(|| {
                AnalysisError::UnknownMode {
                    label: tag.clone(),
                    speed: speeds[0],
                    available: diagram.tracks.iter().map(|t| t.tag.clone()).collect(),
                }
            })?;
        out.push(ModeDamping::of(track));
    }
    Ok(out)
}

/// ζ of the lowest `count` forward and backward whirls over `speeds` (rad/s, ascending),
/// tracked, by their frequency at the first speed.
pub fn lowest_damping(
    rotor: &Rotor,
    settings: &Settings,
    speeds: &[f64],
    count: usize,
    progress: &dyn crate::progress::Progress,
) -> Result<Vec<ModeDamping>, AnalysisError> {
    check_speeds(speeds)?;
    let diagram = campbell(rotor, settings, speeds, count, progress)?;
    Ok(diagram.tracks.into_iter().filter(|t| t.enters.is_none()).map(ModeDamping::of).collect())
}
