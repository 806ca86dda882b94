//! Complex matrix products and exponentials in real arithmetic.
//!
//! A complex n×n matrix A = A_r + i·A_i is held as the real 2n×2n block matrix
//! [[A_r, A_i], [−A_i, A_r]], whose top n rows [A_r A_i] are its *row form*. The row form
//! of a product is a real product, [A_r A_i]·[[B_r, B_i], [−B_i, B_r]] =
//! [A_rB_r − A_iB_i, A_rB_i + A_iB_r], and the bottom rows are copies of the top ones.
//! The exponential is a Taylor polynomial of such products ([`SplitMatrix::exp_in`]).
//!
//! Why: for the 16×16 matrices of the paper's reduced model faer's complex kernel takes
//! ~1.4 µs per product, the real 16×32·32×32 product ~0.8 µs, and the Taylor exponential
//! 1.3–2× less than the Padé `expm` with its linear solve (`cargo bench --bench kernels`,
//! same run). The fast monodromy path uses these; the reference paths keep faer's complex
//! products and the Padé `expm`, so the two stay independent.

use super::with_modulus;
use faer::linalg::matmul::matmul;
use faer::{c64, Accum, Mat, MatRef, Par};

/// A complex n×n matrix in block form [[A_r, A_i], [−A_i, A_r]] (real 2n×2n).
#[derive(Debug, Clone)]
pub struct SplitMatrix {
    block: Mat<f64>,
}

impl SplitMatrix {
    /// The n×n zero matrix.
    pub fn zeros(n: usize) -> SplitMatrix {
        SplitMatrix { block: Mat::zeros(2 * n, 2 * n) }
    }

    /// From a complex matrix.
    pub fn from_complex(a: MatRef<'_, c64>) -> SplitMatrix {
        let n = a.nrows();
        let mut s = SplitMatrix::zeros(n);
        for j in 0..n {
            for i in 0..n {
                s.block[(i, j)] = a[(i, j)].re;
                s.block[(i, n + j)] = a[(i, j)].im;
            }
        }
        s.complete();
        s
    }

    /// The complex matrix.
    pub fn to_complex(&self) -> Mat<c64> {
        let n = self.size();
        Mat::from_fn(n, n, |i, j| c64::new(self.block[(i, j)], self.block[(i, n + j)]))
    }

    /// n, the complex size.
    pub fn size(&self) -> usize {
        self.block.nrows() / 2
    }

