//! The eigenvalues of the real quadratic eigenproblem `(λ²M + λD + K) x = 0` nearest a
//! real shift σ, with their vectors, without the dense solve of the whole spectrum: block
//! shift-invert Krylov with Rayleigh–Ritz.
//!
//! With the state z = [x; λx], the pencil A = [[0, I], [−K, −D]], B = [[I, 0], [0, M]]
//! has A·z = λ·B·z, and the operator Op = (A − σB)⁻¹·B has the eigenvalues
//! θ = 1/(λ − σ): those of λ nearest σ are the largest θ, which a Krylov space of Op
//! finds first. Op needs no M⁻¹ (a massless DOF is an infinite λ, θ = 0) and one LU of
//! the n × n dynamic stiffness P(σ) = K + σD + σ²M: for z = [u; v],
//! Op·z = [p; u + σp] with P(σ)·p = −M·v − (D + σM)·u.
//!
//! The space is built in the energy coordinates z̃ = [L_Sᵀ·x; L_Mᵀ·v] (M = L_M·L_Mᵀ,
//! K_s = (K + Kᵀ)/2 = L_S·L_Sᵀ), the coordinates of the dense solver's first-order form
//! ([`super::solve_qep_real`]): there a lightly damped Op is nearly normal, and a Ritz
//! pair's residual bounds its eigenvalue's error. In the plain coordinates [x; v] the
//! displacement of a whirl at |λ| is 1/|λ| of its velocity, and the shortest elements'
//! 12EI/l³ dwarf the modal stiffnesses: measured, the whirls of a 200-element rotor came
//! out 1e-7 from the dense solver's at 30 times the lowest, against 1e-10 now.
//!
//! The space is grown a block of [`KRYLOV_BLOCK`] vectors at a time from a seeded random
//! block (the same on every machine), orthonormalised twice against the basis (classical
//! Gram–Schmidt repeated, as DGKS), and H = Vᵀ·Op·V is formed explicitly, so the
//! Rayleigh–Ritz pairs do not rely on the Arnoldi recurrence. A block rather than a
//! single vector because a single Krylov sequence holds one vector of a multiple
//! eigenvalue: an isotropic rotor at rest has each whirl twice in real coordinates.
//!
//! Every kernel runs with `Par::Seq` ([`super::seq`]).

use super::seq::{self, Lu};
use faer::linalg::matmul::matmul;
use faer::linalg::matmul::triangular::{self, BlockStructure};
use faer::linalg::triangular_solve::solve_upper_triangular_in_place;
use faer::{c64, Accum, Mat, MatMut, MatRef, Par};

/// Vectors added to the Krylov space per step. Four: a whirl of an isotropic rotor at rest
/// is double in real coordinates, and two identical rings can double it again; a cluster
/// of as many eigenvalues as the block may hide more copies, and is refused
/// ([`NearestEigen`] is `None`).
pub const KRYLOV_BLOCK: usize = 4;

/// A Ritz pair (θ, y) is converged when ‖Op·y − θ·y‖ ≤ this × |θ|·‖y‖ (energy
/// coordinates). Round-off leaves ~ε·|θ₁| in Op·y (θ₁ the largest): measured 1.7e-15 to
/// 6e-15 of |θ| on the 200-element rotor's whirls up to 30 times the lowest, so 1e-13 is
/// met a few steps after a pair is resolved, by whirls up to ~100 times the lowest. The
/// operator being nearly normal there, the eigenvalue is as accurate, and the vector to
/// 1e-13 over its relative gap.
pub const KRYLOV_TOLERANCE: f64 = 1e-13;

/// Relative margin kept below the radius a solve is complete to: the two members of a
/// conjugate pair (equal |θ| to round-off) or of a degenerate whirl (equal to
/// [`crate::analysis::modes::DEGENERATE_WHIRLS`]) are returned together or not at all.
pub const RADIUS_MARGIN: f64 = 1e-8;

/// Relative distance below which returned eigenvalues are counted as one cluster for the
/// multiplicity check: as many as [`KRYLOV_BLOCK`] within it may hide one more copy the
/// block could not hold.
pub const CLUSTER_DISTANCE: f64 = 1e-8;

