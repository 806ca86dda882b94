//! The tuned-parameter report of a design run: the content (serialised as report.json)
//! and its Markdown rendering (report.md). Rendering only: no file I/O here.

use crate::analysis::regions::{Band, Bound};
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

fn branches_table(s: &mut String, rows: &[BranchRow]) {
    if rows.iter().any(|b| b.ring.is_some()) {
        let _ =
            writeln!(s, "| ring | branch | C_f (F) | L (H) | R (Ω) | tuning ω (rad/s) |\n|---|---|---|---|---|---|");
    } else {
        let _ = writeln!(s, "| branch | C_f (F) | L (H) | R (Ω) | tuning ω (rad/s) |\n|---|---|---|---|---|");
    }
    for b in rows {
        let ring = b.ring.as_ref().map(|r| format!("| {r} ")).unwrap_or_default();
        let _ = writeln!(
            s,
            "{ring}| {} | {:.4e} | {:.4} | {:.3} | {:.2} |",
            b.branch, b.c_f, b.inductance, b.resistance, b.tuning_frequency
        );
    }
}

/// Markdown of a design report.
pub fn markdown(r: &DesignReport) -> String {
    let o = &r.outcome;
    let p = &r.provenance;
    let spec = &o.spec;
    let mut s = String::new();
    let _ = writeln!(s, "# Shunt design report: {}\n", r.title);
    let _ = writeln!(
        s,
        "- problem: `{}`{} (SHA-256 of text and overrides: `{}`)",
        p.problem,
        if p.overrides.is_empty() { String::new() } else { format!(" with `--set {}`", p.overrides.join(" ")) },
        p.input_sha256
    );
    let _ = writeln!(s, "- tool: {}; settings: `{}`", p.tool, serde_json::to_string(&p.settings).unwrap_or_default());
    let objective = match &spec.objective {
        Objective::WidestStableBand { .. } => {
            format!(
                "widest stable band at β_op = {} containing φ_op = {} rad/s",
                spec.level,
                opt(spec.objective.phi_op(), 1)
            )
        }
        Objective::ClearBands { .. } => {
            format!(
                "clear {} operating band(s) at β_op = {} with the least change",
                spec.objective.bands().len(),
                spec.level
            )
        }
        Objective::MinPeakResponse { response } => format!(
            "least peak unbalance response at node {} over {}..{} rad/s ({} speeds, peaks refined)",
            response.node, response.speeds.lo, response.speeds.hi, response.points
        ),
    };
    let _ = writeln!(s, "- objective: {objective}; speeds {:?} rad/s", spec.speeds);
    let status = match o.status {
        Status::Improved => "**improved**: the tuned band is wider than the reference's, and verified",
        Status::Unchanged => "**unchanged**: no start beat the reference design, which is kept (verified)",
        Status::Feasible => "**feasible**: every band is clear by its clearance, and verified",
        Status::Infeasible => {
            "**infeasible**: no design inside the bounds clears every band; the violated bands are listed below, and the optimiser's best effort is `best-effort.toml`, not a result"
        }
        Status::NotVerified => {
            "**not verified**: the design found failed its independent verification (below); `best-effort.toml` is not a result"
        }
    };
    let _ = writeln!(s, "- status: {status}");
    let _ = writeln!(
        s,
        "- cost: {} candidate designs, {} Floquet (monodromy) evaluations, {:.1} s{}\n",
        o.candidates,
        o.floquet_evaluations,
        o.seconds,
        if o.failed_candidates > 0 {
            format!(
                "; {} candidates failed (first: {})",
                o.failed_candidates,
                o.first_failure.clone().unwrap_or_default()
            )
        } else {
            String::new()
        }
    );
    let _ = writeln!(s, "## Circuit before\n");
    branches_table(&mut s, &r.branches_before);
    let _ = writeln!(s, "\n## Circuit after\n");
    branches_table(&mut s, &r.branches_after);
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
    let criterion = r.provenance.settings.clone();
    let _ = writeln!(
        s,
        "\nCriterion: unstable when max|μ| > {}{}{}; tongues searched up to order {}.",
        criterion.instability_tolerance,
        if criterion.min_growth_rate > 0.0 {
            format!(", counted when the growth rate is at least {} 1/s", criterion.min_growth_rate)
        } else {
            String::new()
        },
        if criterion.min_tongue_width > 0.0 {
            format!(", tongues narrower than {} rad/s ignored", criterion.min_tongue_width)
        } else {
            String::new()
        },
        criterion.max_tongue_order
    );
    match spec.objective {
        Objective::WidestStableBand { .. } => {
            let _ = writeln!(s, "\n## Stable band around φ_op (rad/s; width in brackets)\n");
            let _ = writeln!(
                s,
                "The band is the interval around φ_op in which no tongue counts by the criterion: {}. It is the same function as `rotorshunt band` over the design's φ range, and the design's objective.\n",
                o.after_bands().first().map_or_else(String::new, |b| b.band.guarantee.clone())
            );
            let _ = writeln!(
                s,
                "| speed | before | after | after: bounded below by | after: bounded above by |\n|---|---|---|---|---|"
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
        Objective::ClearBands { .. } => {
            let _ = writeln!(s, "\n## Operating bands\n\n| band (rad/s) | clearance (rad/s) | tongues inside before | tongues inside after | unstable verification grid points after |\n|---|---|---|---|---|");
            for (i, b) in spec.objective.bands().iter().enumerate() {
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
                let _ =
                    writeln!(s, "\nThe linearised constraints at the final point have no solution inside the bounds.");
            }
        }
        Objective::MinPeakResponse { .. } => peak_section(&mut s, o),
    }
    constraints_section(&mut s, o);
    vibration_section(&mut s, o);
    let _ = writeln!(s, "\n## Verification of the tuned design\n");
    let _ = writeln!(
        s,
        "Independent of the optimiser: (1) the full catalogue of the tuned design over φ = {}..{} rad/s; (2) the reference (DSTM) Floquet point at the centre of every catalogued tongue near the band(s); (3) a grid chart over the band(s). Result: **{}**.\n",
        spec.phi_range.0,
        spec.phi_range.1,
        if o.verified { "passed" } else { "failed" }
    );
    for d in &o.after_speeds {
        let unstable_centres = d.centres.iter().filter(|c| c.inside && c.unstable).count();
        let _ = writeln!(
            s,
            "- Ω = {} rad/s: catalogue band {}; {} tongue centres checked by DSTM, {} inside the band(s) unstable; {}",
            d.speed,
            d.catalogue_band.map_or_else(|| "–".to_string(), |b| format!("{b:.2}")),
            d.centres.len(),
            unstable_centres,
            d.grids
                .iter()
                .map(|g| format!(
                    "grid {:.2} at {} rad/s: {} points, {} unstable",
                    g.window,
                    g.step,
                    g.points,
                    g.unstable.len()
                ))
                .collect::<Vec<_>>()
                .join("; ")
        );
        for f in &d.failures {
            let _ = writeln!(s, "  - failed: {f}");
        }
    }
    for (name, designs) in [("before", &o.before_speeds), ("after", &o.after_speeds)] {
        for d in designs.iter() {
            let _ = writeln!(s, "\n## Whirl frequencies {name}, Ω = {} rad/s\n", d.speed);
            let _ = writeln!(s, "| mode | rad/s |\n|---|---|");
            for w in &d.whirls {
                let _ = writeln!(s, "| {} | {:.2} |", w.tag, w.frequency);
            }
            let c = &d.catalogue;
            let _ = writeln!(
                s,
                "\n## Regions {name}, Ω = {} rad/s (φ = {}..{} rad/s, onset below β = {}, edges at β_op = {})\n",
                d.speed, c.range.lo, c.range.hi, c.beta_max, c.level
            );
            let _ = writeln!(
                s,
                "| region | k | start (rad/s) | onset β | left | right | width |\n|---|---|---|---|---|---|---|"
            );
            for g in &c.regions {
                let _ = writeln!(
                    s,
                    "| {} | {} | {:.2} | {:.4} | {} | {} | {} |",
                    g.label,
                    g.order,
                    g.start,
                    g.onset_beta,
                    opt(g.left, 2),
                    opt(g.right, 2),
                    opt(g.width, 2)
                );
            }
            for u in &c.unexplained {
                let _ = writeln!(
                    s,
                    "| (unexplained, guard lattice) | – | – | – | {:.2} | {:.2} | {:.2} |",
                    u.lo,
                    u.hi,
                    u.width()
                );
            }
        }
    }
    let _ = writeln!(s, "\n## Optimiser\n");
    match spec.objective {
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
    let digits = if o.peak_findings().is_some() { 4 } else { 2 };
    for st in &o.starts {
        let objective = if digits == 4 { format!("{:.4e}", st.objective) } else { format!("{:.2}", st.objective) };
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
    let figures: Vec<&String> = r.files.iter().filter(|f| f.ends_with(".png")).collect();
    if !figures.is_empty() {
        let _ = writeln!(s, "\n## Figures\n");
        for f in figures {
            let _ = writeln!(s, "![{}]({f})\n", figure_caption(f));
        }
    }
    let _ = writeln!(s, "\n## Files\n");
    for f in &r.files {
        let _ = writeln!(s, "- `{f}`");
    }
    s
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

/// The min-peak-response section: the peaks of the reference, classic, unconstrained and
/// tuned designs, the classic tuning, the price of the constraints and the convex steps.
fn peak_section(s: &mut String, o: &DesignOutcome) {
    let Some(f) = o.peak_findings() else { return };
    let vals = |v: &[f64]| v.iter().map(|x| format!("{x:.6e}")).collect::<Vec<_>>().join(", ");
    let _ = writeln!(s, "\n## Peak unbalance response\n");
    let _ = writeln!(s, "| design | values | peak (m) | at (rad/s) | constraints met |\n|---|---|---|---|---|");
    let mut rows = vec![("reference", &f.before), ("tuned", &f.after), ("unconstrained optimum", &f.unconstrained)];
    if let Some(c) = &f.classic_design {
        rows.push(("classic tuning", c));
    }
    for (name, d) in rows {
        let _ = writeln!(
            s,
            "| {name} | {} | {:.4e}{} | {:.2} | {} |",
            vals(&d.values),
            d.peak.amplitude,
            if d.peak.unbounded { " (unbounded)" } else { "" },
            d.peak.speed,
            if d.constraints.is_empty() { "–".to_string() } else { d.feasible.to_string() }
        );
    }
    if let Some(price) = f.price {
        let _ = writeln!(
            s,
            "\nPrice of the constraints in response: tuned peak − unconstrained peak = {:+.4e} m ({:+.2} %).",
            price.metres, price.percent
        );
    }
    if let Some(c) = &f.classic {
        let _ = writeln!(
            s,
            "\nClassic single-mode tuning of {} on branch {} (series R–L shunt, equal-peak optimum: ω_e = ω_open, Hagood & von Flotow 1991; r = √(3/2)·K, Thomas, Ducarne & Deü 2012): ω_open = {:.3} rad/s (branch removed), ω_short = {:.3} rad/s (branch with L = R = 0), K² = (ω_open² − ω_short²)/ω_short² = {:.5}; loop capacitance C = {:.5e} F; L_opt = 1/(ω_open²·C) = {:.5} H (tuning frequency by Eq. 4: {:.3} rad/s), R_opt = √(3/2)·K/(C·ω_short) = {:.4} Ω{}.",
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

/// The constraints judged afresh on the tuned design.
fn constraints_section(s: &mut String, o: &DesignOutcome) {
    if o.constraints_after.is_empty() {
        return;
    }
    let _ =
        writeln!(s, "\n## Constraints on the tuned design\n\n| constraint | value | limit | met |\n|---|---|---|---|");
    for c in &o.constraints_after {
        let _ = writeln!(s, "| {} | {:.6e} | {:e} | {} |", c.name, c.value, c.limit, c.met);
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
