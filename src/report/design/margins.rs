//! The margins of the band around φ_op on the report's page one (issue 27, point 1): load
//! margin, frequency margins, the largest max|μ| sampled inside, the strict-criterion band
//! beside the declared one, and the `[design.margins]` check at the margin level.

use crate::design::DesignOutcome;
use std::fmt::Write;

/// The margins table (nothing when the design has no band around φ_op).
pub(super) fn margins_table(s: &mut String, o: &DesignOutcome) {
    let rows: Vec<_> = o
        .before_speeds
        .iter()
        .zip(&o.after_speeds)
        .filter_map(|(b, a)| Some((a.speed, b.margins.as_ref()?, a.margins.as_ref()?, a)))
        .collect();
    if rows.is_empty() {
        return;
    }
    let criterion = o.after_speeds.first().map(|d| d.catalogue.criterion);
    let declared_rule = criterion.map_or(String::new(), |c| c.threshold.describe().replace('|', "\\|"));
    // The strict band beside the declared one only where the declared criterion has slack
    // (the paper's tolerance, floors): otherwise it is the declared band.
    let slack = criterion.is_some_and(|c| !c.is_strict());
    let (strict_text, strict_header, strict_rule) = if slack {
        (
            "; the strict band counts every point with ln max\\|μ\\| above the fast path's floor",
            format!(" strict band (unstable when {}) |", rows[0].2.strict.describe().replace('|', "\\|")),
            "---|",
        )
    } else {
        ("", String::new(), "")
    };
    let _ = writeln!(
        s,
        "\nMargins of the band around φ_op at β_op = {} (load margin: the lowest onset above β_op of a counted tongue born inside the band, as onset/β_op − 1; frequency margins φ_op − lo and hi − φ_op in rad/s; largest max\\|μ\\| over the band search's points inside the band{strict_text}):\n\n| {} | | load margin | φ_op − lo | hi − φ_op | largest max\\|μ\\| inside | band (unstable when {declared_rule}) |{strict_header}\n|---|---|---|---|---|---|---|{strict_rule}",
        o.spec.level,
        super::speed_header(o.spec.speed_unit),
    );
    for (speed, before, after, at) in &rows {
        for (which, m, band) in [
            ("before", *before, o.before_speeds.iter().find(|d| d.speed == *speed).and_then(|d| d.band.as_ref())),
            ("after", *after, at.band.as_ref()),
        ] {
            let declared = band
                .and_then(|b| b.band)
                .map_or("–".into(), |b| format!("[{:.2}, {:.2}] ({:.2})", b.lo, b.hi, b.width()));
            let strict = match (slack, m.strict_band) {
                (false, _) => String::new(),
                (true, Some(b)) => format!(" [{:.2}, {:.2}] ({:.2}) |", b.lo, b.hi, b.width()),
                (true, None) => " none |".into(),
            };
            let _ = writeln!(
                s,
                "| {} | {which} | {} | {:.2} | {:.2} | {} | {declared} |{strict}",
                super::speed_cell(o.spec.speed_unit, *speed),
                m.load_text().replace('|', "\\|"),
                m.phi_below,
                m.phi_above,
                m.max_multiplier.map_or("–".into(), |x| format!("{x:.7} ({} points)", m.sampled)),
            );
        }
    }
    if let Some(req) = o.spec.constraints.margins {
        let _ = writeln!(
            s,
            "\n`[design.margins]` beta = {}, phi = {} rad/s: the band must hold up to β = {:.6} with φ_op at least {} rad/s from each edge.",
            req.beta,
            req.phi,
            req.level(o.spec.level),
            req.phi
        );
        for d in &o.after_speeds {
            if let Some(mc) = &d.margin_check {
                let band = mc.band.map_or("none (φ_op unstable)".into(), |b| format!("[{:.2}, {:.2}]", b.lo, b.hi));
                let _ = writeln!(
                    s,
                    "- {}: the catalogue at β = {:.6} gives the band {band} around φ_op (φ_op − lo = {}, hi − φ_op = {} rad/s), {} counted tongue(s) within {} rad/s of φ_op, {} of {} grid points unstable.",
                    super::speed_text(o.spec.speed_unit, d.speed),
                    mc.level,
                    super::opt(mc.phi_below, 2),
                    super::opt(mc.phi_above, 2),
                    mc.intruders.len(),
                    req.phi,
                    mc.grid.as_ref().map_or(0, |g| g.unstable.len()),
                    mc.grid.as_ref().map_or(0, |g| g.points),
                );
            }
        }
    }
}