/// The eigenpairs nearest σ.
#[derive(Debug, Clone)]
pub struct NearestEigen {
    /// λ, by |λ − σ| ascending.
    pub values: Vec<c64>,
    /// x (the displacement half of z), unit 2-norm columns, in the order of `values`.
    pub vectors: Mat<c64>,
    /// Every eigenvalue with |λ − σ| below this is in `values` (∞ when the space is the
    /// whole state).
    pub radius: f64,
    /// The Krylov space's final dimension (for the record and the tests).
    pub dimension: usize,
}

/// A block shift-invert Krylov space of the pencil at σ, grown on demand.
pub struct ShiftInvert<'a> {
    sigma: f64,
    /// Cholesky factors of M and of K's symmetric part: the energy coordinates.
    l_m: Mat<f64>,
    l_s: Mat<f64>,
    /// D (the velocity matrix).
    d: MatRef<'a, f64>,
    lu: Lu,
    /// P(σ).
    p: Mat<f64>,
    /// Orthonormal basis, columns 0..basis.
    v: Mat<f64>,
    /// Op·V, columns 0..applied.
    w: Mat<f64>,
    /// Vᵀ·W over the applied columns.
    h: Mat<f64>,
    basis: usize,
    applied: usize,
    /// The last block Op was applied to: its first column and width.
    last: (usize, usize),
    limit: usize,
    seed: u64,
}

