//! One candidate design: the machine with the variables set, its Floquet systems at the
//! operating speeds, and the quantities the optimiser works on: the true stable band at
//! β_op around φ_op ([`crate::analysis::regions::band_around`], the same function as
//! `rotorshunt band`) and the tongues intruding into the operating bands (from the same
//! unstable set at β_op, [`Level::scan`]).

use super::machine::Machine;
use super::spec::{Band as OperatingRange, DesignSpec, Parameter};
use super::DesignError;
use crate::analysis::floquet::FloquetSystem;
use crate::analysis::regions::{band_around, seeds_for, Band, Counter, Level, Probe, RegionSettings, Seed, Tongue};
use crate::analysis::{Criterion, Interval, Rotor};
use crate::model::BranchError;
use crate::progress::AskOnly;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// The machine with the design variables set to `values` (SI units) on its model
/// ([`crate::model::Model::set_branch`]: each variable's branch in the rings the file
/// means, [`Machine::targets`]), checked as the file layer checks a branch.
pub fn machine_at(base: &Machine, spec: &DesignSpec, values: &[f64]) -> Result<Machine, DesignError> {
    let mut model = base.model.clone();
    let error =
        |index: usize, error| DesignError::Candidate { variable: index, name: spec.variables[index].name(), error };
    // (ring, branch, C_p^T of its tuning, the variable that set it last).
    let mut touched: Vec<(usize, usize, f64, usize)> = Vec::new();
    for (i, (v, &x)) in spec.variables.iter().zip(values).enumerate() {
        for t in base.targets(v.ring) {
            model.set_branch(t.ring, v.branch, v.parameter, x, t.cp_t).map_err(|e| error(i, e))?;
            touched.retain(|&(r, b, ..)| (r, b) != (t.ring, v.branch));
            touched.push((t.ring, v.branch, t.cp_t, i));
        }
    }
    // The final branches' coefficients, as a re-read of the tuned file checks them; an
    // overflow is blamed on the variable of the parameter behind it, if one set it.
    for &(ring, branch, cp_t, last) in &touched {
        model.check_branch(ring, branch, cp_t).map_err(|e| {
            let own = match &e {
                BranchError::Overflow { parameter, .. } => spec.variables.iter().rposition(|v| {
                    v.branch == branch
                        && v.parameter == *parameter
                        && base.targets(v.ring).iter().any(|t| t.ring == ring)
                }),
                _ => None,
            };
            error(own.unwrap_or(last), e)
        })?;
    }
    Ok(base.with_model(model))
}

