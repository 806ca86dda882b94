//! Page one of a design report: question, answer, circuit, the objective's figures,
//! constraints, verification and the key figure.

use super::*;
use crate::analysis::regions::{Bound, Margins};
use crate::design::spec::{DesignSpec, WarningLevels};
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
    spec.objective.question(spec, &vars, &at, o_constrained(&r.outcome))
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
    spec.objective.page_one(&mut s, o);
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
    edge_warnings(&mut w, o);
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

/// The answers that sit on an edge: a tuned variable on a bound of its box, starts that
/// stopped at their iteration limit, and margins under the spec's [`WarningLevels`].
fn edge_warnings(w: &mut Vec<String>, o: &DesignOutcome) {
    let spec = &o.spec;
    if o.status != Status::Stopped {
        for (i, upper) in super::map::at_bounds(spec, &o.after) {
            let v = &spec.variables[i];
            let (side, key, bound) = if upper { ("upper", "max", v.max) } else { ("lower", "min", v.min) };
            w.push(format!(
                "{} = {} {} sits on its {side} bound (`design.variables[{i}].{key}` = {bound}): the best design may lie beyond it; widen the bound to look.",
                v.name(),
                crate::numbers::sig(o.after[i], 5),
                v.parameter.unit()
            ));
        }
    }
    let limited = o.starts.iter().filter(|s| super::map::hit_iteration_limit(s)).count();
    if limited > 0 {
        w.push(format!(
            "{limited} of {} starts stopped at their iteration limit (`design.max_iterations` = {}) before converging: more iterations may find a better design.",
            o.starts.len(),
            spec.max_iterations
        ));
    }
    for d in &o.after_speeds {
        if let Some(m) = &d.margins {
            margin_warnings(w, m, &speed_text(spec.speed_unit, d.speed), spec.phi_op(), &spec.warnings);
        }
    }
    run_up_warning(w, spec);
}

/// A damping design (`[design.response]`) whose stability is asked at operating speeds
/// only, while its response range reaches below them: the machine runs up through those
/// speeds (the critical speed the shunt damps among them), and nothing checked it there.
fn run_up_warning(w: &mut Vec<String>, spec: &DesignSpec) {
    let (Some(r), Some(_), None) = (spec.response(), spec.phi_op(), spec.speed_range) else { return };
    let lowest = spec.speeds.iter().copied().fold(f64::INFINITY, f64::min);
    if r.speeds.lo < lowest {
        w.push(format!(
            "Stability is judged at {} only, while the response is minimised over {}: add `design.speed_range` over the run-up (e.g. [{}, {}]) to judge it at the speeds the machine runs through.",
            speeds_text(spec.speed_unit, &spec.speeds),
            spec.speed_unit.range(r.speeds.lo, r.speeds.hi),
            crate::numbers::sig(r.speeds.lo, 4),
            crate::numbers::sig(spec.speeds.iter().copied().fold(f64::NEG_INFINITY, f64::max), 4)
        ));
    }
}