    /// The row form [A_r A_i] (n×2n).
    pub fn row(&self) -> MatRef<'_, f64> {
        self.block.as_ref().subrows(0, self.size())
    }

    /// Set from a row form [A_r A_i] (n×2n).
    pub fn set_row(&mut self, row: MatRef<'_, f64>) {
        let n = self.size();
        self.block.as_mut().subrows_mut(0, n).copy_from(row);
        self.complete();
    }

    /// self ← A·B, A given by its row form (n×2n).
    pub fn set_product(&mut self, a_row: MatRef<'_, f64>, b: &SplitMatrix) {
        let n = self.size();
        let top = self.block.as_mut().subrows_mut(0, n);
        matmul(top, Accum::Replace, a_row, b.block.as_ref(), 1.0, Par::Seq);
        self.complete();
    }

    /// Largest |real or imaginary part| of an entry.
    pub fn norm_max(&self) -> f64 {
        self.row().norm_max()
    }

    /// The complex 1-norm: the largest column sum of moduli ([`with_modulus`], as
    /// [`crate::linalg::norm1`]). NaN if an entry is NaN.
    pub fn norm1(&self) -> f64 {
        let n = self.size();
        with_modulus(|modulus| {
            (0..n)
                .map(|j| {
                    let (re, im) = (self.block.col_as_slice(j), self.block.col_as_slice(n + j));
                    re[..n].iter().zip(&im[..n]).map(|(x, y)| modulus(*x, *y)).sum::<f64>()
                })
                .fold(0.0, |m: f64, x| if x.is_nan() { f64::NAN } else { m.max(x) })
        })
    }

    /// self ← other (same size).
    pub fn copy_from(&mut self, other: &SplitMatrix) {
        self.block.copy_from(&other.block);
    }

    /// self ← self + c·other.
    pub fn add_scaled(&mut self, c: f64, other: &SplitMatrix) {
        let terms = std::slice::from_ref(other);
        let rows = 2 * self.size();
        pulp::Arch::new().dispatch(Combination { acc: &mut self.block, identity: 0.0, c: &[c], terms, rows });
    }

    /// Multiply by a real factor.
    pub fn scale(&mut self, factor: f64) {
        for j in 0..self.block.ncols() {
            for x in self.block.col_as_slice_mut(j) {
                *x *= factor;
            }
        }
    }

    /// The row form of the transpose Aᵀ: [A_rᵀ A_iᵀ].
    pub fn transposed_row(&self) -> Mat<f64> {
        let n = self.size();
        Mat::from_fn(n, 2 * n, |i, j| if j < n { self.block[(j, i)] } else { self.block[(j - n, n + i)] })
    }

    /// e^A by its Taylor polynomial, evaluated by Paterson–Stockmeyer, with scaling and
    /// squaring above `TAYLOR_DEGREES`' last degree. Every product is a real one; there
    /// is no linear solve (a Padé approximant needs one, which for 16×16 costs as much as
    /// three products). Input with an infinite or NaN entry, or a 1-norm beyond f64::MAX,
    /// gives a matrix of NaN at once.
    pub fn exp(&self) -> SplitMatrix {
        let mut workspace = ExpWorkspace::new(self.size());
        self.exp_in(&mut workspace).clone()
    }

    /// [`Self::exp`] in a reusable workspace (no allocation after the first call of a
    /// size); the result lives in the workspace.
    pub fn exp_in<'w>(&self, ws: &'w mut ExpWorkspace) -> &'w SplitMatrix {
        let n = self.size();
        if ws.acc.size() != n {
            *ws = ExpWorkspace::new(n);
        }
        let norm = self.norm1();
        // Infinite or NaN entries (or a 1-norm beyond f64::MAX, whose exponential overflows).
        if !norm.is_finite() {
            ws.acc.block.fill(f64::NAN);
            return &ws.acc;
        }
        let (degree, block, squarings) = taylor_plan(norm);
        // 1/k! for k = 0..=degree.
        let mut c = [1.0; TAYLOR_MAX_DEGREE + 1];
        for k in 1..=degree {
            c[k] = c[k - 1] / k as f64;
        }
        // powers[k − 1] = A^k for k = 1 … s, s = the block size.
        let powers = &mut ws.powers;
        powers[0].block.copy_from(&self.block);
        if squarings > 0 {
            powers[0].scale(0.5f64.powi(squarings));
        }
        for k in 2..=block {
            let (done, rest) = powers.split_at_mut(k - 1);
            rest[0].set_product(done[k - 2].row(), &done[0]);
        }
        let powers = &ws.powers[..block];
        // T(A) = Σ_i B_i·(A^s)^i with B_i = Σ_{l<s} c_{is+l}·A^l, by Horner in A^s; the top
        // block B_r = c_m·I is folded into the first step (m = r·s).
        let blocks = degree / block;
        let (acc, next) = (&mut ws.acc, &mut ws.next);
        acc.block.as_mut().subrows_mut(0, n).fill(0.0);
        acc.add_combination_top(&c[(blocks - 1) * block..=degree], powers);
        acc.complete();
        for i in (0..blocks - 1).rev() {
            matmul(
                next.block.as_mut().subrows_mut(0, n),
                Accum::Replace,
                powers[block - 1].row(),
                acc.block.as_ref(),
                1.0,
                Par::Seq,
            );
            next.add_combination_top(&c[i * block..(i + 1) * block], powers);
            next.complete();
            std::mem::swap(acc, next);
        }
        for _ in 0..squarings {
            next.set_product(acc.row(), acc);
            std::mem::swap(acc, next);
        }
        &ws.acc
    }

    /// Top rows only (the bottom rows follow at [`Self::complete`]): self ← self +
    /// c_0·I + Σ_{l≥1} c_l·powers[l − 1], in one pass over each column.
    fn add_combination_top(&mut self, c: &[f64], powers: &[SplitMatrix]) {
        let (identity, c, terms, rows) = (c[0], &c[1..], powers, self.size());
        pulp::Arch::new().dispatch(Combination { acc: &mut self.block, identity, c, terms, rows });
    }

    /// The bottom rows [−A_i, A_r] from the top ones.
    fn complete(&mut self) {
        let n = self.size();
        pulp::Arch::new().dispatch(Complete { block: &mut self.block, n });
    }
}

