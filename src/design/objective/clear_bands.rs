//! `clear-bands`: keep every operating band clear of instability at β_op by its
//! clearance with the least weighted change to the reference design, by sequential
//! convex programming ([`crate::design::optimise`]).

use super::{AnyObjective, FileKeys, KeyRefusal, Objective, ObjectiveKeys, ObjectiveKind};
use crate::analysis::Interval;
use crate::design::content::band_window;
use crate::design::evaluate::Intrusion;
use crate::design::optimise::{self, Context, FindingsKind};
use crate::design::pareto::{NoTradeOff, TradeOff};
use crate::design::spec::{Band, DesignSpec};
use crate::design::text::speed_text;
use crate::design::verify::DesignAtSpeed;
use crate::design::{DesignError, DesignOutcome, Status};
use std::fmt::Write;

/// The objective's kind: `design.objective = "clear-bands"`.
pub const KIND: ObjectiveKind = ObjectiveKind::new("clear-bands", from_file, from_json).judging_tolerances();

/// Keep every operating band clear of instability at β_op by its clearance, with the
/// least weighted change to the reference design.
#[derive(Debug, Clone, PartialEq)]
pub struct ClearBands {
    /// The operating bands (at least one).
    pub bands: Vec<Band>,
}

/// Needs `[[design.bands]]`, its own; `design.phi_op` only for a band-width constraint.
fn from_file(k: &FileKeys<'_>) -> Result<AnyObjective, KeyRefusal> {
    if k.phi_op.is_some() && !k.min_band_width {
        return Err(KeyRefusal::new(
            "design.phi_op",
            "`phi_op` belongs to the widest-stable-band objective, not clear-bands",
        ));
    }
    if k.bands.is_empty() {
        return Err(KeyRefusal::new("design.bands", "the clear-bands objective needs [[design.bands]]"));
    }
    Ok(AnyObjective::new(ClearBands { bands: k.bands.to_vec() }))
}

fn from_json(k: &ObjectiveKeys<'_>) -> Result<AnyObjective, &'static str> {
    Ok(AnyObjective::new(ClearBands { bands: k.bands.unwrap_or(&[]).to_vec() }))
}

impl Objective for ClearBands {
    fn kind(&self) -> ObjectiveKind {
        KIND
    }

    fn keys(&self) -> ObjectiveKeys<'_> {
        ObjectiveKeys { bands: Some(&self.bands), ..Default::default() }
    }

    /// The global pass (4 per start and the reference), 2·(2·variables + 1) per convex
    /// step, and the result.
    fn most_candidates(&self, spec: &DesignSpec) -> usize {
        let (starts, iterations, variables) = (spec.starts, spec.max_iterations, spec.variables.len());
        4 * starts + 1 + 2 * iterations * (2 * variables + 1) + 1 + crate::design::optimise::slice_points(variables)
    }

    fn optimise(&self, ctx: &Context<'_>, out: &mut DesignOutcome) -> Result<(), DesignError> {
        optimise::clear_bands(ctx, out)
    }

    fn findings(&self) -> FindingsKind {
        FindingsKind::Intrusions
    }

    fn trade_off(&self, _spec: &DesignSpec) -> Result<TradeOff, NoTradeOff> {
        Err(NoTradeOff {
            key: "design.objective".into(),
            reason: "clear-bands has a single objective (the least change that clears the bands), so there is no trade-off: a front trades the peak unbalance response against the stable band around phi_op (min-peak-response with phi_op and constraints.min_band_width, or widest-stable-band with [design.response])".into(),
        })
    }

    /// The operating bands widened by their clearances.
    fn verified_windows(
        &self,
        spec: &DesignSpec,
        _band: Option<Interval>,
        _d: &mut DesignAtSpeed,
    ) -> (Vec<Interval>, usize) {
        (spec.kept_clear().iter().map(|b| b.guarded()).collect(), 0)
    }

    /// The operating bands widened by their clearances and a quarter of their span each
    /// side.
    fn chart_window(&self, spec: &DesignSpec) -> (f64, f64) {
        band_window(spec.kept_clear())
    }

    fn question(&self, spec: &DesignSpec, variables: &str, speeds: &str, _constrained: bool) -> String {
        format!(
            "Which {variables}, changed as little as possible, keep every instability region at β_op = {} out of the operating band(s) {} at {speeds}?",
            spec.level,
            self.bands
                .iter()
                .map(|b| format!("[{}, {}] rad/s ± {} rad/s", b.lo, b.hi, b.clearance))
                .collect::<Vec<_>>()
                .join(", ")
        )
    }

    /// Each band with the tongues inside it before and after, and the unstable points of
    /// its verification grid.
    fn page_one(&self, s: &mut String, o: &DesignOutcome) {
        let _ = writeln!(s, "\nOperating bands at β_op = {} (rad/s):\n\n| band | clearance | tongues inside before | after | unstable grid points after |\n|---|---|---|---|---|", o.spec.level);
        for (i, b) in self.bands.iter().enumerate() {
            let names = |v: &[Intrusion]| {
                let l: Vec<String> = v
                    .iter()
                    .filter(|x| x.band == i)
                    .map(|x| match &x.build {
                        Some(b) => format!("{} [{:.1}, {:.1}] (built `{b}`)", x.label, x.left, x.right),
                        None => format!("{} [{:.1}, {:.1}]", x.label, x.left, x.right),
                    })
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
        if let (Some(t), Some(p)) =
            (&o.spec.tolerances, o.verification.parts.iter().find(|p| p.part == "tolerance-bands"))
        {
            let verdict = if p.failed == 0 {
                format!("every band clear in all {} builds", p.checked)
            } else {
                format!(
                    "a tongue reaches into a band in {} of {} builds (verification, `tolerance-bands`)",
                    p.failed, p.checked
                )
            };
            let _ = writeln!(
                s,
                "\nAs built ({}): {verdict}: the centre and {} corners of the tolerance box, which the optimiser kept clear, and {} Monte Carlo samples.",
                t.text(),
                t.corners().len() - 1,
                t.samples
            );
        }
    }

    /// The tongues inside the bands before and after, and each violation of an infeasible
    /// design.
    fn summary(&self, o: &DesignOutcome) -> String {
        let mut s = format!(
            "\nbands: {} tongue(s) inside before, {} after",
            o.before_intrusions().len(),
            o.after_intrusions().len()
        );
        if o.status == Status::Infeasible {
            for it in o.after_intrusions() {
                let Some(b) = self.bands.get(it.band) else { continue };
                s += &format!(
                    "\nviolated: band [{}, {}] (clearance {}) at {}: {} at [{:.2}, {:.2}] rad/s",
                    b.lo,
                    b.hi,
                    b.clearance,
                    speed_text(o.spec.speed_unit, it.speed),
                    it.label,
                    it.left,
                    it.right
                );
                if let Some(build) = &it.build {
                    s += &format!(" (built `{build}`)");
                }
            }
        }
        s
    }

    fn optimiser_method(&self, _starts: usize) -> String {
        "Coarse global pass (objective = minus the total intrusion, rad/s), then sequential convex steps (clarabel QP) from the reference and from the best global point.\n\n| point | values | | −intrusion (rad/s) | evaluations | iterations | stage |\n|---|---|---|---|---|---|---|\n".into()
    }

    fn history_axes(&self) -> (&'static str, &'static str) {
        ("convex step", "total intrusion into the bands (rad/s)")
    }

    /// The run from the reference, then the one from the best global point.
    fn history_series(&self, k: usize) -> Option<&'static str> {
        Some(if k == 0 { "from the reference" } else { "from the best global point" })
    }
}
