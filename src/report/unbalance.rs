//! Unbalance response rendering: the Bode plot (amplitude on a log scale over the phase),
//! the Pareto plot of designs, the CSV, the text table of peaks, and the damping table.

use super::clip;
use super::plot::{area_box, draw_pieces, with_legend_column, Curve, CurvePlot, Drawing, Layout, PlotError};
use super::style::{self, err, Dash, Entry, Key, Marker};
use crate::analysis::damping::ModeDamping;
use crate::analysis::unbalance::UnbalanceResult;
use crate::numbers::SpeedUnit;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::cell::Cell;

/// Smallest amplitude drawn, relative to the largest: the log axis spans at most eight
/// decades (the response vanishes like Ω² at rest, and an exact zero has no logarithm).
const AMPLITUDE_DECADES: f64 = 1e-8;

/// One configuration drawn in a Bode plot.
pub struct BodeLayer<'a> {
    /// Legend suffix: the file or the overrides.
    pub name: String,
    /// Drawn dashed (the compared configuration).
    pub dashed: bool,
    /// This configuration's unbalance response: speeds Ω (rad/s), each probe's amplitude
    /// (m) and phase (rad).
    pub result: &'a UnbalanceResult,
}

/// A Bode plot of one or two configurations: every probe's amplitude (m, log scale) over
/// its phase (rad, unwrapped along the speed), against the speed (rad/s, or rpm when the
/// speeds were given in rpm). Each curve is the grid with the samples of the peaks'
/// refinement ([`crate::analysis::unbalance::ProbeResponse::curve`]), so it passes through
/// every refined peak, and the amplitude axis spans every peak.
pub struct BodePlot<'a> {
    /// Caption drawn above the plot (shrunk or wrapped to fit).
    pub title: String,
    /// The configurations (solid, then dashed).
    pub layers: Vec<BodeLayer<'a>>,
    /// The unit of the speed axis.
    pub unit: crate::numbers::SpeedUnit,
}

/// A probe's drawn curve in a [`BodePlot`]: its index (colour), layer, points (x in the
/// axis unit, |U| m, arg U rad) and refined peaks.
type DrawnProbe<'a> = (usize, &'a BodeLayer<'a>, Vec<[f64; 3]>, &'a [crate::analysis::unbalance::Peak]);
/// A probe's phase curve: its index, layer and points (x, arg U in degrees).
type PhaseCurve<'a> = (usize, &'a BodeLayer<'a>, Vec<(f64, f64)>);

/// The phase unwrapped along the speeds (rad): jumps of more than π are taken as 2π
/// wraps, so the curve is continuous through −π.
pub fn unwrapped(phase: &[f64]) -> Vec<f64> {
    let mut out = Vec::with_capacity(phase.len());
    let mut shift = 0.0;
    for (i, &p) in phase.iter().enumerate() {
        if i > 0 {
            let d = p - phase[i - 1];
            if d > std::f64::consts::PI {
                shift -= 2.0 * std::f64::consts::PI;
            } else if d < -std::f64::consts::PI {
                shift += 2.0 * std::f64::consts::PI;
            }
        }
        out.push(p + shift);
    }
    out
}

impl BodePlot<'_> {
    /// The drawn amplitude curves, one per layer and probe: (x in the axis unit, |U| m),
    /// the grid and the refinement's samples merged by speed.
    pub fn drawn(&self) -> Vec<Vec<(f64, f64)>> {
        self.layers
            .iter()
            .flat_map(|l| l.result.probes.iter().map(|p| p.curve(&l.result.speeds)))
            .map(|c| c.into_iter().map(|[w, a, _]| (self.unit.value(w), a)).collect())
            .collect()
    }

    /// The amplitude axis (m) and the smallest amplitude drawn: the drawn curves and every
    /// refined peak inside, at most `AMPLITUDE_DECADES` below the largest.
    pub fn amplitude_axis(&self) -> ((f64, f64), f64) {
        let curves = self.drawn();
        let peaks =
            self.layers.iter().flat_map(|l| l.result.probes.iter().flat_map(|p| p.peaks.iter().map(|k| k.amplitude)));
        let amax = curves.iter().flatten().map(|p| p.1).chain(peaks).filter(|a| a.is_finite()).fold(0.0, f64::max);
        let amax = amax.max(f64::MIN_POSITIVE);
        let floor = amax * AMPLITUDE_DECADES;
        let amin = curves.iter().flatten().map(|p| p.1).filter(|a| *a >= floor).fold(amax, f64::min);
        let range = if amin < amax { (amin / 1.5, amax * 1.5) } else { (amax / 10.0, amax * 10.0) };
        (range, floor)
    }

    /// Legend: a colour per probe (the first layer's names), a line style per
    /// configuration when there are two.
    fn legend(&self) -> Vec<Entry> {
        let mut entries = Vec::new();
        if let Some(first) = self.layers.first() {
            for (k, p) in first.result.probes.iter().enumerate() {
                entries.push(Entry {
                    key: Key::Line(style::color(k), Dash::Solid, style::marker(k)),
                    text: p.probe.name.clone(),
                });
            }
        }
        if self.layers.len() > 1 {
            for layer in &self.layers {
                let dash = if layer.dashed { Dash::Dashed } else { Dash::Solid };
                let what = if layer.dashed { "dashed" } else { "solid" };
                entries.push(Entry {
                    key: Key::Line((0, 0, 0), dash, Marker::None),
                    text: format!("{what}: {}", layer.name),
                });
            }
        }
        entries.push(Entry { key: Key::Line((0, 0, 0), Dash::Solid, Marker::Circle), text: "peak".into() });
        entries
    }
}

