//! Supports: bearings and seals with full 2×2 coefficient matrices, and vibration rings,
//! each at one shaft node.

use super::{Circuit, Ring};
use serde::Serialize;

/// What a support with coefficient matrices is: the physics is the same (forces from the
/// shaft's deflection and velocity to the ground); the kind names it in labels and
/// outputs, as ROSS's BearingElement and SealElement.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SupportKind {
    /// A bearing (`[[bearings]]`).
    Bearing,
    /// A seal (`[[seals]]`).
    Seal,
}

impl std::fmt::Display for SupportKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            SupportKind::Bearing => "bearing",
            SupportKind::Seal => "seal",
        })
    }
}

/// The names of the eight coefficients, in the order of [`Bearing::coefficients`]:
/// stiffnesses (N/m) then dampings (N·s/m). The force on the shaft is
/// F_x = −(k_xx·x + k_xy·y) − (c_xx·ẋ + c_xy·ẏ), F_y = −(k_yx·x + k_yy·y) − (c_yx·ẋ + c_yy·ẏ),
/// x the deflection v and y the deflection w (u = v + jw).
pub const COEFFICIENT_NAMES: [&str; 8] = ["kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy"];

/// A 2×2 real matrix `[[xx, xy], [yx, yy]]`.
pub type Matrix2 = [[f64; 2]; 2];

/// A bearing or seal: stiffness and damping matrices from the shaft's deflection to the
/// ground at a shaft node, each coefficient a constant or a table over the rotating
/// speed, and an optional mass lumped at that node. It has no DOF of its own.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Bearing {
    /// Bearing or seal.
    pub kind: SupportKind,
    /// Shaft node (0-based).
    pub node: usize,
    /// The speeds of the coefficient tables (rad/s), strictly increasing; empty when
    /// every coefficient is a constant.
    pub speeds: Vec<f64>,
    /// kxx, kxy, kyx, kyy (N/m), cxx, cxy, cyx, cyy (N·s/m) ([`COEFFICIENT_NAMES`]): each
    /// one value (a constant) or one value per speed of [`Bearing::speeds`].
    pub coefficients: [Vec<f64>; 8],
    /// Support mass (kg), lumped at the node's deflection in both directions.
    pub mass: f64,
}

/// The stiffness and damping matrices of a support at one speed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SupportMatrices {
    /// `[[kxx, kxy], [kyx, kyy]]` (N/m).
    pub k: Matrix2,
    /// `[[cxx, cxy], [cyx, cyy]]` (N·s/m).
    pub c: Matrix2,
}

impl Bearing {
    /// A plain isotropic bearing: kxx = kyy = `stiffness` (N/m), cxx = cyy = `damping`
    /// (N·s/m), no cross-coupling, constant, with `mass` (kg).
    pub fn isotropic(node: usize, stiffness: f64, damping: f64, mass: f64) -> Bearing {
        let one = |x: f64| vec![x];
        Bearing {
            kind: SupportKind::Bearing,
            node,
            speeds: Vec::new(),
            coefficients: [
                one(stiffness),
                one(0.0),
                one(0.0),
                one(stiffness),
                one(damping),
                one(0.0),
                one(0.0),
                one(damping),
            ],
            mass,
        }
    }

    /// Whether the support is what the complex coordinates carry: constant coefficients
    /// (every table flat), kxx = kyy, cxx = cyy and no cross-coupling. Such a support is
    /// one real spring and damper per direction, the same in both.
    pub fn is_isotropic(&self) -> bool {
        let constant = |v: &Vec<f64>| v.iter().all(|x| *x == v[0]);
        let c = &self.coefficients;
        c.iter().all(constant)
            && c[0][0] == c[3][0]
            && c[4][0] == c[7][0]
            && [1, 2, 5, 6].iter().all(|&i| c[i][0] == 0.0)
    }

    /// kxx at the first table point (N/m): the stiffness of an isotropic support.
    pub fn stiffness(&self) -> f64 {
        self.coefficients[0][0]
    }

    /// cxx at the first table point (N·s/m): the damping of an isotropic support.
    pub fn damping(&self) -> f64 {
        self.coefficients[4][0]
    }

