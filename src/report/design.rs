//! The tuned-parameter report of a design run: the content (serialised as report.json)
//! and its Markdown rendering (report.md). Rendering only: no file I/O here.

use super::chart::{Layer, Span, StabilityPlot};
use super::plot::{Figure, LinePlot, Series};
use super::unbalance::{BodeLayer, BodePlot};
use crate::analysis::regions::{Band, Bound};
use crate::analysis::Interval;
use crate::design::content::DesignContent;
use crate::design::spec::Objective;
use crate::design::{DesignOutcome, Status};
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
    /// Files written next to the report.
    pub files: Vec<String>,
}

fn opt(x: Option<f64>, digits: usize) -> String {
    x.map(|v| format!("{v:.digits$}")).unwrap_or_else(|| "–".into())
}

fn band_text(b: &Band) -> String {
    match (b.band, b.containing) {
        (Some(x), _) => format!("[{:.2}, {:.2}] ({:.2})", x.lo, x.hi, x.width()),
        (None, Some(t)) => format!("φ_op unstable, inside [{:.2}, {:.2}]", t.lo, t.hi),
        _ => "φ_op unstable".into(),
    }
}

fn bound_text(b: &Option<Bound>) -> String {
    match b {
        Some(Bound::Tongue { label, edge, .. }) => format!("{label} at {edge:.2}"),
        _ => "window end".into(),
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
    let mut s = page_one(r);
    let _ = writeln!(s, "\n{PAGE_ONE_END}\n");
    details(&mut s, r);
    s
}

/// The variables' names, joined for a sentence.
fn variable_names(r: &DesignReport) -> String {
    let names: Vec<String> = r.outcome.spec.variables.iter().map(|v| v.name()).collect();
    match names.as_slice() {
        [] => "no variable".into(),
        [one] => one.clone(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    }
}

fn speeds_text(speeds: &[f64]) -> String {
    let v: Vec<String> = speeds.iter().map(|w| format!("{w}")).collect();
    format!("Ω = {} rad/s", v.join(", "))
}

/// The question the design answers, in one sentence.
fn question(r: &DesignReport) -> String {
    let spec = &r.outcome.spec;
    let vars = variable_names(r);
    let at = speeds_text(&spec.speeds);
    match &spec.objective {
        Objective::WidestStableBand { phi_op } => format!(
            "Which {vars} (inside their bounds) give the widest stable band at β_op = {} around the load frequency φ_op = {phi_op} rad/s, at {at}?",
            spec.level
        ),
        Objective::ClearBands { bands } => format!(
            "Which {vars}, changed as little as possible, keep every instability region at β_op = {} out of the operating band(s) {} at {at}?",
            spec.level,
            bands.iter().map(|b| format!("[{}, {}] rad/s ± {} rad/s", b.lo, b.hi, b.clearance)).collect::<Vec<_>>().join(", ")
        ),
        Objective::MinPeakResponse { response } => format!(
            "Which {vars} give the smallest peak unbalance response at node {} over the rotating speeds {}..{} rad/s{}?",
            response.node,
            response.speeds.lo,
            response.speeds.hi,
            if o_constrained(&r.outcome) {
                format!(", with the stability constraints below met at β_op = {} and {at}", spec.level)
            } else {
                String::new()
            }
        ),
    }
}

fn o_constrained(o: &DesignOutcome) -> bool {
    !o.spec.kept_clear().is_empty() || !o.constraints_after.is_empty()
}

/// The status in one sentence.
fn status_sentence(status: Status) -> &'static str {
    match status {
        Status::Improved => "**Improved**: the tuned design is better than the reference's, and verified.",
        Status::Unchanged => "**Unchanged**: no start beat the reference design, which is kept (verified).",
        Status::Feasible => "**Feasible**: every band is clear by its clearance, and verified.",
        Status::Infeasible => {
            "**Infeasible**: no design inside the bounds meets every requirement; the violations are listed below, and `best-effort.toml` is the optimiser's best effort, not a result."
        }
        Status::NotVerified => {
            "**Not verified**: the design found failed its independent verification (below); `best-effort.toml` is not a result."
        }
    }
}

/// One table of every branch before and after: a changed value reads `before → after`.
fn circuit_table(s: &mut String, before: &[BranchRow], after: &[BranchRow]) {
    let rings = after.iter().any(|b| b.ring.is_some());
    let _ = writeln!(
        s,
        "{}| branch | C_f (F) | L (H) | R (Ω) | tuning ω (rad/s) |\n{}|---|---|---|---|---|",
        if rings { "| ring " } else { "" },
        if rings { "|---" } else { "" }
    );
    let change = |a: String, b: String| if a == b { a } else { format!("{a} → **{b}**") };
    for (b, a) in before.iter().zip(after) {
        let ring = a.ring.as_ref().map(|r| format!("| {r} ")).unwrap_or_default();
        let _ = writeln!(
            s,
            "{ring}| {} | {} | {} | {} | {} |",
            a.branch,
            change(format!("{:.4e}", b.c_f), format!("{:.4e}", a.c_f)),
            change(format!("{:.4}", b.inductance), format!("{:.4}", a.inductance)),
            change(format!("{:.3}", b.resistance), format!("{:.3}", a.resistance)),
            change(format!("{:.2}", b.tuning_frequency), format!("{:.2}", a.tuning_frequency))
        );
    }
}

/// Page one: question, answer, circuit, the objective's figures, verification, figure.
fn page_one(r: &DesignReport) -> String {
    let o = &r.outcome;
    let spec = &o.spec;
    let mut s = String::new();
    let _ = writeln!(s, "# Shunt design report: {}\n", r.title);
    let _ = writeln!(s, "**Question.** {}\n", question(r));
    let _ = writeln!(s, "**Answer.** {}\n", status_sentence(o.status));
    let _ = writeln!(s, "Circuit, before → after (changed values in bold):\n");
    circuit_table(&mut s, &r.branches_before, &r.branches_after);
    match &spec.objective {
        Objective::WidestStableBand { .. } => widest_band_table(&mut s, o),
        Objective::ClearBands { .. } => clear_bands_table(&mut s, o),
        Objective::MinPeakResponse { .. } => peak_table(&mut s, o),
    }
    constraints_table(&mut s, o);
    verification_sentences(&mut s, o);
    if let Some(f) = r.files.iter().find(|f| f.ends_with(".png")) {
        let _ = writeln!(s, "\n![{}]({f})", figure_caption(f));
    }
    let _ = writeln!(
        s,
        "\nBelow: regions near the band, whirls, the optimiser's runs, settings, a glossary of the terms and labels, and the files. Everything is also in `report.json`."
    );
    s
}

fn widest_band_table(s: &mut String, o: &DesignOutcome) {
    let _ = writeln!(
        s,
        "\nStable band at β_op = {} around φ_op (rad/s; width in brackets):\n\n| Ω (rad/s) | before | after | after: bounded below by | above by |\n|---|---|---|---|---|",
        o.spec.level
    );
    for (b, a) in o.before_bands().iter().zip(o.after_bands()) {
        let _ = writeln!(
            s,
            "| {:.0} | {} | {} | {} | {} |",
            b.speed,
            band_text(&b.band),
            band_text(&a.band),
            bound_text(&a.band.left),
            bound_text(&a.band.right)
        );
    }
    for a in o.after_bands() {
        for t in &a.band.ignored {
            let _ = writeln!(
                s,
                "\nIgnored by the criterion at Ω = {}: {} at [{:.3}, {:.3}] rad/s.",
                a.speed,
                t.label(),
                t.extent.lo,
                t.extent.hi
            );
        }
    }
}

fn clear_bands_table(s: &mut String, o: &DesignOutcome) {
    let _ = writeln!(s, "\nOperating bands at β_op = {} (rad/s):\n\n| band | clearance | tongues inside before | after | unstable grid points after |\n|---|---|---|---|---|", o.spec.level);
    for (i, b) in o.spec.objective.bands().iter().enumerate() {
        let names = |v: &[crate::design::evaluate::Intrusion]| {
            let l: Vec<String> = v
                .iter()
                .filter(|x| x.band == i)
                .map(|x| format!("{} [{:.1}, {:.1}]", x.label, x.left, x.right))
                .collect();
            if l.is_empty() {
                "none".to_string()
            } else {
                l.join(", ")
            }
        };
        let g = b.guarded();
        let fine: usize = o
            .after_speeds
            .iter()
            .flat_map(|d| d.grids.iter().filter(|x| x.window == g).map(|x| x.unstable.len()))
            .sum();
        let _ = writeln!(
            s,
            "| [{}, {}] | {} | {} | {} | {} |",
            b.lo,
            b.hi,
            b.clearance,
            names(o.before_intrusions()),
            names(o.after_intrusions()),
            fine
        );
    }
    if o.linear_infeasible() {
        let _ = writeln!(s, "\nThe linearised constraints at the final point have no solution inside the bounds.");
    }
}

/// The peaks of the reference, tuned, unconstrained and classic designs, and the price.
fn peak_table(s: &mut String, o: &DesignOutcome) {
    let Some(f) = o.peak_findings() else { return };
    let _ = writeln!(
        s,
        "\nPeak unbalance response (m):\n\n| design | peak (m) | at (rad/s) | constraints met |\n|---|---|---|---|"
    );
    let mut rows = vec![("reference", &f.before), ("tuned", &f.after), ("unconstrained optimum", &f.unconstrained)];
    if let Some(c) = &f.classic_design {
        rows.push(("classic tuning", c));
    }
    for (name, d) in rows {
        let _ = writeln!(
            s,
            "| {name} | {:.4e}{} | {:.2} | {} |",
            d.peak.amplitude,
            if d.peak.unbounded { " (unbounded)" } else { "" },
            d.peak.speed,
            if d.constraints.is_empty() { "–".to_string() } else { d.feasible.to_string() }
        );
    }
    if let Some(price) = f.price {
        let _ = writeln!(
            s,
            "\nPrice of the constraints: tuned peak − unconstrained peak = {:+.4e} m ({:+.2} %).",
            price.metres, price.percent
        );
    }
}

/// The constraints judged afresh on the tuned design.
fn constraints_table(s: &mut String, o: &DesignOutcome) {
    if o.constraints_after.is_empty() {
        return;
    }
    let _ =
        writeln!(s, "\nConstraints on the tuned design:\n\n| constraint | value | limit | met |\n|---|---|---|---|");
    for c in &o.constraints_after {
        let _ = writeln!(s, "| {} | {:.6e} | {:e} | {} |", c.name, c.value, c.limit, c.met);
    }
}

/// The independent verification, one sentence per check (each over every speed).
fn verification_sentences(s: &mut String, o: &DesignOutcome) {
    let spec = &o.spec;
    let _ = writeln!(
        s,
        "\n**Verification: {}** (independent of the optimiser, on the tuned design):\n",
        if o.verified { "passed" } else { "FAILED" }
    );
    let each = |f: &dyn Fn(&crate::design::verify::DesignAtSpeed) -> String| {
        o.after_speeds.iter().map(|d| format!("at Ω = {} rad/s {}", d.speed, f(d))).collect::<Vec<_>>().join("; ")
    };
    let _ = writeln!(
        s,
        "- Catalogue: the full region catalogue over φ = {}..{} rad/s, {}.",
        spec.phi_range.0,
        spec.phi_range.1,
        each(&|d| match d.catalogue_band {
            Some(b) => format!("gives the band [{:.2}, {:.2}]", b.lo, b.hi),
            None => {
                let bands: Vec<Interval> = spec.kept_clear().iter().map(|b| b.guarded()).collect();
                let inside = near_rows(&d.catalogue, &bands).iter().filter(|r| r.distance == 0.0).count();
                format!(
                    "finds {} regions, {inside} of them at β_op in a band widened by its clearance",
                    d.catalogue.regions.len()
                )
            }
        })
    );
    let _ = writeln!(
        s,
        "- Tongue centres: the reference (DSTM) Floquet point at every catalogued tongue centre near the band(s), {}.",
        each(&|d| {
            let inside = d.centres.iter().filter(|c| c.inside).count();
            let bad = d.centres.iter().filter(|c| c.inside && c.unstable).count();
            format!("{} centres near the band(s), {inside} of them inside, {bad} unstable inside", d.centres.len())
        })
    );
    let _ = writeln!(
        s,
        "- Grid: the fast path on a fine grid over the band(s) at β_op, {}.",
        each(&|d| {
            let points: usize = d.grids.iter().map(|g| g.points).sum();
            let bad: usize = d.grids.iter().map(|g| g.unstable.len()).sum();
            let step = d.grids.first().map_or(0.0, |g| g.step);
            format!("{points} points {step} rad/s apart, {bad} unstable")
        })
    );
    for d in &o.after_speeds {
        for f in &d.failures {
            let _ = writeln!(s, "- Failed at Ω = {} rad/s: {f}", d.speed);
        }
    }
}

/// Everything below page one.
fn details(s: &mut String, r: &DesignReport) {
    let o = &r.outcome;
    let p = &r.provenance;
    let spec = &o.spec;
    let _ = writeln!(s, "## Problem and run\n");
    let _ = writeln!(
        s,
        "- problem: `{}`{} (SHA-256 of text and overrides: `{}`)",
        p.problem,
        if p.overrides.is_empty() { String::new() } else { format!(" with `--set {}`", p.overrides.join(" ")) },
        p.input_sha256
    );
    let _ = writeln!(s, "- tool: {}", p.tool);
    let failed = if o.failed_candidates > 0 {
        format!("; {} candidates failed (first: {})", o.failed_candidates, o.first_failure.clone().unwrap_or_default())
    } else {
        String::new()
    };
    // The wall times end the line (after the last ", "), so that tests and the output
    // comparison can set them aside.
    let _ = writeln!(
        s,
        "- cost: {} candidate designs, {} + {} Floquet (monodromy) evaluations (optimiser + verification){failed}, {:.1} s + {:.1} s",
        o.candidates,
        o.floquet_evaluations,
        o.verification_cost.evaluations,
        o.seconds,
        o.verification_cost.seconds
    );
    let _ = writeln!(s, "- criterion: {}", criterion_text(&p.settings));
    for w in &p.warnings {
        let _ = writeln!(s, "- warning: {w}");
    }
    let _ = writeln!(
        s,
        "\n## Design variables\n\n| variable | unit | min | max | before | after |\n|---|---|---|---|---|---|"
    );
    for (j, v) in spec.variables.iter().enumerate() {
        let _ = writeln!(
            s,
            "| {} | {} | {:.4e} | {:.4e} | {:.6e} | {:.6e} |",
            v.name(),
            v.parameter.unit(),
            v.min,
            v.max,
            o.before[j],
            o.after[j]
        );
    }
    if let Some(f) = o.peak_findings() {
        classic_section(s, f);
    }
    vibration_section(s, o);
    near_regions_section(s, o);
    whirls_section(s, o);
    optimiser_section(s, o);
    settings_table(s, &p.settings);
    let _ = writeln!(s, "\n{}", super::glossary::glossary());
    let figures: Vec<&String> = r.files.iter().filter(|f| f.ends_with(".png")).collect();
    if figures.len() > 1 {
        let _ = writeln!(s, "## Figures\n");
        for f in figures.iter().skip(1) {
            let _ = writeln!(s, "![{}]({f})\n", figure_caption(f));
        }
    }
    let _ = writeln!(s, "## Files\n");
    for f in &r.files {
        let _ = writeln!(s, "- `{f}`");
    }
}

fn criterion_text(c: &crate::analysis::Settings) -> String {
    format!(
        "unstable when max|μ| > {}{}{}; tongues searched up to order {}",
        c.instability_tolerance,
        if c.min_growth_rate > 0.0 {
            format!(", counted when the growth rate is at least {} 1/s", c.min_growth_rate)
        } else {
            String::new()
        },
        if c.min_tongue_width > 0.0 {
            format!(", tongues narrower than {} rad/s ignored", c.min_tongue_width)
        } else {
            String::new()
        },
        c.max_tongue_order
    )
}

/// A tongue at β_op near the band(s) of interest: label, order, start, onset, edges.
struct NearRow {
    label: String,
    order: Option<usize>,
    start: Option<f64>,
    onset: Option<f64>,
    edges: Interval,
    distance: f64,
}

/// The φ intervals a design's regions are judged against: its band around φ_op (or φ_op
/// itself when it is unstable), else the operating bands widened by their clearances.
fn targets(o: &DesignOutcome, k: usize, after: bool) -> Vec<Interval> {
    let spec = &o.spec;
    let bands = if after { o.after_bands() } else { o.before_bands() };
    if let Some(b) = bands.get(k) {
        return vec![b.band.band.or(b.band.containing).unwrap_or(Interval::new(b.band.phi_op, b.band.phi_op))];
    }
    let mut t: Vec<Interval> = spec.kept_clear().iter().map(|b| b.guarded()).collect();
    if let Some(p) = spec.phi_op() {
        t.push(Interval::new(p, p));
    }
    t
}

/// Distance (rad/s) between two intervals; 0 when they touch or overlap.
fn gap(a: &Interval, b: &Interval) -> f64 {
    (a.lo - b.hi).max(b.lo - a.hi).max(0.0)
}

/// The tongues at β_op nearest the targets (counted ones, with edges), nearest first.
fn near_rows(c: &crate::analysis::regions::Catalogue, targets: &[Interval]) -> Vec<NearRow> {
    let dist = |e: &Interval| targets.iter().map(|t| gap(e, t)).fold(f64::INFINITY, f64::min);
    let mut rows: Vec<NearRow> = c
        .regions
        .iter()
        .filter(|g| g.counted)
        .filter_map(|g| {
            let edges = Interval::new(g.left?, g.right?);
            Some(NearRow {
                label: g.label.clone(),
                order: Some(g.order),
                start: Some(g.start),
                onset: Some(g.onset_beta),
                distance: dist(&edges),
                edges,
            })
        })
        .chain(c.unexplained.iter().map(|u| NearRow {
            label: "(unexplained, guard lattice)".into(),
            order: None,
            start: None,
            onset: None,
            distance: dist(u),
            edges: *u,
        }))
        .collect();
    rows.sort_by(|a, b| a.distance.total_cmp(&b.distance).then(a.edges.lo.total_cmp(&b.edges.lo)));
    rows
}

/// The region table near the band(s): the tongues at β_op nearest to them, before and
/// after, at most [`NEAR_REGION_ROWS`] rows in all; the full catalogue is in report.json.
fn near_regions_section(s: &mut String, o: &DesignOutcome) {
    let tables = 2 * o.after_speeds.len();
    let per_table = (NEAR_REGION_ROWS / tables.max(1)).max(1);
    let _ = writeln!(
        s,
        "\n## Regions near the band(s) at β_op = {}\n\nThe {per_table} tongues at β_op nearest the band (or the operating bands with their clearances) per design and speed, sorted by φ; distance 0 means the tongue bounds or enters it. The full catalogues (every region over φ = {}..{} rad/s, onsets below β = {}) are in `report.json` (`outcome.before_speeds[].catalogue`, `outcome.after_speeds[].catalogue`) and from `rotorshunt regions tuned.toml`.",
        o.spec.level, o.spec.phi_range.0, o.spec.phi_range.1, o.spec.beta_max
    );
    for (name, designs, after) in [("before", &o.before_speeds, false), ("after", &o.after_speeds, true)] {
        for (k, d) in designs.iter().enumerate() {
            let targets = targets(o, k, after);
            if targets.is_empty() {
                continue;
            }
            let all = near_rows(&d.catalogue, &targets);
            let mut shown: Vec<&NearRow> = all.iter().take(per_table).collect();
            shown.sort_by(|a, b| a.edges.lo.total_cmp(&b.edges.lo));
            let _ = writeln!(
                s,
                "\n{name}, Ω = {} rad/s ({} of {} tongues at β_op):\n\n| region | k | start (rad/s) | onset β | edges at β_op (rad/s) | width (rad/s) | distance (rad/s) |\n|---|---|---|---|---|---|---|",
                d.speed,
                shown.len(),
                all.len()
            );
            for g in shown {
                let _ = writeln!(
                    s,
                    "| {} | {} | {} | {} | [{:.2}, {:.2}] | {:.2} | {:.2} |",
                    g.label,
                    g.order.map_or("–".into(), |k| k.to_string()),
                    opt(g.start, 2),
                    opt(g.onset, 4),
                    g.edges.lo,
                    g.edges.hi,
                    g.edges.width(),
                    g.distance
                );
            }
        }
    }
}

fn whirls_section(s: &mut String, o: &DesignOutcome) {
    for (k, after) in o.after_speeds.iter().enumerate() {
        let before = o.before_speeds.get(k);
        let _ = writeln!(s, "\n## Whirl frequencies at Ω = {} rad/s\n", after.speed);
        let _ = writeln!(s, "| mode | before (rad/s) | after (rad/s) |\n|---|---|---|");
        for w in &after.whirls {
            let b = before.and_then(|b| b.whirls.iter().find(|x| x.tag == w.tag));
            let _ = writeln!(s, "| {} | {} | {:.2} |", w.tag, opt(b.map(|b| b.frequency), 2), w.frequency);
        }
    }
}

fn optimiser_section(s: &mut String, o: &DesignOutcome) {
    let _ = writeln!(s, "\n## Optimiser\n");
    match o.spec.objective {
        Objective::WidestStableBand { .. } => {
            let _ = writeln!(s, "Nelder–Mead (argmin) from {} starts in parallel; objective = smallest band width over the speeds (rad/s).\n", o.starts.len());
            let _ = writeln!(s, "| start | initial | best | objective (rad/s) | evaluations | iterations | termination |\n|---|---|---|---|---|---|---|");
        }
        Objective::ClearBands { .. } => {
            let _ = writeln!(s, "Coarse global pass (objective = minus the total intrusion, rad/s), then sequential convex steps (clarabel QP) from the reference and from the best global point.\n");
            let _ = writeln!(s, "| point | values | | −intrusion (rad/s) | evaluations | iterations | stage |\n|---|---|---|---|---|---|---|");
        }
        Objective::MinPeakResponse { .. } => {
            let _ = writeln!(s, "Nelder–Mead (argmin) on ln(peak) from {} starts in parallel, first without constraints, then with them as an exact penalty; then sequential convex steps (clarabel QP) on the linearised constraints. Objective column: the start's best peak (m).\n", o.starts.len());
            let _ = writeln!(s, "| start | initial | best | peak (m) | evaluations | iterations | termination |\n|---|---|---|---|---|---|---|");
        }
    }
    let vals = |v: &[f64]| v.iter().map(|x| format!("{x:.5e}")).collect::<Vec<_>>().join(", ");
    let peak = o.peak_findings().is_some();
    for st in &o.starts {
        let objective = if peak { format!("{:.4e}", st.objective) } else { format!("{:.2}", st.objective) };
        let _ = writeln!(
            s,
            "| {} | {} | {} | {objective} | {} | {} | {} |",
            st.origin,
            vals(&st.initial),
            vals(&st.best),
            st.evaluations,
            st.iterations,
            st.termination
        );
    }
    if !o.convex_steps.is_empty() {
        let _ = writeln!(s, "\n| step | trust | constraints | intrusion before | intrusion after | accepted | values |\n|---|---|---|---|---|---|---|");
        for c in &o.convex_steps {
            let _ = writeln!(
                s,
                "| {} | {:.4} | {} | {:.2} | {} | {} | {} |",
                c.iteration,
                c.trust,
                c.constraints,
                c.intrusion_before,
                opt(c.intrusion_after, 2),
                c.accepted,
                vals(&c.values)
            );
        }
    }
    if let Some(f) = o.peak_findings() {
        if !f.convex_steps.is_empty() {
            let _ = writeln!(s, "\n| convex step | trust | constraints | peak before (m) | peak after (m) | feasible | accepted | values |\n|---|---|---|---|---|---|---|---|");
            for c in &f.convex_steps {
                let _ = writeln!(
                    s,
                    "| {} | {:.4} | {} | {:.4e} | {:.4e} | {} | {} | {} |",
                    c.iteration,
                    c.trust,
                    c.constraints,
                    c.peak_before,
                    c.peak_after,
                    c.feasible,
                    c.accepted,
                    vals(&c.values)
                );
            }
        }
    }
}

/// What each numerical setting does (the `[analysis]` keys).
const SETTING_MEANINGS: [(&str, &str); 12] = [
    ("mac_threshold", "least modal assurance criterion for a Campbell track to continue (−)"),
    ("electrical_fraction", "share of a mode's kinetic energy in the charges above which it is electrical (−)"),
    ("oscillation_tolerance", "\\|Im λ\\|/\\|λ\\| below which an eigenvalue is not a whirl (−)"),
    ("reduced_modes", "modes M of the reduced model of the Floquet analysis (Eq. 22)"),
    ("instability_tolerance", "unstable when max\\|μ\\| exceeds this (Eq. 28) (−)"),
    ("min_growth_rate", "growth-rate floor of the criterion (1/s); 0: the paper's criterion"),
    ("min_tongue_width", "narrowest tongue at β_op that counts (rad/s); 0: every tongue"),
    ("max_tongue_order", "highest order k of the tongues searched: the bands are complete up to it"),
    ("method", "monodromy path of charts and points (fast: CFM4 on the reduced model; dstm: the paper's)"),
    ("steps_per_period", "CFM4 steps per load period of the fast path (least)"),
    ("reference_steps", "steps per period of the reference DSTM path (Eq. 26–27)"),
    ("max_step_phase", "largest phase of the lowest mode over one CFM4 step (rad)"),
];

/// The settings in force as a table: file key, value, meaning.
fn settings_table(s: &mut String, settings: &crate::analysis::Settings) {
    let _ = writeln!(s, "\n## Settings\n\n| key | value | meaning |\n|---|---|---|");
    let value = serde_json::to_value(settings).unwrap_or_default();
    if let Some(map) = value.as_object() {
        for (k, v) in map {
            let meaning = SETTING_MEANINGS.iter().find(|(name, _)| name == k).map_or("", |(_, m)| m);
            let v = v.as_str().map_or_else(|| v.to_string(), str::to_string);
            let _ = writeln!(s, "| `analysis.{k}` | {v} | {meaning} |");
        }
    }
}

/// The caption of a figure of the design folder, from its file name.
fn figure_caption(file: &str) -> String {
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

/// The classic single-mode tuning the min-peak design starts from.
fn classic_section(s: &mut String, f: &crate::design::optimise::PeakFindings) {
    if let Some(c) = &f.classic {
        let _ = writeln!(
            s,
            "\n\n## Classic tuning\n\nClassic single-mode tuning of {} on branch {} (series R–L shunt, equal-peak optimum: ω_e = ω_open, Hagood & von Flotow 1991; r = √(3/2)·K, Thomas, Ducarne & Deü 2012): ω_open = {:.3} rad/s (branch removed), ω_short = {:.3} rad/s (branch with L = R = 0), K² = (ω_open² − ω_short²)/ω_short² = {:.5}; loop capacitance C = {:.5e} F; L_opt = 1/(ω_open²·C) = {:.5} H (tuning frequency by Eq. 4: {:.3} rad/s), R_opt = √(3/2)·K/(C·ω_short) = {:.4} Ω{}.",
            c.mode,
            c.branch + 1,
            c.omega_open,
            c.omega_short,
            c.coupling,
            c.capacitance,
            c.inductance,
            c.tuning_frequency,
            c.resistance,
            if c.clamped { "; clamped to the variables' bounds for the start" } else { "" }
        );
    }
}

/// The unbalance response before and after (peaks table) and the damping ratios.
fn vibration_section(s: &mut String, o: &DesignOutcome) {
    let Some(v) = &o.vibration else { return };
    let _ = writeln!(
        s,
        "\n## Unbalance response at node {} (`bode.svg`, `bode.png`: before solid, after dashed)\n",
        v.response.node
    );
    let _ = writeln!(
        s,
        "| design | peak speed (rad/s) | amplitude (m) | amplification factor (API 684) |\n|---|---|---|---|"
    );
    let mut layers = vec![("before", &v.before), ("after", &v.after)];
    if let Some(u) = &v.unconstrained {
        layers.push(("unconstrained optimum", u));
    }
    for (name, r) in layers {
        for p in r.probes.iter() {
            let (w, a, unbounded) = p.largest(&r.speeds);
            if p.peaks.is_empty() {
                let _ = writeln!(s, "| {name} | {w:.3} (largest, no interior peak) | {a:.4e} | – |");
            }
            for k in &p.peaks {
                let af = match (k.amplification_factor, k.unbounded) {
                    (_, true) => "unbounded".to_string(),
                    (Some(af), false) => format!("{af:.2}"),
                    (None, false) => "– (half-power point beyond the range)".to_string(),
                };
                let _ = writeln!(s, "| {name} | {:.3} | {:.4e} | {af} |", k.speed, k.amplitude);
            }
            let _ = unbounded;
        }
    }
    let _ = writeln!(s, "\n## Damping ratios ζ = −Re λ/|λ| of the lowest whirls over the operating speeds\n");
    let _ = writeln!(s, "| mode | ζ min before | at (rad/s) | ζ min after | at (rad/s) |\n|---|---|---|---|---|");
    for b in &v.damping_before {
        let a = v.damping_after.iter().find(|a| a.tag == b.tag);
        let _ = writeln!(
            s,
            "| {} | {:.6e} | {:.1} | {} | {} |",
            b.tag,
            b.min_damping_ratio,
            b.min_speed,
            a.map_or("–".into(), |a| format!("{:.6e}", a.min_damping_ratio)),
            a.map_or("–".into(), |a| format!("{:.1}", a.min_speed))
        );
    }
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

/// Colour of the reference design's layer and band.
const BEFORE_COLOR: (u8, u8, u8) = (31, 119, 180);
/// Colour of the tuned design's layer and band.
const AFTER_COLOR: (u8, u8, u8) = (214, 39, 40);
/// Height of a band's bar on the charts, as a fraction of β_op (the charts show β up to
/// 2 β_op: each bar is then 3 % of the height).
const BAR_HEIGHT: f64 = 0.06;
/// Colour of an operating band kept clear.
const OPERATING_COLOR: (u8, u8, u8) = (0, 158, 115);
/// Colour of a band's clearances.
const CLEARANCE_COLOR: (u8, u8, u8) = (230, 159, 0);

/// The spans of the design's bands on its charts at speed index `k`: the stable bands
/// before and after (widest band), each operating band and its clearances.
fn spans(o: &DesignOutcome, k: usize) -> Vec<Span> {
    let level = o.spec.level;
    let mut spans = Vec::new();
    // The bands found at β_op: two bars just below the level, the tuned one on top.
    for (name, bands, color, beta) in [
        ("stable band at β_op, before", o.before_bands(), BEFORE_COLOR, (1.0 - 2.0 * BAR_HEIGHT, 1.0 - BAR_HEIGHT)),
        ("stable band at β_op, after", o.after_bands(), AFTER_COLOR, (1.0 - BAR_HEIGHT, 1.0)),
    ] {
        if let Some(b) = bands.get(k).and_then(|b| b.band.band) {
            spans.push(Span {
                lo: b.lo,
                hi: b.hi,
                beta: Some((beta.0 * level, beta.1 * level)),
                name: name.into(),
                color,
            });
        }
    }
    for b in o.spec.kept_clear() {
        spans.push(Span {
            lo: b.lo,
            hi: b.hi,
            beta: None,
            name: "operating band kept clear".into(),
            color: OPERATING_COLOR,
        });
        if b.clearance > 0.0 {
            let g = b.guarded();
            for (lo, hi) in [(g.lo, b.lo), (b.hi, g.hi)] {
                spans.push(Span { lo, hi, beta: None, name: "clearance".into(), color: CLEARANCE_COLOR });
            }
        }
    }
    spans
}

/// The figures of a design report, in the order the report shows them (the first is the
/// key figure of page one): (file stem, figure).
pub fn figures<'a>(o: &'a DesignOutcome, content: &DesignContent, title: &str) -> Vec<(String, Box<dyn Figure + 'a>)> {
    let spec = &o.spec;
    let mut out: Vec<(String, Box<dyn Figure + 'a>)> = Vec::new();
    if let Some(v) = &o.vibration {
        let layers = vec![
            BodeLayer { name: "reference circuit".into(), dashed: false, result: &v.before },
            BodeLayer { name: "tuned circuit".into(), dashed: true, result: &v.after },
        ];
        let plot = BodePlot { title: format!("Unbalance response before and after the design: {title}"), layers };
        out.push(("bode".into(), Box::new(plot)));
    }
    let markers: Vec<(f64, String)> = spec.phi_op().map(|p| (p, format!("φ_op = {p}"))).into_iter().collect();
    for (k, c) in content.charts.iter().enumerate() {
        let layers = vec![
            Layer { name: "reference circuit".into(), color: BEFORE_COLOR, chart: c.before.clone() },
            Layer { name: "tuned circuit".into(), color: AFTER_COLOR, chart: c.after.clone() },
        ];
        let plot = StabilityPlot::new(&format!("Stability before and after the design, Ω = {} rad/s", c.speed), layers)
            .with_spans(spans(o, k))
            .with_levels(vec![(spec.level, format!("β_op = {}", spec.level))])
            .with_markers(markers.clone());
        let name = if content.charts.len() == 1 { "charts".to_string() } else { format!("charts-{}", k + 1) };
        out.push((name, Box::new(plot)));
    }
    let campbell =
        super::campbell::campbell_plot(&content.campbell, &format!("Campbell diagram, tuned circuit: {title}"));
    out.push(("campbell".into(), Box::new(campbell)));
    out.push(("history".into(), Box::new(history_plot(o))));
    out
}

/// The optimiser's best objective so far against its evaluations, one line per start.
fn history_plot(o: &DesignOutcome) -> LinePlot {
    let starts = o.history.iter().map(|h| h.start).max().map_or(0, |m| m + 1);
    let series: Vec<Series> = (0..starts)
        .map(|k| Series {
            name: match o.spec.objective {
                Objective::ClearBands { .. } if k == 0 => "from the reference".into(),
                Objective::ClearBands { .. } => "from the best global point".into(),
                _ => o.starts.get(k).map_or(format!("start {k}"), |s| s.origin.clone()),
            },
            color: super::style::color(k),
            dashed: false,
            points: o.history.iter().filter(|h| h.start == k).map(|h| (h.step as f64, h.best)).collect(),
        })
        .collect();
    let ys: Vec<f64> = series.iter().flat_map(|s| s.points.iter().map(|p| p.1)).filter(|y| y.abs() < 1e8).collect();
    let (y0, y1) = ys.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &y| (a.min(y), b.max(y)));
    let (y0, y1) = if y0.is_finite() && y1 > y0 { (y0, y1) } else { (y0.min(0.0) - 1.0, y1.max(0.0) + 1.0) };
    let x1 = series.iter().flat_map(|s| s.points.iter().map(|p| p.0)).fold(1.0, f64::max);
    let (x_label, y_label) = match o.spec.objective {
        Objective::WidestStableBand { .. } => {
            ("candidate evaluations of the start", "smallest band width over the speeds (rad/s)")
        }
        Objective::ClearBands { .. } => ("convex step", "total intrusion into the bands (rad/s)"),
        Objective::MinPeakResponse { .. } => {
            ("candidate evaluations of the start", "peak response, with the constraints' penalty (m)")
        }
    };
    LinePlot {
        title: "Optimiser history (best so far)".into(),
        x_label: x_label.into(),
        y_label: y_label.into(),
        x_range: (0.0, x1),
        y_range: (y0 - 0.05 * (y1 - y0), y1 + 0.05 * (y1 - y0)),
        series: series.into_iter().filter(|s| !s.points.is_empty()).collect(),
    }
}
