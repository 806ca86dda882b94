//! The critical load curve β_c(φ): the smallest β in [0, β_max] with max|μ| above the
//! instability tolerance, by bracketing from below and bisection.

use super::bisect::{bisect, Bracket, Split};
use super::Probe;
use crate::analysis::floquet::fast::PhiTable;
use crate::analysis::Interval;
use serde::Serialize;

/// Result of one β_c(φ) evaluation.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, serde::Deserialize)]
pub struct CriticalLoad {
    /// φ (rad/s).
    pub phi: f64,
    /// β_c, or None if stable up to the load searched.
    pub beta: Option<f64>,
}

impl Probe<'_> {
    /// β_c(φ) in [0, β_max]: bracket from below at `beta_bracket`, then bisect.
    pub fn critical_load(&self, phi: f64, beta_max: f64) -> CriticalLoad {
        let table = self.system().table(phi, beta_max);
        let crossing = self.crossing(&table, Interval::new(0.0, beta_max), self.settings().beta_tolerance);
        CriticalLoad { phi, beta: crossing.map(|b| b.hi) }
    }

    /// The first stable → unstable crossing in β in (`span.lo`, `span.hi`] on one per-φ
    /// table: bracket upward from `span.lo` (known stable, or 0, which is evaluated) at the
    /// multiples of `beta_bracket` and `span.hi` itself, then bisect to `tolerance`. The
    /// bracket [stable, unstable], at most the tolerance wide; [0, 0] if unstable at β = 0;
    /// None if stable up to `span.hi`.
    pub fn crossing(&self, table: &PhiTable, span: Interval, tolerance: f64) -> Option<Interval> {
        let s = self.settings();
        let from = span.lo;
        if from == 0.0 && self.unstable_on(table, 0.0) {
            return Some(Interval::new(0.0, 0.0));
        }
        let first = (from / s.beta_bracket).floor() as usize + 1;
        let last = (span.hi / s.beta_bracket).ceil().max(1.0) as usize;
        let mut lo = from;
        for k in first..=last {
            let hi = (k as f64 * s.beta_bracket).min(span.hi);
            if hi <= lo {
                continue;
            }
            if self.unstable_on(table, hi) {
                return Some(self.narrowed(table, Interval::new(lo, hi), tolerance));
            }
            lo = hi;
        }
        None
    }

    /// A bracket [stable, unstable] in β bisected to `tolerance` on its table.
    pub fn narrowed(&self, table: &PhiTable, bracket: Interval, tolerance: f64) -> Interval {
        let b = bisect(Bracket { inside: bracket.hi, outside: bracket.lo }, Split::Halves(tolerance), |beta| {
            self.unstable_on(table, beta)
        });
        Interval::new(b.outside, b.inside)
    }

    /// β_c(φ) below a load `beta_hi` known to be near the region's onset (the β_c of a
    /// point within 0.3 % of φ): None if φ is stable at `beta_hi`, otherwise step down from
    /// `beta_hi` at `beta_bracket` to the first stable sample (or 0) and bisect. Next to a
    /// tip the region is a wedge, so the crossing found is the first from below.
    pub fn critical_load_below(&self, phi: f64, beta_hi: f64) -> CriticalLoad {
        let s = self.settings();
        let table = self.system().table(phi, beta_hi);
        if !self.unstable_on(&table, beta_hi) {
            return CriticalLoad { phi, beta: None };
        }
        // ⌈β_hi/step⌉ samples down to 0, the last at 0 itself: counted, not subtracted, so
        // round-off leaves no sliver sample above 0.
        let samples = (beta_hi / s.beta_bracket).ceil().max(1.0) as usize;
        let mut hi = beta_hi;
        for k in 1..=samples {
            let lo = if k == samples { 0.0 } else { (hi - s.beta_bracket).max(0.0) };
            if !self.unstable_on(&table, lo) {
                let beta = self.narrowed(&table, Interval::new(lo, hi), s.beta_tolerance).hi;
                return CriticalLoad { phi, beta: Some(beta) };
            }
            hi = lo;
        }
        CriticalLoad { phi, beta: Some(0.0) }
    }
}
