//! The fast monodromy path.
//!
//! 1. **Integrator**: fourth-order commutator-free Magnus (CFM4, two Gauss points): each
//!    step of length h is `exp(τ(B0 + x₂B1))·exp(τ(B0 + x₁B1))` with τ = h/2 and scalars
//!    x_i = 2β(w_i·cos φt₁ + w̄_i·cos φt₂). B0 is integrated exactly inside each
//!    exponential, so the error depends on the parametric coupling, not on the highest
//!    whirl frequency (measured: N⁻⁴ convergence with h·ω_max up to 8).
//! 2. **Exponentials shared across β and steps**: for one φ every exponential is
//!    E(x) = exp(τ(B0 + xB1)) for a scalar x with |x| ≤ x_max, an entire function of x.
//!    It is interpolated once per φ at Chebyshev points (a handful of exponentials); for
//!    each β the steps' exponentials Σ_j c_j·T_j(x/x_max) are then formed 8 at a time as
//!    one real matrix product (coefficients × Chebyshev values).
//! 3. **Half a period**: with X = [[0, I], [I, D̃]] (complex symmetric, constant),
//!    B(t)ᵀ = X·B(t)·X⁻¹, so every step satisfies Eᵀ = X·E·X⁻¹. cos φt is symmetric about
//!    T/2, so the exponentials of the second half are those of the first in reverse order,
//!    and Φ(T) = X⁻¹·Lᵀ·X·L with L the first half's product.
//! 4. **Real arithmetic**: the complex products and the exponentials at the Chebyshev
//!    points are real ones in split form ([`SplitMatrix`]: Taylor exponential, no linear
//!    solve), ~1.8× and 1.3–2× faster than faer's complex product and the Padé `expm`
//!    (`cargo bench --bench kernels`). [`monodromy_cfm4_direct`] keeps the Padé `expm`
//!    and complex products: the test of the fast path against it checks these too.

use super::product::{ScaledProduct, ScaledSplit};
use super::PointIssue;
use crate::analysis::reduction::PeriodicSystem;
use crate::linalg::{expm, with_modulus, ExpWorkspace, SplitMatrix};
use faer::linalg::matmul::matmul;
use faer::{c64, Accum, Mat, MatRef, Par};

/// Largest Chebyshev degree tried; beyond it the point is flagged (see [`PhiTable::converged`]).
const MAX_CHEBYSHEV_POINTS: usize = 64;
/// Chebyshev point counts tried, in order (the interpolant is rebuilt at each). Every
/// count up to 10: the coefficient bound picks the smallest that suffices, and on the
/// paper's problems that is 5–10 at the first attempt.
const CHEBYSHEV_DEGREES: [usize; 15] = [4, 5, 6, 7, 8, 9, 10, 12, 14, 16, 20, 24, 32, 48, 64];
/// Largest coupling a = x_max·‖τB1‖ (frequency-scaled) per exponential before the step
/// count is doubled. The interpolant converges at any a (its degree grows like a), but the
/// CFM4 error does not: at β = 400, φ = 100 rad/s (a ≈ 35 at the default steps) ln max|μ|
/// was 3.6e-5 off an RK4 reference. On the paper's charts (β ≤ 1) a stays below 0.5.
pub const MAX_COUPLING: f64 = 2.0;
/// Most CFM4 steps per period the automatic doubling goes to.
pub const MAX_STEPS: usize = 4096;
/// Relative size of the trailing Chebyshev coefficients accepted as converged. Summed
/// over the steps of a period (32 by default) the interpolation error is of order
/// 3e-10 of Φ: far below the CFM4 error (1e-6 of a converged reference) and the
/// instability tolerance (1e-4), and inside the 1e-9 the fast path is checked to against
/// the straightforward CFM4 (tests/floquet_paths.rs); a tighter value buys digits no
/// verdict uses (docs/decisions.md, "Chebyshev tolerance").
const CHEBYSHEV_TOLERANCE: f64 = 1e-11;

