//! The shaft as a list of sections, each cut into equal beam elements (Rayleigh or
//! Timoshenko, uniform or tapered).

use super::element::{cowper_shear_coefficient, BeamElement};
use serde::Serialize;
use std::f64::consts::PI;

/// The beam theory of a section's elements.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Default)]
#[serde(rename_all = "snake_case", tag = "theory")]
pub enum Beam {
    /// Euler–Bernoulli bending with rotary inertia and gyroscopic effects, no shear
    /// deformation (the paper's element).
    #[default]
    Rayleigh,
    /// Rayleigh plus shear deformation (docs/model.md).
    Timoshenko {
        /// Shear modulus G (Pa).
        shear_modulus: f64,
        /// Shear coefficient κ (−); `None`: Cowper's of each element
        /// (`cowper_shear_coefficient` with Poisson's ratio E/(2G) − 1 and the ratio of
        /// the element's mean inner to mean outer diameter).
        shear_coefficient: Option<f64>,
    },
}

/// One section of the shaft: a circular (solid or hollow) tube of one material, uniform
/// or tapered (diameters varying linearly from the left end to the right one).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Section {
    /// Length (m).
    pub length: f64,
    /// Outer diameter D at the left end (m).
    pub outer_diameter: f64,
    /// Inner diameter d at the left end (m), 0 for a solid section; d < D.
    pub inner_diameter: f64,
    /// Number of equal elements in the section.
    pub elements: usize,
    /// Young's modulus E (Pa).
    pub youngs_modulus: f64,
    /// Density ρ (kg/m³).
    pub density: f64,
    /// Outer diameter at the right end (m); equal to `outer_diameter` unless tapered.
    pub outer_diameter_right: f64,
    /// Inner diameter at the right end (m); equal to `inner_diameter` unless tapered.
    pub inner_diameter_right: f64,
    /// The beam theory of its elements.
    pub beam: Beam,
    /// Concentric layers over the same nodes (ROSS's shaft elements of one `n`, e.g. a
    /// sleeve), each with its own diameters, material and beam theory: their element
    /// matrices add to the section's. Their `length`, `elements` and `layers` are the
    /// section's (and none).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub layers: Vec<Section>,
}

