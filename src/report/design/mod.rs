//! The tuned-parameter report of a design run: the content (serialised as report.json),
//! its Markdown rendering (report.md: page one, then the details) and its figures
//! ([`figures()`]). Rendering only: no file I/O here.

mod details;
mod figures;
pub mod map;
mod map_plot;
mod margins;
mod page_one;
pub mod pareto;

pub use figures::figures;

use crate::design::DesignOutcome;
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

pub use crate::design::text::speed_text;
use crate::design::text::{speed_cell, speed_header};

pub(super) fn opt(x: Option<f64>, digits: usize) -> String {
    x.map(|v| format!("{v:.digits$}")).unwrap_or_else(|| "–".into())
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
    let map = "Map of the objective over the box (colour: the objective; the reference, the starts and the tuned design marked)";
    if stem == "map" {
        return map.to_string();
    }
    if let Some(pair) = stem.strip_prefix("map-") {
        return format!(
            "Slice of the map through the tuned design over variables {} (colour: the objective; the other variables at their tuned values; the tuned design marked)",
            pair.replace('-', " and ")
        );
    }
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
