//! `widest-stable-band`: maximise the smallest width over the speeds of the stable band
//! at β_op around φ_op, by multi-start Nelder–Mead ([`crate::design::optimise`]).

use super::{AnyObjective, CostAt, FileKeys, KeyRefusal, Objective, ObjectiveKeys, ObjectiveKind};
use crate::analysis::cost::{self, Estimate, DESIGN_BAND_EVALUATIONS};
use crate::analysis::Interval;
use crate::design::content::chart_window;
use crate::design::optimise::{self, Context, FindingsKind};
use crate::design::pareto::{NoTradeOff, TradeOff};
use crate::design::spec::DesignSpec;
use crate::design::text::{band_text, bound_text, speed_cell, speed_header, speed_text};
use crate::design::verify::{DesignAtSpeed, SAME_EDGE};
use crate::design::{DesignError, DesignOutcome};
use std::fmt::Write;

/// The objective's kind: `design.objective = "widest-stable-band"`.
pub const KIND: ObjectiveKind = ObjectiveKind::new("widest-stable-band", from_file, from_json).judging_tolerances();

/// Maximise the width of the stable band at β_op containing φ_op (the smallest over the
/// speeds).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WidestStableBand {
    /// The operating frequency φ_op (rad/s) whose stable band is widened.
    pub phi_op: f64,
}

/// Needs `design.phi_op`; the `[[design.bands]]` are constraints.
fn from_file(k: &FileKeys<'_>) -> Result<AnyObjective, KeyRefusal> {
    let Some(phi_op) = k.phi_op else {
        return Err(KeyRefusal::new("design.phi_op", "the widest-stable-band objective needs `phi_op` (rad/s)"));
    };
    Ok(AnyObjective::new(WidestStableBand { phi_op }))
}