impl<'a> ShiftInvert<'a> {
    /// The operator at σ for `(λ²M + λD + K)x = 0` (n × n each), with a space of at most
    /// `limit` vectors (capped at the state's 2n). `None` when P(σ) is singular or not
    /// finite (σ an eigenvalue, a free body at σ = 0).
    pub fn new(
        m: MatRef<'a, f64>,
        d: MatRef<'a, f64>,
        k: MatRef<'a, f64>,
        sigma: f64,
        limit: usize,
    ) -> Option<ShiftInvert<'a>> {
        let n = m.nrows();
        let big = 2 * n;
        if n == 0 {
            return None;
        }
        let p = Mat::from_fn(n, n, |i, j| k[(i, j)] + sigma * d[(i, j)] + sigma * sigma * m[(i, j)]);
        if !(p.norm_max().is_finite() && d.norm_max().is_finite() && m.norm_max().is_finite()) {
            return None;
        }
        // The energy coordinates: a massless DOF or a stiffness whose symmetric part is
        // not positive definite has none (the dense solver takes those).
        let l_m = seq::cholesky(m).ok()?;
        let k_s = Mat::from_fn(n, n, |i, j| 0.5 * (k[(i, j)] + k[(j, i)]));
        let l_s = seq::cholesky(k_s.as_ref()).ok()?;
        let lu = Lu::new(p.as_ref());
        let (lo, hi) = lu.pivot_range();
        // A pivot at round-off of the largest: P(σ) is singular to working accuracy.
        if !(hi.is_finite() && lo > f64::EPSILON * hi) {
            return None;
        }
        let limit = limit.clamp(KRYLOV_BLOCK.min(big), big);
        let cap = (limit + KRYLOV_BLOCK).min(big);
        let mut me = ShiftInvert {
            sigma,
            l_m,
            l_s,
            d,
            lu,
            p,
            v: Mat::zeros(big, cap),
            w: Mat::zeros(big, cap),
            h: Mat::zeros(cap, cap),
            basis: 0,
            applied: 0,
            last: (0, 0),
            limit,
            seed: 0x9e37_79b9_7f4a_7c15,
        };
        let start = Mat::from_fn(big, KRYLOV_BLOCK.min(big), |_, _| me.random());
        me.append(start);
        Some(me)
    }

    /// A uniform number in [−0.5, 0.5) from a fixed-seed LCG: the same space everywhere.
    fn random(&mut self) -> f64 {
        self.seed = self.seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    }

    /// x = L_S⁻ᵀ·z̃₁: the displacements of a block in energy coordinates.
    fn displacement(&self, top: MatRef<'_, f64>) -> Mat<f64> {
        let mut x = top.to_owned();
        solve_upper_triangular_in_place(self.l_s.transpose(), x.as_mut(), Par::Seq);
        x
    }

    /// Op·Z̃ for a block Z̃ (2n × c) in energy coordinates: with x = L_S⁻ᵀ·z̃₁ and
    /// M·v = L_M·z̃₂, P(σ)·p = −M·v − (D + σM)·x and Op·z = [p; x + σp], returned as
    /// [L_Sᵀ·p; L_Mᵀ·(x + σp)].
    pub(super) fn apply(&self, z: MatRef<'_, f64>, out: MatMut<'_, f64>) {
        let n = self.l_m.nrows();
        let c = z.ncols();
        let (top, bottom) = z.split_at_row(n);
        let x = self.displacement(top);
        // rhs = −L_M·z̃₂ − D·x − σ·M·x.
        let mut rhs = Mat::<f64>::zeros(n, c);
        let lower = BlockStructure::TriangularLower;
        let full = BlockStructure::Rectangular;
        triangular::matmul(rhs.as_mut(), full, Accum::Replace, self.l_m.as_ref(), lower, bottom, full, -1.0, Par::Seq);
        matmul(rhs.as_mut(), Accum::Add, self.d, x.as_ref(), -1.0, Par::Seq);
        if self.sigma != 0.0 {
            let mut lx = Mat::<f64>::zeros(n, c);
            let upper = BlockStructure::TriangularUpper;
            triangular::matmul(
                lx.as_mut(),
                full,
                Accum::Replace,
                self.l_m.transpose(),
                upper,
                x.as_ref(),
                full,
                1.0,
                Par::Seq,
            );
            triangular::matmul(
                rhs.as_mut(),
                full,
                Accum::Add,
                self.l_m.as_ref(),
                lower,
                lx.as_ref(),
                full,
                -self.sigma,
                Par::Seq,
            );
        }
        // One step of iterative refinement: the solve's backward error becomes ~ε
        // componentwise, which the lowest whirls need (P's norm is the shortest
        // element's 12EI/l³, far above their modal stiffness: unrefined, the lowest whirl
        // of a 200-element rotor moved by 2.4e-9).
        let b = rhs.clone();
        self.lu.solve_in_place(rhs.as_mut());
        let mut r = b;
        matmul(r.as_mut(), Accum::Add, self.p.as_ref(), rhs.as_ref(), -1.0, Par::Seq);
        self.lu.solve_in_place(r.as_mut());
        let mut q = x;
        for j in 0..c {
            for i in 0..n {
                rhs[(i, j)] += r[(i, j)];
                q[(i, j)] += self.sigma * rhs[(i, j)];
            }
        }
        let upper = BlockStructure::TriangularUpper;
        let (out_top, out_bottom) = out.split_at_row_mut(n);
        triangular::matmul(
            out_top,
            full,
            Accum::Replace,
            self.l_s.transpose(),
            upper,
            rhs.as_ref(),
            full,
            1.0,
            Par::Seq,
        );
        triangular::matmul(
            out_bottom,
            full,
            Accum::Replace,
            self.l_m.transpose(),
            upper,
            q.as_ref(),
            full,
            1.0,
            Par::Seq,
        );
    }

    /// Orthonormalise the block `y` against the basis and within itself and append it;
    /// a column that vanishes (the space is invariant in it) is replaced by a random one.
    /// Returns false when the basis is full.
    fn append(&mut self, mut y: Mat<f64>) -> bool {
        let big = self.v.nrows();
        for c in 0..y.ncols() {
            let mut tries = 0;
            loop {
                if self.basis >= self.v.ncols() {
                    return false;
                }
                let before = norm(y.as_ref(), c);
                // Twice against the basis and the columns of this block already taken.
                for _ in 0..2 {
                    let basis = self.v.as_ref().subcols(0, self.basis);
                    let col = y.as_ref().subcols(c, 1);
                    let mut coef = Mat::<f64>::zeros(self.basis, 1);
                    matmul(coef.as_mut(), Accum::Replace, basis.transpose(), col, 1.0, Par::Seq);
                    let mut col = y.as_mut().subcols_mut(c, 1);
                    matmul(col.as_mut(), Accum::Add, basis, coef.as_ref(), -1.0, Par::Seq);
                }
                let after = norm(y.as_ref(), c);
                if after > 1e-8 * before && after > 0.0 && after.is_finite() {
                    for i in 0..big {
                        self.v[(i, self.basis)] = y[(i, c)] / after;
                    }
                    self.basis += 1;
                    break;
                }
                tries += 1;
                if tries > 3 {
                    return false;
                }
                for i in 0..big {
                    y[(i, c)] = self.random();
                }
            }
        }
        true
    }

    /// Apply Op to the basis columns not yet applied and extend H = Vᵀ·W.
    fn extend(&mut self) {
        let (a, b) = (self.applied, self.basis);
        if a == b {
            return;
        }
        let block = self.v.as_ref().subcols(a, b - a).to_owned();
        let mut out = Mat::<f64>::zeros(block.nrows(), b - a);
        self.apply(block.as_ref(), out.as_mut());
        self.w.as_mut().subcols_mut(a, b - a).copy_from(&out);
        let v = self.v.as_ref().subcols(0, b);
        let w = self.w.as_ref().subcols(0, b);
        // New columns H[0..b, a..b] and new rows H[a..b, 0..a].
        let mut cols = Mat::<f64>::zeros(b, b - a);
        matmul(cols.as_mut(), Accum::Replace, v.transpose(), w.subcols(a, b - a), 1.0, Par::Seq);
        self.h.as_mut().submatrix_mut(0, a, b, b - a).copy_from(&cols);
        if a > 0 {
            let mut rows = Mat::<f64>::zeros(b - a, a);
            matmul(rows.as_mut(), Accum::Replace, v.subcols(a, b - a).transpose(), w.subcols(0, a), 1.0, Par::Seq);
            self.h.as_mut().submatrix_mut(a, 0, b - a, a).copy_from(&rows);
        }
        self.applied = b;
        self.last = (a, b - a);
    }

    /// At least `wanted` eigenpairs nearest σ with every eigenvalue closer than the
    /// returned radius among them; `None` when the space reaches its limit first, or
    /// when a cluster of [`KRYLOV_BLOCK`] or more eigenvalues is found (it may hold
    /// more copies than the block can).
    pub fn nearest(&mut self, wanted: usize) -> Option<NearestEigen> {
        loop {
            self.extend();
            let m = self.applied;
            // Rayleigh–Ritz once the space is at least twice what is asked (ARPACK's rule
            // of thumb), or when it is full.
            if m >= 2 * wanted + KRYLOV_BLOCK || m >= self.limit {
                if let Some(found) = self.ritz(wanted) {
                    return Some(found);
                }
            }
            if m >= self.limit {
                return None;
            }
            let (a, len) = self.last;
            let next = self.w.as_ref().subcols(a, len).to_owned();
            if !self.append(next) && self.basis == m {
                return None;
            }
        }
    }

    /// The converged Ritz pairs nearest σ, if at least `wanted` of them lie within the
    /// radius the space resolves.
    fn ritz(&self, wanted: usize) -> Option<NearestEigen> {
        let m = self.applied;
        let big = self.v.nrows();
        let h = self.h.as_ref().submatrix(0, 0, m, m);
        if !h.norm_max().is_finite() {
            return None;
        }
        let evd = seq::eigen_real(h).ok()?;
        let mut order: Vec<usize> = (0..m).collect();
        order.sort_by(|&a, &b| evd.values[b].norm().total_cmp(&evd.values[a].norm()).then(a.cmp(&b)));
        let theta_1 = evd.values[order[0]].norm();
        if !(theta_1 > 0.0 && theta_1.is_finite()) {
            return None;
        }
        // Within a run of equal moduli, by Im θ: the copies of a multiple value adjacent,
        // rather than interleaved with their conjugates.
        let mut start = 0;
        while start < m {
            let modulus = evd.values[order[start]].norm();
            let mut end = start + 1;
            while end < m && modulus - evd.values[order[end]].norm() <= CLUSTER_DISTANCE * modulus {
                end += 1;
            }
            order[start..end].sort_by(|&a, &b| evd.values[b].im.total_cmp(&evd.values[a].im).then(a.cmp(&b)));
            start = end;
        }
        // The Ritz values and vectors (of H) in that order, a cluster's vectors replaced by
        // a basis of its invariant subspace ([`cluster_vectors`]).
        let mut values: Vec<c64> = order.iter().map(|&c| evd.values[c]).collect();
        let mut s_all = Mat::from_fn(m, m, |i, c| evd.vectors[(i, order[c])]);
        let mut start = 0;
        while start < m {
            let mut end = start + 1;
            while end < m && (values[end] - values[start]).norm() <= CLUSTER_DISTANCE * values[start].norm() {
                end += 1;
            }
            if end - start > 1 {
                let (vals, vecs) = cluster_vectors(h, values[start], end - start, start as u64)?;
                for (c, value) in vals.into_iter().enumerate() {
                    values[start + c] = value;
                    for i in 0..m {
                        s_all[(i, start + c)] = vecs[(i, c)];
                    }
                }
            }
            start = end;
        }
        // Residuals of the leading pairs, in order, until the first that has not converged.
        let v = self.v.as_ref().subcols(0, m);
        let w = self.w.as_ref().subcols(0, m);
        let mut taken = Vec::new();
        let mut radius = f64::INFINITY;
        const BATCH: usize = 16;
        let mut at = 0;
        'outer: while at < m {
            let cols: Vec<usize> = (at..(at + BATCH).min(m)).collect();
            let s_re = Mat::from_fn(m, cols.len(), |i, c| s_all[(i, cols[c])].re);
            let s_im = Mat::from_fn(m, cols.len(), |i, c| s_all[(i, cols[c])].im);
            let (yr, yi) = (seq::product(v, s_re.as_ref()), seq::product(v, s_im.as_ref()));
            let (zr, zi) = (seq::product(w, s_re.as_ref()), seq::product(w, s_im.as_ref()));
            for (c, &col) in cols.iter().enumerate() {
                let theta = values[col];
                let (mut r2, mut y2) = (0.0, 0.0);
                for i in 0..big {
                    let y = c64::new(yr[(i, c)], yi[(i, c)]);
                    let r = c64::new(zr[(i, c)], zi[(i, c)]) - theta * y;
                    r2 += r.norm_sqr();
                    y2 += y.norm_sqr();
                }
                // A space of the whole state holds every eigenvector: H is Op in an
                // orthonormal basis and its eigenvalues are Op's to ε·|θ₁|, as the dense
                // solver's; the pairs far from σ cannot meet the relative test there.
                let whole = m == big;
                let converged =
                    theta.norm() > 0.0 && (whole || r2.sqrt() <= KRYLOV_TOLERANCE * theta.norm() * y2.sqrt());
                if !converged {
                    radius = if theta.norm() > 0.0 { 1.0 / theta.norm() } else { f64::INFINITY };
                    break 'outer;
                }
                let y = (0..big).map(|i| c64::new(yr[(i, c)], yi[(i, c)])).collect::<Vec<_>>();
                taken.push((theta, y));
            }
            at += cols.len();
        }
        if taken.len() == m && m < big {
            // Every Ritz pair converged but the space is not the whole state: nothing is
            // known beyond the last one.
            radius = 1.0 / taken.last()?.0.norm();
        }
        self.resolve(taken, radius, wanted, m)
    }

    /// The state size 2n of the operator.
    pub(super) fn state(&self) -> usize {
        self.v.nrows()
    }

    /// The first vector of the seeded random start block (2n × 1, unit 2-norm, energy
    /// coordinates).
    pub(super) fn start(&self) -> MatRef<'_, f64> {
        self.v.as_ref().subcols(0, 1)
    }

    /// The eigenpairs λ = σ + 1/θ of the converged pairs `taken` (θ, ỹ in energy
    /// coordinates, by |θ| descending) that lie within `radius` less [`RADIUS_MARGIN`],
    /// with their displacements after one power step; `None` when fewer than `wanted` do
    /// or a cluster as large as the block is among them. `dimension`: the space's, for
    /// the record.
    pub(super) fn resolve(
        &self,
        taken: Vec<(c64, Vec<c64>)>,
        radius: f64,
        wanted: usize,
        dimension: usize,
    ) -> Option<NearestEigen> {
        let big = self.v.nrows();
        let n = big / 2;
        let limit = radius * (1.0 - RADIUS_MARGIN);
        let kept: Vec<(c64, Vec<c64>)> = taken
            .into_iter()
            .map(|(theta, y)| (c64::new(self.sigma, 0.0) + theta.inv(), y))
            .filter(|(lambda, _)| (lambda - self.sigma).norm() < limit)
            .collect();
        if kept.len() < wanted {
            return None;
        }
        // A cluster as large as the block may hide one more copy.
        let mut start = 0;
        while start < kept.len() {
            let mut end = start + 1;
            while end < kept.len() && (kept[end].0 - kept[start].0).norm() <= CLUSTER_DISTANCE * kept[start].0.norm() {
                end += 1;
            }
            if end - start >= KRYLOV_BLOCK {
                return None;
            }
            start = end;
        }
        // One step of the power method on each vector (ỹ ← Op·ỹ) damps what it holds of
        // the eigenvectors farther from σ by their θ ratios; x = L_S⁻ᵀ·ỹ₁.
        let k = kept.len();
        let block_re = Mat::from_fn(big, k, |i, c| kept[c].1[i].re);
        let block_im = Mat::from_fn(big, k, |i, c| kept[c].1[i].im);
        let mut out_re = Mat::<f64>::zeros(big, k);
        let mut out_im = Mat::<f64>::zeros(big, k);
        self.apply(block_re.as_ref(), out_re.as_mut());
        self.apply(block_im.as_ref(), out_im.as_mut());
        let x_re = self.displacement(out_re.as_ref().subrows(0, n));
        let x_im = self.displacement(out_im.as_ref().subrows(0, n));
        let mut vectors = Mat::<c64>::zeros(n, k);
        for c in 0..k {
            let mut norm2 = 0.0;
            for i in 0..n {
                let x = c64::new(x_re[(i, c)], x_im[(i, c)]);
                vectors[(i, c)] = x;
                norm2 += x.norm_sqr();
            }
            let norm = norm2.sqrt();
            if !(norm > 0.0 && norm.is_finite()) {
                return None;
            }
            for i in 0..n {
                vectors[(i, c)] /= norm;
            }
        }
        Some(NearestEigen { values: kept.into_iter().map(|(l, _)| l).collect(), vectors, radius, dimension })
    }
}

