//! Grid points as cells, merged into blocks of one colour, and the axis ranges.

use super::*;

/// Cell edges around grid values: halfway between neighbours, the outer edges half a
/// spacing beyond the end values (±5 % of the value, or ±0.05, for a single value).
pub(super) fn cell_edges(v: &[f64]) -> Vec<f64> {
    match v.len() {
        0 => Vec::new(),
        1 => {
            let h = if v[0] != 0.0 { 0.05 * v[0].abs() } else { 0.05 };
            vec![v[0] - h, v[0] + h]
        }
        n => {
            let mut e = Vec::with_capacity(n + 1);
            e.push(v[0] - 0.5 * (v[1] - v[0]));
            e.extend(v.windows(2).map(|w| 0.5 * (w[0] + w[1])));
            e.push(v[n - 1] + 0.5 * (v[n - 1] - v[n - 2]));
            e
        }
    }
}

/// A rectangle of grid cells with one key: φ indices × β indices (half-open).
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Block<K> {
    pub(super) phi: Range<usize>,
    pub(super) beta: Range<usize>,
    pub(super) key: K,
}

/// Cells with `Some(key)` merged into blocks: runs along φ within a β row, then identical
/// runs of consecutive β rows.
pub(super) fn blocks<K: Copy + Eq + Hash>(
    chart: &ChartResult,
    key: impl Fn(&ChartPoint) -> Option<K>,
) -> Vec<Block<K>> {
    let (np, nb) = (chart.phis.len(), chart.betas.len());
    let key_at = |ip: usize, ib: usize| chart.points.get(ip * nb + ib).and_then(&key);
    let mut out: Vec<Block<K>> = Vec::new();
    let mut prev: HashMap<(usize, usize, K), usize> = HashMap::new();
    for ib in 0..nb {
        let mut cur = HashMap::new();
        let mut ip = 0;
        while ip < np {
            let Some(k) = key_at(ip, ib) else {
                ip += 1;
                continue;
            };
            let start = ip;
            ip += 1;
            while ip < np && key_at(ip, ib) == Some(k) {
                ip += 1;
            }
            let idx = match prev.get(&(start, ip, k)) {
                Some(&i) => {
                    out[i].beta.end = ib + 1;
                    i
                }
                None => {
                    out.push(Block { phi: start..ip, beta: ib..ib + 1, key: k });
                    out.len() - 1
                }
            };
            cur.insert((start, ip, k), idx);
        }
        prev = cur;
    }
    out
}

/// A point that has a verdict and is unstable.
pub(super) fn unstable(p: &ChartPoint) -> bool {
    !p.stable && p.status != PointStatus::Failed
}

/// Axis ranges covering every cell of every chart ((0, 1) for an empty axis).
pub(super) fn ranges<'a>(charts: impl Iterator<Item = &'a ChartResult> + Clone) -> ((f64, f64), (f64, f64)) {
    let span = |edges: Vec<Vec<f64>>| {
        let (lo, hi) = edges
            .iter()
            .flatten()
            .filter(|v| v.is_finite())
            .fold((f64::MAX, f64::MIN), |(lo, hi), &v| (lo.min(v), hi.max(v)));
        if lo < hi {
            (lo, hi)
        } else if lo == hi {
            (lo - 0.5, hi + 0.5)
        } else {
            (0.0, 1.0)
        }
    };
    (span(charts.clone().map(|c| cell_edges(&c.phis)).collect()), span(charts.map(|c| cell_edges(&c.betas)).collect()))
}
