//! Everything below page one of a design report: provenance and cost, variables, the
//! classic tuning, the response, the regions near the band, whirls, the optimiser, the
//! settings, the glossary, the figures and the files.

use super::*;
use crate::analysis::Interval;
use crate::design::DesignOutcome;
use crate::report::html::markdown_code;
use std::fmt::Write;

/// Everything below page one.
pub(super) fn details(s: &mut String, r: &DesignReport) {
    let o = &r.outcome;
    let p = &r.provenance;
    let spec = &o.spec;
    let _ = writeln!(s, "## Problem and run\n");
    let _ = writeln!(
        s,
        "- problem: {}{} (SHA-256 of text and overrides: `{}`)",
        markdown_code(&p.problem),
        if p.overrides.is_empty() {
            String::new()
        } else {
            format!(" with {}", markdown_code(&format!("--set {}", p.overrides.join(" "))))
        },
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
    basis_section(s, o);
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
    vibration_section(s, o, &r.whirls);
    near_regions_section(s, o);
    whirls_section(s, o, &r.whirls);
    optimiser_section(s, o);
    settings_table(s, &p.settings);
    let _ = writeln!(s, "\n{}", crate::report::glossary::glossary());
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

/// The warnings of page one, all of them, and the basis: the sizes its convergence tried
/// with each movement, and the refined check at each speed.
fn basis_section(s: &mut String, o: &DesignOutcome) {
    let warnings = super::page_one::warnings(o);
    if !warnings.is_empty() {
        let _ = writeln!(s, "\n## Warnings\n");
        for w in &warnings {
            let _ = writeln!(s, "- {w}");
        }
    }
    let _ = writeln!(s, "\n## Reduced basis\n");
    match &o.basis {
        Some(b) => {
            let _ = writeln!(s, "Every candidate was judged on the {}.\n", b.text());
            let _ = writeln!(s, "| M | movement from the size before |\n|---|---|");
            for step in &b.steps {
                let m = step.movement.as_ref().map_or("–".to_string(), |m| m.text().replace('|', "\\|"));
                let _ = writeln!(s, "| {} | {m} |", step.modes);
            }
        }
        None => {
            let _ = writeln!(s, "Not recorded.");
        }
    }
    for c in &o.refined {
        let moved: Vec<String> = c.movements.iter().map(|m| m.text().replace('|', "\\|")).collect();
        let _ = writeln!(
            s,
            "\nRefined check at {}: M = {} → {}{}: {}.",
            speed_text(o.spec.speed_unit, c.speed),
            c.modes,
            c.refined_modes,
            c.refined_band.map_or(String::new(), |b| format!(", band [{:.2}, {:.2}] rad/s", b.lo, b.hi)),
            if moved.is_empty() { "nothing to compare".to_string() } else { moved.join("; ") }
        );
    }
}

fn criterion_text(c: &crate::analysis::Settings) -> String {
    format!(
        "unstable when {}{}{}; tongues searched up to order {}",
        c.threshold().describe().replace('|', "\\|"),
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
pub(super) struct NearRow {
    label: String,
    order: Option<usize>,
    start: Option<f64>,
    onset: Option<f64>,
    edges: Interval,
    pub(super) distance: f64,
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
pub(super) fn near_rows(c: &crate::analysis::regions::Catalogue, targets: &[Interval]) -> Vec<NearRow> {
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
                "\n{name}, {} ({} of {} tongues at β_op):\n\n| region | k | start (rad/s) | onset β | edges at β_op (rad/s) | width (rad/s) | distance (rad/s) |\n|---|---|---|---|---|---|---|",
                speed_text(o.spec.speed_unit, d.speed),
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

/// The whirls of the tuned design at each speed beside the reference's whirl of the same
/// mode shape (`paired`, by MAC): a label follows frequency order, so the same label may
/// name another mode before and after.
fn whirls_section(s: &mut String, o: &DesignOutcome, paired: &[crate::design::content::SpeedWhirls]) {
    let unit = o.spec.speed_unit;
    for (k, after) in o.after_speeds.iter().enumerate() {
        let _ = writeln!(s, "\n## Whirl frequencies at {}\n", speed_text(unit, after.speed));
        match paired.get(k).filter(|p| !p.pairs.is_empty()) {
            Some(p) => {
                let _ = writeln!(
                    s,
                    "Each tuned whirl beside the reference whirl with the same mode shape (the largest MAC, one to one): labels follow frequency order, so a mode may carry another label after the design.\n\n| mode after | after (rad/s) | same mode before | before (rad/s) | MAC |\n|---|---|---|---|---|"
                );
                for w in &p.pairs {
                    let _ = writeln!(
                        s,
                        "| {} | {:.2} | {} | {} | {} |",
                        w.after,
                        w.after_frequency,
                        w.before.as_deref().unwrap_or("none (no reference whirl with MAC ≥ 0.5)"),
                        opt(w.before_frequency, 2),
                        opt(w.mac, 3)
                    );
                }
            }
            None => {
                let before = o.before_speeds.get(k);
                let _ = writeln!(s, "| mode | before (rad/s) | after (rad/s) |\n|---|---|---|");
                for w in &after.whirls {
                    let b = before.and_then(|b| b.whirls.iter().find(|x| x.tag == w.tag));
                    let _ = writeln!(s, "| {} | {} | {:.2} |", w.tag, opt(b.map(|b| b.frequency), 2), w.frequency);
                }
            }
        }
    }
}

fn optimiser_section(s: &mut String, o: &DesignOutcome) {
    let _ = writeln!(s, "\n## Optimiser\n");
    s.push_str(&o.spec.objective.optimiser_method(o.starts.len()));
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
            super::map::ending(&o.spec, st)
        );
    }
    super::map::map_section(s, o);
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
const SETTING_MEANINGS: [(&str, &str); 17] = [
    ("mac_threshold", "least modal assurance criterion for a Campbell track to continue (−)"),
    ("electrical_fraction", "share of a mode's kinetic energy in the charges above which it is electrical (−)"),
    ("oscillation_tolerance", "\\|Im λ\\|/\\|λ\\| below which an eigenvalue is not a whirl (−)"),
    ("reduced_modes", "modes M of the reduced model of the Floquet analysis (Eq. 22), or auto: sized by convergence"),
    ("basis", "the reduced basis: loaded (modes under the static load) or unloaded (the paper's)"),
    ("convergence_relative", "edges converged within this share of the band's width (−)"),
    ("convergence_absolute", "edges converged within this at least (rad/s)"),
    ("convergence_onset", "onsets converged within this share of themselves (−)"),
    (
        "instability_tolerance",
        "the paper's rule: unstable when max\\|μ\\| exceeds this (Eq. 28) (−); unset: the growth rule",
    ),
    ("decay_margin", "σ_req: unstable when ln max\\|μ\\| exceeds 1e-6 − σ_req·T (1/s)"),
    ("min_growth_rate", "growth-rate floor of the criterion (1/s); 0: every growth counts"),
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
fn vibration_section(s: &mut String, o: &DesignOutcome, paired: &[crate::design::content::SpeedWhirls]) {
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
                    (Some(af), false) => format!("{af:.2}{}", k.split_note()),
                    (None, false) => "– (half-power point beyond the range)".to_string(),
                };
                let _ = writeln!(s, "| {name} | {:.3} | {:.4e} | {af} |", k.speed, k.amplitude);
            }
            let _ = unbounded;
        }
    }
    let _ = writeln!(s, "\n## Damping ratios ζ = −Re λ/|λ| of the lowest whirls over the operating speeds\n");
    let _ = writeln!(
        s,
        "The same mode before and after, paired by mode shape at the first operating speed (MAC), whatever its label.\n\n| mode | ζ min before | at (rad/s) | ζ min after | at (rad/s) |\n|---|---|---|---|---|"
    );
    for b in &v.damping_before {
        // The tuned whirl with this reference whirl's shape, else the same label.
        let tag = paired
            .first()
            .and_then(|p| p.pairs.iter().find(|w| w.before.as_deref() == Some(b.tag.as_str())))
            .map_or(b.tag.as_str(), |w| w.after.as_str());
        let a = v.damping_after.iter().find(|a| a.tag == tag);
        let name = if tag == b.tag { b.tag.clone() } else { format!("{} (after: {tag})", b.tag) };
        let _ = writeln!(
            s,
            "| {} | {:.6e} | {:.1} | {} | {} |",
            name,
            b.min_damping_ratio,
            b.min_speed,
            a.map_or("–".into(), |a| format!("{:.6e}", a.min_damping_ratio)),
            a.map_or("–".into(), |a| format!("{:.1}", a.min_speed))
        );
    }
    if let (Some(b), Some(a)) = (&v.crossing_before, &v.crossing_after) {
        let _ = writeln!(
            s,
            "\nAt the critical speed the run-up crosses, where the shunt works: ζ of the lowest whirls at the speed of each design's largest response at node {} (before {:.2} rad/s, after {:.2} rad/s).\n\n| mode | ζ before | ζ after |\n|---|---|---|",
            v.response.node, b.speed, a.speed
        );
        for w in &b.whirls {
            let after = a.whirls.iter().find(|x| x.tag == w.tag);
            let _ = writeln!(
                s,
                "| {} | {:.6e} | {} |",
                w.tag,
                w.min_damping_ratio,
                after.map_or("–".into(), |x| format!("{:.6e}", x.min_damping_ratio))
            );
        }
    }
}
