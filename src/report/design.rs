//! The tuned-parameter report of a design run: the content (serialised as report.json)
//! and its Markdown rendering (report.md). Rendering only: no file I/O here.

use crate::analysis::regions::Catalogue;
use crate::design::evaluate::OperatingBand;
use crate::design::spec::Objective;
use crate::design::{DesignOutcome, Status};
use serde::Serialize;
use std::fmt::Write;

/// One branch of a circuit as a designer reads it.
#[derive(Debug, Clone, Serialize)]
pub struct BranchRow {
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

/// A whirl frequency.
#[derive(Debug, Clone, Serialize)]
pub struct WhirlRow {
    /// `f1`, `b1`, `fr1`, …
    pub tag: String,
    /// Frequency (rad/s).
    pub frequency: f64,
}

/// One design (before or after) at one speed.
#[derive(Debug, Clone, Serialize)]
pub struct DesignAtSpeed {
    /// Ω (rad/s).
    pub speed: f64,
    /// Lowest whirls.
    pub whirls: Vec<WhirlRow>,
    /// Region catalogue at β_op over the design's φ range.
    pub catalogue: Catalogue,
}

/// The whole report.
#[derive(Debug, Clone, Serialize)]
pub struct DesignReport {
    /// Tool, problem, input hash, overrides and settings.
    #[serde(flatten)]
    pub provenance: crate::commands::Provenance,
    /// Title of the problem.
    pub title: String,
    /// Circuit before.
    pub branches_before: Vec<BranchRow>,
    /// Circuit after.
    pub branches_after: Vec<BranchRow>,
    /// Whirls and regions before, per speed.
    pub before: Vec<DesignAtSpeed>,
    /// The same after.
    pub after: Vec<DesignAtSpeed>,
    /// The optimiser's outcome (bands, intrusions, starts, history, counts).
    pub outcome: DesignOutcome,
    /// Files written next to the report.
    pub files: Vec<String>,
}

fn opt(x: Option<f64>, digits: usize) -> String {
    x.map(|v| format!("{v:.digits$}")).unwrap_or_else(|| "–".into())
}

fn band_text(b: Option<[f64; 2]>) -> String {
    b.map(|b| format!("[{:.1}, {:.1}] ({:.1})", b[0], b[1], b[1] - b[0])).unwrap_or_else(|| "φ_op unstable".into())
}

fn branches_table(s: &mut String, rows: &[BranchRow]) {
    let _ = writeln!(s, "| branch | C_f (F) | L (H) | R (Ω) | tuning ω (rad/s) |\n|---|---|---|---|---|");
    for b in rows {
        let _ = writeln!(
            s,
            "| {} | {:.4e} | {:.4} | {:.3} | {:.2} |",
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
        Objective::WidestStableBand => {
            format!("widest stable band at β_op = {} containing φ_op = {} rad/s", spec.level, opt(spec.phi_op, 1))
        }
        Objective::ClearBands => {
            format!("clear {} operating band(s) at β_op = {} with the least change", spec.bands.len(), spec.level)
        }
    };
    let _ = writeln!(s, "- objective: {objective}; speeds {:?} rad/s", spec.speeds);
    let status = match o.status {
        Status::Improved => "**improved**: the tuned band is wider than the reference's (checked on a 1 rad/s grid)",
        Status::Unchanged => "**unchanged**: no start beat the reference design, which is kept",
        Status::Feasible => "**feasible**: every band is clear by its clearance (checked on a 1 rad/s grid)",
        Status::Infeasible => {
            "**infeasible**: no design inside the bounds clears every band; the violated bands are listed below"
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
    match spec.objective {
        Objective::WidestStableBand => {
            let _ = writeln!(s, "\n## Stable band around φ_op (rad/s; width in brackets)\n");
            let _ = writeln!(s, "| speed | before (march + bisection) | before (1 rad/s grid) | after (march + bisection) | after (1 rad/s grid) |\n|---|---|---|---|---|");
            for (k, b) in o.before_bands.iter().enumerate() {
                let a: &OperatingBand = &o.after_bands[k];
                let _ = writeln!(
                    s,
                    "| {:.0} | {} | {} | {} | {} |",
                    b.speed,
                    band_text(b.band),
                    band_text(o.before_verified[k].1),
                    band_text(a.band),
                    band_text(o.after_verified[k].1)
                );
            }
            // Regions of the catalogue inside a verified band are thinner than the 1 rad/s
            // grid the band is verified on: say so rather than leave them to the table.
            for (k, d) in r.after.iter().enumerate() {
                let Some(band) = o.after_verified.get(k).and_then(|v| v.1) else { continue };
                let thin: Vec<String> = d
                    .catalogue
                    .regions
                    .iter()
                    .filter_map(|g| Some((g, g.left?, g.right?)))
                    .filter(|(_, l, h)| *h > band[0] && *l < band[1])
                    .map(|(g, l, h)| format!("{} (k = {}) [{l:.2}, {h:.2}]", g.label, g.order))
                    .collect();
                if !thin.is_empty() {
                    let _ = writeln!(
                        s,
                        "\nAt Ω = {} rad/s the catalogue finds tongues thinner than the 1 rad/s verification grid inside the band after: {}.",
                        d.speed,
                        thin.join(", ")
                    );
                }
            }
        }
        Objective::ClearBands => {
            let _ = writeln!(s, "\n## Operating bands\n\n| band (rad/s) | clearance (rad/s) | regions inside before | regions inside after | unstable 1 rad/s grid points after |\n|---|---|---|---|---|");
            for (i, b) in spec.bands.iter().enumerate() {
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
                let fine = o.fine_unstable.iter().filter(|(_, p)| *p >= g.0 && *p <= g.1).count();
                let _ = writeln!(
                    s,
                    "| [{}, {}] | {} | {} | {} | {} |",
                    b.lo,
                    b.hi,
                    b.clearance,
                    names(&o.before_intrusions),
                    names(&o.after_intrusions),
                    fine
                );
            }
            if o.linear_infeasible {
                let _ =
                    writeln!(s, "\nThe linearised constraints at the final point have no solution inside the bounds.");
            }
        }
    }
    for (name, designs) in [("before", &r.before), ("after", &r.after)] {
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
                d.speed, c.range[0], c.range[1], c.beta_max, c.level
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
                    "| (unexplained, guard scan) | – | – | – | {:.2} | {:.2} | {:.2} |",
                    u.left,
                    u.right,
                    u.right - u.left
                );
            }
        }
    }
    let _ = writeln!(s, "\n## Optimiser\n");
    match spec.objective {
        Objective::WidestStableBand => {
            let _ = writeln!(s, "Nelder–Mead (argmin) from {} starts in parallel; objective = smallest band width over the speeds (rad/s).\n", o.starts.len());
            let _ = writeln!(s, "| start | initial | best | objective (rad/s) | evaluations | iterations | termination | width on 1 rad/s grid |\n|---|---|---|---|---|---|---|---|");
        }
        Objective::ClearBands => {
            let _ = writeln!(s, "Coarse global pass (objective = minus the total intrusion, rad/s), then sequential convex steps (clarabel QP) from the reference and from the best global point.\n");
            let _ = writeln!(s, "| point | values | | −intrusion (rad/s) | evaluations | iterations | stage | |\n|---|---|---|---|---|---|---|---|");
        }
    }
    let vals = |v: &[f64]| v.iter().map(|x| format!("{x:.5e}")).collect::<Vec<_>>().join(", ");
    for st in &o.starts {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {:.2} | {} | {} | {} | {} |",
            st.origin,
            vals(&st.initial),
            vals(&st.best),
            st.objective,
            st.evaluations,
            st.iterations,
            st.termination,
            opt(st.checked_width, 2)
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
    let _ = writeln!(s, "\n## Files\n");
    for f in &r.files {
        let _ = writeln!(s, "- `{f}`");
    }
    s
}
