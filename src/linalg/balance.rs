//! Diagonal balancing (Parlett & Reinsch 1969): a similarity D⁻¹AD with D a diagonal of
//! powers of two (exact in floating point) that equalises row and column norms. The
//! Floquet state [q̇; q] mixes scales (q̇ ~ ω·q), which makes the multipliers needlessly
//! ill-conditioned; balancing first restores their accuracy at negligible cost.

use faer::{c64, Mat};

/// Balance `a` in place (eigenvalues unchanged).
pub fn balance(a: &mut Mat<c64>) {
    const RADIX: f64 = 2.0;
    let n = a.nrows();
    let mut done = false;
    let mut sweeps = 0;
    while !done && sweeps < 100 {
        done = true;
        sweeps += 1;
        for i in 0..n {
            let (mut c, mut r) = (0.0, 0.0);
            // |re| + |im| as in LAPACK's gebal: equivalent for choosing powers of two,
            // and without the square root of the modulus.
            let abs1 = |z: c64| z.re.abs() + z.im.abs();
            for j in 0..n {
                if j != i {
                    c += abs1(a[(j, i)]);
                    r += abs1(a[(i, j)]);
                }
            }
            if c == 0.0 || r == 0.0 || !c.is_finite() || !r.is_finite() {
                continue;
            }
            let s = c + r;
            let mut f = 1.0;
            let (mut cc, mut rr) = (c, r);
            while cc < rr / RADIX {
                cc *= RADIX;
                rr /= RADIX;
                f *= RADIX;
            }
            while cc >= rr * RADIX {
                cc /= RADIX;
                rr *= RADIX;
                f /= RADIX;
            }
            if (cc + rr) < 0.95 * s {
                done = false;
                for j in 0..n {
                    a[(i, j)] /= f;
                    a[(j, i)] *= f;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn balancing_recovers_the_eigenvalues_of_a_badly_scaled_similarity() {
        // A = D·C·D⁻¹ with D = diag(1, 1e4, 1e8) and the well-scaled C = (i + 2j + 1):
        // same eigenvalues. Unbalanced, the eigensolver loses ~1e-7 absolute on them;
        // balanced, A is brought back to C's scale and they are accurate to round-off.
        let c = Mat::from_fn(3, 3, |i, j| c64::new((i + 2 * j) as f64 + 1.0, 0.0));
        let a = Mat::from_fn(3, 3, |i, j| c[(i, j)] * 10f64.powi(4 * (i as i32 - j as i32)));
        let mut b = a.clone();
        balance(&mut b);
        let sorted = |m: &Mat<c64>| {
            let mut v: Vec<c64> = crate::linalg::seq::eigenvalues(m.as_ref()).unwrap();
            v.sort_by(|x, y| x.re.total_cmp(&y.re));
            v
        };
        for (x, y) in sorted(&b).iter().zip(&sorted(&c)) {
            assert!((x - y).norm() < 1e-12 * c.norm_max(), "{x} vs {y}");
        }
        assert!(b.norm_max() < 1e-3 * a.norm_max());
    }
}