/// The element-wise loops of the exponential and the products, each a pulp kernel: pulp
/// runs it compiled for the widest SIMD instructions the processor has (runtime dispatch,
/// as in faer's own kernels), so that the loops vectorise. The results are the same bit
/// for bit (no reassociation).
///
/// acc ← acc + identity·I + Σ_l c_l·T_l on the first `rows` rows (n: the top rows, with
/// the identity; 2n: all rows, identity 0).
struct Combination<'a> {
    acc: &'a mut Mat<f64>,
    identity: f64,
    c: &'a [f64],
    terms: &'a [SplitMatrix],
    rows: usize,
}

impl pulp::WithSimd for Combination<'_> {
    type Output = ();

    #[inline(always)]
    #[expect(
        clippy::disallowed_macros,
        reason = "a debug-build guard for a future caller, compiled out of release builds: the two callers in \
                  this file pass identity 0 (add_scaled, all rows) or rows = n (add_combination_top), so the \
                  condition holds by construction"
    )]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        let (n, rows) = (self.acc.nrows() / 2, self.rows);
        // The identity goes on the top-left block only: callers complete the bottom rows.
        debug_assert!(rows == n || self.identity == 0.0);
        for j in 0..self.acc.ncols() {
            let x = &mut self.acc.col_as_slice_mut(j)[..rows];
            if j < n {
                x[j] += self.identity;
            }
            for (&cl, term) in self.c.iter().zip(self.terms) {
                for (x, y) in x.iter_mut().zip(&term.block.col_as_slice(j)[..rows]) {
                    *x += cl * y;
                }
            }
        }
    }
}

/// The bottom rows [−A_i, A_r] of a block from its top rows.
struct Complete<'a> {
    block: &'a mut Mat<f64>,
    n: usize,
}

impl pulp::WithSimd for Complete<'_> {
    type Output = ();

    #[inline(always)]
    #[expect(
        clippy::expect_used,
        reason = "an owned faer::Mat is column-major with unit row stride, so every column view of it is \
                  contiguous and the Option is always Some (faer's own col_as_slice_mut unwraps it alike); the \
                  matrix is SplitMatrix's own, never data. Copying through a buffer or a strided fallback cost \
                  4-15 % on the chart and the catalogue (docs/decisions.md)"
    )]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        let n = self.n;
        let (mut left, mut right) = self.block.split_at_col_mut(n);
        for j in 0..n {
            let contiguous = "the columns of an owned matrix are contiguous";
            let l = left.as_mut().col_mut(j).try_as_col_major_mut().expect(contiguous).as_slice_mut();
            let r = right.as_mut().col_mut(j).try_as_col_major_mut().expect(contiguous).as_slice_mut();
            let ((re, re_low), (im, im_low)) = (l.split_at_mut(n), r.split_at_mut(n));
            for (low, x) in re_low.iter_mut().zip(im.iter()) {
                *low = -x;
            }
            im_low.copy_from_slice(re);
        }
    }
}

/// Buffers of [`SplitMatrix::exp_in`]: the powers A^1 … A^s and two accumulators.
#[derive(Debug, Clone)]
pub struct ExpWorkspace {
    powers: Vec<SplitMatrix>,
    acc: SplitMatrix,
    next: SplitMatrix,
}

impl ExpWorkspace {
    /// Buffers for n×n matrices.
    pub fn new(n: usize) -> ExpWorkspace {
        let most = TAYLOR_DEGREES.iter().map(|&(_, s)| s).max().unwrap_or(1);
        let powers = (0..most).map(|_| SplitMatrix::zeros(n)).collect();
        ExpWorkspace { powers, acc: SplitMatrix::zeros(n), next: SplitMatrix::zeros(n) }
    }
}

