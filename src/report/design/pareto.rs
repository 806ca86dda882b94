//! The report of a Pareto front (`design --pareto K`): the table of its points with the
//! verifier's figures, each point's verification, and the plot of peak response against
//! band width. Rendering only: no file I/O here.

use super::BranchRow;
use crate::design::pareto::{Front, FrontPoint, Role};
use crate::design::verify::PartStatus;
use crate::report::plot::{Curve, CurvePlot};
use crate::report::style::{self, Dash, Marker};
use serde::Serialize;
use std::fmt::Write;

/// The whole report of a front (report.json).
#[derive(Debug, Clone, Serialize)]
pub struct FrontReport {
    /// Tool, problem, input hash, overrides and settings.
    #[serde(flatten)]
    pub provenance: crate::problem::provenance::Provenance,
    /// Title of the problem.
    pub title: String,
    /// The circuit of the input file (C_f, L, R).
    pub branches_before: Vec<BranchRow>,
    /// The variables' names and units, in the order of each point's values.
    pub variables: Vec<String>,
    /// The front, each point with its whole run.
    pub front: Front,
    /// The design file of each point, in order: `tuned-k.toml` for a verified result,
    /// `best-effort-k.toml` otherwise.
    pub design_files: Vec<String>,
    /// Files written next to the report.
    pub files: Vec<String>,
}

/// The design file of point `p`.
pub fn point_file(p: &FrontPoint) -> String {
    if p.verified && p.status.is_result() {
        format!("tuned-{}.toml", p.index)
    } else {
        format!("best-effort-{}.toml", p.index)
    }
}

fn role(r: Role) -> &'static str {
    match r {
        Role::BestDamping => "best damping",
        Role::Between => "between",
        Role::WidestBand => "widest band",
    }
}

/// The band of a point in words (rad/s).
fn band_text(p: &FrontPoint) -> String {
    match p.band {
        Some(b) => format!("[{:.2}, {:.2}]", b.lo, b.hi),
        None => "φ_op unstable".into(),
    }
}

/// The peak of a point in words: amplitude (m) at speed (rad/s), units written when
/// `units`.
fn peak_text(p: &FrontPoint, units: bool) -> String {
    let (m, r) = if units { (" m", " rad/s") } else { ("", "") };
    if p.peak.unbounded {
        format!("unbounded at {:.2}{r}", p.peak.speed)
    } else {
        format!("{:.4e}{m} at {:.2}{r}", p.peak.amplitude, p.peak.speed)
    }
}

/// A status as report.json writes it (kebab-case).
fn status_word(s: crate::design::Status) -> String {
    serde_json::to_value(s).ok().and_then(|v| v.as_str().map(str::to_string)).unwrap_or_default()
}

/// One line per point for standard output.
pub fn point_line(p: &FrontPoint, variables: &[String]) -> String {
    let values: Vec<String> = variables.iter().zip(&p.values).map(|(n, v)| format!("{n} = {v:.6e}")).collect();
    format!(
        "{}. {}: band {} ({:.2} rad/s), peak {}; {}; {}, verification {}",
        p.index,
        role(p.role),
        band_text(p),
        p.width,
        peak_text(p, true),
        values.join(", "),
        status_word(p.status),
        p.verdict
    )
}

