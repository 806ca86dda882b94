//! The chart CSV.

use super::*;

/// A number for the CSV: shortest round-trip text, exponent form from 1e15 on, empty if
/// not finite.
fn csv_number(v: f64) -> String {
    if !v.is_finite() {
        String::new()
    } else if v.abs() >= 1e15 {
        format!("{v:e}")
    } else {
        v.to_string()
    }
}

/// One row per grid point, φ-major (the order of `chart.points`). `verdict` is
/// `stable`, `unstable` or `failed`; failed points have empty numeric fields (their
/// stored values are placeholders). `status` is `ok`, `inaccurate` or `failed`.
pub fn chart_csv(chart: &ChartResult) -> Result<String, csv::Error> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "phi_rad_s",
        "beta",
        "max_multiplier",
        "ln_max_multiplier",
        "growth_rate_per_s",
        "verdict",
        "status",
    ])?;
    for p in &chart.points {
        let failed = p.status == PointStatus::Failed;
        let value = |v: f64| if failed { String::new() } else { csv_number(v) };
        let verdict = if failed {
            "failed"
        } else if p.stable {
            "stable"
        } else {
            "unstable"
        };
        let status = match p.status {
            PointStatus::Ok => "ok",
            PointStatus::Inaccurate => "inaccurate",
            PointStatus::Failed => "failed",
        };
        w.write_record([
            csv_number(p.phi),
            csv_number(p.beta),
            value(p.max_multiplier),
            value(p.ln_max_multiplier),
            value(p.growth_rate),
            verdict.to_string(),
            status.to_string(),
        ])?;
    }
    let bytes = w.into_inner().map_err(|e| e.into_error())?;
    Ok(String::from_utf8_lossy(&bytes).into_owned())
}