/// The Chebyshev point count a table tries first at coupling `a` per exponential: the
/// smallest whose coefficient bound 2(a/2)^(p−2)/(p−2)! is below a tenth of
/// [`CHEBYSHEV_TOLERANCE`] (8 when none is).
pub(crate) fn first_chebyshev_points(a: f64) -> usize {
    let bound = |p: usize| 2.0 * (1..=p - 2).fold(1.0, |acc, i| acc * (a / 2.0) / i as f64);
    CHEBYSHEV_DEGREES.iter().copied().find(|&p| bound(p) <= 0.1 * CHEBYSHEV_TOLERANCE).unwrap_or(8)
}

/// The Chebyshev point counts a table tries after `points` when it has not converged.
pub(crate) fn chebyshev_points_after(points: usize) -> impl Iterator<Item = usize> {
    CHEBYSHEV_DEGREES.into_iter().filter(move |&p| p > points)
}

/// The CFM4 weights and nodes (Blanes & Moan; Alvermann & Fehske).
fn cfm4() -> ((f64, f64), (f64, f64)) {
    let r3 = 3f64.sqrt();
    ((0.5 - r3 / 6.0, 0.5 + r3 / 6.0), (0.25 + r3 / 6.0, 0.25 - r3 / 6.0))
}

/// Everything that depends on φ but not on β: the step scalars and the Chebyshev
/// interpolant of E(x).
#[derive(Debug, Clone)]
pub struct PhiTable {
    /// Excitation frequency φ (rad/s).
    pub phi: f64,
    /// Steps per period N (even).
    pub steps: usize,
    /// x = β·ξ for the exponentials of the first half period, in order of application.
    xi: Vec<f64>,
    /// Interval half-width of the interpolant in x.
    x_max: f64,
    /// Chebyshev coefficients, one per column (c₀ halved, so E(x) = Σ_j c_j·T_j(x/x_max)):
    /// rows 0..n² hold the real parts of the n×n matrix (column-major), rows n²..2n² the
    /// imaginary parts — a real matrix, so that many exponentials are one real product.
    cheb: Mat<f64>,
    /// State dimension n = 2M.
    n: usize,
    /// False if the interpolant did not reach its tolerance (trailing Chebyshev
    /// coefficients below `CHEBYSHEV_TOLERANCE` of the leading one).
    pub converged: bool,
    /// a = x_max·‖τB1‖ in frequency-scaled coordinates: the parametric coupling over
    /// one exponential, which drives both the interpolant's degree and the CFM4 error.
    coupling: f64,
    /// Whether `xi` covers the whole period (the real coordinates, where no transpose
    /// symmetry closes it from its first half) or its first half.
    full_period: bool,
}

/// Columns of exponentials evaluated per real matrix product in [`PhiTable::monodromy`]:
/// 8 columns of 2n² = 512 (M = 8) are 32 KB, which stay in the L1 cache (wider blocks
/// were slower: docs/decisions.md, "Exponential blocks").
const EVALUATION_BATCH: usize = 8;

/// The split real form of an n×n complex matrix written into one column `out` (2n² long):
/// real parts, then imaginary, each column-major — its row form [E_r E_i] — with entry
/// (i, j) multiplied by `factor(i, j)`.
fn split_into(m: &SplitMatrix, factor: impl Fn(usize, usize) -> f64, out: &mut [f64]) {
    let (n, row) = (m.size(), m.row());
    let n2 = n * n;
    for j in 0..n {
        for i in 0..n {
            let (k, f) = (i + j * n, factor(i, j));
            out[k] = row[(i, j)] * f;
            out[n2 + k] = row[(i, n + j)] * f;
        }
    }
}

