//! Page one of a design report: question, answer, circuit, the objective's figures,
//! constraints, verification and the key figure.

use super::*;
use crate::design::spec::Objective;
use crate::design::{DesignOutcome, Status};
use crate::numbers::SpeedUnit;
use std::fmt::Write;

/// The variables' names, joined for a sentence.
fn variable_names(r: &DesignReport) -> String {
    let names: Vec<String> = r.outcome.spec.variables.iter().map(|v| v.name()).collect();
    match names.as_slice() {
        [] => "no variable".into(),
        [one] => one.clone(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    }
}

fn speeds_text(unit: SpeedUnit, speeds: &[f64]) -> String {
    let v: Vec<String> = speeds.iter().map(|w| unit.text(*w)).collect();
    format!("{} = {}", unit.symbol(), v.join(", "))
}

/// The question the design answers, in one sentence.
fn question(r: &DesignReport) -> String {
    let spec = &r.outcome.spec;
    let vars = variable_names(r);
    let at = speeds_text(spec.speed_unit, &spec.speeds);
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
            "Which {vars} give the smallest peak unbalance response at node {} over the rotating speeds {}{}?",
            response.node,
            spec.speed_unit.range(response.speeds.lo, response.speeds.hi),
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
fn status_sentence(o: &DesignOutcome) -> String {
    let fixed = match o.status {
        Status::Improved => "**Improved**: the tuned design is better than the reference's, and verified.",
        Status::Unchanged => "**Unchanged**: no start beat the reference design, which is kept (verified).",
        Status::Feasible => "**Feasible**: every band is clear by its clearance, and verified.",
        Status::Infeasible => {
            "**Infeasible**: no design inside the bounds meets every requirement; the violations are listed below, and `best-effort.toml` is the optimiser's best effort, not a result."
        }
        Status::NotVerified => {
            "**Not verified**: the design found failed its independent verification (below); `best-effort.toml` is not a result."
        }
        Status::NotRobust => {
            "**Not robust**: the design holds at its nominal component values but not at every build of the tolerance box (the failing build is named below); `best-effort.toml` is not a result."
        }
        Status::Stopped => {
            return format!(
                "**Stopped, NOT A RESULT**: the run was stopped before it ended ({}). `best-effort.toml` is the best design judged so far, neither optimised to the end nor verified; run again with a larger limit for a result.",
                o.stop.as_deref().unwrap_or("no reason recorded")
            )
        }
    };
    fixed.to_string()
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
pub(super) fn page_one(r: &DesignReport) -> String {
    let o = &r.outcome;
    let spec = &o.spec;
    let mut s = String::new();
    let _ = writeln!(s, "# Shunt design report: {}\n", crate::report::html::markdown_literal(&r.title));
    let _ = writeln!(s, "**Question.** {}\n", question(r));
    let _ = writeln!(s, "**Answer.** {}\n", status_sentence(o));
    model_line(&mut s, o);
    warnings_block(&mut s, o);
    let _ = writeln!(s, "Circuit, before → after (changed values in bold):\n");
    circuit_table(&mut s, &r.branches_before, &r.branches_after);
    if o.status == Status::Stopped {
        // Nothing of the objective or the verification was judged to the end.
        let _ = writeln!(
            s,
            "\n**Not verified**: the run stopped before its verification; the figures of the optimiser's runs so far are below.\n"
        );
        return s;
    }
    match &spec.objective {
        Objective::WidestStableBand { .. } => widest_band_table(&mut s, o),
        Objective::ClearBands { .. } => clear_bands_table(&mut s, o),
        Objective::MinPeakResponse { .. } => peak_table(&mut s, o),
    }
    constraints_table(&mut s, o);
    super::margins::margins_table(&mut s, o);
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

/// Lines the page-one warnings block may take; more warnings are counted in its last line
/// and listed in the details.
pub const WARNING_LINES: usize = 6;

/// The model every verdict rests on, in one line: the basis and its convergence, and the
/// criterion.
fn model_line(s: &mut String, o: &DesignOutcome) {
    let none =
        if o.status == Status::Stopped { "the run stopped before its basis was sized" } else { "basis not recorded" };
    let basis = o.basis.as_ref().map_or(none.to_string(), |b| b.text());
    let rule = o.after_speeds.first().map(|d| d.catalogue.criterion.threshold.describe().replace('|', "\\|"));
    let rule = rule.map_or(String::new(), |r| format!("; unstable when {r}"));
    let _ = writeln!(s, "**Model.** {basis}{rule}.\n");
}

/// What the answer rests on that a reader must know first (a band clipped by the window,
/// φ_op unstable, a basis that did not converge or that a refined basis moves), at most
/// [`WARNING_LINES`] lines; nothing when all is well.
pub fn warnings(o: &DesignOutcome) -> Vec<String> {
    let mut w = Vec::new();
    let unit = o.spec.speed_unit;
    for d in &o.after_speeds {
        let Some(b) = &d.band else { continue };
        match (b.band, b.containing) {
            (None, t) => w.push(format!(
                "φ_op = {} rad/s is **unstable** at β_op at {}{}: no stable band contains it.",
                b.phi_op,
                speed_text(unit, d.speed),
                t.map_or(String::new(), |t| format!(" (inside [{:.2}, {:.2}] rad/s)", t.lo, t.hi))
            )),
            (Some(x), _) if b.clipped() => {
                let range = o.spec.range();
                let end = if matches!(b.left, Some(Bound::Window)) { range.lo } else { range.hi };
                w.push(format!(
                    "The band at {} reaches the end of the φ range at {end} rad/s: it is at least {:.2} rad/s wide, and the objective counted only what tongues bound; widen `design.phi_range` past {end} rad/s to see its edge.",
                    speed_text(unit, d.speed),
                    x.width()
                ));
            }
            _ => {}
        }
    }
    if let Some(b) = o.basis.as_ref().filter(|b| !b.converged()) {
        w.push(format!("The reduced basis did not converge: {}; the answers may move on a larger basis.", b.text()));
    }
    for c in o.refined.iter().filter(|c| !c.held) {
        let worst = c.movements.iter().filter(|m| !m.within()).map(|m| m.text()).collect::<Vec<_>>().join("; ");
        w.push(format!(
            "A basis twice as large (M = {}) moves the answer at {} beyond its tolerance: {worst}.",
            c.refined_modes,
            speed_text(unit, c.speed)
        ));
    }
    w
}

/// The warnings block: one line each, at most [`WARNING_LINES`] with the count of the rest.
fn warnings_block(s: &mut String, o: &DesignOutcome) {
    let w = warnings(o);
    if w.is_empty() {
        return;
    }
    let shown = if w.len() > WARNING_LINES { WARNING_LINES - 1 } else { w.len() };
    for line in &w[..shown] {
        let _ = writeln!(s, "> **Warning.** {line}");
    }
    if w.len() > shown {
        let _ = writeln!(s, "> … and {} more warnings (details, \"Warnings\").", w.len() - shown);
    }
    let _ = writeln!(s);
}

fn widest_band_table(s: &mut String, o: &DesignOutcome) {
    let _ = writeln!(
        s,
        "\nStable band at β_op = {} around φ_op (rad/s; width in brackets):\n\n| {} | before | after | after: bounded below by | above by |\n|---|---|---|---|---|",
        o.spec.level,
        speed_header(o.spec.speed_unit)
    );
    for (b, a) in o.before_bands().iter().zip(o.after_bands()) {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} |",
            speed_cell(o.spec.speed_unit, b.speed),
            band_text(&b.band),
            band_text(&a.band),
            bound_text(&a.band.left),
            bound_text(&a.band.right)
        );
    }
    if let Some(r) = &o.speed_check {
        let _ =
            writeln!(s, "\nSpeed range {}.", crate::design::robust::speed_range_text(o.speed_check_before.as_ref(), r));
    }
    if let Some(r) = &o.robustness {
        let _ = writeln!(
            s,
            "\nAs built, with parts inside the tolerances ({}): {}.",
            r.tolerances.text(),
            crate::design::robust::guaranteed_text(r)
        );
    }
    for a in o.after_bands() {
        for t in &a.band.ignored {
            let _ = writeln!(
                s,
                "\nIgnored by the criterion at {}: {} at [{:.3}, {:.3}] rad/s.",
                speed_text(o.spec.speed_unit, a.speed),
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

/// The peaks of the open circuit, the reference, classic, unconstrained and tuned designs
/// in one table (the baselines' amplification factors and the tuned peak relative to
/// each), and the price of the constraints.
fn peak_table(s: &mut String, o: &DesignOutcome) {
    let Some(f) = o.peak_findings() else { return };
    let _ = writeln!(
        s,
        "\nPeak unbalance response (m), each by the same response computation:\n\n| design | peak (m) | at (rad/s) | amplification factor (−) | tuned peak vs it | constraints met |\n|---|---|---|---|---|---|"
    );
    let baseline = |name: &str| f.baselines.iter().find(|b| b.design == name);
    let tuned = f.after.peak.amplitude;
    let af = |name: &str| {
        baseline(name).map_or("–".to_string(), |b| {
            b.amplification_factor.map_or("– (no half-power band in the range)".to_string(), |a| format!("{a:.1}"))
        })
    };
    let row = |s: &mut String, name: &str, peak: &crate::design::vibration::PeakValue, af: String, met: String| {
        let vs = if name == "tuned" {
            "–".to_string()
        } else {
            format!("{:+.1} %", 100.0 * (tuned / peak.amplitude - 1.0))
        };
        let _ = writeln!(
            s,
            "| {name} | {:.4e}{} | {:.2} | {af} | {vs} | {met} |",
            peak.amplitude,
            if peak.unbounded { " (unbounded)" } else { "" },
            peak.speed
        );
    };
    if let Some(b) = baseline("open circuit") {
        row(s, "open circuit", &b.peak, af("open circuit"), "–".to_string());
    }
    let met = |d: &crate::design::optimise::JudgedDesign| {
        if d.constraints.is_empty() {
            "–".to_string()
        } else {
            d.feasible.to_string()
        }
    };
    let mut rows = vec![("reference", &f.before, af("reference circuit"))];
    if let Some(c) = &f.classic_design {
        rows.push(("classic tuning", c, af("classic tuning")));
    }
    rows.push(("unconstrained optimum", &f.unconstrained, "–".to_string()));
    rows.push(("tuned", &f.after, af("tuned")));
    for (name, d, a) in rows {
        row(s, name, &d.peak, a, met(d));
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

/// The independent verification, one sentence per part (each over every speed): its
/// status, what it checked with counts, or why it is not applicable.
fn verification_sentences(s: &mut String, o: &DesignOutcome) {
    use crate::design::verify::PartStatus;
    let v = &o.verification;
    let _ = writeln!(s, "\n**Verification: {}** (independent of the optimiser, on the tuned design):\n", v.verdict);
    for p in &v.parts {
        let name = match p.part.as_str() {
            "operating-point" => "Operating point",
            "refined-basis" => "Refined basis",
            "catalogue" => "Catalogue",
            "centres" => "Tongue centres",
            "grid" => "Grid",
            "constraints" => "Constraints",
            "peak" => "Peak",
            "tolerances" => "Tolerances",
            "speeds" => "Speed range",
            "margins" => "Margins",
            other => other,
        };
        let status = match p.status {
            PartStatus::Passed => "passed",
            PartStatus::Failed => "**FAILED**",
            PartStatus::NotApplicable => "*not applicable*",
        };
        let _ = writeln!(s, "- {name}: {status}, {}.", p.summary);
    }
    for d in &o.after_speeds {
        for f in &d.failures {
            let _ = writeln!(s, "- Failed at {}: {f}", speed_text(o.spec.speed_unit, d.speed));
        }
    }
}