/// The layout's plotting area is the amplitude and phase axes as one box.
impl Drawing for BodePlot<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>, layout: &Cell<Layout>) -> Result<(), PlotError> {
        root.fill(&WHITE).map_err(err)?;
        let area = style::titled(&root, &self.title)?;
        let entries = self.legend();
        let (area, legend_area) = with_legend_column(area, &entries)?;
        let (top, bottom) = area.split_vertically((area.dim_in_pixel().1 as f64 * 0.6) as u32);
        let unit = self.unit;
        // Each probe's drawn curve: (x in the axis unit, |U|, arg U).
        let curves: Vec<DrawnProbe<'_>> = self
            .layers
            .iter()
            .flat_map(|l| {
                l.result.probes.iter().enumerate().map(move |(k, p)| {
                    let c = p.curve(&l.result.speeds).into_iter().map(|[w, a, ph]| [unit.value(w), a, ph]).collect();
                    (k, l, c, p.peaks.as_slice())
                })
            })
            .collect();
        let xs = || curves.iter().flat_map(|c| c.2.iter().map(|p| p[0]));
        let x0 = xs().fold(f64::INFINITY, f64::min);
        let x1 = xs().fold(f64::NEG_INFINITY, f64::max);
        let (x0, x1) = if x1 > x0 { (x0, x1) } else { (x0 - 1.0, x0 + 1.0) };
        let ((ylo, yhi), floor) = self.amplitude_axis();
        let curve = |k: usize, layer: &BodeLayer<'_>, points: Vec<(f64, f64)>| Curve {
            dash: if layer.dashed { Dash::Dashed } else { Dash::Solid },
            marker: style::marker(k),
            ..Curve::new("", style::color(k), points)
        };
        let mut amp = ChartBuilder::on(&top)
            .margin(style::MARGIN)
            .x_label_area_size(30)
            .y_label_area_size(85)
            .build_cartesian_2d(x0..x1, (ylo..yhi).log_scale())
            .map_err(err)?;
        amp.configure_mesh()
            .y_desc(style::axis_label("amplitude", "|U|", "m"))
            .x_label_formatter(&style::tick)
            .y_label_formatter(&style::log_tick)
            .label_style((style::FONT, style::TICK_SIZE))
            .axis_desc_style((style::FONT, style::AXIS_LABEL_SIZE))
            .draw()
            .map_err(err)?;
        for (k, layer, points, peaks) in &curves {
            let points: Vec<(f64, f64)> = points.iter().filter(|p| p[1] >= floor).map(|p| (p[0], p[1])).collect();
            let pieces = clip::clip_polyline(&points, (x0, x1), (ylo, yhi));
            draw_pieces(&mut amp, &curve(*k, layer, Vec::new()), pieces)?;
            let c = style::rgb(style::color(*k));
            amp.draw_series(
                peaks.iter().map(|p| Circle::new((unit.value(p.speed), p.amplitude), 4, c.stroke_width(2))),
            )
            .map_err(err)?;
        }
        let amp_box = area_box(amp.plotting_area());

        let phases: Vec<PhaseCurve<'_>> = curves
            .iter()
            .map(|(k, l, c, _)| {
                let phase: Vec<f64> = c.iter().map(|p| p[2]).collect();
                let deg = unwrapped(&phase).into_iter().map(f64::to_degrees);
                (*k, *l, c.iter().map(|p| p[0]).zip(deg).collect())
            })
            .collect();
        let plo = phases.iter().flat_map(|x| x.2.iter().map(|p| p.1)).fold(f64::INFINITY, f64::min);
        let phi = phases.iter().flat_map(|x| x.2.iter().map(|p| p.1)).fold(f64::NEG_INFINITY, f64::max);
        let (plo, phi) = if phi > plo { (plo - 10.0, phi + 10.0) } else { (-180.0, 30.0) };
        let mut ph = ChartBuilder::on(&bottom)
            .margin(style::MARGIN)
            .x_label_area_size(50)
            .y_label_area_size(85)
            .build_cartesian_2d(x0..x1, plo..phi)
            .map_err(err)?;
        ph.configure_mesh()
            .x_desc(style::axis_label("speed", unit.symbol(), unit.unit()))
            .y_desc(style::axis_label("phase", "arg U", "deg"))
            .x_label_formatter(&style::tick)
            .y_label_formatter(&style::tick)
            .label_style((style::FONT, style::TICK_SIZE))
            .axis_desc_style((style::FONT, style::AXIS_LABEL_SIZE))
            .draw()
            .map_err(err)?;
        for (k, layer, points) in &phases {
            let pieces = clip::clip_polyline(points, (x0, x1), (plo, phi));
            draw_pieces(&mut ph, &curve(*k, layer, Vec::new()), pieces)?;
        }
        let ph_box = area_box(ph.plotting_area());
        let mut legend_box = None;
        if let Some(l) = legend_area {
            let off = area_box(&l)[0];
            legend_box = style::draw_legend_panel(&l, &entries, (amp_box[0].1 - off.1).max(0))?
                .map(|b| [(b[0].0 + off.0, b[0].1 + off.1), (b[1].0 + off.0, b[1].1 + off.1)]);
        }
        layout.set(Layout { plot: [amp_box[0], (amp_box[1].0.max(ph_box[1].0), ph_box[1].1)], legend: legend_box });
        root.present().map_err(err)
    }
}

