//! Beam element kernels (per bending plane, local DOFs `[u1, θ1, u2, θ2]`).
//!
//! In the complex coordinates of Eq. (13) (`u = v + j·w`, θ the cross-section's rotation,
//! `∂u/∂x` for a Rayleigh beam) the two bending planes of Eq. (5) share the same real
//! symmetric element matrices; the gyroscopic coupling becomes `−jΩ·G` with `G` symmetric
//! (Eq. 14).
//!
//! The uniform Rayleigh element has the closed forms below (the paper's). Timoshenko and
//! tapered elements are [`beam`]: the energies integrated exactly, by Gauss–Legendre
//! quadrature, over the element's shape functions, with the cross-section varying along it
//! (docs/model.md).

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

/// Shear coefficient κ of a circular tube by Cowper (1966, "The shear coefficient in
/// Timoshenko's beam theory"), as ROSS 2.3.0 computes it by default:
/// κ = 6(1 + ν)(1 + r²)² / ((7 + 6ν)(1 + r²)² + (20 + 12ν)r²), with ν Poisson's ratio and
/// r = d/D the ratio of the inner to the outer diameter (0 for a solid section:
/// κ = 6(1 + ν)/(7 + 6ν)).
pub fn cowper_shear_coefficient(poisson: f64, ratio: f64) -> f64 {
    let r2 = ratio * ratio;
    let r12 = (1.0 + r2) * (1.0 + r2);
    6.0 * r12 * (1.0 + poisson) / (r12 * (7.0 + 6.0 * poisson) + r2 * (20.0 + 12.0 * poisson))
}

/// The shear coefficient ROSS 2.3.0 evaluates for `shear_method_calc = "hutchinson"`
/// (`ShaftElement.__init__`, "kappa as per Hutchinson (2001)"), written as ROSS writes it:
/// κ = 6(1 + r²)²(1 + ν) / ((1 + r²)²(7 + 12ν + 4ν²) + 4r²(5 + 6ν + 2ν²)). Used by the
/// ROSS import only, so that an imported element has the κ ROSS gave it
/// (docs/ross-format.md).
pub fn ross_hutchinson_shear_coefficient(poisson: f64, ratio: f64) -> f64 {
    let r2 = ratio * ratio;
    let r12 = (1.0 + r2) * (1.0 + r2);
    let nu = poisson;
    6.0 * r12 * (1.0 + nu) / (r12 * (7.0 + 12.0 * nu + 4.0 * nu * nu) + 4.0 * r2 * (5.0 + 6.0 * nu + 2.0 * nu * nu))
}

/// One beam element for `beam`: a circular tube whose outer and inner diameters vary
/// linearly from the left node to the right one (equal ends: a uniform element).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BeamElement {
    /// Length l (m).
    pub length: f64,
    /// Density ρ (kg/m³).
    pub density: f64,
    /// Young's modulus E (Pa).
    pub youngs_modulus: f64,
    /// Outer diameter at the left and the right node (m).
    pub outer: (f64, f64),
    /// Inner diameter at the left and the right node (m), 0 for a solid element.
    pub inner: (f64, f64),
    /// κG (Pa), the shear coefficient times the shear modulus, for a Timoshenko element;
    /// `None` for a Rayleigh element (no shear deformation).
    pub shear: Option<f64>,
}

/// The element matrices of [`beam`], per bending plane (local DOFs `[u1, θ1, u2, θ2]`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BeamMatrices {
    /// Mass, translational plus rotary inertia (kg, kg·m, kg·m²).
    pub mass: ElementMatrix,
    /// Stiffness, bending plus shear (N/m, N, N·m).
    pub stiffness: ElementMatrix,
    /// Gyroscopic matrix per unit speed (polar inertia 2I).
    pub gyroscopic: ElementMatrix,
    /// Geometric matrix per unit axial load (1/m, −, m).
    pub geometric: ElementMatrix,
    /// The shear parameter Φ = 12EI/(κGAl²) of the element (A and I at its middle); 0
    /// for a Rayleigh element.
    pub phi: f64,
}

