//! Component tolerances (`[design.tolerances]`): the circuit as built differs from the
//! circuit as designed by a relative error on each inductance L, resistance R, branch
//! capacitance C_f and stack capacitance C_p^T.
//!
//! A [`Perturbation`] is one such build: a factor on every component of a kind (the same
//! factor for every branch and ring, as parts of one batch share a bias). It scales the
//! model's branches (L, R, C_f as built: the tuning frequency follows from them by Eq. 4)
//! and the stack's capacitance at constant stress and at constant strain together
//! (C_p^S = C_p^T·(1 − k²): the same dielectric), which moves k_eq2 (Eq. 1). The axial
//! load stays the nominal design's force (its P_cr).
//!
//! The **tolerance box** of a design is every factor in [1 − t, 1 + t] for its kind's
//! tolerance t. The optimiser judges a candidate at the box's centre and corners
//! ([`Tolerances::corners`]: 2^d points for d toleranced kinds, at most 16); the result is
//! then checked on [`Tolerances::samples`] points drawn uniformly from the box by a seeded
//! ChaCha8 generator (the same points on every machine and thread count), each judged by
//! the same band function as `rotorshunt band` on the perturbed design.

use crate::model::Model;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

/// The seed of the Monte Carlo check's generator: fixed, so a report is reproducible.
pub const SAMPLE_SEED: u64 = 0x0051_0ad5_e7ee_d127;

/// Relative tolerances of the shunt's components (−, each in [0, 1)), and the Monte Carlo
/// sample count of the check.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Tolerances {
    /// Of every inductance L.
    pub inductance: f64,
    /// Of every resistance R.
    pub resistance: f64,
    /// Of every branch capacitance C_f.
    pub c_f: f64,
    /// Of every stack capacitance C_p^T (and C_p^S with it).
    pub cp_t: f64,
    /// Monte Carlo samples of the check on the result (≥ 1).
    pub samples: usize,
}

/// One build of the circuit: a factor (−) on every component of each kind.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Perturbation {
    /// `nominal`, a corner like `L+ R-`, or `sample k`.
    pub name: String,
    /// Factor on every L.
    pub inductance: f64,
    /// Factor on every R.
    pub resistance: f64,
    /// Factor on every C_f.
    pub c_f: f64,
    /// Factor on every C_p^T and C_p^S.
    pub cp_t: f64,
}

impl Perturbation {
    /// The design as designed: every factor 1.
    pub fn nominal() -> Perturbation {
        Perturbation { name: "nominal".into(), inductance: 1.0, resistance: 1.0, c_f: 1.0, cp_t: 1.0 }
    }

    /// The model as built with this perturbation, under the axial load of the design as
    /// designed: `critical_load` (N) is the nominal design's P_cr, so P(t) stays the same
    /// force when the stack's capacitance (and with it the open-circuit stiffness that
    /// P_cr is computed with) moves.
    pub fn apply(&self, model: &Model, critical_load: f64) -> Model {
        let mut m = model.clone();
        m.load.critical_load = Some(critical_load);
        for ring in &mut m.rings {
            ring.ring.cp_t *= self.cp_t;
            ring.ring.cp_s *= self.cp_t;
            for b in &mut ring.circuit.branches {
                b.inductance *= self.inductance;
                b.resistance *= self.resistance;
                b.c_f *= self.c_f;
            }
        }
        m
    }
}

impl Tolerances {
    /// The toleranced kinds: (short name, tolerance) of each with a tolerance above 0.
    fn kinds(&self) -> Vec<(&'static str, f64)> {
        [("L", self.inductance), ("R", self.resistance), ("C_f", self.c_f), ("C_p", self.cp_t)]
            .into_iter()
            .filter(|(_, t)| *t > 0.0)
            .collect()
    }

    /// The perturbation with factor 1 + s_k·t_k for each toleranced kind k.
    fn at(&self, name: String, signs: &[f64]) -> Perturbation {
        let mut p = Perturbation { name, ..Perturbation::nominal() };
        for ((kind, t), s) in self.kinds().into_iter().zip(signs) {
            let f = 1.0 + s * t;
            match kind {
                "L" => p.inductance = f,
                "R" => p.resistance = f,
                "C_f" => p.c_f = f,
                _ => p.cp_t = f,
            }
        }
        p
    }

    /// The centre of the box (the nominal design) and its 2^d corners, named like
    /// `L+ R-`.
    pub fn corners(&self) -> Vec<Perturbation> {
        let kinds = self.kinds();
        let d = kinds.len();
        let mut out = vec![Perturbation::nominal()];
        for mask in 0..(1usize << d) {
            let signs: Vec<f64> = (0..d).map(|k| if mask >> k & 1 == 1 { 1.0 } else { -1.0 }).collect();
            let name = kinds
                .iter()
                .zip(&signs)
                .map(|((kind, _), s)| format!("{kind}{}", if *s > 0.0 { '+' } else { '-' }))
                .collect::<Vec<_>>()
                .join(" ");
            out.push(self.at(name, &signs));
        }
        out
    }

    /// [`Tolerances::samples`] points drawn uniformly from the box (`SAMPLE_SEED`).
    pub fn draw(&self) -> Vec<Perturbation> {
        let d = self.kinds().len();
        let mut rng = ChaCha8Rng::seed_from_u64(SAMPLE_SEED);
        (0..self.samples)
            .map(|i| {
                let signs: Vec<f64> = (0..d).map(|_| rng.random_range(-1.0..=1.0)).collect();
                self.at(format!("sample {}", i + 1), &signs)
            })
            .collect()
    }

    /// Whether any kind has a tolerance (an all-zero table checks nothing).
    pub fn any(&self) -> bool {
        !self.kinds().is_empty()
    }

    /// The tolerances in words, e.g. `L ±5 %, R ±20 %`.
    pub fn text(&self) -> String {
        self.kinds().iter().map(|(k, t)| format!("{k} ±{} %", 100.0 * t)).collect::<Vec<_>>().join(", ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tol(l: f64, r: f64) -> Tolerances {
        Tolerances { inductance: l, resistance: r, c_f: 0.0, cp_t: 0.0, samples: 50 }
    }

    #[test]
    fn corners_are_the_centre_and_every_sign_combination() {
        let c = tol(0.05, 0.2).corners();
        assert_eq!(c.len(), 5);
        assert_eq!(c[0], Perturbation::nominal());
        let mut seen: Vec<(f64, f64)> = c[1..].iter().map(|p| (p.inductance, p.resistance)).collect();
        seen.sort_by(|a, b| a.partial_cmp(b).unwrap());
        assert_eq!(seen, vec![(0.95, 0.8), (0.95, 1.2), (1.05, 0.8), (1.05, 1.2)]);
        assert!(c[1..].iter().all(|p| p.c_f == 1.0 && p.cp_t == 1.0));
    }

    #[test]
    fn samples_lie_in_the_box_and_repeat() {
        let t = tol(0.05, 0.2);
        let a = t.draw();
        assert_eq!(a.len(), 50);
        assert!(a.iter().all(|p| (p.inductance - 1.0).abs() <= 0.05 && (p.resistance - 1.0).abs() <= 0.2));
        assert_eq!(a, t.draw());
        // Not all on one side: the draw spreads over the box.
        assert!(a.iter().any(|p| p.inductance > 1.0) && a.iter().any(|p| p.inductance < 1.0));
    }
}