impl PhiTable {
    /// Precompute for φ (rad/s), at least `steps` CFM4 steps per period (rounded up to
    /// even) and loads up to `beta_max`. Where E(x) varies too much over one step for the
    /// interpolant to converge (long periods, large β), the step count is doubled: both
    /// the interpolant and the CFM4 error are governed by τ·‖B1‖·β.
    ///
    /// `full_period`: step the whole period (the real coordinates: with D̃ not symmetric,
    /// the symmetry X of [`Symmetry`] does not hold) instead of half of it.
    pub fn new(sys: &PeriodicSystem, phi: f64, beta_max: f64, steps: usize, full_period: bool) -> PhiTable {
        let mut steps = steps;
        loop {
            let t = PhiTable::build(sys, phi, beta_max, steps, full_period);
            if (t.converged && t.coupling <= MAX_COUPLING) || steps >= MAX_STEPS {
                return t;
            }
            steps *= 2;
        }
    }

    fn build(sys: &PeriodicSystem, phi: f64, beta_max: f64, steps: usize, full_period: bool) -> PhiTable {
        let steps = steps.max(2).next_multiple_of(2);
        let n = sys.b0.nrows();
        let h = 2.0 * std::f64::consts::PI / phi / steps as f64;
        let tau = h / 2.0;
        let ((c1, c2), (w1, w2)) = cfm4();
        let mut xi = Vec::with_capacity(steps);
        let stepped = if full_period { steps } else { steps / 2 };
        for k in 0..stepped {
            let t = k as f64 * h;
            let (f1, f2) = ((phi * (t + c1 * h)).cos(), (phi * (t + c2 * h)).cos());
            xi.push(2.0 * (w1 * f1 + w2 * f2));
            xi.push(2.0 * (w2 * f1 + w1 * f2));
        }
        let x_max = beta_max * xi.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        // In the coordinates [q̇; w·q] every block of τB is ~τω ≲ 1 instead of τω²: exp is
        // computed there (no squaring) and scaled back (PeriodicSystem::frequency_scaling).
        let scale = sys.frequency_scaling();
        // τB0 and τB1 in the scaled coordinates, formed once per table.
        let scaled = |b: &Mat<c64>| {
            SplitMatrix::from_complex(Mat::from_fn(n, n, |i, j| b[(i, j)] * (tau * scale[i] / scale[j])).as_ref())
        };
        let (b0, b1) = (scaled(&sys.b0), scaled(&sys.b1));
        // E(x) into a column, scaled back.
        let (mut arg, mut workspace) = (b0.clone(), ExpWorkspace::new(n));
        let mut e = |x: f64, out: &mut [f64]| {
            arg.copy_from(&b0);
            arg.add_scaled(x, &b1);
            split_into(arg.exp_in(&mut workspace), |i, j| scale[j] / scale[i], out);
        };
        if x_max == 0.0 {
            let mut cheb = Mat::<f64>::zeros(2 * n * n, 1);
            e(0.0, cheb.col_as_slice_mut(0));
            return PhiTable { phi, steps, xi, x_max, cheb, n, converged: true, coupling: 0.0, full_period };
        }
        // Chebyshev coefficients of E(x) decay like those of e^{a·u}, u ∈ [−1, 1], with
        // a = x_max·‖τB1‖ (balanced coordinates): c_k ≈ 2(a/2)^k/k!. Start from the
        // smallest degree that bound accepts, rather than from a fixed 8 doubled to 16:
        // a failed attempt costs as many exponentials as the interpolant itself.
        let a = x_max * b1.norm1();
        let mut points = first_chebyshev_points(a);
        loop {
            // Samples at the Chebyshev points, one split column each; the coefficients are
            // their discrete cosine transform, one real product: C = S·W.
            let mut s_mat = Mat::<f64>::zeros(2 * n * n, points);
            for j in 0..points {
                let x = x_max * (std::f64::consts::PI * (j as f64 + 0.5) / points as f64).cos();
                e(x, s_mat.col_as_slice_mut(j));
            }
            let w = Mat::from_fn(points, points, |j, k| {
                let c =
                    2.0 / points as f64 * (std::f64::consts::PI * k as f64 * (j as f64 + 0.5) / points as f64).cos();
                if k == 0 {
                    0.5 * c
                } else {
                    c
                }
            });
            let mut cheb = Mat::<f64>::zeros(2 * n * n, points);
            matmul(cheb.as_mut(), Accum::Replace, s_mat.as_ref(), w.as_ref(), 1.0, Par::Seq);
            // Largest |entry| of coefficient k (the halved c₀ counts twice).
            let size = |k: usize| {
                let (re, im) = cheb.col_as_slice(k).split_at(n * n);
                let m = with_modulus(|modulus| re.iter().zip(im).map(|(x, y)| modulus(*x, *y)).fold(0.0, f64::max));
                if k == 0 {
                    2.0 * m
                } else {
                    m
                }
            };
            let scale = size(0).max(1e-300);
            let tail = (points - 2..points).map(size).fold(0.0, f64::max);
            // Non-finite samples (an exponential that overflowed) are never converged:
            // `inf <= tol·inf` would say they are.
            let finite = (0..points).all(|k| size(k).is_finite());
            let converged = finite && tail <= CHEBYSHEV_TOLERANCE * scale;
            if converged || points >= MAX_CHEBYSHEV_POINTS {
                return PhiTable { phi, steps, xi, x_max, cheb, n, converged, coupling: a, full_period };
            }
            points = CHEBYSHEV_DEGREES.iter().copied().find(|&p| p > points).unwrap_or(MAX_CHEBYSHEV_POINTS);
        }
    }

