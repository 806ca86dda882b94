//! Campbell diagram rendering: plot, CSV.

use super::plot::{LinePlot, Series};
use crate::analysis::campbell::CampbellResult;
use crate::analysis::modes::{ModeKind, Whirl};

/// Forward whirls in blue, backward in red (dashed), electrical modes in green/orange,
/// and the synchronous line ω = Ω in grey, as in Figs. 6 and 7.
pub fn campbell_plot(r: &CampbellResult, title: &str) -> LinePlot {
    let x_max = r.speeds.iter().copied().fold(f64::MIN, f64::max);
    let x_min = r.speeds.iter().copied().fold(f64::MAX, f64::min);
    let y_max = r.tracks.iter().flat_map(|t| t.points.iter().map(|p| p.frequency)).fold(0.0, f64::max) * 1.05;
    let mut series: Vec<Series> = r
        .tracks
        .iter()
        .map(|t| Series {
            name: t.tag.clone(),
            color: match (t.whirl, t.kind) {
                (Whirl::Forward, ModeKind::Mechanical) => (31, 119, 180),
                (Whirl::Backward, ModeKind::Mechanical) => (214, 39, 40),
                (Whirl::Forward, ModeKind::Electrical) => (44, 160, 44),
                (Whirl::Backward, ModeKind::Electrical) => (255, 127, 14),
            },
            dashed: t.whirl == Whirl::Backward,
            points: t.points.iter().map(|p| (p.speed, p.frequency)).collect(),
        })
        .collect();
    series.push(Series {
        name: "ω = Ω".into(),
        color: (120, 120, 120),
        dashed: true,
        points: vec![(x_min, x_min), (x_max, x_max.min(y_max))],
    });
    LinePlot {
        title: title.to_string(),
        x_label: "speed Ω (rad/s)".into(),
        y_label: "whirl frequency ω (rad/s)".into(),
        x_range: (x_min, if x_max > x_min { x_max } else { x_min + 1.0 }),
        y_range: (0.0, y_max.max(1.0)),
        series,
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
