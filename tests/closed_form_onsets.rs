//! Onsets of the region search against closed forms, on small linear time-periodic systems
//! given by their matrices ([`rotorshunt::analysis::ltp::LtpSystem`]), under the default
//! growth criterion (ln max|μ| above the path's floor): the onsets are where the growth
//! per period crosses that threshold, so where |μ| = 1 to within 1e-6 per period.
//!
//! References: the method of multiple scales to first order (Nayfeh & Mook, *Nonlinear
//! Oscillations*, 1979, §5.7), written out for each system in its test.

use faer::Mat;
use rotorshunt::analysis::ltp::LtpSystem;
use rotorshunt::analysis::regions::{Probe, RegionSettings};
use rotorshunt::analysis::Settings;

/// The onset of the region whose start is sought from `seed` (rad/s), within ±0.3 % of it
/// (the catalogue's start window), up to β = `beta_max`.
fn onset(sys: &LtpSystem, seed: f64, beta_max: f64) -> f64 {
    let fs = sys.floquet(&Settings::default(), 0.0).expect("a Floquet system");
    let s = RegionSettings::default();
    let start = Probe::new(&fs, &s).locate_start(seed, 0.003 * seed, beta_max, beta_max).expect("a start");
    assert!(start.resolved, "the tip was not located: {start:?}");
    start.onset
}

fn diag(v: &[f64]) -> Mat<f64> {
    Mat::from_fn(v.len(), v.len(), |i, j| if i == j { v[i] } else { 0.0 })
}

/// x″ + 2ζωx′ + ω²(1 − h cos 2ωt)x = 0: with x = A e^{iωt} + c.c., the secular terms give
/// A′ = −ζωA − i(hω/4)Ā, unstable when hω/4 > ζω: h_c = 4ζ to first order (its next
/// correction is O(ζ²), 1e-4 relative here). As an LTP system: M = 1, C = 2ζω, K = ω²,
/// S = ω², P_ref = 1, α = 0, β = h, φ = 2ω.
#[test]
fn damped_mathieu_principal_onset_is_four_zeta() {
    let (w, zeta) = (100.0, 0.01);
    let sys = LtpSystem::new(diag(&[1.0]), diag(&[2.0 * zeta * w]), diag(&[w * w]), diag(&[w * w]), None, 1.0, 0.0)
        .expect("a valid system");
    let h = onset(&sys, 2.0 * w, 0.2);
    let closed = 4.0 * zeta;
    println!("damped Mathieu, zeta = {zeta}: onset h = {h:.6}, closed form 4 zeta = {closed}");
    assert!((h / closed - 1.0).abs() < 5e-3, "onset {h} against {closed}");
}

/// Two modes, M = I, K = diag(ω_p², ω_q²), C = diag(2σ_p, 2σ_q), S coupling them
/// (a_pq = P_ref·S_pq, zero diagonal). With q_p = A_p e^{iω_p t} + c.c. near
/// φ = ω_p + ω_q, the secular terms give A_p′ = −σ_p A_p − i(βa_pq/4ω_p)Ā_q and
/// Ā_q′ = −σ_q Ā_q + i(βa_qp/4ω_q)A_p, unstable when β²a_pq·a_qp/(16ω_pω_q) > σ_pσ_q.
/// With the couplings c_pq = a_pq/(2ω_p), c_qp = a_qp/(2ω_q) this is
/// β_c = 2√(σ_pσ_q/|c_pq·c_qp|). The test takes σ and c from its own matrices.
#[test]
fn two_mode_sum_type_onset_matches_multiple_scales() {
    let (wp, wq) = (100.0, 170.0);
    let (sp, sq) = (0.5, 0.8);
    let a = 6600.0;
    let m = diag(&[1.0, 1.0]);
    let c = diag(&[2.0 * sp, 2.0 * sq]);
    let k = diag(&[wp * wp, wq * wq]);
    let s = Mat::from_fn(2, 2, |i, j| if i == j { 0.0 } else { a });
    // σ and c from the matrices (M = I: modal already).
    let (sigma_p, sigma_q) = (c[(0, 0)] / 2.0, c[(1, 1)] / 2.0);
    let (c_pq, c_qp) = (s[(0, 1)] / (2.0 * k[(0, 0)].sqrt()), s[(1, 0)] / (2.0 * k[(1, 1)].sqrt()));
    let closed = 2.0 * (sigma_p * sigma_q / (c_pq * c_qp).abs()).sqrt();
    let sys = LtpSystem::new(m, c, k, s, None, 1.0, 0.0).expect("a valid system");
    let found = onset(&sys, wp + wq, 0.2);
    println!("two modes: onset {found:.6}, multiple scales {closed:.6} ({:+.3} %)", 100.0 * (found / closed - 1.0));
    assert!((found / closed - 1.0).abs() < 0.02, "onset {found} against {closed}");
}

/// The gyroscopic form takes G too, and matrices that do not make a system are refused
/// with what is wrong.
#[test]
fn ltp_matrices_are_checked() {
    let one = || diag(&[1.0]);
    let bad = LtpSystem::new(one(), one(), one(), Mat::from_fn(1, 2, |_, _| 1.0), None, 1.0, 0.0).unwrap_err();
    assert!(bad.to_string().contains("matrix S is 1 x 2"), "{bad}");
    let asym = Mat::from_fn(2, 2, |i, j| if i < j { 1.0 } else { 0.0 });
    let e = LtpSystem::new(diag(&[1.0, 1.0]), diag(&[0.0, 0.0]), diag(&[1.0, 2.0]), asym, None, 1.0, 0.0).unwrap_err();
    assert!(e.to_string().contains("matrix S is not symmetric"), "{e}");
    let nan = LtpSystem::new(one(), diag(&[f64::NAN]), one(), one(), None, 1.0, 0.0).unwrap_err();
    assert!(nan.to_string().contains("matrix C has a non-finite entry"), "{nan}");
    // A gyroscopic pair at speed: whirls split around the rest frequency.
    let g = Mat::from_fn(2, 2, |i, j| if i == j { 0.1 } else { 0.0 });
    let sys = LtpSystem::new(diag(&[1.0, 1.0]), diag(&[0.0, 0.0]), diag(&[1e4, 4e4]), one_by(2), Some(g), 1.0, 0.0);
    let fs = sys.expect("valid").floquet(&Settings::default(), 100.0).expect("a system");
    let (f, b) = fs.whirls().expect("whirls");
    assert!(f[0] > 100.0 && b[0] < 100.0, "{f:?} {b:?}");
}

fn one_by(n: usize) -> Mat<f64> {
    Mat::from_fn(n, n, |i, j| if i == j { 1.0 } else { 0.0 })
}
