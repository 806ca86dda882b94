//! The verification of a design run, from scratch: the reference and the tuned design
//! rebuilt, their full catalogues, the checks on the tuned one part by part, the
//! unbalance response of both, and the status those decide.

use super::*;

/// Verify `out` (an optimised outcome on the basis of `base`): its speeds, verification
/// parts, vibration report, costs and status.
pub(super) fn verify_outcome(
    base: &Machine,
    spec: &DesignSpec,
    out: &mut DesignOutcome,
    progress: &dyn Progress,
) -> Result<(), DesignError> {
    let regions = base.regions.clone();
    // Verification, from scratch: the reference and the tuned design rebuilt, their full
    // catalogues, and the checks on the tuned one.
    let checked = Instant::now();
    progress.phase("verification", 0);
    let count = Counter::default();
    let ev = EvalContext { spec, regions: &regions, count: &count };
    let reference = Candidate::new(base, spec, &out.before)?;
    let tuned = Candidate::new(base, spec, &out.after)?;
    out.before_speeds = describe(&reference, spec, &regions, progress)?;
    out.after_speeds = describe(&tuned, spec, &regions, progress)?;
    count.add(out.before_speeds.iter().chain(&out.after_speeds).map(|d| d.catalogue.evaluations).sum());
    let mut after_speeds = std::mem::take(&mut out.after_speeds);
    let mut parts = verify(&tuned, spec, out.after_bands(), &mut after_speeds, &count, progress);
    out.after_speeds = after_speeds;
    parts.push(operating_point_part(spec, &out.after_speeds));
    // The tuned design on a basis twice as large: its band and catalogues again.
    if spec.refined_check {
        let bands: Vec<_> = out.after_speeds.iter().map(|d| d.band.clone()).collect();
        out.refined = crate::design::sizing::refined_check(&tuned, &ev, &bands, progress)?;
        parts.push(refined_part(&out.refined));
    } else {
        let why = "switched off (design.refined_check = false): the answer is not checked on a larger basis";
        parts.push(VerificationPart::of("refined-basis", 0, 0, String::new(), why));
    }
    match &mut out.findings {
        // Intrusions named after the full model's whirls: the catalogue's region with the
        // same edges (the lattice-refined edges are the same numbers).
        Findings::ClearBands { before, after, .. } => {
            for (ints, speeds) in [(before, &out.before_speeds), (after, &out.after_speeds)] {
                // A corner's tongues (`[design.tolerances]`) keep their own labels: the
                // catalogue is the design's as designed.
                for it in ints.iter_mut().filter(|it| it.build.is_none()) {
                    let Some(d) = speeds.iter().find(|d| d.speed == it.speed) else { continue };
                    let same =
                        |r: &&crate::analysis::regions::Region| r.left == Some(it.left) && r.right == Some(it.right);
                    if let Some(r) = d.catalogue.regions.iter().filter(same).min_by_key(|r| r.order) {
                        it.label = format!("{}/{}", r.label, r.order);
                    }
                }
            }
        }
        Findings::MinPeak(_) => {}
        // The bands with the full model's labels (the same numbers, checked by `verify`).
        Findings::WidestBand { before, after } => {
            for (bands, speeds) in [(before, &out.before_speeds), (after, &out.after_speeds)] {
                for (b, d) in bands.iter_mut().zip(speeds) {
                    if let Some(l) = d.band.as_ref().filter(|l| l.band == b.band.band) {
                        b.band = l.clone();
                    }
                }
            }
        }
    }
    // The constraints, judged afresh on the tuned design.
    if !spec.constraints.is_empty() {
        let peak = match spec.response() {
            Some(r) => Some(crate::design::vibration::peak_of(&tuned.rotor, r)?),
            None => None,
        };
        out.constraints_after = crate::design::vibration::check_constraints(&tuned, &ev, peak)?;
        for c in out.constraints_after.iter().filter(|c| !c.met) {
            let message = format!("constraint {} not met: {:e}", c.name, c.value);
            if let Some(d) = out.after_speeds.first_mut() {
                d.failures.push(message);
            }
        }
        let failed = out.constraints_after.iter().filter(|c| !c.met).count();
        let names: Vec<String> = out
            .constraints_after
            .iter()
            .map(|c| format!("{} ({:.6e}: {})", c.name, c.value, if c.met { "met" } else { "NOT met" }))
            .collect();
        parts.push(VerificationPart::of(
            "constraints",
            out.constraints_after.len(),
            failed,
            format!(
                "{} constraint(s) judged afresh on the rebuilt tuned design (bands by the same search as `rotorshunt band`), {failed} not met: {}",
                out.constraints_after.len(),
                names.join("; ")
            ),
            "the constraint list judged empty",
        ));
    }
    // The min-peak design's peak found again on a finer grid by another refinement.
    let mut recheck = None;
    if let (Some(r), Some(f)) = (spec.response(), out.peak_findings()) {
        let optimiser = f.after.peak;
        let (again, points) = crate::design::vibration::peak_recheck(&tuned.rotor, r, PEAK_GRID_FACTOR)?;
        let relative_difference = (again.amplitude - optimiser.amplitude).abs() / optimiser.amplitude.abs();
        let agree = relative_difference <= PEAK_AGREEMENT;
        parts.push(VerificationPart::of(
            "peak",
            1,
            usize::from(!agree),
            format!(
                "the tuned design's peak at node {} over {}..{} rad/s found again on {points} speeds ({PEAK_GRID_FACTOR}× the optimiser's {}), every local maximum refined by parabolic steps: {:.6e} m at {:.3} rad/s against the optimiser's {:.6e} m at {:.3} rad/s, {:.4} % apart (at most {} %)",
                r.node,
                r.speeds.lo,
                r.speeds.hi,
                r.points,
                again.amplitude,
                again.speed,
                optimiser.amplitude,
                optimiser.speed,
                100.0 * relative_difference,
                100.0 * PEAK_AGREEMENT
            ),
            "no peak to recheck",
        ));
        if !agree {
            if let Some(d) = out.after_speeds.first_mut() {
                d.failures.push(format!(
                    "the peak found again ({:.6e} m) differs from the optimiser's ({:.6e} m) by {:.3} %",
                    again.amplitude,
                    optimiser.amplitude,
                    100.0 * relative_difference
                ));
            }
        }
        recheck = Some(PeakRecheck { optimiser, recheck: again, points, relative_difference });
    }
    // The tuned design as built: every corner of the tolerance box and Monte Carlo samples.
    if let (Some(t), Some(phi_op)) = (&spec.tolerances, spec.phi_op()) {
        progress.extend((t.corners().len() + t.samples) as u64);
        let r = robust::check(&tuned, spec, t, phi_op, &regions, &|| progress.advance(1))?;
        count.add(r.evaluations);
        parts.push(VerificationPart::of("tolerances", r.checked(), r.failed(), robust::summary(&r, phi_op), ""));
        out.robustness = Some(r);
    }
    // The min-peak design's peak as built: every corner and sample of the tolerance box.
    if let (Some(t), Some(r)) = (&spec.tolerances, spec.response()) {
        if let Findings::MinPeak(f) = &mut out.findings {
            progress.extend((t.corners().len() + t.samples) as u64);
            let optimiser = f.after.worst_corner.as_ref();
            let max_peak = spec.constraints.max_peak;
            let (as_built, part) = peak_as_built::check(&tuned, t, r, optimiser, max_peak, &|| progress.advance(1))?;
            parts.push(part);
            f.as_built = Some(as_built);
        }
    }
    // The clear-bands design as built: the tongues of every corner and sample of the box.
    if let (Some(t), Findings::ClearBands { .. }) = (&spec.tolerances, &out.findings) {
        progress.extend((t.corners().len() + t.samples) as u64);
        let (part, evaluations) = bands_as_built::check(&tuned, spec, t, &regions, &|| progress.advance(1))?;
        count.add(evaluations);
        parts.push(part);
    }
    // The tuned design over its speed range, on a grid finer than the optimiser's.
    if let Some(range) = spec.speed_range {
        match spec.phi_op() {
            Some(phi_op) => {
                progress.extend(crate::design::spec::VERIFY_SPEEDS as u64);
                let r = robust::speed_check(&tuned, spec, range, phi_op, &regions, &|| progress.advance(1))?;
                count.add(r.evaluations);
                let summary = robust::speed_summary(&r, phi_op);
                parts.push(VerificationPart::of("speeds", r.bands.len(), r.failing.len(), summary, ""));
                out.speed_check = Some(r);
                // The reference on the same grid, for the report: where it failed.
                let before = robust::speed_check(&reference, spec, range, phi_op, &regions, &|| {})?;
                count.add(before.evaluations);
                out.speed_check_before = Some(before);
            }
            None => parts.push(VerificationPart::of(
                "speeds",
                0,
                0,
                String::new(),
                "the design has no band around phi_op to follow over the speed range; its bands are checked at the optimiser's speeds only",
            )),
        }
    }
    out.verification = Verification::of(parts, recheck);
    crate::design::vibration::vibration_report(base, spec, out)?;
    if !out.verified() && out.status != Status::Infeasible {
        // Not robust when the builds of the tolerance box are all that failed.
        let failed: Vec<&str> = out
            .verification
            .parts
            .iter()
            .filter(|p| p.status == crate::design::verify::PartStatus::Failed)
            .map(|p| p.part.as_str())
            .collect();
        let as_built = |p: &&str| matches!(*p, "tolerances" | "tolerance-peaks" | "tolerance-bands");
        out.status = if failed.iter().all(as_built) { Status::NotRobust } else { Status::NotVerified };
    }
    out.verification_cost = Cost { evaluations: count.get(), seconds: checked.elapsed().as_secs_f64() };
    Ok(())
}

