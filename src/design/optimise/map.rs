//! The map before the local search: the objective on a space-filling set of points over
//! the whole box of the variables, whose best distinct basins the Nelder–Mead starts
//! begin from (a start from the reference alone, or from a few fixed points, ends in
//! whatever basin is nearest: docs/design.md, "The map").

use super::halton;
use serde::{Deserialize, Serialize};

/// Map points per design variable: 24 for the two variables of the paper's design, fewer than
/// the candidate evaluations of the two Halton starts the map replaced there (25; the
/// `design` bench compares them side by side).
pub const MAP_POINTS_PER_VARIABLE: usize = 12;

/// The starts from the map's basins beyond those `design.starts` leaves room for, with
/// `variables` variables: one per variable beyond three (a larger box has more basins).
pub fn extra_starts(variables: usize) -> usize {
    variables.saturating_sub(3)
}

/// The points of the map of a design of `variables` variables.
pub fn map_points(variables: usize) -> usize {
    MAP_POINTS_PER_VARIABLE * variables.max(1)
}

/// One point of the map.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MapPoint {
    /// The design variables (SI units, in the order of `[[design.variables]]`).
    pub values: Vec<f64>,
    /// The objective there, in its unit (widest band: the band width it steers by, rad/s);
    /// None where the candidate could not be analysed.
    pub objective: Option<f64>,
}

/// The objective over the box before the local search: the points of a Halton set in the
/// scaled variables (the same set on every run), their objective values, and which of
/// them the local searches started from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ObjectiveMap {
    /// What the objective is, with its unit.
    pub objective: String,
    /// Whether larger is better (widest band) or smaller (least peak response).
    pub maximise: bool,
    /// The points, in the order of the Halton set.
    pub points: Vec<MapPoint>,
    /// The indices of the points the local searches started from (the best distinct
    /// basins, best first).
    pub basins: Vec<usize>,
    /// With more than two variables, one slice per pair of variables through the tuned
    /// design ([`MapSlice`]); empty with two or fewer.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub slices: Vec<MapSlice>,
}

/// Points per side of a slice of the map: a 5 × 5 grid over the pair's box, the corners
/// and the centre included, 25 candidates a pair.
pub const SLICE_POINTS: usize = 5;

/// The objective over one pair of variables through the tuned design: a grid of
/// [`SLICE_POINTS`] × [`SLICE_POINTS`] points over the pair's box (on the scale the design
/// searches each variable on), every other variable at its tuned value.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MapSlice {
    /// The two variables (indices into `[[design.variables]]`, the first on x).
    pub pair: (usize, usize),
    /// The grid's points, x fastest.
    pub points: Vec<MapPoint>,
}

/// The candidates of the slices of a design of `variables` variables: none for two or
/// fewer, [`SLICE_POINTS`]² per pair of variables for more.
pub fn slice_points(variables: usize) -> usize {
    if variables > 2 {
        variables * (variables - 1) / 2 * SLICE_POINTS * SLICE_POINTS
    } else {
        0
    }
}

/// A pair of variables and the scaled points of its slice.
pub(super) type SliceGrid = ((usize, usize), Vec<Vec<f64>>);

/// The scaled points of each slice through `optimum` (scaled), pair by pair (x fastest).
pub(super) fn slice_grids(optimum: &[f64]) -> Vec<SliceGrid> {
    let n = optimum.len();
    let step = |k: usize| k as f64 / (SLICE_POINTS - 1) as f64;
    let mut out = Vec::new();
    for i in 0..n {
        for j in i + 1..n {
            let grid = (0..SLICE_POINTS)
                .flat_map(|b| (0..SLICE_POINTS).map(move |a| (a, b)))
                .map(|(a, b)| {
                    let mut u = optimum.to_vec();
                    u[i] = step(a);
                    u[j] = step(b);
                    u
                })
                .collect();
            out.push(((i, j), grid));
        }
    }
    out
}

/// The scaled points of a map of `count` points in `dims` dimensions: the Halton set, whose
/// first points are the Halton starts the searches used before the map.
pub(super) fn points(count: usize, dims: usize) -> Vec<Vec<f64>> {
    (0..count).map(|k| halton(k, dims)).collect()
}