/// Markdown of the front's report.
pub fn markdown(r: &FrontReport) -> String {
    let f = &r.front;
    let mut s = String::new();
    let _ = writeln!(s, "# Pareto front: {}\n", r.title);
    let _ = writeln!(
        s,
        "**Question.** How much stable band around φ_op = {} rad/s at β_op = {} does each step of damping cost, for the peak unbalance response at node {} over {}..{} rad/s?\n",
        f.phi_op, f.level, f.response.node, f.response.speeds.lo, f.response.speeds.hi
    );
    let verified = f.points.iter().filter(|p| p.verified && p.status.is_result()).count();
    let _ = writeln!(
        s,
        "**Answer.** {} designs from the best damping to the widest band, {verified} of them verified; the front is {}{}.{}\n",
        f.points.len(),
        if f.monotone { "monotone (a wider band always costs peak response)" } else { "NOT monotone (see the dominated points)" },
        if f.ends_consistent {
            ""
        } else {
            "; its ends are NOT ends: a point between is wider than the widest-band end or damped better than the best-damping end, after one run again from it"
        },
        if f.collapsed {
            " The best-damped design already has the widest band found: there is no trade-off, and the front is its two ends."
        } else {
            ""
        }
    );
    let _ = writeln!(s, "![Peak response against band width](pareto.png)\n");
    let _ = writeln!(
        s,
        "| # | role | band asked (rad/s) | stable band at β_op (rad/s) | width (rad/s) | peak (m) at Ω (rad/s) | AF | {} | status | file |",
        r.variables.join(" | ")
    );
    let _ = writeln!(s, "|{}", "---|".repeat(9 + r.variables.len()));
    for (p, file) in f.points.iter().zip(&r.design_files) {
        let values: Vec<String> = p.values.iter().map(|v| format!("{v:.4e}")).collect();
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {:.2} | {} | {} | {} | {}{} | {file} |",
            p.index,
            role(p.role),
            p.asked_width.map_or("–".into(), |w| format!("{w:.2}")),
            band_text(p),
            p.width,
            peak_text(p, false),
            p.amplification_factor.map_or("–".into(), |a| format!("{a:.1}")),
            values.join(" | "),
            status_word(p.status),
            match p.dominated_by {
                Some(i) => format!(", dominated by {i}"),
                None => String::new(),
            }
        );
    }
    let _ = writeln!(
        s,
        "\nEvery figure is the verifier's: the band is the full region catalogue's stable band around φ_op (the narrowest over the operating speeds), the peak the response found again on a grid {}× finer than the optimiser's, refined. The band asked is the point's band-width constraint (the best-damping end asks {} rad/s: φ_op stable; the widest-band end asks none).",
        crate::design::verify::PEAK_GRID_FACTOR,
        crate::design::pareto::FLOOR_WIDTH
    );
    if let Some(w) = f.file_min_width {
        let meets: Vec<String> = f
            .points
            .iter()
            .filter(|p| p.width >= w - crate::design::verify::SAME_EDGE)
            .map(|p| p.index.to_string())
            .collect();
        let _ = writeln!(
            s,
            "\nThe file asks a band of at least {w} rad/s: point(s) {} meet it.",
            if meets.is_empty() { "none".to_string() } else { meets.join(", ") }
        );
    }
    let _ = writeln!(
        s,
        "\n{} design runs ({} candidates, {} Floquet evaluations), {:.1} s.\n",
        f.runs, f.candidates, f.evaluations, f.seconds
    );
    let _ = writeln!(s, "## Verification of each point\n");
    for p in &f.points {
        let _ = writeln!(s, "**Point {}** ({}): {}\n", p.index, role(p.role), p.verdict);
        for part in &p.outcome.verification.parts {
            let status = match part.status {
                PartStatus::Passed => "passed",
                PartStatus::Failed => "FAILED",
                PartStatus::NotApplicable => "not applicable",
            };
            let _ = writeln!(s, "- {} {status} ({} checked): {}", part.part, part.checked, part.summary);
        }
        for d in &p.outcome.after_speeds {
            for failure in &d.failures {
                let _ = writeln!(s, "- at Ω = {} rad/s: {failure}", d.speed);
            }
        }
        let _ = writeln!(s);
    }
    s
}

/// Colour of the file's own band-width constraint on the plot: a reference line, not a
/// design.
const REFERENCE_GREY: (u8, u8, u8) = (90, 90, 90);

/// Peak response (m) against band width (rad/s), the points in order and numbered; the
/// file's own band-width constraint as a dashed vertical line.
pub fn front_plot(r: &FrontReport) -> CurvePlot {
    let f = &r.front;
    let points: Vec<(f64, f64)> = f.points.iter().map(|p| (p.width, p.peak.amplitude)).collect();
    let (x0, x1) = points.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.0), b.max(p.0)));
    let (y0, y1) = points.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.1), b.max(p.1)));
    let dx = (x1 - x0).max(1.0);
    let mut x_range = (x0 - 0.08 * dx, x1 + 0.08 * dx);
    if let Some(w) = f.file_min_width {
        x_range = (x_range.0.min(w - 0.05 * dx), x_range.1.max(w + 0.05 * dx));
    }
    let (y0, y1) = if y1 > y0 { (y0, y1) } else { (0.5 * y0, 1.5 * y1) };
    let y_range = ((y0 / (y1 / y0).powf(0.08)).max(f64::MIN_POSITIVE), y1 * (y1 / y0).powf(0.08));
    // The front as a line, each design a marker of its own in the legend.
    let mut curves = vec![Curve::new("", style::color(0), points.clone())];
    for (k, p) in f.points.iter().enumerate() {
        let name = match (p.role, p.dominated_by) {
            (_, Some(i)) => format!("point {}: dominated by {i}", p.index),
            (Role::BestDamping, None) => format!("point {} (best damping)", p.index),
            (Role::WidestBand, None) => format!("point {} (widest band)", p.index),
            (Role::Between, None) => format!("point {}", p.index),
        };
        let marker = if p.dominated_by.is_some() { Marker::Cross } else { Marker::Circle };
        curves.push(Curve { marker, ..Curve::new(name, style::color(k + 1), vec![(p.width, p.peak.amplitude)]) });
    }
    if let Some(w) = f.file_min_width {
        curves.push(Curve {
            dash: Dash::Dashed,
            ..Curve::new(
                format!("the file's least band width, {w} rad/s"),
                REFERENCE_GREY,
                vec![(w, y_range.0), (w, y_range.1)],
            )
        });
    }
    CurvePlot {
        title: format!("Pareto front: peak response against stable band around φ_op = {} rad/s", f.phi_op),
        x_label: style::axis_label("stable band width at β_op", "Δφ", "rad/s"),
        y_label: style::axis_label(&format!("peak response at node {}", f.response.node), "|U|", "m"),
        x_range,
        y_range,
        log_y: true,
        curves,
    }
}
