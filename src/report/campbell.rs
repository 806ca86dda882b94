//! Campbell diagram rendering: plot, CSV, and the critical speeds (the 1× crossings).

use super::plot::{Curve, CurvePlot};
use super::style::{self, Dash, Marker};
use crate::analysis::campbell::{CampbellResult, Track};
use crate::analysis::modes::{ModeKind, Whirl};
use crate::numbers::SpeedUnit;
use serde::Serialize;

/// Colour of the synchronous line ω = Ω.
const SYNCHRONOUS_COLOR: (u8, u8, u8) = (40, 40, 40);

/// A critical speed: where a tracked whirl crosses the synchronous line ω = Ω (1×), the
/// speed at which unbalance excites it in resonance.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CriticalSpeed {
    /// The track's tag at its first point (its identity, [`Track::tag`]).
    pub track: String,
    /// Forward, backward or mixed whirl.
    pub whirl: Whirl,
    /// Mechanical or electrical (at the track's first point).
    pub kind: ModeKind,
    /// Speed Ω of the crossing (rad/s), interpolated linearly between the two speeds of
    /// the grid around it.
    pub speed: f64,
    /// The same speed in rpm.
    pub speed_rpm: f64,
}

/// The crossings of every track with the 1× line (ω = Ω), by speed: each sign change of
/// ω − Ω between consecutive points of a track, interpolated linearly. Forward whirls are
/// the critical speeds unbalance excites; backward crossings are listed too (with their
/// whirl), as an anisotropic support can excite them.
pub fn critical_speeds(r: &CampbellResult) -> Vec<CriticalSpeed> {
    let mut out = Vec::new();
    for t in &r.tracks {
        for w in t.points.windows(2) {
            let (g0, g1) = (w[0].frequency - w[0].speed, w[1].frequency - w[1].speed);
            if (g0 > 0.0) == (g1 > 0.0) || g0 == g1 {
                continue;
            }
            let speed = w[0].speed + (w[1].speed - w[0].speed) * g0 / (g0 - g1);
            out.push(CriticalSpeed {
                track: t.tag.clone(),
                whirl: t.whirl,
                kind: t.kind,
                speed,
                speed_rpm: speed / crate::problem::units::RAD_PER_S_PER_RPM,
            });
        }
    }
    out.sort_by(|a, b| a.speed.total_cmp(&b.speed));
    out
}

/// What a whirl is, in words: `forward`, `backward, electrical`.
fn character(whirl: Whirl, kind: ModeKind) -> String {
    let w = match whirl {
        Whirl::Forward => "forward",
        Whirl::Backward => "backward",
        Whirl::Mixed => "mixed",
    };
    match kind {
        ModeKind::Mechanical => w.to_string(),
        ModeKind::Electrical => format!("{w}, electrical"),
    }
}

/// Legend name of a track: its tag and what it is (`f1 (forward)`, `br1 (backward,
/// electrical)`); where the mode changes character along the range (a veering), what it
/// becomes (`bs1, becomes b3 (backward, electrical)`); and the speed it enters the window
/// at when it does.
pub fn track_name(t: &Track, unit: SpeedUnit) -> String {
    let mut name = t.tag.clone();
    if t.last_tag != t.tag {
        name += &format!(", becomes {}", t.last_tag);
    }
    name += &format!(" ({})", character(t.whirl, t.kind));
    if let Some(w) = t.enters {
        name += &format!(", enters at {} {}", crate::numbers::sig(unit.value(w), 4), unit.unit());
    }
    name
}

/// Colour of an operating speed's line.
const OPERATING_COLOR: (u8, u8, u8) = (0, 0, 0);

/// The Campbell diagram of Figs. 6 and 7: one colour (and, beyond 12 modes, marker) per
/// mode, forward whirls solid and backward dashed, the synchronous line ω = Ω (1×)
/// dotted; the operating speeds as vertical lines and the critical speeds (the 1×
/// crossings of forward whirls, [`critical_speeds`]) as circles, each in the legend
/// with its speed; the speed axis in `unit` (rpm when the user gave rpm), the whirl
/// frequency in rad/s. The legend beside the plot names each mode by identity
/// ([`track_name`]).
pub fn campbell_plot(r: &CampbellResult, title: &str, unit: SpeedUnit, operating: &[f64]) -> CurvePlot {
    let x_max = r.speeds.iter().copied().fold(f64::MIN, f64::max);
    let x_min = r.speeds.iter().copied().fold(f64::MAX, f64::min);
    let x_range = (x_min, if x_max > x_min { x_max } else { x_min + 1.0 });
    let y_max =
        (r.tracks.iter().flat_map(|t| t.points.iter().map(|p| p.frequency)).fold(0.0, f64::max) * 1.05).max(1.0);
    let mut curves: Vec<Curve> = r
        .tracks
        .iter()
        .enumerate()
        .map(|(k, t)| Curve {
            dash: if t.whirl == Whirl::Backward { Dash::Dashed } else { Dash::Solid },
            marker: style::marker(k),
            ..Curve::new(
                track_name(t, unit),
                style::color(k),
                t.points.iter().map(|p| (unit.value(p.speed), p.frequency)).collect(),
            )
        })
        .collect();
    let top = x_range.1.min(y_max);
    let bottom = x_range.0.max(0.0);
    curves.push(Curve {
        dash: Dash::Dotted,
        width: style::THIN + 1,
        ..Curve::new("1× (ω = Ω)", SYNCHRONOUS_COLOR, vec![(unit.value(bottom), bottom), (unit.value(top), top)])
    });
    for &w in operating.iter().filter(|&&w| w >= x_range.0 && w <= x_range.1) {
        curves.push(Curve {
            dash: Dash::Dashed,
            width: style::THIN + 1,
            ..Curve::new(
                format!("operating speed {}", unit.text(w)),
                OPERATING_COLOR,
                vec![(unit.value(w), 0.0), (unit.value(w), y_max)],
            )
        });
    }
    for c in critical_speeds(r).iter().filter(|c| c.whirl != Whirl::Backward) {
        curves.push(Curve {
            marker: Marker::Circle,
            ..Curve::new(
                format!("critical speed ({}): {}", c.track, unit.text(c.speed)),
                SYNCHRONOUS_COLOR,
                vec![(unit.value(c.speed), c.speed)],
            )
        });
    }
    CurvePlot {
        title: title.to_string(),
        x_label: style::axis_label("speed", unit.symbol(), unit.unit()),
        y_label: style::axis_label("whirl frequency", "ω", "rad/s"),
        x_range: (unit.value(x_range.0), unit.value(x_range.1)),
        y_range: (0.0, y_max),
        log_y: false,
        curves,
    }
}

/// Long-format CSV: one row per track and speed.
pub fn campbell_csv(r: &CampbellResult) -> Result<String, csv::Error> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(["track", "whirl", "kind", "speed_rad_s", "frequency_rad_s", "damping_ratio", "mac", "flagged"])?;
    for t in &r.tracks {
        for p in &t.points {
            w.write_record([
                t.tag.clone(),
                format!("{:?}", t.whirl).to_lowercase(),
                format!("{:?}", t.kind).to_lowercase(),
                p.speed.to_string(),
                p.frequency.to_string(),
                p.damping_ratio.to_string(),
                p.mac.to_string(),
                p.flagged.to_string(),
            ])?;
        }
    }
    let bytes = w.into_inner().map_err(|e| e.into_error())?;
    Ok(String::from_utf8_lossy(&bytes).into_owned())
}
