//! Campbell diagram rendering: plot, CSV.

use super::plot::{Curve, CurvePlot};
use super::style::{self, Dash};
use crate::analysis::campbell::{CampbellResult, Track};
use crate::analysis::modes::Whirl;

/// Colour of the synchronous line ω = Ω.
const SYNCHRONOUS_COLOR: (u8, u8, u8) = (40, 40, 40);

/// Legend name of a track: its tag, `tag → last tag` where the mode changes character
/// along the range (a veering), and the speed it enters the window from when it does.
pub fn track_name(t: &Track) -> String {
    let mut name = t.tag.clone();
    if t.last_tag != t.tag {
        name += &format!(" → {}", t.last_tag);
    }
    if let Some(w) = t.enters {
        name += &format!(" (enters at Ω = {})", style::tick(&w));
    }
    name
}

/// The Campbell diagram of Figs. 6 and 7: one colour (and, beyond 12 modes, marker) per
/// mode, forward whirls solid and backward dashed, the synchronous line ω = Ω (1×)
/// dotted; the legend beside the plot names each mode by identity ([`track_name`]).
pub fn campbell_plot(r: &CampbellResult, title: &str) -> CurvePlot {
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
                format!("{} ({})", track_name(t), if t.whirl == Whirl::Backward { "backward" } else { "forward" }),
                style::color(k),
                t.points.iter().map(|p| (p.speed, p.frequency)).collect(),
            )
        })
        .collect();
    let top = x_range.1.min(y_max);
    curves.push(Curve {
        dash: Dash::Dotted,
        width: style::THIN + 1,
        ..Curve::new("1× (ω = Ω)", SYNCHRONOUS_COLOR, vec![(x_range.0.max(0.0), x_range.0.max(0.0)), (top, top)])
    });
    CurvePlot {
        title: title.to_string(),
        x_label: style::axis_label("speed", "Ω", "rad/s"),
        y_label: style::axis_label("whirl frequency", "ω", "rad/s"),
        x_range,
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
