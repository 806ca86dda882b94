//! Regression pins: expected values that are this program's own earlier output rather than
//! an independent source (a closed form, the paper, ROSS, a check made inside the test).
//! They are kept in this one file, each with its origin. A pin shows that a figure has not
//! moved, not that it is right; where an independent check of the same figure exists, it
//! is named. A change that moves a pin says why in its commit.

/// `examples/library_tour.rs`, step 2: unstable points of the Fig. 11 chart around
/// ω_b1 + ω_r (φ 1150–1250 rad/s by 1, β 0–0.5 by 0.05). The 1111 is the grid, 101 × 11;
/// the 136 has no independent source. Origin: the tour's output when it was written
/// (commit 81d199d, issue 15), quoted in docs/library.md.
pub const TOUR_CHART: &str = "chart: 136 of 1111 points unstable";

/// `examples/library_tour.rs`, step 4: the stable band around φ_op = 1230 rad/s at
/// β_op = 0.3 of problems/fig11-closed-2000.toml, [1191.625, 1233.75] rad/s printed to
/// 0.01. Origin: `rotorshunt band` since the band was made true (issue 13,
/// docs/decisions.md, "A true stable band"), quoted in docs/library.md. Independent checks
/// of it: tests/band_truth.rs (a 0.05 rad/s grid of plain Floquet points inside it and an
/// unstable point within 0.5 rad/s beyond each edge) and tests/criterion.rs (the unstable
/// point at 1234 rad/s that bounds it above).
pub const TOUR_BAND: &str = "stable band around 1230 rad/s: [1191.62, 1233.75] rad/s";

/// `examples/library_tour.rs`, step 1: the first forward and backward whirls at
/// Ω = 2000 rad/s as printed (0.1 rad/s). Origin: the tour's output (commit 81d199d).
/// Independent check: the paper's Table 3 (398.5 and 300.1 rad/s) within 0.1 %, in
/// tests/paper_tables.rs and in tests/readme_library.rs on the tour's own output.
pub const TOUR_WHIRLS: [&str; 2] = ["f1     398.6 rad/s", "b1     300.1 rad/s"];

/// `examples/library_tour.rs`, step 3: the first-order regions of 1000–1400 rad/s up to
/// β = 1. Origin: the tour's output (commit 81d199d). The paper's Fig. 11 shows the
/// combination regions of ω_b1 with the rings' modes r1, r2 (about 1180 rad/s) and of ω_f1
/// with them (about 1280 rad/s); tests/paper_findings.rs checks those regions exist.
pub const TOUR_REGIONS: [&str; 4] = ["region    r1+b1", "region    r2+b1", "region    f1+r1", "region    f1+r2"];