/// A Pareto plot of designs: peak unbalance response (m, log scale) against the width of
/// the stable band (rad/s), one marker per design with its label beside the legend.
/// `points` are (peak response m, stable band width rad/s); `labels` name them (missing
/// labels: `design k`).
pub fn plot_pareto(points: &[(f64, f64)], labels: &[String], title: &str) -> CurvePlot {
    let xs = || points.iter().map(|p| p.1).filter(|v| v.is_finite());
    let ys = || points.iter().map(|p| p.0).filter(|v| v.is_finite() && *v > 0.0);
    let (x0, x1) = (xs().fold(f64::INFINITY, f64::min), xs().fold(f64::NEG_INFINITY, f64::max));
    let (y0, y1) = (ys().fold(f64::INFINITY, f64::min), ys().fold(f64::NEG_INFINITY, f64::max));
    let pad = ((x1 - x0) * 0.05).max(1.0);
    let (x0, x1) = if x0.is_finite() { (x0 - pad, x1 + pad) } else { (0.0, 1.0) };
    let (y0, y1) = if y0.is_finite() { (y0 / 1.5, y1 * 1.5) } else { (1e-6, 1.0) };
    let curves = points
        .iter()
        .enumerate()
        .map(|(k, p)| Curve {
            marker: match style::marker(k) {
                Marker::None => Marker::Circle,
                m => m,
            },
            ..Curve::new(
                labels.get(k).cloned().unwrap_or_else(|| format!("design {}", k + 1)),
                style::color(k),
                vec![(p.1, p.0)],
            )
        })
        .collect();
    CurvePlot {
        title: title.to_string(),
        x_label: style::axis_label("stable band width", "", "rad/s"),
        y_label: style::axis_label("peak response", "", "m"),
        x_range: (x0, x1),
        y_range: (y0, y1),
        log_y: true,
        curves,
    }
}