impl BeamElement {
    /// Outer and inner diameter at ξ = x/l ∈ [0, 1] (m).
    fn diameters(&self, xi: f64) -> (f64, f64) {
        let lerp = |(a, b): (f64, f64)| (1.0 - xi) * a + xi * b;
        (lerp(self.outer), lerp(self.inner))
    }
    /// Area A and second moment I at ξ (m², m⁴).
    fn section(&self, xi: f64) -> (f64, f64) {
        let (d_o, d_i) = self.diameters(xi);
        let (o2, i2) = (d_o * d_o, d_i * d_i);
        (std::f64::consts::PI * (o2 - i2) / 4.0, std::f64::consts::PI * (o2 * o2 - i2 * i2) / 64.0)
    }
    /// Φ = 12EI/(κGAl²) with A and I at the element's middle; 0 without shear.
    pub fn shear_parameter(&self) -> f64 {
        match self.shear {
            Some(kappa_g) => {
                let (a, i) = self.section(0.5);
                12.0 * self.youngs_modulus * i / (kappa_g * a * self.length * self.length)
            }
            None => 0.0,
        }
    }
}

/// Gauss–Legendre points and weights on [0, 1], 5 points: exact for polynomials of degree
/// ≤ 9. The integrands of [`beam`] are of degree ≤ 8 (a quartic I(x) times two quadratic
/// rotation shape functions; a quadratic A(x) times two cubic deflection ones).
const GAUSS_5: [(f64, f64); 5] = [
    (0.046910077030668004, 0.11846344252809454),
    (0.23076534494715845, 0.23931433524968324),
    (0.5, 0.28444444444444444),
    (0.7692346550528415, 0.23931433524968324),
    (0.953089922969332, 0.11846344252809454),
];

/// Shape functions at ξ = x/l of an element of length `l` and shear parameter `phi`
/// (Nelson 1980, "A finite rotating shaft element using Timoshenko beam theory"; the
/// Hermite cubics at Φ = 0): deflection N, its slope N', the rotation P and its slope P'.
/// They solve the static homogeneous Timoshenko equations of a uniform element, so the
/// shear strain N' − P is constant along it.
fn shape(xi: f64, l: f64, phi: f64) -> [[f64; 4]; 4] {
    let d = 1.0 + phi;
    let (x2, x3) = (xi * xi, xi * xi * xi);
    let n = [
        (1.0 - 3.0 * x2 + 2.0 * x3 + phi * (1.0 - xi)) / d,
        l * (xi - 2.0 * x2 + x3 + 0.5 * phi * (xi - x2)) / d,
        (3.0 * x2 - 2.0 * x3 + phi * xi) / d,
        l * (-x2 + x3 + 0.5 * phi * (x2 - xi)) / d,
    ];
    let dn = [
        (-6.0 * xi + 6.0 * x2 - phi) / (d * l),
        (1.0 - 4.0 * xi + 3.0 * x2 + 0.5 * phi * (1.0 - 2.0 * xi)) / d,
        (6.0 * xi - 6.0 * x2 + phi) / (d * l),
        (-2.0 * xi + 3.0 * x2 + 0.5 * phi * (2.0 * xi - 1.0)) / d,
    ];
    let p = [
        6.0 * (x2 - xi) / (d * l),
        (1.0 - 4.0 * xi + 3.0 * x2 + phi * (1.0 - xi)) / d,
        6.0 * (xi - x2) / (d * l),
        (-2.0 * xi + 3.0 * x2 + phi * xi) / d,
    ];
    let dp = [
        6.0 * (2.0 * xi - 1.0) / (d * l * l),
        (-4.0 + 6.0 * xi - phi) / (d * l),
        6.0 * (1.0 - 2.0 * xi) / (d * l * l),
        (-2.0 + 6.0 * xi + phi) / (d * l),
    ];
    [n, dn, p, dp]
}