    /// Whether `speed` (rad/s) lies outside the coefficient tables' speeds, where the
    /// coefficients are held at the nearest end (a warning, not an extrapolation).
    pub fn outside_table(&self, speed: f64) -> bool {
        match (self.speeds.first(), self.speeds.last()) {
            (Some(&lo), Some(&hi)) => speed < lo || speed > hi,
            _ => false,
        }
    }

    /// The coefficient `index` ([`COEFFICIENT_NAMES`]) at `speed` (rad/s): a constant as
    /// it is; a table interpolated over [`Bearing::speeds`] by [`interpolate`].
    pub fn coefficient_at(&self, index: usize, speed: f64) -> f64 {
        let values = &self.coefficients[index];
        if values.len() == 1 {
            values[0]
        } else {
            interpolate(&self.speeds, values, speed)
        }
    }

    /// The stiffness and damping matrices at `speed` (rad/s).
    pub fn matrices_at(&self, speed: f64) -> SupportMatrices {
        let v = |i| self.coefficient_at(i, speed);
        SupportMatrices { k: [[v(0), v(1)], [v(2), v(3)]], c: [[v(4), v(5)], [v(6), v(7)]] }
    }
}

/// A coefficient table `values` over `speeds` (rad/s, strictly increasing, same length)
/// at `speed`, as ROSS's BearingElement interpolates its tables: with four points or more
/// the cubic spline through them with not-a-knot ends (the spline FITPACK's
/// `UnivariateSpline` returns for such data, ROSS's choice); with three points the
/// parabola through them, with two the line (ROSS's `interp1d` of order n − 1); one point
/// is a constant. Outside [speeds₀, speeds_last] the value at the nearest end is held:
/// ROSS extrapolates the end polynomial, which for fluid-film coefficients soon turns
/// unphysical; rotorshunt warns instead ([`Bearing::outside_table`], docs/model.md).
/// Time and memory are linear in the table's length (the spline is solved anew at each
/// call); a problem file's tables have at most [`crate::problem::MAX_TABLE_POINTS`] speeds.
pub fn interpolate(speeds: &[f64], values: &[f64], speed: f64) -> f64 {
    let n = values.len().min(speeds.len());
    if n == 0 {
        return f64::NAN;
    }
    if n == 1 {
        return values[0];
    }
    let x = speed.clamp(speeds[0], speeds[n - 1]);
    if n == 2 {
        let t = (x - speeds[0]) / (speeds[1] - speeds[0]);
        return values[0] + t * (values[1] - values[0]);
    }
    if n == 3 {
        // Lagrange form of the parabola through the three points.
        let (x0, x1, x2) = (speeds[0], speeds[1], speeds[2]);
        let l0 = (x - x1) * (x - x2) / ((x0 - x1) * (x0 - x2));
        let l1 = (x - x0) * (x - x2) / ((x1 - x0) * (x1 - x2));
        let l2 = (x - x0) * (x - x1) / ((x2 - x0) * (x2 - x1));
        return values[0] * l0 + values[1] * l1 + values[2] * l2;
    }
    let m = spline_moments(&speeds[..n], &values[..n]);
    // The interval [x_i, x_{i+1}] holding x (the last one for x = x_{n−1}).
    let i = speeds[..n].partition_point(|&s| s <= x).saturating_sub(1).min(n - 2);
    let h = speeds[i + 1] - speeds[i];
    let (a, b) = ((speeds[i + 1] - x) / h, (x - speeds[i]) / h);
    a * values[i] + b * values[i + 1] + ((a * a * a - a) * m[i] + (b * b * b - b) * m[i + 1]) * h * h / 6.0
}

