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
    let objective = match spec.objective {
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
    }
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
    }
    let vals = |v: &[f64]| v.iter().map(|x| format!("{x:.5e}")).collect::<Vec<_>>().join(", ");
    for st in &o.starts {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {:.2} | {} | {} | {} |",
            st.origin,
            vals(&st.initial),
            vals(&st.best),
            st.objective,
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
        other => other,
    };
    format!("{what}{speed}")
}