impl Section {
    /// A uniform Rayleigh section (the paper's kind).
    pub fn uniform(length: f64, outer: f64, inner: f64, elements: usize, youngs_modulus: f64, density: f64) -> Section {
        Section {
            length,
            outer_diameter: outer,
            inner_diameter: inner,
            elements,
            youngs_modulus,
            density,
            outer_diameter_right: outer,
            inner_diameter_right: inner,
            beam: Beam::Rayleigh,
            layers: Vec::new(),
        }
    }
    /// Whether both diameters are the same at both ends.
    pub fn is_uniform(&self) -> bool {
        self.outer_diameter == self.outer_diameter_right && self.inner_diameter == self.inner_diameter_right
    }
    /// Whether the section's elements are the closed-form uniform Rayleigh elements of
    /// the paper (`crate::model::element`), assembled as before Timoshenko and tapered
    /// sections existed, to the bit.
    pub fn is_uniform_rayleigh(&self) -> bool {
        self.is_uniform() && self.beam == Beam::Rayleigh
    }
    /// Outer and inner diameters at the fraction `t` ∈ [0, 1] of the section's length
    /// (m): linear between the ends, exactly the ends' values at t = 0 and 1.
    pub fn diameters_at(&self, t: f64) -> (f64, f64) {
        let lerp = |a: f64, b: f64| if a == b { a } else { (1.0 - t) * a + t * b };
        (lerp(self.outer_diameter, self.outer_diameter_right), lerp(self.inner_diameter, self.inner_diameter_right))
    }
    /// Element `k` (0-based within the section) as a `BeamElement`: its end diameters on
    /// the section's taper, its material and, for a Timoshenko section, κG with κ given or
    /// Cowper's at the element's mean diameters.
    pub fn element(&self, k: usize) -> BeamElement {
        let n = self.elements as f64;
        let (ol, il) = self.diameters_at(k as f64 / n);
        let (or, ir) = self.diameters_at((k + 1) as f64 / n);
        let shear = match self.beam {
            Beam::Rayleigh => None,
            Beam::Timoshenko { shear_modulus, shear_coefficient } => {
                let kappa = shear_coefficient.unwrap_or_else(|| {
                    let poisson = self.youngs_modulus / (2.0 * shear_modulus) - 1.0;
                    cowper_shear_coefficient(poisson, ((il + ir) / 2.0) / ((ol + or) / 2.0))
                });
                Some(kappa * shear_modulus)
            }
        };
        BeamElement {
            length: self.element_length(),
            density: self.density,
            youngs_modulus: self.youngs_modulus,
            outer: (ol, or),
            inner: (il, ir),
            shear,
        }
    }
    fn radii(&self) -> (f64, f64) {
        (self.outer_diameter / 2.0, self.inner_diameter / 2.0)
    }
    /// Cross-section area A = π(r_o² − r_i²) (m²). Written as πr_o² − πr_i², so that a
    /// solid section gives the same bits as πr².
    pub fn area(&self) -> f64 {
        let (ro, ri) = self.radii();
        PI * ro * ro - PI * ri * ri
    }
    /// Diametral second moment I = π(r_o⁴ − r_i⁴)/4 (m⁴); the polar one is 2I.
    pub fn inertia(&self) -> f64 {
        let (ro, ri) = self.radii();
        PI * (ro.powi(4) - ri.powi(4)) / 4.0
    }
    /// Element length l = length/elements (m).
    pub fn element_length(&self) -> f64 {
        self.length / self.elements as f64
    }
    /// Section mass (kg): ρAL, or for a tapered section ρ times the frustum's volume
    /// πL/12·((D₁² + D₁D₂ + D₂²) − (d₁² + d₁d₂ + d₂²)).
    pub fn mass(&self) -> f64 {
        if self.layers.is_empty() {
            return self.own_mass();
        }
        self.own_mass() + self.layers.iter().map(Section::own_mass).sum::<f64>()
    }
    /// The mass of the section's own tube, without its layers (kg).
    fn own_mass(&self) -> f64 {
        if self.is_uniform() {
            return self.density * self.area() * self.length;
        }
        let (o1, o2, i1, i2) =
            (self.outer_diameter, self.outer_diameter_right, self.inner_diameter, self.inner_diameter_right);
        let volume = PI * self.length / 12.0 * ((o1 * o1 + o1 * o2 + o2 * o2) - (i1 * i1 + i1 * i2 + i2 * i2));
        self.density * volume
    }
    /// Bending stiffness EI (N·m²), at the left end.
    pub fn bending_stiffness(&self) -> f64 {
        self.youngs_modulus * self.inertia()
    }
    /// The smallest second moment I over the section (m⁴): at the ends for a uniform
    /// section; for a tapered one, I(x) is a quartic of x, sampled at the ends and at
    /// 64 equal steps between (a lower bound for the text of the Euler load only).
    pub fn min_inertia(&self) -> f64 {
        if self.is_uniform() {
            return self.inertia();
        }
        const STEPS: usize = 64;
        (0..=STEPS)
            .map(|k| {
                let (o, i) = self.diameters_at(k as f64 / STEPS as f64);
                PI * (o.powi(4) - i.powi(4)) / 64.0
            })
            .fold(f64::INFINITY, f64::min)
    }
}

/// The shaft: sections from left (x = 0) to right, nodes numbered 0..=Σ elements.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Shaft {
    /// The sections, left to right (at least one).
    pub sections: Vec<Section>,
}

