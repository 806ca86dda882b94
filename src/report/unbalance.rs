//! Unbalance response rendering: the Bode plot (amplitude on a log scale over the phase),
//! the CSV, the text table of peaks, and the damping table.

use super::plot::{render_png, render_svg, PlotError};
use crate::analysis::damping::ModeDamping;
use crate::analysis::unbalance::{ProbeResponse, UnbalanceResult};
use plotters::coord::Shift;
use plotters::prelude::*;

/// Colours of the probes, in order (matplotlib's tab10).
const COLORS: [(u8, u8, u8); 10] = [
    (31, 119, 180),
    (255, 127, 14),
    (44, 160, 44),
    (214, 39, 40),
    (148, 103, 189),
    (140, 86, 75),
    (227, 119, 194),
    (127, 127, 127),
    (188, 189, 34),
    (23, 190, 207),
];

/// Smallest amplitude drawn, relative to the largest: the log axis spans at most eight
/// decades (the response vanishes like Ω² at rest, and an exact zero has no logarithm).
const AMPLITUDE_DECADES: f64 = 1e-8;

/// One configuration drawn in a Bode plot.
pub struct BodeLayer<'a> {
    /// Legend suffix: the file or the overrides.
    pub name: String,
    /// Drawn dashed (the compared configuration).
    pub dashed: bool,
    /// The response.
    pub result: &'a UnbalanceResult,
}

/// A Bode plot of one or two configurations: every probe's amplitude (m, log scale) over
/// its phase (rad, unwrapped along the speed), against the speed (rad/s).
pub struct BodePlot<'a> {
    /// Caption.
    pub title: String,
    /// The configurations (solid, then dashed).
    pub layers: Vec<BodeLayer<'a>>,
}

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

fn err<E: std::fmt::Debug>(e: E) -> PlotError {
    PlotError(format!("{e:?}"))
}

impl BodePlot<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        root.fill(&WHITE).map_err(err)?;
        let root = root.titled(&self.title, ("sans-serif", 24)).map_err(err)?;
        let (top, bottom) = root.split_vertically((root.dim_in_pixel().1 as f64 * 0.62) as u32);
        let all = || self.layers.iter().flat_map(|l| l.result.probes.iter().map(move |p| (l, p)));
        let speeds = || self.layers.iter().flat_map(|l| l.result.speeds.iter().copied());
        let x0 = speeds().fold(f64::INFINITY, f64::min);
        let x1 = speeds().fold(f64::NEG_INFINITY, f64::max);
        let (x0, x1) = if x1 > x0 { (x0, x1) } else { (x0 - 1.0, x0 + 1.0) };
        let amax = all().flat_map(|(_, p)| p.amplitude.iter().copied()).fold(0.0, f64::max).max(f64::MIN_POSITIVE);
        let floor = amax * AMPLITUDE_DECADES;
        let amin = all().flat_map(|(_, p)| p.amplitude.iter().copied()).filter(|a| *a >= floor).fold(amax, f64::min);
        // Two decades above the largest amplitude: room for the legend above the curves.
        let (ylo, yhi) = if amin < amax { (amin / 1.5, amax * 100.0) } else { (amax / 10.0, amax * 100.0) };
        let mut amp = ChartBuilder::on(&top)
            .margin(15)
            .x_label_area_size(30)
            .y_label_area_size(90)
            .build_cartesian_2d(x0..x1, (ylo..yhi).log_scale())
            .map_err(err)?;
        amp.configure_mesh()
            .y_desc("amplitude |U| (m)")
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .label_style(("sans-serif", 15))
            .axis_desc_style(("sans-serif", 17))
            .draw()
            .map_err(err)?;
        let style_of = |k: usize, dashed: bool| {
            let c = COLORS[k % COLORS.len()];
            (ShapeStyle::from(&RGBColor(c.0, c.1, c.2)).stroke_width(2), dashed)
        };
        for layer in &self.layers {
            for (k, p) in layer.result.probes.iter().enumerate() {
                let (style, dashed) = style_of(k, layer.dashed);
                let points: Vec<(f64, f64)> = layer
                    .result
                    .speeds
                    .iter()
                    .zip(&p.amplitude)
                    .filter(|(_, a)| **a >= floor)
                    .map(|(w, a)| (*w, *a))
                    .collect();
                if dashed {
                    amp.draw_series(DashedLineSeries::new(points, 6, 4, style)).map_err(err)?;
                } else {
                    amp.draw_series(LineSeries::new(points, style)).map_err(err)?;
                }
                amp.draw_series(
                    p.peaks
                        .iter()
                        .filter(|k| k.amplitude >= floor && k.amplitude <= yhi)
                        .map(|k| Circle::new((k.speed, k.amplitude), 4, style)),
                )
                .map_err(err)?;
            }
        }
        // The legend: a colour per probe (the first layer's names), a line style per
        // configuration when there are two.
        if let Some(first) = self.layers.first() {
            for (k, p) in first.result.probes.iter().enumerate() {
                let (style, _) = style_of(k, false);
                amp.draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
                    .map_err(err)?
                    .label(p.probe.name.clone())
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
            }
        }
        if self.layers.len() > 1 {
            for layer in &self.layers {
                let style = ShapeStyle::from(&BLACK).stroke_width(2);
                let dashed = layer.dashed;
                let what = if dashed { "dashed" } else { "solid" };
                amp.draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
                    .map_err(err)?
                    .label(format!("{what}: {}", layer.name))
                    .legend(move |(x, y)| {
                        // Two segments: a gap between them for the dashed configuration.
                        let (end, start) = if dashed { (7, 13) } else { (10, 10) };
                        EmptyElement::at((x, y))
                            + PathElement::new(vec![(0, 0), (end, 0)], style)
                            + PathElement::new(vec![(start, 0), (20, 0)], style)
                    });
            }
        }
        amp.configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 13))
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(err)?;

        let phases: Vec<(usize, &BodeLayer<'_>, &ProbeResponse, Vec<f64>)> = self
            .layers
            .iter()
            .flat_map(|l| l.result.probes.iter().enumerate().map(move |(k, p)| (k, l, p, unwrapped(&p.phase))))
            .collect();
        let plo = phases.iter().flat_map(|x| x.3.iter().copied()).fold(f64::INFINITY, f64::min);
        let phi = phases.iter().flat_map(|x| x.3.iter().copied()).fold(f64::NEG_INFINITY, f64::max);
        let (plo, phi) = if phi > plo { (plo - 0.2, phi + 0.2) } else { (-std::f64::consts::PI, 0.5) };
        let mut ph = ChartBuilder::on(&bottom)
            .margin(15)
            .x_label_area_size(50)
            .y_label_area_size(90)
            .build_cartesian_2d(x0..x1, plo..phi)
            .map_err(err)?;
        ph.configure_mesh()
            .x_desc("speed Ω (rad/s)")
            .y_desc("phase arg U (rad)")
            .label_style(("sans-serif", 15))
            .axis_desc_style(("sans-serif", 17))
            .draw()
            .map_err(err)?;
        for (k, layer, _, values) in &phases {
            let (style, dashed) = style_of(*k, layer.dashed);
            let points: Vec<(f64, f64)> = layer.result.speeds.iter().copied().zip(values.iter().copied()).collect();
            if dashed {
                ph.draw_series(DashedLineSeries::new(points, 6, 4, style)).map_err(err)?;
            } else {
                ph.draw_series(LineSeries::new(points, style)).map_err(err)?;
            }
        }
        root.present().map_err(err)
    }

    /// Render as SVG text.
    pub fn svg(&self) -> Result<String, PlotError> {
        render_svg(|root| self.draw(root))
    }

    /// Render as PNG bytes.
    pub fn png(&self) -> Result<Vec<u8>, PlotError> {
        render_png(|root| self.draw(root))
    }
}