/// The verification part `operating-point`: φ_op must be stable at β_op on the tuned
/// design at every speed (a design whose φ_op stays inside a tongue is neither improved
/// nor verified, whatever the other parts checked); not applicable without a φ_op.
fn operating_point_part(spec: &DesignSpec, after: &[crate::design::verify::DesignAtSpeed]) -> VerificationPart {
    let Some(phi_op) = spec.phi_op() else {
        return VerificationPart::of("operating-point", 0, 0, String::new(), "the design has no phi_op");
    };
    let unstable: Vec<String> = after
        .iter()
        .filter(|d| d.band.as_ref().is_some_and(|b| b.band.is_none()))
        .map(|d| {
            let t = d.band.as_ref().and_then(|b| b.containing);
            let inside = t.map_or(String::new(), |t| format!(" (inside the tongue [{:.2}, {:.2}] rad/s)", t.lo, t.hi));
            format!("{} rad/s{inside}", d.speed)
        })
        .collect();
    let checked = after.iter().filter(|d| d.band.is_some()).count();
    let summary = if unstable.is_empty() {
        format!("phi_op = {phi_op} rad/s is stable at beta_op = {} at each of the {checked} speed(s)", spec.level)
    } else {
        format!("phi_op = {phi_op} rad/s is UNSTABLE at beta_op = {} at Omega = {}", spec.level, unstable.join(", "))
    };
    VerificationPart::of("operating-point", checked, unstable.len(), summary, "no band around phi_op was searched")
}