impl Shaft {
    /// A uniform solid shaft of radius r (m): the paper's rotor and the `[shaft]` shorthand.
    pub fn uniform(length: f64, radius: f64, elements: usize, youngs_modulus: f64, density: f64) -> Shaft {
        Shaft { sections: vec![Section::uniform(length, 2.0 * radius, 0.0, elements, youngs_modulus, density)] }
    }
    /// Total length L (m).
    pub fn length(&self) -> f64 {
        self.sections.iter().fold(0.0, |a, s| a + s.length)
    }
    /// Number of elements Σ n_i.
    pub fn elements(&self) -> usize {
        self.sections.iter().map(|s| s.elements).sum()
    }
    /// Number of nodes Σ n_i + 1.
    pub fn nodes(&self) -> usize {
        self.elements() + 1
    }
    /// The last node index Σ n_i (the right end).
    pub fn last_node(&self) -> usize {
        self.elements()
    }
    /// Shaft mass Σ ρAL (kg).
    pub fn mass(&self) -> f64 {
        self.sections.iter().fold(0.0, |a, s| a + s.mass())
    }
    /// The section of each element, with the index of its first node, left to right.
    pub fn elements_by_section(&self) -> impl Iterator<Item = (usize, &Section)> {
        let mut first = 0;
        self.sections.iter().flat_map(move |s| {
            let start = first;
            first += s.elements;
            (start..start + s.elements).map(move |e| (e, s))
        })
    }
    /// The shaft's own stiffness scale (N/m): the largest translational entry on the
    /// diagonal of its stiffness matrix, at each node the sum of k_uu over the elements
    /// (and concentric layers) that meet there: 12EI/l³ for a uniform Rayleigh element,
    /// 12EI/(l³(1 + Φ)) with shear. The supports' coefficients are judged against it
    /// (`crate::problem`'s `MAX_SUPPORT_STIFFNESS_RATIO`).
    pub fn stiffness_scale(&self) -> f64 {
        self.largest_translational(|m| m.stiffness)
    }
    /// The shaft's own mass scale (kg): the largest translational entry on the diagonal of
    /// its mass matrix (156ρAl/420 + 36ρI/(30l) per element end for a uniform Rayleigh
    /// element, summed at each node). With [`Shaft::stiffness_scale`] K_s it gives the
    /// damping scale √(K_s·M_s), the critical damping of the stiffest node.
    pub fn mass_scale(&self) -> f64 {
        self.largest_translational(|m| m.mass)
    }
    /// The largest translational diagonal entry of one of the shaft's element matrices
    /// (`pick` chooses it), summed at each node over the elements and layers there.
    fn largest_translational(&self, pick: impl Fn(super::element::BeamMatrices) -> [[f64; 4]; 4]) -> f64 {
        let mut diagonal = vec![0.0f64; self.nodes()];
        let mut first = 0;
        for s in &self.sections {
            for part in std::iter::once(s).chain(&s.layers) {
                let uniform = part.is_uniform().then(|| pick(super::element::beam(&part.element(0))));
                for k in 0..s.elements {
                    let e = uniform.unwrap_or_else(|| pick(super::element::beam(&part.element(k))));
                    diagonal[first + k] += e[0][0];
                    diagonal[first + k + 1] += e[2][2];
                }
            }
            first += s.elements;
        }
        diagonal.into_iter().fold(0.0, f64::max)
    }
    /// Position of node `node` from the left end (m): the section's start plus whole
    /// element lengths, so a single section gives exactly `node · l`.
    pub fn node_position(&self, node: usize) -> f64 {
        let (mut start, mut first) = (0.0, 0);
        for s in &self.sections {
            if node <= first + s.elements {
                return start + (node - first) as f64 * s.element_length();
            }
            start += s.length;
            first += s.elements;
        }
        start
    }
    /// The node nearest to `position` (m from the left end, within the shaft): in the
    /// first section that contains it, the rounded number of its element lengths.
    pub fn nearest_node(&self, position: f64) -> usize {
        let (mut start, mut first) = (0.0, 0);
        for s in &self.sections {
            if position <= start + s.length {
                let local = ((position - start) / s.element_length()).round() as usize;
                return first + local.min(s.elements);
            }
            start += s.length;
            first += s.elements;
        }
        first
    }
    /// Euler buckling load π²·EI_min/L² of the pinned-pinned shaft (N): the closed form of
    /// a uniform shaft, and a lower bound of a stepped one (its weakest section's EI).
    pub fn euler_load(&self) -> f64 {
        let l2 = self.length().powi(2);
        // Per section in the uniform formula's order of operations (the same bits for one).
        self.sections.iter().map(|s| PI.powi(2) * s.youngs_modulus * s.min_inertia() / l2).fold(f64::INFINITY, f64::min)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_solid_section_is_the_uniform_formula_to_the_bit() {
        let r = 0.035_f64;
        let s = Shaft::uniform(0.7, r, 64, 2.06e11, 7900.0);
        assert_eq!(s.sections[0].area(), PI * r * r);
        assert_eq!(s.sections[0].inertia(), PI * r.powi(4) / 4.0);
        assert_eq!(s.node_position(17), 17.0 * (0.7 / 64.0));
        assert_eq!(s.nearest_node(0.7 / 4.0), (0.7_f64 / 4.0 / (0.7 / 64.0)).round() as usize);
    }

    #[test]
    fn nodes_and_positions_follow_the_sections() {
        let sec = |length: f64, elements| Section::uniform(length, 0.05, 0.02, elements, 2e11, 7800.0);
        let s = Shaft { sections: vec![sec(0.2, 4), sec(0.6, 3)] };
        assert_eq!(s.nodes(), 8);
        assert!((s.node_position(4) - 0.2).abs() < 1e-15);
        assert!((s.node_position(5) - 0.4).abs() < 1e-15);
        assert!((s.node_position(7) - 0.8).abs() < 1e-15);
        assert_eq!(s.nearest_node(0.31), 5);
        assert_eq!(s.nearest_node(0.8), 7);
        assert_eq!(s.elements_by_section().map(|(e, _)| e).collect::<Vec<_>>(), (0..7).collect::<Vec<_>>());
        let hollow = &s.sections[0];
        let a = PI * (0.05f64.powi(2) - 0.02f64.powi(2)) / 4.0;
        assert!((hollow.area() - a).abs() < 1e-15);
    }
}
