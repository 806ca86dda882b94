//! One candidate design: the problem with the variables set, its Floquet systems at the
//! operating speeds, and the quantities the optimiser works on (the signed width of the
//! operating band, the regions intruding into the operating bands).

use super::spec::{Band, DesignSpec, Parameter};
use super::DesignError;
use crate::analysis::floquet::FloquetSystem;
use crate::analysis::modes::{whirl_modes_of, ModesResult};
use crate::analysis::regions::{band_at, catalogue, edges_at, unstable_at, Counter, RegionSettings};
use crate::analysis::Rotor;
use crate::problem::{Problem, ProblemFile};
use serde::Serialize;

/// The problem with the design variables set to `values` (SI units).
pub fn problem_at(base: &Problem, spec: &DesignSpec, values: &[f64]) -> Result<Problem, DesignError> {
    let mut data: ProblemFile = base.data.clone();
    for (v, &x) in spec.variables.iter().zip(values) {
        let b = &mut data.circuit.branches[v.branch];
        match v.parameter {
            Parameter::CF => b.c_f = x,
            Parameter::Resistance => b.resistance = x,
            Parameter::Inductance => {
                b.inductance = Some(x);
                b.tuning_frequency = None;
            }
            Parameter::TuningFrequency => {
                b.tuning_frequency = Some(x);
                b.inductance = None;
            }
        }
    }
    Ok(Problem::from_data(data, &base.file, &base.overrides)?)
}

/// The current values of the variables in a problem (SI units): L from Eq. (4) where the
/// branch is given by its tuning frequency and the other way round.
pub fn values_of(problem: &Problem, spec: &DesignSpec) -> Vec<f64> {
    let cp_t = problem.model.left.cp_t;
    spec.variables
        .iter()
        .map(|v| {
            let b = &problem.model.circuit.branches[v.branch];
            match v.parameter {
                Parameter::CF => b.c_f,
                Parameter::Resistance => b.resistance,
                Parameter::Inductance => b.inductance,
                Parameter::TuningFrequency => b.tuning_frequency(cp_t),
            }
        })
        .collect()
}

/// A candidate prepared at every operating speed.
pub struct Candidate {
    /// The problem with the variables set.
    pub problem: Problem,
    /// Its assembled rotor.
    pub rotor: Rotor,
    /// (speed, reduced periodic system) per operating speed.
    pub systems: Vec<(f64, FloquetSystem)>,
}

impl Candidate {
    /// Build the rotor and the reduced systems at the spec's speeds.
    pub fn new(base: &Problem, spec: &DesignSpec, values: &[f64]) -> Result<Candidate, DesignError> {
        let problem = problem_at(base, spec, values)?;
        let rotor = Rotor::new(&problem.model)?;
        let systems = spec
            .speeds
            .iter()
            .map(|&w| Ok((w, FloquetSystem::new(&rotor, &problem.settings, w)?)))
            .collect::<Result<Vec<_>, DesignError>>()?;
        Ok(Candidate { problem, rotor, systems })
    }

    /// Full-model whirls at each speed (for region labels).
    pub fn modes(&self) -> Result<Vec<ModesResult>, DesignError> {
        self.systems.iter().map(|(w, _)| Ok(whirl_modes_of(&self.rotor, &self.problem.settings, *w)?)).collect()
    }
}

/// The operating band at one speed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct OperatingBand {
    /// Speed Ω (rad/s).
    pub speed: f64,
    /// The stable band [lo, hi] containing φ_op at β_op, or None when φ_op is unstable.
    pub band: Option<[f64; 2]>,
    /// Width of the band (rad/s) if stable; minus the distance from φ_op to the nearer
    /// edge of the region containing it otherwise (continuous across the transition).
    pub signed_width: f64,
}

