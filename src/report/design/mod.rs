//! The tuned-parameter report of a design run: the content (serialised as report.json),
//! its Markdown rendering (report.md: page one, then the details) and its figures
//! ([`figures()`]). Rendering only: no file I/O here.

mod details;
mod figures;
mod margins;
mod page_one;
pub mod pareto;

pub use figures::figures;

use crate::analysis::regions::{Band, Bound};
use crate::design::DesignOutcome;
use crate::numbers::SpeedUnit;
use serde::Serialize;
use std::fmt::Write;

/// One branch of a circuit as a designer reads it.
#[derive(Debug, Clone, Serialize)]
pub struct BranchRow {
    /// The ring whose circuit this is, when the rings' circuits differ (absent: the
    /// circuit every ring carries).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ring: Option<String>,
    /// Branch number (from 1).
    pub branch: usize,
    /// C_f (F).
    pub c_f: f64,
    /// L (H).
    pub inductance: f64,
    /// R (Ω).
    pub resistance: f64,
    /// Tuning frequency of Eq. (4) (rad/s).
    pub tuning_frequency: f64,
}

/// The whole report.
#[derive(Debug, Clone, Serialize)]
pub struct DesignReport {
    /// Tool, problem, input hash, overrides and settings.
    #[serde(flatten)]
    pub provenance: crate::problem::provenance::Provenance,
    /// Title of the problem.
    pub title: String,
    /// The circuit's branches before the design (C_f, L, R).
    pub branches_before: Vec<BranchRow>,
    /// The circuit's branches after the design (C_f, L, R).
    pub branches_after: Vec<BranchRow>,
    /// The optimiser's outcome (bands, intrusions, catalogues, verification, starts,
    /// history, counts).
    pub outcome: DesignOutcome,
    /// The tuned design's lowest whirls at each operating speed, each paired with the
    /// reference design's whirl of the same mode shape (by MAC, not by label).
    pub whirls: Vec<crate::design::content::SpeedWhirls>,
    /// Files written next to the report.
    pub files: Vec<String>,
}

/// `Ω = 1256.6 rad/s`, or `n = 12000 rpm (1256.6 rad/s)`.
pub fn speed_text(unit: SpeedUnit, speed: f64) -> String {
    format!("{} = {}", unit.symbol(), unit.text(speed))
}

/// The header of a table's speed column: `Ω (rad/s)` or `n (rpm)`.
pub(super) fn speed_header(unit: SpeedUnit) -> String {
    format!("{} ({})", unit.symbol(), unit.unit())
}

/// A speed in a table's speed column (its header's unit), to the rpm or rad/s.
pub(super) fn speed_cell(unit: SpeedUnit, speed: f64) -> String {
    format!("{:.0}", unit.value(speed))
}

pub(super) fn opt(x: Option<f64>, digits: usize) -> String {
    x.map(|v| format!("{v:.digits$}")).unwrap_or_else(|| "–".into())
}

pub(super) fn band_text(b: &Band) -> String {
    match (b.band, b.containing) {
        (Some(x), _) if b.clipped() => {
            format!("[{:.2}, {:.2}] (at least {:.2}: clipped by the window)", x.lo, x.hi, x.width())
        }
        (Some(x), _) => format!("[{:.2}, {:.2}] ({:.2})", x.lo, x.hi, x.width()),
        (None, Some(t)) => format!("φ_op unstable, inside [{:.2}, {:.2}]", t.lo, t.hi),
        _ => "φ_op unstable".into(),
    }
}

pub(super) fn bound_text(b: &Option<Bound>) -> String {
    match b {
        Some(Bound::Tongue { label, edge, unexplained: Some(u), .. }) => format!(
            "{label} at {edge:.2} (Floquet exponent {:.2} rad/s; nearest {} = {:.2})",
            u.exponent_frequency, u.nearest, u.nearest_frequency
        ),
        Some(Bound::Tongue { label, edge, .. }) => format!("{label} at {edge:.2}"),
        Some(Bound::Window) => "window end (clipped: widen design.phi_range)".into(),
        // No band: φ_op is unstable, and nothing bounds it.
        None => "–".into(),
    }
}

/// Lines of Markdown page one may take: it must read in a minute.
pub const PAGE_ONE_LINES: usize = 60;
/// Rows of the region table near the bands, over all its speeds and designs; the full
/// catalogue is in report.json and `rotorshunt regions`.
pub const NEAR_REGION_ROWS: usize = 24;
/// The line that ends page one (a thematic break in Markdown and HTML).
pub const PAGE_ONE_END: &str = "---";

/// Markdown of a design report: page one (question, answer, circuit before and after,
/// the band or clearances or peak, verification, the key figure), then the details.
pub fn markdown(r: &DesignReport) -> String {
    let mut s = page_one::page_one(r);
    let _ = writeln!(s, "\n{PAGE_ONE_END}\n");
    details::details(&mut s, r);
    s
}

/// The caption of a figure of the design folder, from its file name.
pub(super) fn figure_caption(file: &str) -> String {
    let stem = file.trim_end_matches(".png");
    let (kind, speed) = match stem.split_once('-') {
        Some((k, n)) => (k, format!(" (design speed {n})")),
        None => (stem, String::new()),
    };
    let what = match kind {
        "charts" => "Stability charts before and after the design (φ in rad/s, β)",
        "campbell" => "Campbell diagram of the tuned design (whirl frequency against speed, rad/s)",
        "history" => "Optimisation history",
        "bode" => {
            "Unbalance response before and after the design (amplitude in m, phase in deg, against speed in rad/s)"
        }
        other => other,
    };
    format!("{what}{speed}")
}

/// Every ring's circuit, branch by branch: one table of the shared circuit when two or
/// more rings carry an identical one (tuning by the first ring's C_p^T, as `check` prints
/// it), else each ring's branches under its name.
pub fn branch_rows(model: &crate::model::Model) -> Vec<BranchRow> {
    let shared = !model.labels_by_ring();
    let rings = if shared { &model.rings[..1.min(model.rings.len())] } else { &model.rings[..] };
    rings
        .iter()
        .flat_map(|r| {
            r.circuit.branches.iter().enumerate().map(move |(i, b)| BranchRow {
                ring: (!shared).then(|| r.name.clone()),
                branch: i + 1,
                c_f: b.c_f,
                inductance: b.inductance,
                resistance: b.resistance,
                tuning_frequency: b.tuning_frequency(r.ring.cp_t),
            })
        })
        .collect()
}