/// The current values of the variables in a machine (SI units): L from Eq. (4) where the
/// branch is given by its tuning frequency and the other way round (with the C_p^T the
/// file tunes the branch with). NaN for a variable whose branch the model lacks (a spec
/// built in code): a candidate at that value is refused as not finite.
pub fn values_of(machine: &Machine, spec: &DesignSpec) -> Vec<f64> {
    spec.variables
        .iter()
        .map(|v| {
            // The first ring the variable sets, with the C_p^T its tuning uses.
            let ring = v.ring.unwrap_or(0);
            let cp_t = machine.targets(v.ring).iter().find(|t| t.ring == ring).map_or(f64::NAN, |t| t.cp_t);
            let Some(b) = machine.model.rings.get(ring).and_then(|s| s.circuit.branches.get(v.branch)) else {
                return f64::NAN;
            };
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
    /// The machine with the variables set on its model ([`machine_at`]).
    pub machine: Machine,
    /// The candidate's assembled rotor (matrices and P_cr).
    pub rotor: Rotor,
    /// (speed, reduced periodic system) per operating speed.
    pub systems: Vec<(f64, FloquetSystem)>,
}

impl Candidate {
    /// Build the rotor and the reduced systems at the spec's speeds.
    pub fn new(base: &Machine, spec: &DesignSpec, values: &[f64]) -> Result<Candidate, DesignError> {
        let machine = machine_at(base, spec, values)?;
        let rotor = Rotor::new(&machine.model)?;
        let systems = spec
            .speeds
            .iter()
            .map(|&w| Ok((w, FloquetSystem::new(&rotor, &machine.settings, w)?)))
            .collect::<Result<Vec<_>, DesignError>>()?;
        Ok(Candidate { machine, rotor, systems })
    }

    /// A candidate from a machine and its rotor already built; the reduced systems at the
    /// spec's speeds only when `stability` (a design judged on the response alone needs
    /// none).
    pub fn from_parts(
        machine: Machine,
        rotor: Rotor,
        spec: &DesignSpec,
        stability: bool,
    ) -> Result<Candidate, DesignError> {
        let systems = if stability {
            spec.speeds
                .iter()
                .map(|&w| Ok((w, FloquetSystem::new(&rotor, &machine.settings, w)?)))
                .collect::<Result<Vec<_>, DesignError>>()?
        } else {
            Vec::new()
        };
        Ok(Candidate { machine, rotor, systems })
    }

    /// The candidate as built with the component factors `p`
    /// (`crate::design::tolerance::Perturbation::apply`), under this candidate's P_cr.
    pub fn perturbed(
        &self,
        spec: &DesignSpec,
        p: &crate::design::tolerance::Perturbation,
    ) -> Result<Candidate, DesignError> {
        let built = self.perturbed_rotor(p)?;
        Candidate::from_parts(built.machine, built.rotor, spec, true)
    }

    /// The candidate as built with the component factors `p`, its rotor only (no reduced
    /// system: for judging at a speed of the caller's choice).
    pub fn perturbed_rotor(&self, p: &crate::design::tolerance::Perturbation) -> Result<Candidate, DesignError> {
        let machine = self.machine.with_model(p.apply(&self.machine.model, self.rotor.critical_load));
        let rotor = Rotor::new(&machine.model)?;
        Ok(Candidate { machine, rotor, systems: Vec::new() })
    }

    /// The declared criterion of the candidate (that of the problem file).
    pub fn criterion(&self) -> Criterion {
        Criterion::of(&self.machine.settings)
    }

    /// The seeds of the design's φ range at speed index `k`, without full-model labels
    /// (the same list, in the same order, as a labelled catalogue of the range takes).
    pub fn seeds(&self, k: usize, spec: &DesignSpec) -> Result<Vec<Seed>, DesignError> {
        self.seeds_of(&self.systems[k].1, spec)
    }

    /// The seeds of the design's φ range on a reduced system `fs` of this candidate (one
    /// of its speeds or another), without full-model labels.
    pub fn seeds_of(&self, fs: &FloquetSystem, spec: &DesignSpec) -> Result<Vec<Seed>, DesignError> {
        Ok(seeds_for(fs, None, spec.range(), self.criterion().max_order)?)
    }
}

/// The operating band at one speed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OperatingBand {
    /// Speed Ω (rad/s).
    pub speed: f64,
    /// The stable band around φ_op at β_op, as `rotorshunt band` gives it over the
    /// design's φ range.
    pub band: Band,
}

impl OperatingBand {
    /// The band's width if φ_op is stable, minus the distance to the nearer edge of the
    /// tongue containing it otherwise (rad/s).
    pub fn signed_width(&self) -> f64 {
        self.band.signed_width()
    }
}

/// What judging a candidate reads besides the candidate: the design problem, the region
/// search's settings, and the counter its Floquet evaluations are added to (whose
/// progress also says when to stop).
#[derive(Debug, Clone, Copy)]
pub struct EvalContext<'a> {
    /// The design problem.
    pub spec: &'a DesignSpec,
    /// The region search's settings.
    pub regions: &'a RegionSettings,
    /// The Floquet evaluations of the searches.
    pub count: &'a Counter<'a>,
}

/// The band around φ_op at every speed; the objective is the smallest signed width.
pub fn operating_bands(c: &Candidate, ev: &EvalContext<'_>, phi_op: f64) -> Result<Vec<OperatingBand>, DesignError> {
    operating_bands_at(c, ev, phi_op, ev.spec.level)
}

/// The band around φ_op at the load `level` (−) at every speed ([`operating_bands`] at
/// another level: the margin level of `[design.margins]`).
pub fn operating_bands_at(
    c: &Candidate,
    ev: &EvalContext<'_>,
    phi_op: f64,
    level: f64,
) -> Result<Vec<OperatingBand>, DesignError> {
    c.systems
        .iter()
        .map(|(speed, fs)| Ok(OperatingBand { speed: *speed, band: band_of_system(c, ev, fs, phi_op, level)? }))
        .collect()
}

/// The band around φ_op at the load `level` (−) of one reduced system `fs` of candidate
/// `c` (at one of its speeds, or another: the speed-range refinement and check), over the
/// design's φ range, with the seeds of that range ([`Candidate::seeds_of`]).
pub fn band_of_system(
    c: &Candidate,
    ev: &EvalContext<'_>,
    fs: &FloquetSystem,
    phi_op: f64,
    level: f64,
) -> Result<Band, DesignError> {
    let seeds = c.seeds_of(fs, ev.spec)?;
    // The search stops when the run is asked to; its evaluations are counted below.
    let ask = AskOnly(ev.count.progress());
    let probe = Probe::reporting(fs, ev.regions, &ask);
    let band = band_around(&Level::new(&probe, c.criterion(), level, ev.spec.range()), &seeds, phi_op);
    ev.count.add(probe.evaluations());
    Ok(band)
}