/// The band around φ_op at every speed; the objective is the smallest signed width.
pub fn operating_bands(c: &Candidate, spec: &DesignSpec, s: &RegionSettings, count: &Counter) -> Vec<OperatingBand> {
    let phi_op = spec.phi_op.expect("validated: widest-stable-band has phi_op");
    c.systems
        .iter()
        .map(|(speed, fs)| {
            let mut n = 0;
            let band = band_at(fs, s, phi_op, spec.level, spec.phi_range, &mut n);
            let signed_width = match band {
                Some(b) => b[1] - b[0],
                None => {
                    let e = edges_at(fs, s, phi_op, spec.level, &mut n);
                    -(phi_op - e.left).min(e.right - phi_op)
                }
            };
            count.add(n);
            OperatingBand { speed: *speed, band, signed_width }
        })
        .collect()
}

/// A region at the level that reaches into an operating band widened by its clearance
/// (`inside`), or lies next to it (within [`NEIGHBOURHOOD`] of the band's centre).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Intrusion {
    /// Whether it reaches into the widened band.
    pub inside: bool,
    /// Speed Ω (rad/s).
    pub speed: f64,
    /// Index of the band in the spec.
    pub band: usize,
    /// Region label and order (`unexplained` for a guard-scan interval).
    pub label: String,
    /// Order k.
    pub order: usize,
    /// Onset β_min of the region.
    pub onset: f64,
    /// Edges at the level (rad/s).
    pub left: f64,
    /// Right edge (rad/s).
    pub right: f64,
    /// How far the region must move down (right edge to band.lo − clearance) (rad/s).
    pub push_down: f64,
    /// How far it must move up (left edge to band.hi + clearance) (rad/s).
    pub push_up: f64,
}

impl Intrusion {
    /// The smaller move that clears the band (rad/s); 0 for a neighbour.
    pub fn violation(&self) -> f64 {
        if self.inside {
            self.push_down.min(self.push_up)
        } else {
            0.0
        }
    }
}

/// Regions whose edges at the level lie within this fraction of a band's centre outside
/// the widened band are its neighbours: a design step must not push them in.
pub const NEIGHBOURHOOD: f64 = 0.05;

/// Unstable points of a 1 rad/s grid over [lo, hi] at the level (rayon over points).
fn unstable_grid(fs: &FloquetSystem, lo: f64, hi: f64, level: f64, count: &Counter) -> Vec<f64> {
    use rayon::prelude::*;
    let grid: Vec<f64> = (0..).map(|k| lo.ceil() + k as f64).take_while(|&p| p <= hi).collect();
    count.add(grid.len());
    grid.par_iter()
        .filter(|&&phi| {
            faer::set_global_parallelism(faer::Par::Seq);
            unstable_at(fs, phi, level, &mut 0)
        })
        .copied()
        .collect()
}

/// An unstable φ within ±`half` of `phi` at the level (stepping outward by 0.25 rad/s),
/// for following a thin unlabelled interval under a small design change.
pub fn unstable_near(fs: &FloquetSystem, phi: f64, half: f64, level: f64, count: &Counter) -> Option<f64> {
    let steps = (half / 0.25).ceil() as usize;
    (0..=steps).flat_map(|k| [phi + 0.25 * k as f64, phi - 0.25 * k as f64]).find(|&p| {
        count.add(1);
        p > 0.0 && unstable_at(fs, p, level, &mut 0)
    })
}