/// Second derivatives M_i of the not-a-knot cubic spline through (x_i, y_i), n ≥ 4: the
/// continuity equations h_{i−1}M_{i−1} + 2(h_{i−1} + h_i)M_i + h_iM_{i+1} = 6(d_i − d_{i−1})
/// at the interior points, and a continuous third derivative at x_1 and x_{n−2}:
/// (M_1 − M_0)/h_0 = (M_2 − M_1)/h_1 and likewise at the other end.
///
/// Solved in O(n) time and memory: the two end conditions give M_0 and M_{n−1} from their
/// neighbours, M_0 = ((h_0 + h_1)M_1 − h_0M_2)/h_1 (and its mirror), and put into the
/// first and last continuity equations they leave a tridiagonal system in M_1 … M_{n−2}
/// whose every row is strictly diagonally dominant (row 1: (h_0 + h_1)(h_0 + 2h_1)/h_1
/// on the diagonal against |h_1² − h_0²|/h_1 beside it; an interior row 2(h_{i−1} + h_i)
/// against h_{i−1} + h_i), which the Thomas algorithm solves stably without pivoting.
fn spline_moments(x: &[f64], y: &[f64]) -> Vec<f64> {
    let n = x.len();
    let h = |i: usize| x[i + 1] - x[i];
    let d = |i: usize| (y[i + 1] - y[i]) / h(i);
    // Row i (1 ≤ i ≤ n − 2) of the reduced system: sub[i]·M_{i−1} + diag[i]·M_i +
    // sup[i]·M_{i+1} = rhs[i], forward-eliminated in place: after the sweep, row i reads
    // M_i + sup[i]·M_{i+1} = rhs[i].
    let mut sup = vec![0.0; n];
    let mut rhs = vec![0.0; n];
    let (h0, h1) = (h(0), h(1));
    let (ha, hb) = (h(n - 3), h(n - 2));
    let mut below = 0.0;
    for i in 1..n - 1 {
        let (hl, hr) = (h(i - 1), h(i));
        let (mut sub, mut diag, mut up) = (hl, 2.0 * (hl + hr), hr);
        if i == 1 {
            // h_0·M_0 with M_0 = ((h_0 + h_1)M_1 − h_0M_2)/h_1.
            diag += h0 * (h0 + h1) / h1;
            up -= h0 * h0 / h1;
            sub = 0.0;
        }
        if i == n - 2 {
            // h_{n−2}·M_{n−1} with M_{n−1} = ((h_{n−3} + h_{n−2})M_{n−2} − h_{n−2}M_{n−3})/h_{n−3}.
            diag += hb * (ha + hb) / ha;
            sub -= hb * hb / ha;
            up = 0.0;
        }
        let r = 6.0 * (d(i) - d(i - 1));
        // Eliminate M_{i−1} with the row above (already normalised).
        let pivot = diag - sub * below;
        sup[i] = up / pivot;
        rhs[i] = (r - sub * rhs[i - 1]) / pivot;
        below = sup[i];
    }
    let mut m = rhs;
    for i in (1..n - 2).rev() {
        m[i] -= sup[i] * m[i + 1];
    }
    m[0] = ((h0 + h1) * m[1] - h0 * m[2]) / h1;
    m[n - 1] = ((ha + hb) * m[n - 2] - hb * m[n - 3]) / ha;
    m
}