/// The highest degree of [`TAYLOR_DEGREES`].
const TAYLOR_MAX_DEGREE: usize = 25;
#[expect(
    clippy::disallowed_macros,
    reason = "a compile-time check: evaluated by the compiler, a build that broke it would not compile"
)]
const _: () = assert!(TAYLOR_DEGREES[TAYLOR_DEGREES.len() - 1].0 == TAYLOR_MAX_DEGREE);

/// Taylor degrees m and their Paterson–Stockmeyer block sizes s (m a multiple of s; the
/// cost is s + m/s − 2 products: 3, 4, 5, 6, 7, 8).
const TAYLOR_DEGREES: [(usize, usize); 6] = [(6, 3), (9, 3), (12, 4), (16, 4), (20, 5), (25, 5)];

/// Most squarings (log2 of f64::MAX is 1024: any finite norm needs fewer).
const MAX_SQUARINGS: i32 = 1100;

/// The bound on the Taylor remainder of e^A of degree m at ‖A‖ = x:
/// Σ_{k>m} x^k/k! ≤ x^{m+1}/(m+1)!·1/(1 − x/(m+2)) for x < m + 2.
fn taylor_remainder(x: f64, m: usize) -> f64 {
    if x >= (m + 2) as f64 {
        return f64::INFINITY;
    }
    let term = (1..=m + 1).fold(1.0, |t, k| t * x / k as f64);
    term / (1.0 - x / (m + 2) as f64)
}

/// Whether degree m at ‖A‖ = x meets unit round-off relative to e^A: the remainder bound
/// below u·e^{−x}, since ‖e^A‖ ≥ 1/‖e^{−A}‖ ≥ e^{−x}.
fn taylor_accepts(x: f64, m: usize) -> bool {
    taylor_remainder(x, m) <= 0.5 * f64::EPSILON * (-x).exp()
}

