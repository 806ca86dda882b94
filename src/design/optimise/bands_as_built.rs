//! The clear-bands design as built (`[design.tolerances]`): the tongues at β_op at the
//! centre and every corner of the tolerance box, which the optimiser keeps out of the
//! widened bands ([`crate::design::evaluate::intrusions_as_built`]), found again, and at
//! the box's Monte Carlo samples, which the corners need not bound; each build on the
//! model rebuilt with the parts' factors under the design's P_cr.

use super::*;
use crate::design::tolerance::{Perturbation, Tolerances};

/// The tongues of one build that reach into a widened band, in words (`fr1+b1/2 at
/// [1180.2, 1190.4] rad/s in band [1150, 1210] ± 5 at 2000 rad/s`).
fn inside(built: &Candidate, ev: &EvalContext<'_>) -> Result<Vec<String>, DesignError> {
    let bands = ev.spec.kept_clear();
    Ok(intrusions(built, ev)?
        .into_iter()
        .filter(|it| it.inside)
        .map(|it| {
            let b = &bands[it.band];
            format!(
                "{} at [{:.2}, {:.2}] rad/s in band [{}, {}] ± {} rad/s at Ω = {} rad/s",
                it.label, it.left, it.right, b.lo, b.hi, b.clearance, it.speed
            )
        })
        .collect())
}

/// The tuned clear-bands design `tuned` over the box `t`: the verification part
/// `tolerance-bands`, which fails when a tongue reaches into a widened band in any build (the
/// first such build named), and the evaluations it made. The builds run in parallel (the
/// outermost loop); `tick` once per build.
pub(crate) fn check(
    tuned: &Candidate,
    spec: &DesignSpec,
    t: &Tolerances,
    regions: &RegionSettings,
    tick: &(dyn Fn() + Sync),
) -> Result<(VerificationPart, usize), DesignError> {
    let count = Counter::default();
    let ev = EvalContext { spec, regions, count: &count };
    let builds: Vec<Perturbation> = t.corners().into_iter().chain(t.draw()).collect();
    let found: Vec<Vec<String>> = builds
        .par_iter()
        .map(|p| {
            let found = inside(&tuned.perturbed(spec, p)?, &ev);
            tick();
            found
        })
        .collect::<Result<_, DesignError>>()?;
    let failing: Vec<(&Perturbation, &Vec<String>)> =
        builds.iter().zip(&found).filter(|(_, f)| !f.is_empty()).collect();
    let corners = t.corners().len() - 1;
    let mut summary = format!(
        "the tuned design built at the centre and {corners} corners of the tolerance box ({}) and at {} Monte Carlo samples: ",
        t.text(),
        t.samples
    );
    match failing.first() {
        None => {
            summary +=
                &format!("no counted tongue at β_op reaches into a widened band in any of the {} builds", builds.len())
        }
        Some((p, f)) => {
            summary += &format!(
                "a counted tongue reaches into a widened band in {} of the {} builds, first `{}`: {}",
                failing.len(),
                builds.len(),
                p.name,
                f.join("; ")
            )
        }
    }
    let part = VerificationPart::of("tolerance-bands", builds.len(), failing.len(), summary, "");
    Ok((part, count.get()))
}
