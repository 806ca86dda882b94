//! Cost of the dense eigensolutions of the full model, from its DOFs.

use super::*;
use crate::assembly::DofMap;
use crate::model::Model;

/// The dense stages a command runs on the full model.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dense {
    /// Assembly and the buckling load (`check`, and every command first).
    Rotor,
    /// Rotor, and the modal basis of the reduced model (Floquet commands).
    Reduced,
    /// Rotor, and the quadratic eigenproblem at `n` speeds (whirls: `modes`, `campbell`),
    /// keeping the mode shapes of every speed when `n` > 1.
    Whirls(usize),
    /// Rotor, modal basis and whirls at one speed (`regions`, `band`).
    ReducedAndWhirls,
}

/// The dense work of `stage` on `model`, from its DOFs alone (nothing is assembled).
/// `threads` stages may run at once (a Campbell diagram's speeds).
pub fn dense(model: &Model, stage: Dense, threads: usize) -> Estimate {
    let n = DofMap::of(model).len() as f64;
    // P_cr is computed on the open-circuit model unless the file gives it.
    let open = DofMap { nodes: model.shaft.nodes(), branches: vec![0; model.rings.len()] }.len() as f64;
    let buckling = if model.load.critical_load.is_some() { 0.0 } else { DENSE_EIGEN_OPS_N3 * cubed(open) };
    let eigen = DENSE_EIGEN_OPS_N3 * cubed(n);
    let qep = QEP_OPS_2N3 * cubed(2.0 * n);
    let dofs = format!("{} complex DOFs", n);
    // Without the buckling eigenproblem a rotor is its five assembled matrices.
    let rotor_bytes = if buckling > 0.0 { ROTOR_BYTES_N2 } else { ASSEMBLED_BYTES_N2 } * n * n;
    let (whole, held) = ((Driver::Dofs, format!("the dense eigenproblems of {dofs}")), (Driver::Dofs, dofs.clone()));
    let (operations, bytes, (memory_driver, memory_detail), (work_driver, work_detail)) = match stage {
        Dense::Rotor => (buckling, rotor_bytes, held, whole),
        Dense::Reduced => (buckling + eigen, ROTOR_BYTES_N2 * n * n, held, whole),
        Dense::ReducedAndWhirls => (buckling + eigen + qep, QEP_BYTES_N2 * n * n, held, whole),
        Dense::Whirls(speeds) if speeds > 1 => {
            let s = speeds as f64;
            let (shapes, working) =
                (SHAPES_BYTES_N2 * n * n * s, QEP_BYTES_N2 * n * n * threads.clamp(1, speeds) as f64);
            let held = (
                if shapes > working { Driver::Grid } else { Driver::Dofs },
                format!("{speeds} speeds × the mode shapes of {dofs}"),
            );
            let work = (
                if qep * s > (buckling + qep) * 4.0 { Driver::Grid } else { Driver::Dofs },
                format!("{speeds} whirl eigenproblems of {dofs}"),
            );
            (buckling + qep * s, working + shapes, held, work)
        }
        Dense::Whirls(_) => (buckling + qep, QEP_BYTES_N2 * n * n, held, whole),
    };
    Estimate {
        work: Part { amount: operations, driver: work_driver, detail: work_detail },
        memory: Part { amount: bytes, driver: memory_driver, detail: memory_detail },
        evaluations: 0.0,
    }
}

/// The unbalance response of `model` at `speeds` speeds with `nodes` extra probes: the
/// rotor (assembly and P_cr), one sparse solve per speed, and at most
/// [`crate::analysis::unbalance::SOLVES_PER_PEAK`] solves for each possible peak of each
/// probe (an upper bound: every other grid speed, and at most 4 per DOF, of every disk
/// node, support and node).
pub fn unbalance(model: &Model, speeds: usize, nodes: usize) -> Estimate {
    use crate::analysis::unbalance::{disk_nodes, SOLVES_PER_PEAK};
    let n = DofMap::of(model).len() as f64;
    let probes = (disk_nodes(model).len() + model.bearings.len() + 2 * model.rings.len() + nodes) as f64;
    // |U_dof(Ω)|² is a ratio of polynomials in Ω of degree at most 4n (A(Ω) is quadratic
    // in Ω: det A and the cofactors have degree ≤ 2n), so it has at most 8n stationary
    // points and 4n local maxima, and a grid at most one peak per two speeds.
    let peaks = probes * ((speeds / 2) as f64).min(4.0 * n);
    let solves = speeds as f64 + peaks * SOLVES_PER_PEAK as f64;
    let detail = format!(
        "{} sparse solves of {n} complex DOFs ({speeds} speeds, {} peaks at most)",
        compact_count(solves),
        compact_count(peaks)
    );
    let mut response = Estimate::work(solves * UNBALANCE_SOLVE_OPS_N * n, Driver::Grid, detail);
    response.memory = Part {
        amount: UNBALANCE_BYTES_PER_VALUE * probes * speeds as f64,
        driver: Driver::Grid,
        detail: format!("{} probes × {speeds} speeds of results and their JSON, CSV and SVG text", probes),
    };
    dense(model, Dense::Rotor, 1).then(response)
}