/// Long-format CSV: one row per probe and speed.
pub fn unbalance_csv(r: &UnbalanceResult) -> Result<String, csv::Error> {
    let mut w = csv::Writer::from_writer(Vec::new());
    // Real coordinates: the orbit's columns after the complex path's (amplitude is then
    // the semi-major axis, phase that of x).
    let orbits = r.probes.iter().any(|p| p.orbit.is_some());
    let mut header = vec!["probe", "kind", "node", "speed_rad_s", "amplitude_m", "phase_rad"];
    if orbits {
        header.extend([
            "x_amplitude_m",
            "x_phase_rad",
            "y_amplitude_m",
            "y_phase_rad",
            "major_m",
            "minor_m",
            "forward_m",
            "backward_m",
        ]);
    }
    w.write_record(&header)?;
    for p in &r.probes {
        let kind =
            serde_json::to_value(p.probe.kind).ok().and_then(|v| v.as_str().map(String::from)).unwrap_or_default();
        let node = p.probe.node.map(|n| n.to_string()).unwrap_or_default();
        for (i, w_) in r.speeds.iter().enumerate() {
            let mut row = vec![
                p.probe.name.clone(),
                kind.clone(),
                node.clone(),
                w_.to_string(),
                p.amplitude[i].to_string(),
                p.phase[i].to_string(),
            ];
            if let Some(o) = &p.orbit {
                for v in [
                    &o.x_amplitude,
                    &o.x_phase,
                    &o.y_amplitude,
                    &o.y_phase,
                    &o.major,
                    &o.minor,
                    &o.forward,
                    &o.backward,
                ] {
                    row.push(v[i].to_string());
                }
            }
            w.write_record(&row)?;
        }
    }
    let bytes = w.into_inner().map_err(|e| e.into_error())?;
    Ok(String::from_utf8_lossy(&bytes).into_owned())
}

/// CSV of the peaks: one row per probe and peak.
pub fn peaks_csv(r: &UnbalanceResult) -> Result<String, csv::Error> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "probe",
        "speed_rad_s",
        "amplitude_m",
        "phase_rad",
        "half_power_low_rad_s",
        "half_power_high_rad_s",
        "amplification_factor",
        "unbounded",
    ])?;
    for p in &r.probes {
        for k in &p.peaks {
            let [lo, hi] = k.half_power.map(|h| h.map(|v| v.to_string())).unwrap_or_default();
            w.write_record([
                p.probe.name.clone(),
                k.speed.to_string(),
                k.amplitude.to_string(),
                k.phase.to_string(),
                lo,
                hi,
                k.amplification_factor.map(|a| a.to_string()).unwrap_or_default(),
                k.unbounded.to_string(),
            ])?;
        }
    }
    let bytes = w.into_inner().map_err(|e| e.into_error())?;
    Ok(String::from_utf8_lossy(&bytes).into_owned())
}

/// The peaks as a text table, with each probe's largest amplitude over the range.
pub fn peaks_text(r: &UnbalanceResult, heading: &str, unit: SpeedUnit) -> String {
    let mut s = format!("{heading}\n");
    for p in &r.probes {
        let (w, a, unbounded) = p.largest(&r.speeds);
        s += &format!(
            "  {}: largest {:.4e} m at {}{}\n",
            p.probe.name,
            a,
            unit.text(w),
            if unbounded { " (unbounded: undamped critical speed)" } else { "" }
        );
        for k in &p.peaks {
            let af = match (k.amplification_factor, k.unbounded) {
                (_, true) => "unbounded (no damping acts on this mode)".to_string(),
                (Some(af), false) => format!("AF = {af:.2}{}", k.split_note()),
                (None, false) => "AF not defined (half-power point beyond the range)".to_string(),
            };
            s += &format!(
                "    peak at {}: {:.4e} m, phase {:+.3} rad, {af}\n",
                unit.text(k.speed),
                k.amplitude,
                k.phase
            );
        }
    }
    s
}

/// The damping ratios as a text table: per mode its ζ at the first and last speed and its
/// smallest ζ with the speed of it.
pub fn damping_text(modes: &[ModeDamping], speeds: &[f64], unit: SpeedUnit) -> String {
    let (first, last) = (speeds.first().copied().unwrap_or(0.0), speeds.last().copied().unwrap_or(0.0));
    let mut s = format!(
        "damping ratios zeta = -Re(lambda)/|lambda| over {} speeds, {}\n{:<14} {:>14} {:>14} {:>14} {:>14} {:>8}\n",
        speeds.len(),
        unit.range(first, last),
        "mode",
        "zeta first",
        "zeta last",
        "zeta min",
        "at (rad/s)",
        "flagged"
    );
    for m in modes {
        let p = &m.track.points;
        let flagged = p.iter().filter(|x| x.flagged).count();
        s += &format!(
            "{:<14} {:>14.6e} {:>14.6e} {:>14.6e} {:>14.2} {:>8}\n",
            m.tag,
            p.first().map_or(f64::NAN, |x| x.damping_ratio),
            p.last().map_or(f64::NAN, |x| x.damping_ratio),
            m.min_damping_ratio,
            m.min_speed,
            flagged
        );
    }
    s
}
