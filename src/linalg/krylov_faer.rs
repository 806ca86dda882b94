//! The eigenpairs nearest σ of [`ShiftInvert`]'s operator by faer's own partial
//! eigensolver (`faer::matrix_free::eigen::partial_eigen`: Krylov–Schur from a single
//! start vector) instead of the block Krylov space of `krylov.rs`: the same operator
//! Op = (A − σB)⁻¹·B in the same energy coordinates with the same LU of P(σ), the same
//! number of eigenvalues asked and the same last step ([`ShiftInvert::resolve`]: the
//! radius, the clusters, one power step, the displacements). Not used by `modes`: kept as
//! the block solver's comparison (benches/modes.rs, group `krylov-vs-faer`), against
//! which it measured slower on the 200-element rotor and falls back to the dense solve on
//! double whirls (docs/decisions.md, issue 48).
//!
//! faer's pairs are taken as it returns them, on its own convergence test: its
//! tolerance is absolute, on its estimate of ‖Op·y − θ·y‖, and is asked as
//! [`KRYLOV_TOLERANCE`]·‖Op·v₀‖ (v₀ the unit start vector, ‖Op·v₀‖ ≤ |θ₁| for a nearly
//! normal Op). The block solver's own test, an explicit relative residual of
//! [`KRYLOV_TOLERANCE`]·|θ| for every pair, is not applied: measured on the 200-element
//! rotor, faer's lowest pair has a relative residual of 3.7e-11 (3.8e-13 on the
//! 28-element one) whatever tolerance is asked, down to 1e-21·|θ₁|, and neither
//! Rayleigh–Ritz on the span of its vectors nor one more application of Op to that span
//! improved it. The whirls' QEP residuals are checked by the caller
//! ([`crate::analysis::modes::whirl_modes_nearest_by`]) as for the block solver.

use super::krylov::{NearestEigen, ShiftInvert, KRYLOV_TOLERANCE};
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::matrix_free::eigen::{partial_eigen, partial_eigen_scratch, PartialEigenParams};
use faer::matrix_free::LinOp;
use faer::{c64, Mat, MatMut, MatRef, Par};

/// faer's smallest default projection space (its `MIN_DIM` doubled): it uses
/// max(this, 2 × asked) vectors, or the whole state when that is larger.
const FAER_MIN_SPACE: usize = 64;

/// [`ShiftInvert`]'s operator as faer's [`LinOp`].
struct Operator<'s, 'a> {
    op: &'s ShiftInvert<'a>,
}

impl core::fmt::Debug for Operator<'_, '_> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "ShiftInvert({0} × {0})", self.op.state())
    }
}

impl LinOp<f64> for Operator<'_, '_> {
    fn apply_scratch(&self, _rhs_ncols: usize, _par: Par) -> StackReq {
        StackReq::EMPTY
    }

    fn nrows(&self) -> usize {
        self.op.state()
    }

    fn ncols(&self) -> usize {
        self.op.state()
    }

    fn apply(&self, out: MatMut<'_, f64>, rhs: MatRef<'_, f64>, _par: Par, _stack: &mut MemStack) {
        self.op.apply(rhs, out);
    }

    fn conj_apply(&self, out: MatMut<'_, f64>, rhs: MatRef<'_, f64>, _par: Par, _stack: &mut MemStack) {
        // Real: the conjugate is the operator itself.
        self.op.apply(rhs, out);
    }
}

impl ShiftInvert<'_> {
    /// At least `wanted` eigenpairs nearest σ, as [`ShiftInvert::nearest`], by faer's
    /// partial eigensolver, whose projection space (max(64, 2 × asked), or the whole
    /// state) must be at most `limit` vectors. `None` when faer converges fewer than
    /// `wanted` within the radius of the pairs it returns (or a cluster as large as the
    /// block is among them).
    pub fn nearest_by_faer(&self, wanted: usize, limit: usize) -> Option<NearestEigen> {
        let big = self.state();
        // Two beyond the count: a conjugate pair is not split at the end, and the last
        // modulus returned bounds the radius.
        let asked = (wanted + 2).min(big);
        let dimension = FAER_MIN_SPACE.max(2 * asked).min(big);
        if dimension > limit.max(asked) {
            return None;
        }
        let operator = Operator { op: self };
        let start = self.start();
        let mut image = Mat::<f64>::zeros(big, 1);
        self.apply(start, image.as_mut());
        let scale = image.norm_l2();
        if !(scale > 0.0 && scale.is_finite()) {
            return None;
        }
        let params = PartialEigenParams::default();
        let mut mem = MemBuffer::new(partial_eigen_scratch::<f64>(&operator, asked, Par::Seq, params));
        let mut vectors = Mat::<c64>::zeros(big, asked);
        let mut values = vec![c64::new(0.0, 0.0); asked];
        let info = partial_eigen::<f64>(
            vectors.as_mut(),
            &mut values,
            &operator,
            start.col(0),
            KRYLOV_TOLERANCE * scale,
            Par::Seq,
            MemStack::new(&mut mem),
            params,
        );
        let found = info.n_converged_eigen.min(asked);
        let mut taken = Vec::with_capacity(found);
        for (c, &theta) in values.iter().enumerate().take(found) {
            let norm = (0..big).map(|i| vectors[(i, c)].norm_sqr()).sum::<f64>().sqrt();
            if !(norm > 0.0 && norm.is_finite() && theta.norm() > 0.0 && theta.norm().is_finite()) {
                return None;
            }
            taken.push((theta, (0..big).map(|i| vectors[(i, c)] / norm).collect::<Vec<_>>()));
        }
        // By |θ| descending, the conjugates of a pair adjacent (Im θ descending).
        taken.sort_by(|a, b| b.0.norm().total_cmp(&a.0.norm()).then(b.0.im.total_cmp(&a.0.im)));
        // Nothing is known beyond the last pair returned, unless faer solved the whole
        // state densely.
        let radius = match taken.last() {
            _ if dimension == big && found == big => f64::INFINITY,
            Some((theta, _)) => 1.0 / theta.norm(),
            None => return None,
        };
        self.resolve(taken, radius, wanted, dimension)
    }
}