    /// Number of Chebyshev terms of the interpolant.
    pub fn terms(&self) -> usize {
        self.cheb.ncols()
    }

    /// a = x_max·‖τB1‖, the parametric coupling over one exponential (frequency-scaled).
    pub fn coupling(&self) -> f64 {
        self.coupling
    }

    /// Why points from this table are less accurate than the path states, if they are:
    /// the interpolant did not converge, or the coupling per exponential is still above
    /// [`MAX_COUPLING`] at the most steps the doubling takes (the CFM4 error is then not
    /// controlled: huge β·P_cr against a long period).
    pub fn issue(&self) -> Option<PointIssue> {
        if !self.converged {
            Some(PointIssue::Interpolant { terms: self.terms() })
        } else if self.coupling.is_nan() || self.coupling > MAX_COUPLING {
            Some(PointIssue::Coupling { coupling: self.coupling, steps: self.steps })
        } else {
            None
        }
    }

    /// Monodromy Φ(T) at load β (≤ the table's β_max), with the symmetry X. The step
    /// exponentials E(β·ξ_k) = Σ_j c_j·T_j(β·ξ_k/x_max) are formed a batch at a time as one
    /// real matrix product (coefficients × Chebyshev values): the same sums Clenshaw's
    /// recurrence would give, at matrix-multiply speed.
    pub fn monodromy(&self, sym: &Symmetry, beta: f64) -> ScaledProduct {
        let (n, n2, p) = (self.n, self.n * self.n, self.terms());
        let mut half: Option<ScaledSplit> = None;
        let mut values = Mat::<f64>::zeros(2 * n2, EVALUATION_BATCH);
        let mut t = Mat::<f64>::zeros(p, EVALUATION_BATCH);
        for chunk in self.xi.chunks(EVALUATION_BATCH) {
            // T_j(u) for each u = β·ξ/x_max of the batch, by the three-term recurrence.
            for (k, &xi) in chunk.iter().enumerate() {
                let u = if self.x_max > 0.0 { beta * xi / self.x_max } else { 0.0 };
                t[(0, k)] = 1.0;
                if p > 1 {
                    t[(1, k)] = u;
                }
                for j in 2..p {
                    t[(j, k)] = 2.0 * u * t[(j - 1, k)] - t[(j - 2, k)];
                }
            }
            let out = values.as_mut().subcols_mut(0, chunk.len());
            matmul(out, Accum::Replace, self.cheb.as_ref(), t.as_ref().subcols(0, chunk.len()), 1.0, Par::Seq);
            for k in 0..chunk.len() {
                // A column holds E_r then E_i, each column-major: the n×2n row form [E_r E_i].
                let step = MatRef::from_column_major_slice(values.col_as_slice(k), n, 2 * n);
                match half.as_mut() {
                    Some(h) => h.left_multiply(step),
                    None => half = Some(ScaledSplit::new(step)),
                }
            }
        }
        match half {
            Some(h) if self.full_period => ScaledProduct::from_matrix(h.matrix.to_complex(), h.log_scale),
            Some(h) => sym.close_period(&h),
            None => ScaledProduct::identity(n),
        }
    }
}

