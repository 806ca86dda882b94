//! The shaft as a list of sections, each cut into equal Rayleigh beam elements.

use serde::Serialize;
use std::f64::consts::PI;

/// One section of the shaft: a uniform circular (solid or hollow) tube of one material.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Section {
    /// Length (m).
    pub length: f64,
    /// Outer diameter D (m).
    pub outer_diameter: f64,
    /// Inner diameter d (m), 0 for a solid section; d < D.
    pub inner_diameter: f64,
    /// Number of equal Rayleigh elements in the section.
    pub elements: usize,
    /// Young's modulus E (Pa).
    pub youngs_modulus: f64,
    /// Density ρ (kg/m³).
    pub density: f64,
}

impl Section {
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
    /// Section mass ρAL (kg).
    pub fn mass(&self) -> f64 {
        self.density * self.area() * self.length
    }
    /// Bending stiffness EI (N·m²).
    pub fn bending_stiffness(&self) -> f64 {
        self.youngs_modulus * self.inertia()
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
        Shaft {
            sections: vec![Section {
                length,
                outer_diameter: 2.0 * radius,
                inner_diameter: 0.0,
                elements,
                youngs_modulus,
                density,
            }],
        }
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
        self.sections.iter().map(|s| PI.powi(2) * s.youngs_modulus * s.inertia() / l2).fold(f64::INFINITY, f64::min)
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
        let sec = |length: f64, elements| Section {
            length,
            outer_diameter: 0.05,
            inner_diameter: 0.02,
            elements,
            youngs_modulus: 2e11,
            density: 7800.0,
        };
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