/// `target += scale · a aᵀ`.
fn add_outer(target: &mut ElementMatrix, a: &[f64; 4], scale: f64) {
    for (row, ai) in target.iter_mut().zip(a) {
        for (t, aj) in row.iter_mut().zip(a) {
            *t += scale * ai * aj;
        }
    }
}

/// The matrices of a Timoshenko or Rayleigh element, uniform or tapered, from its
/// energies integrated exactly over Nelson's shape functions with Φ of the
/// element's middle section (docs/model.md):
/// - mass ∫ρA NᵀN + ∫ρI PᵀP, gyroscopic 2∫ρI PᵀP;
/// - stiffness ∫EI P′ᵀP′ + ∫κGA (N′ − P)ᵀ(N′ − P) (the second term only with shear);
/// - geometric ∫N′ᵀN′: the axial load works on the slope of the deflection.
///
/// For a uniform element these are Nelson's (1980) closed forms; at Φ = 0 and uniform,
/// the Rayleigh closed forms above (to round-off, not to the bit: uniform Rayleigh
/// sections keep using those).
pub fn beam(e: &BeamElement) -> BeamMatrices {
    let (l, rho, young) = (e.length, e.density, e.youngs_modulus);
    let phi = e.shear_parameter();
    let zero = [[0.0; 4]; 4];
    let (mut mass, mut stiffness, mut gyroscopic, mut geometric) = (zero, zero, zero, zero);
    for (xi, w) in GAUSS_5 {
        let (a, i) = e.section(xi);
        let [n, dn, p, dp] = shape(xi, l, phi);
        let wl = w * l;
        add_outer(&mut mass, &n, wl * rho * a);
        add_outer(&mut mass, &p, wl * rho * i);
        add_outer(&mut gyroscopic, &p, wl * 2.0 * rho * i);
        add_outer(&mut stiffness, &dp, wl * young * i);
        if let Some(kappa_g) = e.shear {
            let strain = [dn[0] - p[0], dn[1] - p[1], dn[2] - p[2], dn[3] - p[3]];
            add_outer(&mut stiffness, &strain, wl * kappa_g * a);
        }
        add_outer(&mut geometric, &dn, wl);
    }
    BeamMatrices { mass, stiffness, gyroscopic, geometric, phi }
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

    /// Relative gap of two element matrices, over the larger's largest entry.
    fn gap(a: &ElementMatrix, b: &ElementMatrix) -> f64 {
        let scale = a.iter().chain(b).flatten().fold(0.0_f64, |m, x| m.max(x.abs()));
        (0..4).flat_map(|i| (0..4).map(move |j| (i, j))).map(|(i, j)| (a[i][j] - b[i][j]).abs()).fold(0.0, f64::max)
            / scale
    }

    fn sum(a: &ElementMatrix, b: &ElementMatrix) -> ElementMatrix {
        let mut c = *a;
        for (r, s) in c.iter_mut().zip(b) {
            for (x, y) in r.iter_mut().zip(s) {
                *x += y;
            }
        }
        c
    }

    /// Round-off of a sum of 5 quadrature terms against a closed form: a few ulps.
    const QUADRATURE_RTOL: f64 = 1e-14;

    #[test]
    fn quadrature_at_zero_shear_is_the_rayleigh_closed_form() {
        let (l, rho, e, d) = (0.03, 7800.0, 2.1e11, 0.05);
        let b = beam(&BeamElement {
            length: l,
            density: rho,
            youngs_modulus: e,
            outer: (d, d),
            inner: (0.0, 0.0),
            shear: None,
        });
        let (a, i) = (std::f64::consts::PI * d * d / 4.0, std::f64::consts::PI * d.powi(4) / 64.0);
        assert_eq!(b.phi, 0.0);
        assert!(gap(&b.mass, &sum(&translational_mass(rho, a, l), &rotary_mass(rho, i, l))) < QUADRATURE_RTOL);
        assert!(gap(&b.stiffness, &bending_stiffness(e, i, l)) < QUADRATURE_RTOL);
        assert!(gap(&b.gyroscopic, &gyroscopic(rho, i, l)) < QUADRATURE_RTOL);
        assert!(gap(&b.geometric, &geometric(l)) < QUADRATURE_RTOL);
    }

    /// A 4×4 symmetric matrix from its upper triangle, times `scale`.
    fn upper(u: [[f64; 4]; 4], scale: f64) -> ElementMatrix {
        let mut m = [[0.0; 4]; 4];
        for i in 0..4 {
            for j in i..4 {
                m[i][j] = u[i][j] * scale;
                m[j][i] = u[i][j] * scale;
            }
        }
        m
    }

    #[test]
    fn uniform_timoshenko_element_is_nelsons_closed_form() {
        // Nelson (1980), "A finite rotating shaft element using Timoshenko beam theory"
        // (as printed in Friswell et al. 2010, "Dynamics of Rotating Machines", section
        // 5.4): translational and rotary mass, stiffness; the geometric matrix of the
        // same shape functions. A short hollow element: Φ ≈ 1.1.
        let (l, rho, e, g, od, id) = (0.04, 7810.0, 2.11e11, 8.12e10, 0.12, 0.04);
        let nu = e / (2.0 * g) - 1.0;
        let kappa = cowper_shear_coefficient(nu, id / od);
        let el = BeamElement {
            length: l,
            density: rho,
            youngs_modulus: e,
            outer: (od, od),
            inner: (id, id),
            shear: Some(kappa * g),
        };
        let b = beam(&el);
        let pi = std::f64::consts::PI;
        let a = pi * (od * od - id * id) / 4.0;
        let i = pi * (od.powi(4) - id.powi(4)) / 64.0;
        let p = 12.0 * e * i / (kappa * g * a * l * l);
        assert!((b.phi / p - 1.0).abs() < 1e-15 && p > 1.0, "Φ = {p}");
        let (l2, p2) = (l * l, p * p);
        let mt = upper(
            [
                [
                    312.0 + 588.0 * p + 280.0 * p2,
                    (44.0 + 77.0 * p + 35.0 * p2) * l,
                    108.0 + 252.0 * p + 140.0 * p2,
                    -(26.0 + 63.0 * p + 35.0 * p2) * l,
                ],
                [
                    0.0,
                    (8.0 + 14.0 * p + 7.0 * p2) * l2,
                    (26.0 + 63.0 * p + 35.0 * p2) * l,
                    -(6.0 + 14.0 * p + 7.0 * p2) * l2,
                ],
                [0.0, 0.0, 312.0 + 588.0 * p + 280.0 * p2, -(44.0 + 77.0 * p + 35.0 * p2) * l],
                [0.0, 0.0, 0.0, (8.0 + 14.0 * p + 7.0 * p2) * l2],
            ],
            rho * a * l / (840.0 * (1.0 + p).powi(2)),
        );
        let mr = upper(
            [
                [36.0, (3.0 - 15.0 * p) * l, -36.0, (3.0 - 15.0 * p) * l],
                [0.0, (4.0 + 5.0 * p + 10.0 * p2) * l2, -(3.0 - 15.0 * p) * l, (-1.0 - 5.0 * p + 5.0 * p2) * l2],
                [0.0, 0.0, 36.0, -(3.0 - 15.0 * p) * l],
                [0.0, 0.0, 0.0, (4.0 + 5.0 * p + 10.0 * p2) * l2],
            ],
            rho * i / (30.0 * l * (1.0 + p).powi(2)),
        );
        let k = upper(
            [
                [12.0, 6.0 * l, -12.0, 6.0 * l],
                [0.0, (4.0 + p) * l2, -6.0 * l, (2.0 - p) * l2],
                [0.0, 0.0, 12.0, -6.0 * l],
                [0.0, 0.0, 0.0, (4.0 + p) * l2],
            ],
            e * i / (l * l2 * (1.0 + p)),
        );
        let s = upper(
            [
                [36.0 + 60.0 * p + 30.0 * p2, 3.0 * l, -(36.0 + 60.0 * p + 30.0 * p2), 3.0 * l],
                [0.0, (4.0 + 5.0 * p + 2.5 * p2) * l2, -3.0 * l, -(1.0 + 5.0 * p + 2.5 * p2) * l2],
                [0.0, 0.0, 36.0 + 60.0 * p + 30.0 * p2, -3.0 * l],
                [0.0, 0.0, 0.0, (4.0 + 5.0 * p + 2.5 * p2) * l2],
            ],
            1.0 / (30.0 * l * (1.0 + p).powi(2)),
        );
        assert!(gap(&b.mass, &sum(&mt, &mr)) < QUADRATURE_RTOL, "M {}", gap(&b.mass, &sum(&mt, &mr)));
        assert!(gap(&b.gyroscopic, &mr.map(|r| r.map(|x| 2.0 * x))) < QUADRATURE_RTOL);
        assert!(gap(&b.stiffness, &k) < QUADRATURE_RTOL, "K {}", gap(&b.stiffness, &k));
        assert!(gap(&b.geometric, &s) < QUADRATURE_RTOL, "S {}", gap(&b.geometric, &s));
    }

    #[test]
    fn cowper_coefficient_of_a_solid_and_a_thin_tube() {
        // Cowper (1966): solid circle 6(1 + ν)/(7 + 6ν); thin-walled tube (r → 1)
        // 2(1 + ν)/(4 + 3ν).
        for nu in [0.0, 0.3, 0.49] {
            assert!((cowper_shear_coefficient(nu, 0.0) - 6.0 * (1.0 + nu) / (7.0 + 6.0 * nu)).abs() < 1e-15);
            assert!((cowper_shear_coefficient(nu, 1.0) - 2.0 * (1.0 + nu) / (4.0 + 3.0 * nu)).abs() < 1e-15);
        }
    }

    #[test]
    fn a_tapered_element_holds_its_mass_and_its_rigid_motions() {
        let el = BeamElement {
            length: 0.2,
            density: 7800.0,
            youngs_modulus: 2.0e11,
            outer: (0.08, 0.05),
            inner: (0.02, 0.03),
            shear: Some(0.8 * 8.0e10),
        };
        let b = beam(&el);
        for m in [&b.mass, &b.stiffness, &b.gyroscopic, &b.geometric] {
            assert!(symmetric(m) || gap(m, &transpose(m)) < 1e-15);
        }
        // A rigid translation has the frustum's mass ρπl/12·((D₁² + D₁D₂ + D₂²) − (d₁² + d₁d₂ + d₂²)).
        let (o, i) = (el.outer, el.inner);
        let volume = std::f64::consts::PI * el.length / 12.0
            * ((o.0 * o.0 + o.0 * o.1 + o.1 * o.1) - (i.0 * i.0 + i.0 * i.1 + i.1 * i.1));
        let t = [1.0, 0.0, 1.0, 0.0];
        let quad = |m: &ElementMatrix, v: &[f64; 4]| -> f64 {
            (0..4).map(|r| (0..4).map(|c| v[r] * m[r][c] * v[c]).sum::<f64>()).sum()
        };
        assert!((quad(&b.mass, &t) / (el.density * volume) - 1.0).abs() < 1e-14);
        // Translation and rigid rotation [0, 1, l, 1] store no strain energy.
        for v in [t, [0.0, 1.0, el.length, 1.0]] {
            assert!(quad(&b.stiffness, &v).abs() < 1e-12 * b.stiffness[0][0]);
        }
    }

    fn transpose(m: &ElementMatrix) -> ElementMatrix {
        let mut t = *m;
        for i in 0..4 {
            for j in 0..4 {
                t[i][j] = m[j][i];
            }
        }
        t
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