/// A load margin under `levels.load_margin` and a frequency margin under
/// `levels.frequency_margin` of φ_op, at the speed `at` (in words).
fn margin_warnings(w: &mut Vec<String>, m: &Margins, at: &str, phi_op: Option<f64>, levels: &WarningLevels) {
    if m.load.is_some() && m.load_margin() < levels.load_margin {
        w.push(format!(
            "The load margin at {at} is {}, under {} % (`design.warnings.load_margin`): a load that much above β_op opens a tongue inside the band.",
            m.load_text(),
            crate::numbers::sig(100.0 * levels.load_margin, 3)
        ));
    }
    if let Some(phi_op) = phi_op {
        let margin = m.phi_below.min(m.phi_above);
        if margin < levels.frequency_margin * phi_op {
            w.push(format!(
                "The frequency margin at {at} is {margin:.2} rad/s ({:.1} % of φ_op), under {} % (`design.warnings.frequency_margin`): φ_op lies near an edge of its band.",
                100.0 * margin / phi_op,
                crate::numbers::sig(100.0 * levels.frequency_margin, 3)
            ));
        }
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::design::optimise::StartReport;

    fn outcome(after: Vec<f64>, terminations: &[&str]) -> DesignOutcome {
        let spec = super::super::map::tests::spec();
        let mut o = DesignOutcome::empty(&spec, vec![900.0, 5.0]);
        o.status = Status::Improved;
        o.after = after.clone();
        o.starts = terminations
            .iter()
            .map(|t| StartReport {
                origin: "reference".into(),
                initial: vec![900.0, 5.0],
                best: after.clone(),
                objective: 300.0,
                evaluations: 10,
                iterations: 5,
                termination: t.to_string(),
            })
            .collect();
        o
    }

    #[test]
    fn a_design_on_a_bound_is_warned_and_one_inside_is_not() {
        let on = warnings(&outcome(vec![1400.0, 9.0], &["Solver converged"]));
        assert_eq!(on.len(), 1, "{on:?}");
        assert!(on[0].contains("sits on its upper bound (`design.variables[0].max` = 1400)"), "{on:?}");
        assert!(warnings(&outcome(vec![1100.0, 9.0], &["Solver converged"])).is_empty());
    }

    #[test]
    fn starts_at_their_iteration_limit_are_counted() {
        let o = outcome(vec![1100.0, 9.0], &["Maximum number of iterations reached", "Solver converged"]);
        let w = warnings(&o);
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(w[0].starts_with("1 of 2 starts stopped at their iteration limit"), "{w:?}");
    }

    /// Margins at β_op = 0.3 around φ_op = 1230 rad/s: a load margin `load` (−) from an
    /// onset found, and `below`, `above` rad/s to the band's edges.
    fn margins(load: f64, below: f64, above: f64) -> Margins {
        let onset = 0.3 * (1.0 + load);
        Margins {
            level: 0.3,
            load: Some(crate::analysis::regions::LoadMargin {
                margin: load,
                onset,
                label: "f1+b1".into(),
                order: 2,
                start: 1240.0,
                resolved: true,
            }),
            searched_to: 0.6,
            phi_below: below,
            phi_above: above,
            max_multiplier: None,
            sampled: 0,
            strict: crate::analysis::criterion::Threshold::GROWTH,
            strict_band: None,
        }
    }

    fn margin_warned(m: &Margins, levels: &WarningLevels) -> Vec<String> {
        let mut w = Vec::new();
        margin_warnings(&mut w, m, "Ω = 2000 rad/s", Some(1230.0), levels);
        w
    }

    #[test]
    fn a_load_margin_under_the_threshold_is_warned_and_one_over_it_is_not() {
        let defaults = WarningLevels::default();
        // 100 rad/s from either edge: 8.1 % of φ_op, no frequency warning.
        let under = margin_warned(&margins(0.0107, 100.0, 120.0), &defaults);
        assert_eq!(under.len(), 1, "{under:?}");
        assert!(under[0].starts_with("The load margin at Ω = 2000 rad/s is +1.07 % (f1+b1"), "{under:?}");
        assert!(under[0].contains("under 10 % (`design.warnings.load_margin`)"), "{under:?}");
        assert!(margin_warned(&margins(0.0537, 100.0, 120.0), &defaults).len() == 1);
        assert!(margin_warned(&margins(0.12, 100.0, 120.0), &defaults).is_empty());
        // The threshold is a setting: at 5 %, a margin of 5.37 % is not warned.
        let five = WarningLevels { load_margin: 0.05, ..defaults };
        assert!(margin_warned(&margins(0.0537, 100.0, 120.0), &five).is_empty());
        assert_eq!(margin_warned(&margins(0.0107, 100.0, 120.0), &five).len(), 1);
    }

    #[test]
    fn a_frequency_margin_under_the_threshold_is_warned_and_one_over_it_is_not() {
        let defaults = WarningLevels::default();
        // 5 % of 1230 rad/s is 61.5 rad/s.
        let near = margin_warned(&margins(0.5, 200.0, 40.0), &defaults);
        assert_eq!(near.len(), 1, "{near:?}");
        assert!(near[0].starts_with("The frequency margin at Ω = 2000 rad/s is 40.00 rad/s (3.3 % of φ_op), under 5 %"));
        assert!(margin_warned(&margins(0.5, 200.0, 62.0), &defaults).is_empty());
        let two = WarningLevels { frequency_margin: 0.02, ..defaults };
        assert!(margin_warned(&margins(0.5, 200.0, 40.0), &two).is_empty());
    }
}