/// Ritz values and orthonormal vectors of a cluster of `k` Ritz values of `h` at
/// `theta`: a real eigensolver's vectors for a multiple eigenvalue are nearly parallel
/// (measured: the second copy of a double whirl of an isotropic rotor at rest had a Ritz
/// residual of 3e-4), so the cluster's invariant subspace is found by two steps of
/// inverse iteration from `k` seeded random vectors at θ(1 + 1e-9) and orthonormalised,
/// and H is diagonalised on it (any basis of a multiple eigenvalue's eigenspace is one of
/// eigenvectors).
fn cluster_vectors(h: MatRef<'_, f64>, theta: c64, k: usize, seed: u64) -> Option<(Vec<c64>, Mat<c64>)> {
    let m = h.nrows();
    let shift = theta * (1.0 + 1e-9);
    let a = Mat::from_fn(m, m, |i, j| c64::new(h[(i, j)], 0.0) - if i == j { shift } else { c64::new(0.0, 0.0) });
    let mut state = 0x2545_f491_4f6c_dd1d_u64 ^ seed;
    let mut random = || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let mut s = Mat::from_fn(m, k, |_, _| c64::new(random(), random()));
    for _ in 0..2 {
        s = seq::lu_solve(a.as_ref(), s.as_ref());
        // Modified Gram–Schmidt, twice.
        for c in 0..k {
            for _ in 0..2 {
                for p in 0..c {
                    let dot: c64 = (0..m).map(|i| s[(i, p)].conj() * s[(i, c)]).sum();
                    for i in 0..m {
                        let v = s[(i, p)];
                        s[(i, c)] -= dot * v;
                    }
                }
            }
            let norm = (0..m).map(|i| s[(i, c)].norm_sqr()).sum::<f64>().sqrt();
            if !(norm > 0.0 && norm.is_finite()) {
                return None;
            }
            for i in 0..m {
                s[(i, c)] /= norm;
            }
        }
    }
    // Rayleigh–Ritz on the subspace: Sᴴ·H·S (k × k).
    let hc = Mat::from_fn(m, m, |i, j| c64::new(h[(i, j)], 0.0));
    let hs = seq::product(hc.as_ref(), s.as_ref());
    let small = Mat::from_fn(k, k, |a, b| (0..m).map(|i| s[(i, a)].conj() * hs[(i, b)]).sum::<c64>());
    let e = seq::eigen(small.as_ref()).ok()?;
    let mut vectors = seq::product(s.as_ref(), e.vectors.as_ref());
    for c in 0..k {
        let norm = (0..m).map(|i| vectors[(i, c)].norm_sqr()).sum::<f64>().sqrt();
        if !(norm > 0.0 && norm.is_finite()) {
            return None;
        }
        for i in 0..m {
            vectors[(i, c)] /= norm;
        }
    }
    Some((e.values, vectors))
}

/// The 2-norm of column `c`.
fn norm(a: MatRef<'_, f64>, c: usize) -> f64 {
    (0..a.nrows()).map(|i| a[(i, c)] * a[(i, c)]).sum::<f64>().sqrt()
}