/// The frequency margin of bands around φ_op (rad/s): the smallest over the speeds of
/// min(φ_op − lo, hi − φ_op), or minus the distance from φ_op to the nearer edge of the
/// tongue containing it where φ_op is unstable (continuous, so an optimiser can climb).
pub fn frequency_margin(bands: &[OperatingBand]) -> f64 {
    bands
        .iter()
        .map(|b| match (b.band.band, b.band.containing) {
            (Some(x), _) => (b.band.phi_op - x.lo).min(x.hi - b.band.phi_op),
            (None, Some(t)) => -(b.band.phi_op - t.lo).min(t.hi - b.band.phi_op),
            (None, None) => 0.0,
        })
        .fold(f64::INFINITY, f64::min)
}

/// How far the bands at the margin level miss `[design.margins]` (rad/s, 0 when met):
/// the shortfall of [`frequency_margin`] below `margins.phi`. With `phi` = 0 a φ_op that
/// is unstable at the margin level still falls short by its distance into the tongue.
pub fn margin_shortfall(bands: &[OperatingBand], margins: &super::spec::MarginSpec) -> f64 {
    let m = frequency_margin(bands);
    if bands.iter().any(|b| b.band.band.is_none()) {
        // Unstable at the margin level: short by the margin and the depth into the tongue.
        return margins.phi - m.min(0.0) + f64::EPSILON;
    }
    (margins.phi - m).max(0.0)
}

/// A counted tongue at β_op that reaches into an operating band widened by its clearance
/// (`inside`), or lies next to it (within [`NEIGHBOURHOOD`] of the band's centre).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Intrusion {
    /// Whether it reaches into the widened band.
    pub inside: bool,
    /// Speed Ω (rad/s).
    pub speed: f64,
    /// Index of the band in the spec.
    pub band: usize,
    /// Label and order of the seed whose pair collides in it, or `unlabelled`.
    pub label: String,
    /// The pair (i, j) and order k of that seed, which identify the tongue in a nearby
    /// design; None when unlabelled. Not serialised: None when read back.
    #[serde(skip)]
    pub identity: Option<((usize, usize), usize)>,
    /// A counted point inside it at β_op (rad/s).
    pub point: f64,
    /// β_c at that point (−): an upper bound of the tongue's onset.
    pub onset: f64,
    /// Left edge at the level (rad/s).
    pub left: f64,
    /// Right edge (rad/s).
    pub right: f64,
    /// How far the tongue must move down (right edge to band.lo − clearance) (rad/s).
    pub push_down: f64,
    /// How far it must move up (left edge to band.hi + clearance) (rad/s).
    pub push_up: f64,
    /// The build it was found on, with `[design.tolerances]`: a corner of the tolerance
    /// box (`L+ R-`, [`crate::design::tolerance::Perturbation::name`]); None for the design
    /// as designed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub build: Option<String>,
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

/// Tongues whose edges at the level lie within this fraction of a band's centre outside
/// the widened band are its neighbours: a design step must not push them in.
pub const NEIGHBOURHOOD: f64 = 0.05;

/// The window around an operating band in which its intruders and neighbours are looked
/// for (rad/s).
pub fn neighbourhood(band: &OperatingRange) -> Interval {
    let g = band.guarded();
    let reach = NEIGHBOURHOOD * g.centre();
    Interval::new((g.lo - reach).max(f64::MIN_POSITIVE), g.hi + reach)
}

/// The intrusion record of a tongue next to band `i`, if it lies in its neighbourhood.
fn intrusion_of(
    t: &Tongue,
    seeds: &[Seed],
    speed: f64,
    i: usize,
    band: &OperatingRange,
    onset: f64,
) -> Option<Intrusion> {
    let (g, near) = (band.guarded(), neighbourhood(band));
    if !t.counted || !t.extent.overlaps(&near) {
        return None;
    }
    let own = t.seeds.first();
    Some(Intrusion {
        inside: t.extent.hi > g.lo && t.extent.lo < g.hi,
        speed,
        band: i,
        label: own
            .map_or_else(|| "unlabelled".to_string(), |(j, _)| format!("{}/{}", seeds[*j].label, seeds[*j].order)),
        identity: own.map(|(j, _)| (seeds[*j].pair, seeds[*j].order)),
        point: own.map_or(t.inside, |(_, p)| *p),
        onset,
        left: t.extent.lo,
        right: t.extent.hi,
        push_down: t.extent.hi - g.lo,
        push_up: g.hi - t.extent.lo,
        build: None,
    })
}

