//! `min-peak-response`: minimise the largest unbalance amplitude at a shaft node over a
//! speed range, with the constraints as an exact penalty, then clarabel steps on them
//! ([`crate::design::optimise`]).

use super::{AnyObjective, FileKeys, KeyRefusal, Objective, ObjectiveKeys, ObjectiveKind};
use crate::design::optimise::{self, Context, FindingsKind, JudgedDesign};
use crate::design::pareto::{NoTradeOff, TradeOff};
use crate::design::spec::{DesignSpec, Response};
use crate::design::vibration::PeakValue;
use crate::design::{DesignError, DesignOutcome};
use std::fmt::Write;

/// The objective's kind: `design.objective = "min-peak-response"`.
pub const KIND: ObjectiveKind = ObjectiveKind::new("min-peak-response", from_file, from_json).judging_tolerances();

/// Minimise the largest unbalance amplitude (m) at a shaft node over a speed range (the
/// steady-state response of [`crate::analysis::unbalance`], peaks refined).
#[derive(Debug, Clone, PartialEq)]
pub struct MinPeakResponse {
    /// Where and over which speeds the response is minimised.
    pub response: Response,
}

/// Needs `[design.response]`, its own; `design.phi_op` only for a band-width constraint;
/// the `[[design.bands]]` are constraints.
fn from_file(k: &FileKeys<'_>) -> Result<AnyObjective, KeyRefusal> {
    if k.phi_op.is_some() && !k.min_band_width {
        // `phi_op` is the band-width constraint's: the missing key is that constraint.
        return Err(KeyRefusal::new(
            "design.constraints.min_band_width",
            "`design.phi_op` of min-peak-response belongs to a band-width constraint: add `min_band_width` (rad/s) or drop `phi_op`",
        ));
    }
    let Some(response) = k.response else {
        return Err(KeyRefusal::new(
            "design.response",
            "the min-peak-response objective needs [design.response] (node, speeds)",
        ));
    };
    Ok(AnyObjective::new(MinPeakResponse { response: response.clone() }))
}

fn from_json(k: &ObjectiveKeys<'_>) -> Result<AnyObjective, &'static str> {
    Ok(AnyObjective::new(MinPeakResponse { response: k.response.ok_or("response")?.clone() }))
}

impl Objective for MinPeakResponse {
    fn kind(&self) -> ObjectiveKind {
        KIND
    }

    fn keys(&self) -> ObjectiveKeys<'_> {
        ObjectiveKeys { response: Some(&self.response), ..Default::default() }
    }

    /// The reference and classic designs; the map's points (`design.map`); each start's
    /// simplex and 2 per iteration, twice (without and with constraints); the convex
    /// steps' differences and trials (clear-bands' linearisation of the bands included).
    fn most_candidates(&self, spec: &DesignSpec) -> usize {
        let (starts, iterations, variables) = (spec.starts, spec.max_iterations, spec.variables.len());
        let runs = if spec.constraints.is_empty() { 1 } else { 2 };
        let starts = starts.max(3);
        let map = if spec.map { crate::design::optimise::map_points(variables) } else { 0 };
        let slices = if spec.map { crate::design::optimise::slice_points(variables) } else { 0 };
        2 + map + runs * starts * (2 * iterations + variables + 1) + 8 * (4 * variables + 1) + slices
    }

    fn optimise(&self, ctx: &Context<'_>, out: &mut DesignOutcome) -> Result<(), DesignError> {
        optimise::min_peak(ctx, out)
    }

    fn findings(&self) -> FindingsKind {
        FindingsKind::Peak
    }

    /// The peak against the band of a band-width constraint.
    fn trade_off(&self, spec: &DesignSpec) -> Result<TradeOff, NoTradeOff> {
        match spec.constraints.min_band_width {
            Some(b) => Ok(TradeOff { phi_op: b.phi_op, response: self.response.clone() }),
            None => Err(NoTradeOff {
                key: "design.objective".into(),
                reason: "min-peak-response without a band around phi_op has no trade-off: add phi_op and constraints.min_band_width (rad/s), whose band the front widens".into(),
            }),
        }
    }

    fn question(&self, spec: &DesignSpec, variables: &str, speeds: &str, constrained: bool) -> String {
        let r = &self.response;
        format!(
            "Which {variables} give the smallest peak unbalance response at node {} over the rotating speeds {}{}?",
            r.node,
            spec.speed_unit.range(r.speeds.lo, r.speeds.hi),
            if constrained {
                format!(", with the stability constraints below met at β_op = {} and {speeds}", spec.level)
            } else {
                String::new()
            }
        )
    }

    /// The peaks of the open circuit, the reference, classic, unconstrained and tuned
    /// designs in one table (the baselines' amplification factors and the tuned peak
    /// relative to each), and the price of the constraints.
    fn page_one(&self, s: &mut String, o: &DesignOutcome) {
        let Some(f) = o.peak_findings() else { return };
        let _ = writeln!(
            s,
            "\nPeak unbalance response (m), each by the same response computation:\n\n| design | peak (m) | at (rad/s) | amplification factor (−) | tuned peak vs it | constraints met |\n|---|---|---|---|---|---|"
        );
        let baseline = |name: &str| f.baselines.iter().find(|b| b.design == name);
        let tuned = f.after.peak.amplitude;
        let af = |name: &str| {
            baseline(name).map_or("–".to_string(), |b| {
                b.amplification_factor.map_or("– (no half-power band in the range)".to_string(), |a| {
                    format!("{a:.1}{}", crate::analysis::unbalance::split_note(b.split_pair))
                })
            })
        };
        let row = |s: &mut String, name: &str, peak: &PeakValue, af: String, met: String| {
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
        let met = |d: &JudgedDesign| {
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
        if let Some(a) = &f.as_built {
            let worst = |d: &JudgedDesign| {
                d.worst_corner
                    .as_ref()
                    .map_or("–".to_string(), |w| format!("`{}` {:.4e} m", w.build, w.peak.amplitude))
            };
            let _ = writeln!(
                s,
                "\nAs built ({}): the worst corner of the tuned design {} (the optimiser minimised it), of the unconstrained optimum {}; the worst of the centre, {} corners and {} samples {:.4e} m (`{}`).",
                a.tolerances.text(),
                worst(&f.after),
                worst(&f.unconstrained),
                a.corners.len().saturating_sub(1),
                a.samples,
                a.worst.peak.amplitude,
                a.worst.build
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

    fn optimiser_method(&self, starts: usize) -> String {
        format!(
            "Nelder–Mead (argmin) on ln(peak) from {starts} starts in parallel, first without constraints, then with them as an exact penalty; then sequential convex steps (clarabel QP) on the linearised constraints. Objective column: the start's best peak (m).\n\n| start | initial | best | peak (m) | evaluations | iterations | termination |\n|---|---|---|---|---|---|---|\n"
        )
    }

    fn history_axes(&self) -> (&'static str, &'static str) {
        ("candidate evaluations of the start", "peak response, with the constraints' penalty (m)")
    }
}
