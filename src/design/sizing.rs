//! The reduced basis a design runs on, and its check on a refined basis.
//!
//! **Sizing.** With `analysis.reduced_modes = "auto"` the basis is sized once, before the
//! optimiser runs, on the reference design (the file's circuit): at every operating
//! speed, the quantity the design is judged by is computed on bases of increasing size
//! until it moves less than the settings' tolerance ([`crate::analysis::basis`]): the
//! band around φ_op at β_op (widest-stable-band, or a band-width constraint), or the
//! stable set at β_op over each kept-clear band's neighbourhood. Each is converged at the
//! smallest size whose answer the next size moved by less than the tolerance; every
//! candidate is then judged on the largest such size over the speeds and bands, a fixed
//! basis for the whole run. A fixed `reduced_modes` is kept as it is.
//!
//! **Refined check** ([`refined_check`]): on a basis twice as large (at most the model's
//! modes), by the design's criterion, the tuned design's band around φ_op searched again
//! over the design's range, and the catalogue of the band itself up to the design's β_max
//! (the tongues born inside it: its load margin) and of each kept-clear band's
//! neighbourhood on both bases: each edge must stay within the edge tolerance, each onset
//! of a region found on both bases within the onset tolerance. It shares the optimiser's search
//! code but not its truncation, which is the blind spot a design parks its edges in.

use super::evaluate::{Candidate, EvalContext};
use super::machine::Machine;
use super::spec::DesignSpec;
use super::DesignError;
use crate::analysis::basis::{BasisReport, Movement, Schedule, Sizing, Tolerance};
use crate::analysis::floquet::FloquetSystem;
use crate::analysis::modes::whirl_modes_of;
use crate::analysis::reduction::ModeSet;
use crate::analysis::regions::sized::{band_movement, catalogue_movement};
use crate::analysis::regions::{
    band_sized, catalogue_sized, catalogue_with, CatalogueRequest, Counter, RegionSettings,
};
use crate::analysis::settings::{ModeCount, MAX_REDUCED_MODES};
use crate::analysis::{Interval, Rotor};
use crate::progress::{Progress, Tally};
use serde::{Deserialize, Serialize};

/// The part of a kept-clear band's neighbourhood searched when sizing the basis: the band
/// widened by its clearance and by this fraction of its centre on each side (the reach of
/// the verification's "near" tongues, [`super::verify::NEAR`]).
const NEIGHBOURHOOD: f64 = super::verify::NEAR;

/// The base machine with its basis fixed at the size the design runs on, and how that
/// size was chosen: at the reference design, at every speed, the largest size the design's
/// quantities needed (module docs). A machine whose basis is fixed, or a design with no
/// stability quantity (min-peak-response without a band), keeps its settings; its report
/// is then that of its fixed (or first) size. The evaluations the sizing made are added
/// to `count`.
pub fn size_basis(
    base: &Machine,
    spec: &DesignSpec,
    count: &Counter,
    progress: &dyn Progress,
) -> Result<(Machine, BasisReport), DesignError> {
    let settings = &base.settings;
    if let ModeCount::Fixed(m) = settings.reduced_modes {
        return Ok((base.clone(), BasisReport::fixed(settings.basis, m)));
    }
    let rotor = Rotor::new(&base.model)?;
    let top = spec.range().hi;
    let schedules = |w: f64| Schedule::new(&rotor, settings, w, top);
    let report = match sized_reports(&rotor, base, spec, &schedules, count, progress)? {
        Some(r) => r.at_smallest_converged(),
        None => first_size(&rotor, base, spec, top)?,
    };
    let mut sized = base.clone();
    sized.settings = settings.with_modes(report.modes);
    Ok((sized, report))
}

/// Whether the basis of `machine` (fixed at M modes by [`size_basis`]) still holds at the
/// design `values`: its quantities at every speed computed from M modes up until they
/// converge. None when they converge from M on (the next size moves them less than the
/// tolerance); otherwise the report of the size they need, the machine to run again with.
/// A basis the user fixed is not checked here (the refined check judges it).
pub fn recheck(
    machine: &Machine,
    requested: &crate::analysis::Settings,
    spec: &DesignSpec,
    values: &[f64],
    count: &Counter,
    progress: &dyn Progress,
) -> Result<Option<(Machine, BasisReport)>, DesignError> {
    let (ModeCount::Auto, Some(m)) = (requested.reduced_modes, machine.settings.reduced_modes.fixed()) else {
        return Ok(None);
    };
    let candidate = super::evaluate::machine_at(machine, spec, values)?;
    let rotor = Rotor::new(&candidate.model)?;
    let basis = machine.settings.basis;
    let schedules = |w: f64| Schedule::starting_at(&rotor, basis, w, m);
    let Some(report) = sized_reports(&rotor, &candidate, spec, &schedules, count, progress)? else {
        return Ok(None);
    };
    let report = report.at_smallest_converged();
    if report.modes <= m {
        return Ok(None);
    }
    let mut sized = machine.clone();
    sized.settings = machine.settings.with_modes(report.modes);
    Ok(Some((sized, report)))
}