/// Every counted tongue at β_op intruding into an operating band (widened by its
/// clearance) or next to it, at every speed, from the unstable set at β_op over each
/// band's neighbourhood ([`Level::scan`]: seeds of every order up to the criterion's and
/// the guard lattice).
pub fn intrusions(c: &Candidate, ev: &EvalContext<'_>) -> Result<Vec<Intrusion>, DesignError> {
    let spec = ev.spec;
    let mut out = Vec::new();
    for (k, (speed, fs)) in c.systems.iter().enumerate() {
        let seeds = c.seeds(k, spec)?;
        let ask = AskOnly(ev.count.progress());
        let probe = Probe::reporting(fs, ev.regions, &ask);
        let level = Level::new(&probe, c.criterion(), spec.level, spec.range());
        for (i, band) in spec.kept_clear().iter().enumerate() {
            let near = neighbourhood(band).clipped(&spec.range());
            for t in level.scan(&seeds, near) {
                let point = t.seeds.first().map_or(t.inside, |(_, p)| *p);
                let onset = probe.critical_load_below(point, spec.level);
                out.extend(intrusion_of(&t, &seeds, *speed, i, band, onset.beta.unwrap_or(spec.level)));
            }
        }
        ev.count.add(probe.evaluations());
    }
    Ok(out)
}

/// [`intrusions`] of the design as designed and, with `[design.tolerances]`, of every
/// corner of the tolerance box ([`crate::design::tolerance::Tolerances::corners`]), each
/// corner's marked with its [`Intrusion::build`]: what the clear-bands objective keeps out
/// of the bands when the parts may be off by their tolerances. The corners in parallel.
pub fn intrusions_as_built(c: &Candidate, ev: &EvalContext<'_>) -> Result<Vec<Intrusion>, DesignError> {
    let Some(t) = &ev.spec.tolerances else { return intrusions(c, ev) };
    let corners = t.corners();
    let mut out = intrusions(c, ev)?;
    let built: Vec<Vec<Intrusion>> = corners[1..]
        .par_iter()
        .map(|p| {
            let mut ints = intrusions(&c.perturbed(ev.spec, p)?, ev)?;
            for it in &mut ints {
                it.build = Some(p.name.clone());
            }
            Ok(ints)
        })
        .collect::<Result<_, DesignError>>()?;
    out.extend(built.into_iter().flatten());
    Ok(out)
}

/// The candidate `c` as the build an intrusion was found on ([`Intrusion::build`]): `c`
/// itself for the design as designed, else `c` with that corner's factors.
pub fn as_build(c: &Candidate, spec: &DesignSpec, build: Option<&str>) -> Result<Option<Candidate>, DesignError> {
    let (Some(name), Some(t)) = (build, &spec.tolerances) else { return Ok(None) };
    match t.corners().into_iter().find(|p| p.name == name) {
        Some(p) => Ok(Some(c.perturbed(spec, &p)?)),
        None => Ok(None),
    }
}

/// The tongue of an intrusion found again in a nearby candidate: by its seed's pair and
/// order where it has one, else as the counted tongue nearest its old point within its
/// old width plus `search` (rad/s). (onset upper bound, left, right) at β_op.
pub fn follow(
    c: &Candidate,
    ev: &EvalContext<'_>,
    it: &Intrusion,
    search: f64,
) -> Result<Option<(f64, f64, f64)>, DesignError> {
    let spec = ev.spec;
    let Some(k) = spec.speeds.iter().position(|&w| w == it.speed) else { return Ok(None) };
    let fs = &c.systems[k].1;
    let seeds = c.seeds(k, spec)?;
    let ask = AskOnly(ev.count.progress());
    let probe = Probe::reporting(fs, ev.regions, &ask);
    let level = Level::new(&probe, c.criterion(), spec.level, spec.range());
    let point = match it.identity {
        Some((pair, order)) => seeds
            .iter()
            .position(|x| x.pair == pair && x.order == order)
            .and_then(|i| level.hits(&seeds, i).into_iter().find(|h| h.seed == Some(i)).map(|h| h.phi)),
        None => {
            let half = 0.5 * (it.right - it.left) + search;
            let mid = 0.5 * (it.left + it.right);
            let steps = (half / level.cell()).ceil() as usize;
            (0..=steps)
                .flat_map(|j| [mid + level.cell() * j as f64, mid - level.cell() * j as f64])
                .find(|&p| p > 0.0 && level.counts(p))
        }
    };
    let out = point.and_then(|p| {
        let e = level.extent(p)?;
        let onset = probe.critical_load_below(p, spec.level);
        Some((onset.beta.unwrap_or(spec.level), e.lo, e.hi))
    });
    ev.count.add(probe.evaluations());
    Ok(out)
}