fn from_json(k: &ObjectiveKeys<'_>) -> Result<AnyObjective, &'static str> {
    Ok(AnyObjective::new(WidestStableBand { phi_op: k.phi_op.ok_or("phi_op")? }))
}

impl Objective for WidestStableBand {
    fn kind(&self) -> ObjectiveKind {
        KIND
    }

    fn keys(&self) -> ObjectiveKeys<'_> {
        ObjectiveKeys { phi_op: Some(self.phi_op), ..Default::default() }
    }

    /// The map over the box (when the starts leave room for its basins, beyond the
    /// reference and the physics seed), then the simplex and 2 per iteration, per start
    /// (one more start per variable beyond three), then each start's final point and the
    /// reference.
    fn most_candidates(&self, spec: &DesignSpec) -> usize {
        let (iterations, variables) = (spec.max_iterations, spec.variables.len());
        use crate::design::optimise::{extra_starts, map_points};
        // At most: the map is made when the physics seed leaves room for a basin.
        let mapped = spec.starts > 1 && spec.map;
        let map = if mapped { map_points(variables) } else { 0 };
        let starts = spec.starts.max(1) + if mapped { extra_starts(variables) } else { 0 };
        map + starts * (2 * iterations + variables + 1) + starts + 1 + crate::design::optimise::slice_points(variables)
    }

    fn optimise(&self, ctx: &Context<'_>, out: &mut DesignOutcome) -> Result<(), DesignError> {
        optimise::widest_band(ctx, out, self.phi_op)
    }

    fn findings(&self) -> FindingsKind {
        FindingsKind::Bands
    }

    /// The band around φ_op against the peak of a `[design.response]`.
    fn trade_off(&self, spec: &DesignSpec) -> Result<TradeOff, NoTradeOff> {
        match spec.response() {
            Some(r) => Ok(TradeOff { phi_op: self.phi_op, response: r.clone() }),
            None => Err(NoTradeOff {
                key: "design.objective".into(),
                reason: "widest-stable-band without [design.response] has no trade-off: add [design.response] (node, speeds), whose peak the front lowers".into(),
            }),
        }
    }

    /// The optimiser's band, which the catalogue's and the labelled band must equal, and
    /// the band constraints' bands widened by their clearances.
    fn verified_windows(
        &self,
        spec: &DesignSpec,
        band: Option<Interval>,
        d: &mut DesignAtSpeed,
    ) -> (Vec<Interval>, usize) {
        let b = band;
        if d.band.as_ref().map(|x| x.band) != Some(b) {
            d.failures.push(format!(
                "the band with labelled seeds ({:?}) differs from the optimiser's ({b:?})",
                d.band.as_ref().and_then(|x| x.band)
            ));
        }
        if let (Some(b), Some(cb)) = (b, d.catalogue_band) {
            if (b.lo - cb.lo).abs() > SAME_EDGE || (b.hi - cb.hi).abs() > SAME_EDGE {
                d.failures.push(format!("the catalogue's stable band {cb:.3} differs from the band {b:.3}"));
            }
        } else if b.is_some() != d.catalogue_band.is_some() {
            d.failures.push(format!(
                "the catalogue's stable band ({:?}) and the band ({:?}) disagree on whether phi_op is stable",
                d.catalogue_band, b
            ));
        }
        let mut w: Vec<Interval> = b.into_iter().collect();
        w.extend(spec.constraints.bands.iter().map(|b| b.guarded()));
        (w, 2)
    }

    /// Half to 1.5 times φ_op.
    fn chart_window(&self, _spec: &DesignSpec) -> (f64, f64) {
        (self.phi_op * 0.5, self.phi_op * 1.5)
    }

    /// The band search around φ_op.
    fn candidate_cost(&self, spec: &DesignSpec, at: &CostAt<'_>) -> Estimate {
        cost::points(at.point, DESIGN_BAND_EVALUATIONS, (0.5 * self.phi_op).max(spec.range().lo), spec.level)
    }

    /// The nominal build at every speed, over a speed range with the worst speed's
    /// refinements (4 golden-section steps); each corner of
    /// `[design.tolerances]` at every speed, or over a range at the refined worst speed
    /// alone (`optimise::Context::judged`).
    fn searches_per_candidate(&self, spec: &DesignSpec) -> f64 {
        let speeds = spec.speeds.len().max(1);
        let corners = spec.builds() - 1;
        let (nominal, each_corner) = match spec.speed_range {
            Some(_) => (speeds + crate::design::robust::SPEED_REFINEMENTS, 1),
            None => (speeds, speeds),
        };
        (nominal + corners * each_corner) as f64
    }

    /// The band, taken as the charts' window around φ_op.
    fn checked_windows(&self, spec: &DesignSpec) -> Vec<Interval> {
        vec![chart_window(spec)]
    }

    fn question(&self, spec: &DesignSpec, variables: &str, speeds: &str, _constrained: bool) -> String {
        format!(
            "Which {variables} (inside their bounds) give the widest stable band at β_op = {} around the load frequency φ_op = {} rad/s, at {speeds}?",
            spec.level, self.phi_op
        )
    }

    /// The band before and after at each speed, with what bounds it after; the speed range
    /// and tolerance checks; the tongues the criterion ignored.
    fn page_one(&self, s: &mut String, o: &DesignOutcome) {
        let unit = o.spec.speed_unit;
        let _ = writeln!(
            s,
            "\nStable band at β_op = {} around φ_op (rad/s; width in brackets):\n\n| {} | before | after | after: bounded below by | above by |\n|---|---|---|---|---|",
            o.spec.level,
            speed_header(unit)
        );
        for (b, a) in o.before_bands().iter().zip(o.after_bands()) {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} |",
                speed_cell(unit, b.speed),
                band_text(&b.band),
                band_text(&a.band),
                bound_text(&a.band.left),
                bound_text(&a.band.right)
            );
        }
        if let Some(r) = &o.speed_check {
            let _ = writeln!(
                s,
                "\nSpeed range {}.",
                crate::design::robust::speed_range_text(o.speed_check_before.as_ref(), r)
            );
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
                    speed_text(unit, a.speed),
                    t.label(),
                    t.extent.lo,
                    t.extent.hi
                );
            }
        }
    }

    /// The band before and after at each speed, its guarantee, the speed range and the
    /// tolerance checks.
    fn summary(&self, o: &DesignOutcome) -> String {
        let spec = &o.spec;
        let at = |w: f64| speed_text(spec.speed_unit, w);
        let w = |v: &[crate::design::evaluate::OperatingBand]| {
            v.iter()
                .map(|b| match b.band.band {
                    Some(x) => format!("[{:.2}, {:.2}] ({:.2} rad/s) at {}", x.lo, x.hi, x.width(), at(b.speed)),
                    None => format!("none (φ_op unstable) at {}", at(b.speed)),
                })
                .collect::<Vec<_>>()
                .join("; ")
        };
        let mut s = format!(
            "\nstable band at beta = {} around phi_op = {} rad/s: before {}; after {}",
            spec.level,
            self.phi_op,
            w(o.before_bands()),
            w(o.after_bands())
        );
        if let Some(b) = o.after_bands().first() {
            s += &format!("\nguarantee: {}", b.band.guarantee);
        }
        if let Some(r) = &o.speed_check {
            s +=
                &format!("\nspeed range {}", crate::design::robust::speed_range_text(o.speed_check_before.as_ref(), r));
        }
        if let Some(r) = &o.robustness {
            s += &format!("\nas built ({}): {}", r.tolerances.text(), crate::design::robust::guaranteed_text(r));
        }
        s
    }

    fn optimiser_method(&self, starts: usize) -> String {
        format!(
            "Nelder–Mead (argmin) from {starts} starts in parallel; objective = smallest band width over the speeds (rad/s).\n\n| start | initial | best | objective (rad/s) | evaluations | iterations | termination |\n|---|---|---|---|---|---|---|\n"
        )
    }

    fn history_axes(&self) -> (&'static str, &'static str) {
        ("candidate evaluations of the start", "smallest band width over the speeds (rad/s)")
    }
}