/// Long-format CSV: one row per probe and speed.
pub fn unbalance_csv(r: &UnbalanceResult) -> Result<String, csv::Error> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(["probe", "kind", "node", "speed_rad_s", "amplitude_m", "phase_rad"])?;
    for p in &r.probes {
        let kind =
            serde_json::to_value(p.probe.kind).ok().and_then(|v| v.as_str().map(String::from)).unwrap_or_default();
        let node = p.probe.node.map(|n| n.to_string()).unwrap_or_default();
        for (i, w_) in r.speeds.iter().enumerate() {
            w.write_record([
                p.probe.name.clone(),
                kind.clone(),
                node.clone(),
                w_.to_string(),
                p.amplitude[i].to_string(),
                p.phase[i].to_string(),
            ])?;
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
pub fn peaks_text(r: &UnbalanceResult, heading: &str) -> String {
    let mut s = format!("{heading}\n");
    for p in &r.probes {
        let (w, a, unbounded) = p.largest(&r.speeds);
        s += &format!(
            "  {}: largest {:.4e} m at {:.2} rad/s{}\n",
            p.probe.name,
            a,
            w,
            if unbounded { " (unbounded: undamped critical speed)" } else { "" }
        );
        for k in &p.peaks {
            let af = match (k.amplification_factor, k.unbounded) {
                (_, true) => "unbounded (no damping acts on this mode)".to_string(),
                (Some(af), false) => format!("AF = {af:.2}"),
                (None, false) => "AF not defined (half-power point beyond the range)".to_string(),
            };
            s += &format!("    peak at {:.3} rad/s: {:.4e} m, phase {:+.3} rad, {af}\n", k.speed, k.amplitude, k.phase);
        }
    }
    s
}

/// The damping ratios as a text table: per mode its ζ at the first and last speed and its
/// smallest ζ with the speed of it.
pub fn damping_text(modes: &[ModeDamping], speeds: &[f64]) -> String {
    let (first, last) = (speeds.first().copied().unwrap_or(0.0), speeds.last().copied().unwrap_or(0.0));
    let mut s = format!(
        "damping ratios zeta = -Re(lambda)/|lambda| over {} speeds, {first} to {last} rad/s\n{:<14} {:>14} {:>14} {:>14} {:>14} {:>8}\n",
        speeds.len(),
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