/// (degree, block size, squarings) for ‖A‖ = `norm`: the cheapest degree that meets unit
/// round-off, or the last one after as many halvings as it needs.
fn taylor_plan(norm: f64) -> (usize, usize, i32) {
    if let Some(&(m, s)) = TAYLOR_DEGREES.iter().find(|&&(m, _)| taylor_accepts(norm, m)) {
        return (m, s, 0);
    }
    let (m, s) = TAYLOR_DEGREES[TAYLOR_DEGREES.len() - 1];
    let squarings = (1..MAX_SQUARINGS).find(|&k| taylor_accepts(norm * 0.5f64.powi(k), m)).unwrap_or(MAX_SQUARINGS);
    (m, s, squarings)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(n: usize, seed: f64) -> Mat<c64> {
        Mat::from_fn(n, n, |i, j| {
            let t = seed + (i * n + j) as f64;
            c64::new((0.7 * t).sin(), (1.3 * t).cos() - 0.2)
        })
    }

    #[test]
    fn split_product_matches_the_complex_product() {
        let n = 7;
        let (a, b) = (sample(n, 0.3), sample(n, 2.9));
        let mut exact = Mat::<c64>::zeros(n, n);
        matmul(exact.as_mut(), Accum::Replace, a.as_ref(), b.as_ref(), c64::new(1.0, 0.0), Par::Seq);
        let sa = SplitMatrix::from_complex(a.as_ref());
        let sb = SplitMatrix::from_complex(b.as_ref());
        let mut sc = SplitMatrix::zeros(n);
        sc.set_product(sa.row(), &sb);
        let c = sc.to_complex();
        // Round-off of a length-7 dot product of O(1) entries.
        let err = (0..n).flat_map(|i| (0..n).map(move |j| (i, j))).map(|(i, j)| (c[(i, j)] - exact[(i, j)]).norm());
        assert!(err.fold(0.0, f64::max) < 1e-14);
        // Linear combinations act on the block form: A + 2.5·B.
        let mut sum = SplitMatrix::zeros(n);
        sum.copy_from(&sa);
        sum.add_scaled(2.5, &sb);
        let exact = SplitMatrix::from_complex(Mat::from_fn(n, n, |i, j| a[(i, j)] + b[(i, j)] * 2.5).as_ref());
        assert!(sum.block == exact.block, "the whole block, bottom rows too");
        // A product is a consistent block form.
        assert!(sc.block == SplitMatrix::from_complex(sc.to_complex().as_ref()).block);
        // The transpose's row form is the row form of Aᵀ.
        let mut st = SplitMatrix::zeros(n);
        st.set_row(sa.transposed_row().as_ref());
        let at = st.to_complex();
        assert!((0..n).all(|i| (0..n).all(|j| at[(i, j)] == a[(j, i)])));
    }

    #[test]
    fn taylor_exponential_agrees_with_nalgebra() {
        // As for `expm`; the scales (1-norms 0.0075 … 750) use every degree and the
        // squarings, which the test checks.
        let mut degrees = Vec::new();
        for (k, scale) in [0.0005, 0.005, 0.02, 0.03, 0.07, 0.1, 0.2, 0.5, 1.0, 10.0, 50.0].into_iter().enumerate() {
            let a = Mat::from_fn(16, 16, |i, j| sample(16, k as f64)[(i, j)] * scale);
            let split = SplitMatrix::from_complex(a.as_ref());
            degrees.push(taylor_plan(split.norm1()));
            let e = split.exp();
            let err = crate::linalg::testing::exp_error_against_nalgebra(&a, &e.to_complex());
            assert!(err < 1e-11, "scale {scale}: relative error {err}");
            // The result is a consistent block form.
            assert!(e.block == SplitMatrix::from_complex(e.to_complex().as_ref()).block);
        }
        assert!(TAYLOR_DEGREES.iter().all(|&(m, _)| degrees.iter().any(|p| p.0 == m && p.2 == 0)), "{degrees:?}");
        assert!(degrees.iter().any(|p| p.2 > 0));
    }

    #[test]
    fn taylor_plan_steps_up_with_the_norm() {
        // Unit round-off needs degree 6 near 0.01 and more squarings as the norm doubles.
        assert_eq!(taylor_plan(0.01), (6, 3, 0));
        let plans: Vec<_> = [0.1, 0.3, 0.7, 1.2, 2.0].iter().map(|&x| taylor_plan(x)).collect();
        assert!(plans.windows(2).all(|w| w[0].0 <= w[1].0));
        assert!(plans.iter().all(|p| p.2 == 0));
        let (_, _, s1) = taylor_plan(10.0);
        let (_, _, s2) = taylor_plan(20.0);
        assert_eq!(s2, s1 + 1);
        // The remainder bound is the series tail: at x = 1, m = 6 it is within 1/(1 − 1/8)
        // of 1/7!, above Σ_{k>6} 1/k! = e − Σ_{k≤6} 1/k!.
        let tail = std::f64::consts::E - (0..=6).map(|k| 1.0 / (1..=k).product::<usize>() as f64).sum::<f64>();
        let bound = taylor_remainder(1.0, 6);
        assert!(bound >= tail && bound < tail * 1.2, "{bound} vs {tail}");
    }

    #[test]
    fn taylor_exponential_of_non_finite_input_is_nan() {
        for bad in [f64::INFINITY, f64::NAN] {
            let mut a = sample(4, 1.0);
            a[(1, 2)] = c64::new(bad, 0.0);
            let e = SplitMatrix::from_complex(a.as_ref()).exp().to_complex();
            assert!((0..4).all(|i| (0..4).all(|j| e[(i, j)].re.is_nan())));
        }
        // Huge but finite: e^{−1e160·I} underflows to 0, as the Padé `expm` gives.
        let a = Mat::from_fn(3, 3, |i, j| c64::new(if i == j { -1e160 } else { 0.0 }, 0.0));
        let e = SplitMatrix::from_complex(a.as_ref()).exp().to_complex();
        assert!((0..3).all(|i| (0..3).all(|j| e[(i, j)] == c64::new(0.0, 0.0))));
    }

    #[test]
    fn norm1_is_the_complex_one_norm() {
        for a in [sample(9, 0.4), Mat::from_fn(2, 2, |i, j| c64::new(if i == j { 1e160 } else { 3e159 }, 1e159))] {
            let (ours, reference) = (SplitMatrix::from_complex(a.as_ref()).norm1(), crate::linalg::norm1(a.as_ref()));
            assert!((ours - reference).abs() <= 1e-15 * reference, "{ours} vs {reference}");
        }
    }
}