/// A vibration ring with its bearing (Eq. 1, 7–10) and its own shunt circuit (Eq. A8),
/// mounted at a shaft node.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RingSupport {
    /// Name, used in mode and region labels when circuits differ between rings.
    pub name: String,
    /// Shaft node (0-based).
    pub node: usize,
    /// The ring's mechanical and piezo parameters.
    pub ring: Ring,
    /// The circuit shunting this ring's stacks.
    pub circuit: Circuit,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cubic_is_reproduced_by_the_not_a_knot_spline() {
        // Not-a-knot reproduces any cubic exactly, inside and at the ends.
        let f = |x: f64| 2.0 + 3.0 * x - 0.5 * x * x + 0.125 * x * x * x;
        let xs = [0.0, 1.0, 2.5, 3.0, 4.5, 7.0];
        let ys: Vec<f64> = xs.iter().map(|&x| f(x)).collect();
        for x in [0.0, 0.3, 1.7, 2.5, 3.9, 6.2, 7.0] {
            assert!((interpolate(&xs, &ys, x) - f(x)).abs() < 1e-12 * f(x).abs().max(1.0), "{x}");
        }
        // Held outside the table.
        assert_eq!(interpolate(&xs, &ys, -3.0), interpolate(&xs, &ys, 0.0));
        assert_eq!(interpolate(&xs, &ys, 9.0), interpolate(&xs, &ys, 7.0));
    }

    /// The not-a-knot system as a dense n × n matrix, solved by Gaussian elimination with
    /// partial pivoting: the route the O(n) solve replaced, kept as its reference.
    fn dense_moments(x: &[f64], y: &[f64]) -> Vec<f64> {
        let n = x.len();
        let h: Vec<f64> = x.windows(2).map(|w| w[1] - w[0]).collect();
        let d: Vec<f64> = (0..n - 1).map(|i| (y[i + 1] - y[i]) / h[i]).collect();
        let mut a = vec![vec![0.0; n]; n];
        let mut r = vec![0.0; n];
        a[0][0] = h[1];
        a[0][1] = -(h[0] + h[1]);
        a[0][2] = h[0];
        for i in 1..n - 1 {
            a[i][i - 1] = h[i - 1];
            a[i][i] = 2.0 * (h[i - 1] + h[i]);
            a[i][i + 1] = h[i];
            r[i] = 6.0 * (d[i] - d[i - 1]);
        }
        a[n - 1][n - 3] = h[n - 2];
        a[n - 1][n - 2] = -(h[n - 3] + h[n - 2]);
        a[n - 1][n - 1] = h[n - 3];
        for col in 0..n {
            let p = (col..n).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs())).unwrap();
            a.swap(col, p);
            r.swap(col, p);
            let (top, rest) = a.split_at_mut(col + 1);
            let pivot_row = &top[col];
            for (offset, row) in rest.iter_mut().enumerate() {
                let f = row[col] / pivot_row[col];
                for (x, p) in row[col..].iter_mut().zip(&pivot_row[col..]) {
                    *x -= f * p;
                }
                r[col + 1 + offset] -= f * r[col];
            }
        }
        let mut out = vec![0.0; n];
        for i in (0..n).rev() {
            let s: f64 = (i + 1..n).map(|k| a[i][k] * out[k]).sum();
            out[i] = (r[i] - s) / a[i][i];
        }
        out
    }

    #[test]
    fn the_linear_solve_agrees_with_the_dense_one_on_random_tables() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(50);
        let mut worst: f64 = 0.0;
        for trial in 0..400 {
            let n = 4 + trial % 37;
            // Steps from 1e-3 to 1e3 (rad/s) side by side, and values of any sign.
            let mut xs = vec![rng.random_range(-100.0..100.0)];
            for _ in 1..n {
                let step = 10f64.powf(rng.random_range(-3.0..3.0));
                xs.push(xs[xs.len() - 1] + step);
            }
            let ys: Vec<f64> = (0..n).map(|_| rng.random_range(-1e7..1e7)).collect();
            let (fast, dense) = (spline_moments(&xs, &ys), dense_moments(&xs, &ys));
            let scale = dense.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for (a, b) in fast.iter().zip(&dense) {
                worst = worst.max((a - b).abs() / scale);
            }
        }
        println!("largest difference of the moments, relative to the largest: {worst:.1e}");
        assert!(worst < 1e-9, "{worst:e}");
    }

    #[test]
    fn short_tables_are_lines_and_parabolas_through_their_points() {
        let line = interpolate(&[1.0, 3.0], &[10.0, 30.0], 2.5);
        assert!((line - 25.0).abs() < 1e-12);
        let p = |x: f64| 1.0 - 2.0 * x + 0.75 * x * x;
        let xs = [0.0, 2.0, 5.0];
        let ys: Vec<f64> = xs.iter().map(|&x| p(x)).collect();
        assert!((interpolate(&xs, &ys, 3.3) - p(3.3)).abs() < 1e-12);
    }

    #[test]
    fn the_isotropic_constructor_is_isotropic_and_a_split_one_is_not() {
        let b = Bearing::isotropic(3, 1e7, 20.0, 0.5);
        assert!(b.is_isotropic());
        assert_eq!(b.matrices_at(123.0).k, [[1e7, 0.0], [0.0, 1e7]]);
        let mut a = b.clone();
        a.coefficients[3] = vec![8e6];
        assert!(!a.is_isotropic());
        let mut x = b;
        x.coefficients[1] = vec![1e5];
        assert!(!x.is_isotropic());
    }
}