/// The best distinct basins of a map, best first, at most `want`: the points better than
/// each of their 2·n nearest neighbours in the scaled box (n the number of variables), then,
/// while fewer than `want`, the best remaining points that are not among a chosen point's
/// neighbours. `values` are to be maximised; None (failed) never counts.
pub(super) fn basins(scaled: &[Vec<f64>], values: &[Option<f64>], want: usize) -> Vec<usize> {
    let n = scaled.first().map_or(1, Vec::len).max(1);
    let k = (2 * n).min(scaled.len().saturating_sub(1));
    let distance = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum::<f64>();
    let neighbours: Vec<Vec<usize>> = (0..scaled.len())
        .map(|i| {
            let mut others: Vec<usize> = (0..scaled.len()).filter(|&j| j != i).collect();
            others.sort_by(|&a, &b| distance(&scaled[i], &scaled[a]).total_cmp(&distance(&scaled[i], &scaled[b])));
            others.truncate(k);
            others
        })
        .collect();
    // Better: a larger value, ties to the earlier point (the same order on every run).
    let better = |a: usize, b: usize| match (values[a], values[b]) {
        (Some(x), Some(y)) => x > y || (x == y && a < b),
        (Some(_), None) => true,
        _ => false,
    };
    let mut order: Vec<usize> = (0..scaled.len()).filter(|&i| values[i].is_some()).collect();
    order.sort_by(|&a, &b| if better(a, b) { std::cmp::Ordering::Less } else { std::cmp::Ordering::Greater });
    let mut chosen: Vec<usize> =
        order.iter().copied().filter(|&i| neighbours[i].iter().all(|&j| better(i, j))).take(want).collect();
    for &i in &order {
        if chosen.len() >= want {
            break;
        }
        if !chosen.contains(&i) && chosen.iter().all(|&c| !neighbours[c].contains(&i)) {
            chosen.push(i);
        }
    }
    chosen
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slices_span_each_pair_through_the_optimum() {
        let optimum = [0.3, 0.6, 0.9];
        let grids = slice_grids(&optimum);
        assert_eq!(grids.iter().map(|g| g.0).collect::<Vec<_>>(), [(0, 1), (0, 2), (1, 2)]);
        assert_eq!(grids.iter().map(|g| g.1.len()).sum::<usize>(), slice_points(3));
        for ((i, j), grid) in &grids {
            let k = 3 - i - j;
            // The third variable stays at the optimum; the pair spans its box, ends included.
            assert!(grid.iter().all(|u| u[k] == optimum[k]));
            let corners = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]];
            assert!(corners.iter().all(|c| grid.iter().any(|u| u[*i] == c[0] && u[*j] == c[1])));
            assert!(grid.iter().any(|u| u[*i] == 0.5 && u[*j] == 0.5));
        }
        assert_eq!(slice_points(2), 0, "two variables: the map itself is the slice");
        assert!(slice_grids(&[0.5, 0.5]).len() == 1, "one pair of two variables");
    }

    #[test]
    fn two_hills_give_two_basins_best_first() {
        // A hill at (0.2, 0.2) of height 1 and one at (0.8, 0.7) of height 2.
        let pts = points(64, 2);
        let hill = |p: &[f64], c: (f64, f64), h: f64| h * (-((p[0] - c.0).powi(2) + (p[1] - c.1).powi(2)) / 0.02).exp();
        let values: Vec<Option<f64>> =
            pts.iter().map(|p| Some(hill(p, (0.2, 0.2), 1.0) + hill(p, (0.8, 0.7), 2.0))).collect();
        let b = basins(&pts, &values, 2);
        assert_eq!(b.len(), 2);
        let near = |i: usize, c: (f64, f64)| (pts[i][0] - c.0).hypot(pts[i][1] - c.1) < 0.15;
        assert!(near(b[0], (0.8, 0.7)), "{:?}", pts[b[0]]);
        assert!(near(b[1], (0.2, 0.2)), "{:?}", pts[b[1]]);
    }

    #[test]
    fn failed_points_are_never_basins_and_the_count_is_kept() {
        let pts = points(16, 1);
        let values: Vec<Option<f64>> = pts.iter().map(|p| if p[0] < 0.5 { None } else { Some(p[0]) }).collect();
        let b = basins(&pts, &values, 3);
        assert_eq!(b.len(), 3);
        assert!(b.iter().all(|&i| values[i].is_some()));
        assert!(pts[b[0]][0] > 0.9, "the best point first: {:?}", pts[b[0]]);
    }
}
