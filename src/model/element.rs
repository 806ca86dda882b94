//! Rayleigh beam element kernels (per bending plane, local DOFs `[u1, θ1, u2, θ2]`).
//!
//! In the complex coordinates of Eq. (13) (`u = v + j·w`, `θ = ∂u/∂x`) the two bending
//! planes of Eq. (5) share the same real symmetric element matrices; the gyroscopic
//! coupling becomes `−jΩ·G` with `G` symmetric (Eq. 14).

/// A 4×4 element matrix, row-major.
pub type ElementMatrix = [[f64; 4]; 4];

/// The pattern shared by the rotary-inertia, gyroscopic and geometric matrices:
/// `[36 3l −36 3l; 3l 4l² −3l −l²; −36 −3l 36 −3l; 3l −l² −3l 4l²]`.
fn rotary_pattern(l: f64, scale: f64) -> ElementMatrix {
    let l2 = l * l;
    let p = [
        [36.0, 3.0 * l, -36.0, 3.0 * l],
        [3.0 * l, 4.0 * l2, -3.0 * l, -l2],
        [-36.0, -3.0 * l, 36.0, -3.0 * l],
        [3.0 * l, -l2, -3.0 * l, 4.0 * l2],
    ];
    p.map(|row| row.map(|x| x * scale))
}

/// Consistent translational mass `ρA·l/420·[156 22l 54 −13l; …]` (kg, kg·m, kg·m²).
pub fn translational_mass(rho: f64, area: f64, l: f64) -> ElementMatrix {
    let l2 = l * l;
    let s = rho * area * l / 420.0;
    [
        [156.0, 22.0 * l, 54.0, -13.0 * l],
        [22.0 * l, 4.0 * l2, 13.0 * l, -3.0 * l2],
        [54.0, 13.0 * l, 156.0, -22.0 * l],
        [-13.0 * l, -3.0 * l2, -22.0 * l, 4.0 * l2],
    ]
    .map(|row| row.map(|x| x * s))
}

/// Rotary inertia `ρI/(30l)·pattern` of the Rayleigh beam (diametral inertia I).
pub fn rotary_mass(rho: f64, inertia: f64, l: f64) -> ElementMatrix {
    rotary_pattern(l, rho * inertia / (30.0 * l))
}

/// Gyroscopic matrix `2ρI/(30l)·pattern` (polar inertia 2I); multiplied by Ω in use.
pub fn gyroscopic(rho: f64, inertia: f64, l: f64) -> ElementMatrix {
    rotary_pattern(l, 2.0 * rho * inertia / (30.0 * l))
}

/// Geometric (axial-load) matrix `1/(30l)·pattern`; enters as `−P·S` (compression positive).
pub fn geometric(l: f64) -> ElementMatrix {
    rotary_pattern(l, 1.0 / (30.0 * l))
}

/// Euler–Bernoulli bending stiffness `EI/l³·[12 6l −12 6l; …]`.
pub fn bending_stiffness(e: f64, inertia: f64, l: f64) -> ElementMatrix {
    let l2 = l * l;
    let s = e * inertia / (l * l2);
    [
        [12.0, 6.0 * l, -12.0, 6.0 * l],
        [6.0 * l, 4.0 * l2, -6.0 * l, 2.0 * l2],
        [-12.0, -6.0 * l, 12.0, -6.0 * l],
        [6.0 * l, 2.0 * l2, -6.0 * l, 4.0 * l2],
    ]
    .map(|row| row.map(|x| x * s))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn symmetric(m: &ElementMatrix) -> bool {
        (0..4).all(|i| (0..4).all(|j| m[i][j] == m[j][i]))
    }

    #[test]
    fn element_matrices_are_symmetric() {
        let l = 0.7 / 64.0;
        for m in [
            translational_mass(7900.0, 7e-4, l),
            rotary_mass(7900.0, 4e-8, l),
            gyroscopic(7900.0, 4e-8, l),
            geometric(l),
            bending_stiffness(2.06e11, 4e-8, l),
        ] {
            assert!(symmetric(&m));
        }
    }

    #[test]
    fn translational_mass_sums_to_element_mass() {
        // A rigid translation u = 1, θ = 0 has kinetic mass ρAl.
        let (rho, a, l) = (7900.0, 7.0e-4, 0.02);
        let m = translational_mass(rho, a, l);
        let total = m[0][0] + m[0][2] + m[2][0] + m[2][2];
        assert!((total - rho * a * l).abs() < 1e-12 * rho * a * l);
    }

    #[test]
    fn rigid_motions_are_free_of_strain() {
        // Translation [1,0,1,0] and rotation [0,1,l,1] produce no bending force.
        let l = 0.05;
        let k = bending_stiffness(2e11, 1e-8, l);
        for v in [[1.0, 0.0, 1.0, 0.0], [0.0, 1.0, l, 1.0]] {
            for row in &k {
                let f: f64 = row.iter().zip(v).map(|(a, b)| a * b).sum();
                assert!(f.abs() < 1e-6 * k[0][0]);
            }
        }
    }
}