/// The design's quantities at every speed of `spec` on the machine `at` (its rotor
/// `rotor`), each on the schedule `schedules(speed)` until it converges: the report that
/// needed the largest size (one that did not converge first), or None when the design has
/// no stability quantity.
fn sized_reports(
    rotor: &Rotor,
    at: &Machine,
    spec: &DesignSpec,
    schedules: &dyn Fn(f64) -> Result<Schedule, crate::analysis::AnalysisError>,
    count: &Counter,
    progress: &dyn Progress,
) -> Result<Option<BasisReport>, DesignError> {
    let settings = &at.settings;
    let s = &at.regions;
    let tally = Tally::new(progress);
    let mut reports: Vec<BasisReport> = Vec::new();
    for &w in &spec.speeds {
        let schedule = schedules(w)?;
        let full = whirl_modes_of(rotor, settings, w)?;
        if let Some(phi_op) = spec.phi_op() {
            let b = band_sized(rotor, settings, &schedule, w, &full, s, spec.range(), phi_op, spec.level, &tally)?;
            reports.push(b.basis);
        }
        for band in spec.kept_clear() {
            let req = neighbourhood(band.guarded(), spec);
            let c = catalogue_sized(rotor, settings, &schedule, w, &full, s, &req, &tally)?;
            reports.push(c.basis);
        }
    }
    count.add(tally.evaluations() as usize);
    // The largest size needed; one that did not converge is said so.
    Ok(reports.into_iter().max_by_key(|r| (r.sizing == Sizing::NotConverged, r.at_smallest_converged_modes())))
}

/// The first size of the schedule, for a design with nothing to size by: its basis is
/// reported as fixed there (no stability quantity was compared).
fn first_size(rotor: &Rotor, base: &Machine, spec: &DesignSpec, top: f64) -> Result<BasisReport, DesignError> {
    let speed = spec.speeds.first().copied().unwrap_or(base.model.speed);
    let m = Schedule::new(rotor, &base.settings, speed, top)?.first();
    Ok(BasisReport::fixed(base.settings.basis, m))
}

/// The catalogue request of a kept-clear window's neighbourhood at β_op, in the design's
/// range.
fn neighbourhood(window: Interval, spec: &DesignSpec) -> CatalogueRequest {
    let reach = NEIGHBOURHOOD * window.centre();
    let range = Interval::new(window.lo - reach, window.hi + reach).clipped(&spec.range());
    CatalogueRequest { range, beta_max: spec.level, level: spec.level, track: false }
}

/// The refined check at one speed: the refined basis's size, the movements seen, and
/// whether they are within the tolerance.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RefinedCheck {
    /// Ω (rad/s).
    pub speed: f64,
    /// Modes of the design's basis (−).
    pub modes: usize,
    /// Modes of the refined basis (−).
    pub refined_modes: usize,
    /// The band around φ_op on the refined basis (rad/s), if there is a φ_op and it is
    /// stable there.
    pub refined_band: Option<Interval>,
    /// Each comparison: the band around φ_op, the catalogue of the band (its onsets), and
    /// the catalogue of each kept-clear band's neighbourhood (its stable set and onsets).
    pub movements: Vec<Movement>,
    /// Whether every movement is within its tolerance.
    pub held: bool,
}

/// The tuned design's band and catalogues again on a basis twice the design's (module
/// docs), at each speed of the candidate; `bands` the design's bands
/// around φ_op at those speeds (None without a φ_op). The refined basis is capped by the
/// model's modes; a basis that cannot be doubled at all (the model has no more modes)
/// compares nothing and says so.
pub fn refined_check(
    tuned: &Candidate,
    ev: &EvalContext<'_>,
    bands: &[Option<crate::analysis::regions::Band>],
    progress: &dyn Progress,
) -> Result<Vec<RefinedCheck>, DesignError> {
    let tally = Tally::new(progress);
    let checks = refined_checks(tuned, ev.spec, ev.regions, bands, &tally);
    ev.count.add(tally.evaluations() as usize);
    checks
}

fn refined_checks(
    tuned: &Candidate,
    spec: &DesignSpec,
    s: &RegionSettings,
    bands: &[Option<crate::analysis::regions::Band>],
    progress: &dyn Progress,
) -> Result<Vec<RefinedCheck>, DesignError> {
    let settings = &tuned.machine.settings;
    let tolerance = Tolerance::of(settings);
    let mut out = Vec::new();
    for (k, (w, fs)) in tuned.systems.iter().enumerate() {
        let modes = fs.modes();
        // The basis modes, solved once: they count the modes and build the refined system.
        let set = ModeSet::new(&tuned.rotor, *w, settings.basis)?;
        let refined_modes = (2 * modes).min(set.available()).min(MAX_REDUCED_MODES);
        if refined_modes <= modes {
            out.push(RefinedCheck {
                speed: *w,
                modes,
                refined_modes,
                refined_band: None,
                movements: Vec::new(),
                held: true,
            });
            continue;
        }
        let rfs = FloquetSystem::from_mode_set(&set, settings, *w, refined_modes)?;
        let full = whirl_modes_of(&tuned.rotor, settings, *w)?;
        let both = |req: &CatalogueRequest| -> Result<Movement, DesignError> {
            let here = catalogue_with(fs, &full, s, req, progress)?;
            let there = catalogue_with(&rfs, &full, s, req, progress)?;
            Ok(catalogue_movement(&here, &there, &tolerance))
        };
        let mut movements = Vec::new();
        let mut refined_band = None;
        if let (Some(phi_op), Some(Some(nominal))) = (spec.phi_op(), bands.get(k)) {
            let b = crate::analysis::regions::band_with(&rfs, &full, s, spec.range(), phi_op, spec.level, progress)?;
            refined_band = b.band;
            movements.push(band_movement(nominal, &b, &tolerance));
            // The onsets of the tongues born inside the band up to the design's β_max
            // (its load margin), on both bases.
            if let Some(inside) = nominal.band {
                let req = CatalogueRequest { range: inside, beta_max: spec.beta_max, level: spec.level, track: false };
                movements.push(both(&req)?);
            }
        }
        for band in spec.kept_clear() {
            movements.push(both(&neighbourhood(band.guarded(), spec))?);
        }
        let held = movements.iter().all(Movement::within);
        out.push(RefinedCheck { speed: *w, modes, refined_modes, refined_band, movements, held });
    }
    Ok(out)
}
