//! The glossary a report carries below its first page: every term and label it uses.

/// The glossary as a Markdown section (heading level 2).
pub fn glossary() -> &'static str {
    GLOSSARY
}

const GLOSSARY: &str = "## Glossary

| term | meaning |
|---|---|
| Ω | rotating speed of the rotor (rad/s) |
| φ | frequency of the periodic axial load P(t) = P_cr(α + β cos φt) (rad/s) |
| α, β | static and dynamic load coefficients, fractions of the buckling load P_cr (−) |
| β_op, φ_op | the load level and the operating frequency a design is judged at |
| f1, b1, f2, … | forward (f) and backward (b) whirl of rotor mode 1, 2, … at Ω, numbered as in the paper's Table 3 |
| fr1, br1, fs1, … | forward and backward whirl of an electrical (shunt) mode: the letter is the branch (r of branch 1, s of branch 2, t of branch 3, …), the digit counts that branch's modes by frequency (one per ring carrying the branch: fr1, fr2 on two rings); `r1@drive` names the ring when rings have different circuits |
| A+B (k = n) | a combination region (tongue) that starts at φ = (ω_A + ω_B)/n on the β = 0 axis, A a forward and B a backward whirl; an electrical whirl drops its f/b letter there (r1, not fr1), its place says which; `2 n1` at Ω = 0: the principal region of mode 1 |
| order k | the n of a tongue: k = 1 is the principal (first-order) region, higher k start at lower φ and are thinner |
| onset | the smallest β at which a region is unstable (−) |
| edges | where a region crosses β_op: its φ interval at that level (rad/s) |
| stable band | the φ interval around φ_op at β_op in which no region counts by the criterion (rad/s; width in brackets) |
| criterion | unstable when the largest Floquet multiplier modulus max\\|μ\\| exceeds 1 + tolerance, counting tongues up to the order stated (the same rule in every command) |
| Floquet multiplier μ | an eigenvalue of the monodromy matrix over one load period 2π/φ; the motion grows where \\|μ\\| > 1 |
| DSTM | the paper's discrete state transition matrix (Eq. 26–27), the reference method |
| fast path | the Magnus (CFM4) monodromy on the reduced model, checked against DSTM |
| verification | from scratch, after the optimiser: the full catalogue of the tuned design, the DSTM point at every tongue centre near the band, and a 0.05 rad/s grid over the band |
| bounded by | the tongue whose edge at β_op ends the stable band on that side; `window end` when the band reaches the end of the φ range searched |
| unlabelled, unexplained | a counted tongue whose whirl pair was not identified (found by the guard lattice, a grid of points that catches tongues no predicted start explains); it bounds bands like any other |
| distance | in the region table near the bands: the gap (rad/s) between a tongue's edges at β_op and the band or operating band; 0 when it bounds or enters it |
| intrusion | a region whose edges at β_op reach into an operating band (with its clearance) |
| clearance | the margin (rad/s) each side of an operating band that must stay stable too |
| peak response | the largest unbalance amplitude (m) at the design's node over its speed range; amplification factor: API 684's, from the half-power points |
| unconstrained optimum, price | the design that damps best without any stability constraint; the price of the constraints is the tuned peak minus its peak (m, %) |
| ζ | the modal damping ratio −Re λ/\\|λ\\| of a whirl (−) |
| C_f, L, R | a shunt branch's capacitance (F), inductance (H) and resistance (Ω); tuning ω = √((C_p^T + C_f)/(L·C_p^T·C_f)) (rad/s, Eq. 4) |
";

#[cfg(test)]
mod tests {
    #[test]
    fn every_row_has_a_term_and_a_meaning() {
        let rows: Vec<&str> =
            super::glossary().lines().filter(|l| l.starts_with("| ") && !l.starts_with("| term")).collect();
        assert!(rows.len() >= 15);
        for r in rows {
            let cells: Vec<&str> = r.split(" | ").collect();
            assert!(cells.len() == 2 && cells[1].len() > 10, "{r}");
        }
    }
}