/// X = [[0, I], [I, D̃]] and X⁻¹ = [[−D̃, I], [I, 0]] of the state y = [q̇; q].
#[derive(Debug, Clone)]
pub struct Symmetry {
    x: SplitMatrix,
    x_inv: SplitMatrix,
}

impl Symmetry {
    /// From B0 = [−D̃, ·; I, 0]: D̃ is minus its upper-left block.
    pub fn new(sys: &PeriodicSystem) -> Symmetry {
        let m = sys.b0.nrows() / 2;
        let d = |i: usize, j: usize| -sys.b0[(i, j)];
        let one = |c: bool| c64::new(if c { 1.0 } else { 0.0 }, 0.0);
        let x = Mat::from_fn(2 * m, 2 * m, |i, j| match (i < m, j < m) {
            (true, true) => one(false),
            (true, false) => one(i == j - m),
            (false, true) => one(i - m == j),
            (false, false) => d(i - m, j - m),
        });
        let x_inv = Mat::from_fn(2 * m, 2 * m, |i, j| match (i < m, j < m) {
            (true, true) => -d(i, j),
            (true, false) => one(i == j - m),
            (false, true) => one(i - m == j),
            (false, false) => one(false),
        });
        Symmetry { x: SplitMatrix::from_complex(x.as_ref()), x_inv: SplitMatrix::from_complex(x_inv.as_ref()) }
    }

    /// Φ(T) = X⁻¹·Lᵀ·X·L from the half-period product L.
    pub fn close_period(&self, half: &ScaledSplit) -> ScaledProduct {
        let n = half.matrix.size();
        let mut xl = SplitMatrix::zeros(n);
        xl.set_product(self.x.row(), &half.matrix);
        let mut ltxl = SplitMatrix::zeros(n);
        ltxl.set_product(half.matrix.transposed_row().as_ref(), &xl);
        let mut full = SplitMatrix::zeros(n);
        full.set_product(self.x_inv.row(), &ltxl);
        ScaledProduct::from_matrix(full.to_complex(), 2.0 * half.log_scale)
    }
}

/// CFM4 with a fresh `expm` for every exponential and the full period stepped: the
/// straightforward form of the same integrator, kept to check the fast one.
pub fn monodromy_cfm4_direct(sys: &PeriodicSystem, phi: f64, beta: f64, steps: usize) -> ScaledProduct {
    let n = sys.b0.nrows();
    let h = 2.0 * std::f64::consts::PI / phi / steps as f64;
    let ((c1, c2), (w1, w2)) = cfm4();
    let mut prod = ScaledProduct::identity(n);
    for k in 0..steps {
        let t = k as f64 * h;
        let (f1, f2) = ((phi * (t + c1 * h)).cos(), (phi * (t + c2 * h)).cos());
        for (a, b) in [(w1, w2), (w2, w1)] {
            let x = 2.0 * beta * (a * f1 + b * f2);
            let e = Mat::from_fn(n, n, |i, j| (sys.b0[(i, j)] + sys.b1[(i, j)] * x) * (h / 2.0));
            prod.left_multiply(expm(e.as_ref()).as_ref());
        }
    }
    prod
}