/// All regions intruding into the operating bands (widened by their clearance) or next to
/// them, at every speed: the labelled regions of the catalogue around each band (onset up
/// to β_op) and, as `unlabelled` (order 0), every other cluster of unstable points of a
/// 1 rad/s grid over the widened band (thin higher-order slivers), edges bisected.
pub fn intrusions(
    c: &Candidate,
    modes: &[ModesResult],
    spec: &DesignSpec,
    s: &RegionSettings,
    count: &Counter,
) -> Result<Vec<Intrusion>, DesignError> {
    let mut out = Vec::new();
    for ((speed, fs), full) in c.systems.iter().zip(modes) {
        for (i, band) in spec.bands.iter().enumerate() {
            let g = band.guarded();
            let reach = NEIGHBOURHOOD * 0.5 * (g.0 + g.1);
            let near = ((g.0 - reach).max(1.0), g.1 + reach);
            let cat = catalogue(fs, full, s, near, spec.level, spec.level, false)?;
            count.add(cat.evaluations);
            let mut found: Vec<Intrusion> = Vec::new();
            let make = |label: String, order: usize, onset: f64, left: f64, right: f64| {
                (right > near.0 && left < near.1).then_some(Intrusion {
                    inside: right > g.0 && left < g.1,
                    speed: *speed,
                    band: i,
                    label,
                    order,
                    onset,
                    left,
                    right,
                    push_down: right - g.0,
                    push_up: g.1 - left,
                })
            };
            for r in &cat.regions {
                if let (Some(l), Some(rr)) = (r.left, r.right) {
                    found.extend(make(r.label.clone(), r.order, r.onset_beta, l, rr));
                }
            }
            let known: Vec<(f64, f64)> =
                found.iter().filter(|x| x.inside).map(|x| (x.left - 1.0, x.right + 1.0)).collect();
            let mut loose: Vec<f64> = unstable_grid(fs, g.0.max(1.0), g.1, spec.level, count)
                .into_iter()
                .filter(|&p| !known.iter().any(|(l, r)| *l <= p && p <= *r))
                .collect();
            loose.sort_by(f64::total_cmp);
            let mut k = 0;
            while k < loose.len() {
                let mut n = 0;
                let mut e = edges_at(fs, s, loose[k], spec.level, &mut n);
                count.add(n);
                e.left = e.left.min(loose[k]);
                found.extend(make("unlabelled".into(), 0, spec.level, e.left, e.right));
                while k < loose.len() && loose[k] <= e.right + 1.0 {
                    k += 1;
                }
            }
            out.extend(found);
        }
    }
    Ok(out)
}

/// Unstable points of a 1 rad/s grid over each widened band at β_op, at every speed:
/// the independent check of a clear-bands result.
pub fn fine_check(c: &Candidate, bands: &[Band], level: f64, count: &Counter) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    for (speed, fs) in &c.systems {
        for b in bands {
            let g = b.guarded();
            out.extend(unstable_grid(fs, g.0.max(1.0), g.1, level, count).into_iter().map(|p| (*speed, p)));
        }
    }
    out
}

/// The widest interval around φ_op free of unstable points of a 1 rad/s grid at β_op,
/// scanning outward from φ_op inside `band`, each end bisected to 0.01 rad/s between the
/// last stable and the first unstable grid point: the independent check of a band.
pub fn fine_band(fs: &FloquetSystem, phi_op: f64, level: f64, band: [f64; 2], count: &Counter) -> [f64; 2] {
    let unstable = |phi: f64| unstable_at(fs, phi, level, &mut 0);
    let side = |dir: f64| -> f64 {
        faer::set_global_parallelism(faer::Par::Seq);
        let mut phi = phi_op;
        let mut n = 0;
        loop {
            let next = if dir < 0.0 { (phi - 1.0).ceil() } else { (phi + 1.0).floor() };
            if (dir < 0.0 && next < band[0]) || (dir > 0.0 && next > band[1]) {
                count.add(n);
                return if dir < 0.0 { band[0] } else { band[1] };
            }
            n += 1;
            if unstable(next) {
                let (mut stable, mut bad) = (phi, next);
                while (bad - stable).abs() > 0.01 {
                    let mid = 0.5 * (stable + bad);
                    n += 1;
                    if unstable(mid) {
                        bad = mid;
                    } else {
                        stable = mid;
                    }
                }
                count.add(n);
                return stable;
            }
            phi = next;
        }
    };
    let (lo, hi) = rayon::join(|| side(-1.0), || side(1.0));
    [lo, hi]
}
