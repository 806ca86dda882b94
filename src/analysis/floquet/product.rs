//! A running product of step matrices, kept finite and normal by rescaling: the true
//! value is e^{log_scale}·matrix, so strongly unstable points never overflow and strongly
//! damped ones never underflow to zero (whose logarithm would be −∞).

use crate::linalg::SplitMatrix;
use faer::linalg::matmul::matmul;
use faer::{c64, Accum, Mat, MatRef, Par};

/// Rescale when an entry exceeds this (far from overflow, far above any O(1) value).
const RESCALE_ABOVE: f64 = 1e100;
/// Rescale when the largest entry falls below this (far from underflow, far below any
/// O(1) value).
const RESCALE_BELOW: f64 = 1e-100;

/// Φ = e^{log_scale}·matrix.
#[derive(Debug, Clone)]
pub struct ScaledProduct {
    /// The scaled matrix.
    pub matrix: Mat<c64>,
    /// Natural logarithm of the scale factor.
    pub log_scale: f64,
    scratch: Mat<c64>,
}

impl ScaledProduct {
    /// The identity of size n.
    pub fn identity(n: usize) -> ScaledProduct {
        ScaledProduct { matrix: Mat::identity(n, n), log_scale: 0.0, scratch: Mat::zeros(n, n) }
    }

    /// e^{log_scale}·matrix.
    pub fn from_matrix(matrix: Mat<c64>, log_scale: f64) -> ScaledProduct {
        let n = matrix.nrows();
        ScaledProduct { matrix, log_scale, scratch: Mat::zeros(n, n) }
    }

    /// stepⁿ by repeated squaring, rescaled like any product.
    pub fn power(step: MatRef<'_, c64>, mut n: usize) -> ScaledProduct {
        let mut result = ScaledProduct::identity(step.nrows());
        let mut base = ScaledProduct::from_matrix(step.to_owned(), 0.0);
        base.rescale();
        while n > 0 {
            if n & 1 == 1 {
                result.left_multiply(base.matrix.as_ref());
                result.log_scale += base.log_scale;
            }
            n >>= 1;
            if n > 0 {
                // (e^s·B)² = e^{2s}·B²; left_multiply adds the rescaling of B² to s.
                let (square, s) = (base.matrix.clone(), base.log_scale);
                base.left_multiply(square.as_ref());
                base.log_scale += s;
            }
        }
        result
    }

    /// Φ ← step·Φ.
    pub fn left_multiply(&mut self, step: MatRef<'_, c64>) {
        matmul(self.scratch.as_mut(), Accum::Replace, step, self.matrix.as_ref(), c64::new(1.0, 0.0), Par::Seq);
        std::mem::swap(&mut self.matrix, &mut self.scratch);
        self.rescale();
    }

    fn rescale(&mut self) {
        if let Some(e) = rescaling(self.matrix.norm_max()) {
            let factor = 0.5f64.powi(e);
            for j in 0..self.matrix.ncols() {
                for i in 0..self.matrix.nrows() {
                    self.matrix[(i, j)] *= factor;
                }
            }
            self.log_scale += e as f64 * std::f64::consts::LN_2;
        }
    }
}

/// For a product whose largest entry is `m`: None, or the power of two 2^e ≤ m it is
/// divided by (a power of two, so that the scaling itself is exact; e < 0 for a tiny
/// product, which is multiplied up).
fn rescaling(m: f64) -> Option<i32> {
    // Normal numbers only below: 2^1022 is the largest factor that stays finite.
    let out_of_range = m > RESCALE_ABOVE || (f64::MIN_POSITIVE..RESCALE_BELOW).contains(&m);
    (out_of_range && m.is_finite()).then(|| m.log2().floor() as i32)
}

/// The same running product with the matrix in split form ([`SplitMatrix`]): the fast
/// path's products, as real matrix products.
#[derive(Debug, Clone)]
pub struct ScaledSplit {
    /// The scaled matrix.
    pub matrix: SplitMatrix,
    /// Natural logarithm of the scale factor.
    pub log_scale: f64,
    scratch: SplitMatrix,
}

impl ScaledSplit {
    /// The product of one matrix, given by its row form [A_r A_i] (n×2n).
    pub fn new(first_row: MatRef<'_, f64>) -> ScaledSplit {
        let n = first_row.nrows();
        let mut matrix = SplitMatrix::zeros(n);
        matrix.set_row(first_row);
        let mut p = ScaledSplit { matrix, log_scale: 0.0, scratch: SplitMatrix::zeros(n) };
        p.rescale();
        p
    }

    /// Φ ← step·Φ, the step given by its row form.
    pub fn left_multiply(&mut self, step_row: MatRef<'_, f64>) {
        self.scratch.set_product(step_row, &self.matrix);
        std::mem::swap(&mut self.matrix, &mut self.scratch);
        self.rescale();
    }

    fn rescale(&mut self) {
        if let Some(e) = rescaling(self.matrix.norm_max()) {
            self.matrix.scale(0.5f64.powi(e));
            self.log_scale += e as f64 * std::f64::consts::LN_2;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn power_equals_the_running_product_with_rescaling() {
        // A step of norm ~30: its 40th power (~1e59 per step squared…) is rescaled on the
        // way; powering by squaring and the plain running product must give the same
        // e^{s}·Φ̂ to round-off, for every n including 0 and 1.
        let step = Mat::from_fn(3, 3, |i, j| c64::new(10.0 + i as f64 - 2.0 * j as f64, 0.5 * (i * j) as f64));
        for n in [0usize, 1, 2, 3, 7, 16, 40] {
            let p = ScaledProduct::power(step.as_ref(), n);
            let mut r = ScaledProduct::identity(3);
            for _ in 0..n {
                r.left_multiply(step.as_ref());
            }
            let scale = (p.log_scale - r.log_scale).exp();
            let err = (0..3)
                .flat_map(|i| (0..3).map(move |j| (i, j)))
                .map(|(i, j)| (p.matrix[(i, j)] * scale - r.matrix[(i, j)]).norm())
                .fold(0.0, f64::max);
            assert!(err < 1e-12 * r.matrix.norm_max(), "n = {n}: {err}");
        }
    }

    #[test]
    fn tiny_products_are_rescaled_up() {
        let mut p = ScaledProduct::identity(2);
        let step = Mat::from_fn(2, 2, |i, j| c64::new(if i == j { 1e-60 } else { 0.0 }, 0.0));
        for _ in 0..20 {
            p.left_multiply(step.as_ref());
        }
        // (1e-60)^20 = 1e-1200 underflows; the scaled product keeps it exactly.
        let ln = p.matrix[(0, 0)].norm().ln() + p.log_scale;
        assert!((ln - 20.0 * (1e-60f64).ln()).abs() < 1e-9 * ln.abs(), "{ln}");
    }
}