/// The verification part `refined-basis` over the speeds' refined checks
/// ([`crate::design::sizing::refined_check`]).
fn refined_part(checks: &[crate::design::sizing::RefinedCheck]) -> VerificationPart {
    let compared: usize = checks.iter().map(|c| c.movements.len()).sum();
    let failed: Vec<String> = checks
        .iter()
        .flat_map(|c| {
            c.movements.iter().filter(|m| !m.within()).map(move |m| format!("{} rad/s: {}", c.speed, m.text()))
        })
        .collect();
    let sizes: Vec<String> = checks.iter().map(|c| format!("M = {} → {}", c.modes, c.refined_modes)).collect();
    let worst = checks
        .iter()
        .flat_map(|c| &c.movements)
        .max_by(|a, b| a.ratio().total_cmp(&b.ratio()))
        .map_or(String::new(), |m| format!("; largest movement {}", m.text()));
    let summary = if failed.is_empty() {
        format!(
            "{compared} comparison(s) on a basis twice the design's ({}) within the tolerance{worst}",
            sizes.join(", ")
        )
    } else {
        format!(
            "{} of {compared} comparison(s) on a basis twice the design's ({}) moved beyond the tolerance: {}",
            failed.len(),
            sizes.join(", "),
            failed.join("; ")
        )
    };
    VerificationPart::of(
        "refined-basis",
        compared,
        failed.len(),
        summary,
        "the model has no more modes than the design's basis, or nothing to compare (no phi_op, no kept-clear band)",
    )
}
