//! The size of the reduced basis, chosen by convergence (`analysis.reduced_modes =
//! "auto"`, the default).
//!
//! The Floquet analysis runs on a reduced model (Eq. 22). A fixed number of modes gives
//! answers true to that model, not to the machine: on the paper's rotor the widest-band
//! design's band moves by 2 % from M = 8 to M = 12 with the paper's basis. So the basis
//! is enlarged until the answer asked for (band edges, onsets, growths at the judged
//! points) moves less than a stated tolerance ([`Tolerance`]), and every answer says
//! which basis it used and how far it moved at the last enlargement ([`BasisReport`]).
//!
//! The sizes tried ([`Schedule`]): first every basis mode whose frequency lies at or below
//! the top of the φ window asked about (at least [`MIN_MODES`]): every whirl that a
//! first-order tongue of the window can pair; then each size a quarter larger (at least 2
//! more modes, a forward–backward pair of each), up to [`GROWTH_LIMIT`] times the first
//! size. The answer given is that of the larger basis of the last comparison.

use super::criterion::PATH_FLOOR;
use super::floquet::{FloquetPoint, FloquetSystem};
use super::reduction::ModeSet;
use super::settings::{Basis, ModeCount, Settings, MAX_REDUCED_MODES};
use super::{AnalysisError, Interval, Rotor};
use serde::{Deserialize, Serialize};

/// The smallest basis sized by convergence: the paper's open-circuit M = 4.
pub const MIN_MODES: usize = 4;

/// The largest basis sized by convergence, as a multiple of the first size: 3 × covers
/// the enlargements the bundled problems need (8 → 12 on the paper's rotor) with room,
/// while a reduced model's cost grows like M³ times its steps per period (which grow
/// with its highest frequency): an answer that has not converged by then is reported as
/// such, never extended without bound.
pub const GROWTH_LIMIT: usize = 3;

/// How far an answer may move at an enlargement of the basis and still have converged.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Tolerance {
    /// Relative part (−): of a band's width for its edges, of the value itself for
    /// growths.
    pub relative: f64,
    /// Absolute floor for edges (rad/s).
    pub absolute: f64,
    /// Relative tolerance of onsets (−).
    pub onset: f64,
}

impl Tolerance {
    /// The tolerance of `settings` (`convergence_relative`, `convergence_absolute`).
    pub fn of(settings: &Settings) -> Tolerance {
        Tolerance {
            relative: settings.convergence_relative,
            absolute: settings.convergence_absolute,
            onset: settings.convergence_onset,
        }
    }

    /// The tolerance on an edge of a band `width` wide (rad/s): the larger of the relative
    /// part of the width and the absolute floor.
    pub fn edge(&self, width: f64) -> f64 {
        (self.relative * width.abs()).max(self.absolute)
    }
}

/// How far an answer moved between two sizes of the basis, against its tolerance.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Movement {
    /// The movement of the quantity that moved most (in `unit`; 0 when the answers
    /// differ in kind).
    pub value: f64,
    /// Its tolerance (in `unit`).
    pub tolerance: f64,
    /// `rad/s` for edges, `relative` for onsets and growths.
    pub unit: String,
    /// Which quantity it was, e.g. `band edge lo` or `onset of f1+b1 (k = 1)`.
    pub quantity: String,
    /// Whether the two answers differ in kind (a band at one size, none at the other; a
    /// verdict that changed; a value not finite at one size): never within a tolerance.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub changed: bool,
}

impl Movement {
    /// No movement of `quantity` (compared, equal).
    pub fn none(quantity: &str, unit: &str, tolerance: f64) -> Movement {
        Movement { value: 0.0, tolerance, unit: unit.into(), quantity: quantity.into(), changed: false }
    }

    /// A movement of `value` (finite) of `quantity` in `unit` against `tolerance`.
    pub fn of(value: f64, tolerance: f64, unit: &str, quantity: String) -> Movement {
        Movement { value, tolerance, unit: unit.into(), quantity, changed: false }
    }

    /// Answers that differ in kind: `quantity` says how.
    pub fn change(quantity: String, unit: &str, tolerance: f64) -> Movement {
        Movement { value: 0.0, tolerance, unit: unit.into(), quantity, changed: true }
    }

    /// Whether the movement is within its tolerance.
    pub fn within(&self) -> bool {
        !self.changed && self.value <= self.tolerance
    }

    /// The movement relative to its tolerance (−): at most 1 when within it, +∞ for a
    /// change in kind.
    pub fn ratio(&self) -> f64 {
        if self.changed {
            f64::INFINITY
        } else {
            self.value / self.tolerance
        }
    }

    /// The larger of two movements (by their ratio to their tolerances).
    pub fn worst(self, other: Movement) -> Movement {
        if other.ratio() > self.ratio() || self.ratio().is_nan() {
            other
        } else {
            self
        }
    }

    /// The movement in words, e.g. `0.12 rad/s (band edge lo; tolerance 0.50 rad/s)`.
    pub fn text(&self) -> String {
        let v = if self.changed { "changed in kind".to_string() } else { self.amount(self.value) };
        format!("{v} ({}; tolerance {})", self.quantity, self.amount(self.tolerance))
    }

    fn amount(&self, x: f64) -> String {
        match self.unit.as_str() {
            "relative" => format!("{:.3} %", 100.0 * x),
            u => format!("{x:.3} {u}"),
        }
    }
}

/// How the basis of an answer was chosen.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Sizing {
    /// Fixed by `analysis.reduced_modes`: no enlargement was tried.
    Fixed,
    /// Enlarged until the answer moved less than its tolerance.
    Converged,
    /// The largest size tried still moved the answer beyond its tolerance (or the model
    /// has no more modes): the answer is that of the largest basis, not shown converged.
    NotConverged,
    /// The first size of the schedule for the φ window, with no enlargement tried: what a
    /// chart or a time response is computed on (their verdicts are the model's; `band`,
    /// `regions` and `floquet` converge theirs).
    Unchecked,
}

/// One size of the basis tried, and the answer's movement from the size before.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BasisStep {
    /// Modes M (−).
    pub modes: usize,
    /// The movement from the previous size (None for the first).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub movement: Option<Movement>,
}

/// The basis an answer was computed on, and what was seen of its convergence.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BasisReport {
    /// The modes' kind.
    pub basis: Basis,
    /// The modes M of the answer given (−).
    pub modes: usize,
    /// Fixed, converged or not converged.
    pub sizing: Sizing,
    /// The sizes tried, in order, with their movements.
    pub steps: Vec<BasisStep>,
}

impl BasisReport {
    /// The report of an answer on a fixed basis of `modes` modes.
    pub fn fixed(basis: Basis, modes: usize) -> BasisReport {
        BasisReport { basis, modes, sizing: Sizing::Fixed, steps: vec![BasisStep { modes, movement: None }] }
    }

    /// The movement at the last enlargement (None on a fixed basis).
    pub fn last_movement(&self) -> Option<&Movement> {
        self.steps.last().and_then(|s| s.movement.as_ref())
    }

    /// The report of a basis an answer was computed on but that the answer turned out to
    /// need more modes than: not converged, whatever its sizing said.
    pub fn not_held(mut self) -> BasisReport {
        self.sizing = Sizing::NotConverged;
        self
    }

    /// The modes of [`BasisReport::at_smallest_converged`].
    pub fn at_smallest_converged_modes(&self) -> usize {
        self.clone().at_smallest_converged().modes
    }

    /// The report with `modes` at the smallest size shown converged: for a converged
    /// answer the size before the last, whose answer the last moved by less than the
    /// tolerance (what a run that judges many candidates on one basis takes); otherwise
    /// as it is.
    pub fn at_smallest_converged(mut self) -> BasisReport {
        if self.sizing == Sizing::Converged {
            if let Some(i) = self.steps.len().checked_sub(2) {
                self.modes = self.steps[i].modes;
            }
        }
        self
    }

    /// The basis in words, e.g. `loaded basis, M = 12 (converged: moved 0.000 rad/s
    /// (band edge lo; tolerance 0.500 rad/s) from M = 10)`.
    pub fn text(&self) -> String {
        let kind = match self.basis {
            Basis::Loaded => "loaded",
            Basis::Unloaded => "unloaded",
        };
        let previous = self.steps.len().checked_sub(2).map(|i| self.steps[i].modes);
        let last = self.steps.last().map_or(self.modes, |s| s.modes);
        let detail = match (self.sizing, self.last_movement(), previous) {
            (Sizing::Fixed, ..) => "fixed by analysis.reduced_modes, convergence not checked".to_string(),
            (Sizing::Unchecked, ..) => {
                "the modes up to the top of the phi window, convergence not checked for this output".to_string()
            }
            (Sizing::Converged, Some(m), Some(p)) => {
                format!("converged: the answer moved {} from M = {p} to M = {last}", m.text())
            }
            (Sizing::NotConverged, Some(m), Some(p)) => {
                format!(
                    "NOT CONVERGED: the answer moved {} from M = {p} to M = {last}, the largest basis tried",
                    m.text()
                )
            }
            (Sizing::NotConverged, ..) => "NOT CONVERGED: the model has no more modes to compare with".to_string(),
            (Sizing::Converged, ..) => "converged".to_string(),
        };
        format!("{kind} basis, M = {} ({detail})", self.modes)
    }

    /// Whether the answer may be taken as converged (fixed and unchecked bases make no
    /// claim either way; only an unconverged one is refused).
    pub fn converged(&self) -> bool {
        self.sizing != Sizing::NotConverged
    }

    /// The report of a system built on the first size of its schedule, unchecked.
    pub fn unchecked(basis: Basis, modes: usize) -> BasisReport {
        BasisReport { basis, modes, sizing: Sizing::Unchecked, steps: vec![BasisStep { modes, movement: None }] }
    }
}

/// The sizes of the basis to try, in order.
#[derive(Debug, Clone, PartialEq)]
pub struct Schedule {
    sizes: Vec<usize>,
    fixed: bool,
}

impl Schedule {
    /// The sizes for `settings` on `rotor` at speed Ω (rad/s), for answers about the φ
    /// window whose top is `top` (rad/s): one fixed size, or the sizes of the module docs,
    /// none beyond the modes the model has.
    pub fn new(rotor: &Rotor, settings: &Settings, speed: f64, top: f64) -> Result<Schedule, AnalysisError> {
        if let ModeCount::Fixed(m) = settings.reduced_modes {
            return Ok(Schedule { sizes: vec![m], fixed: true });
        }
        let modes = ModeSet::new(rotor, speed, settings.basis)?;
        let available = modes.available();
        let first = first_size(&modes, speed, top, settings.convergence_relative)?;
        Ok(Schedule::grown(first.min(available), available))
    }

    /// The sizes from `first` on (an automatic schedule whatever the settings say), up to
    /// [`GROWTH_LIMIT`] times it, none beyond the modes the model has: the check that a
    /// basis of `first` modes, chosen elsewhere, holds for another answer.
    pub fn starting_at(rotor: &Rotor, basis: Basis, speed: f64, first: usize) -> Result<Schedule, AnalysisError> {
        let available = available(rotor, basis, speed)?;
        Ok(Schedule::grown(first.min(available), available))
    }

    /// The sizes from `first` up to [`GROWTH_LIMIT`] times it and at most `available`.
    fn grown(first: usize, available: usize) -> Schedule {
        let last = (GROWTH_LIMIT * first).min(available).min(MAX_REDUCED_MODES);
        let mut sizes = vec![first];
        let mut m = first;
        while m < last {
            m = (m + (m / 4).max(2)).min(last);
            sizes.push(m);
        }
        Schedule { sizes, fixed: false }
    }

    /// A fixed schedule of `modes` modes.
    pub fn fixed(modes: usize) -> Schedule {
        Schedule { sizes: vec![modes], fixed: true }
    }

    /// The sizes to try.
    pub fn sizes(&self) -> &[usize] {
        &self.sizes
    }

    /// The first size.
    pub fn first(&self) -> usize {
        self.sizes[0]
    }

    /// Whether the size is fixed (no convergence is checked).
    pub fn is_fixed(&self) -> bool {
        self.fixed
    }
}

/// The modes M a reduced model of `rotor` with a basis of kind `basis` can have at speed
/// Ω (rad/s): its finite modes (per plane on the general path).
pub fn available(rotor: &Rotor, basis: Basis, speed: f64) -> Result<usize, AnalysisError> {
    Ok(ModeSet::new(rotor, speed, basis)?.available())
}

/// The first size of an automatic schedule: from the modes at or below `top` (at least
/// [`MIN_MODES`]), the smallest basis whose whirls at or below `top` (rad/s), forward and
/// backward, are within `relative` of those of a basis [`GROWTH_LIMIT`] times as large.
/// The whirls place the tongues (their sums); a basis without a mode that a whirl of the
/// window couples to gyroscopically has that whirl wrong (on the paper's rotor without its
/// third mode, b2 is 1710 against 1655 rad/s at Ω = 2000 rad/s), and a tongue's answer
/// compared between two such bases (which only differ by modes that do not couple to it)
/// would look converged.
fn first_size(modes: &ModeSet, speed: f64, top: f64, relative: f64) -> Result<usize, AnalysisError> {
    let available = modes.available();
    let per_plane = if modes.real() { 2 } else { 1 };
    let below = modes.frequencies().iter().filter(|w| **w <= top).count().div_ceil(per_plane);
    let start = below.max(MIN_MODES).min(available);
    let reference = (GROWTH_LIMIT * start).min(available).min(MAX_REDUCED_MODES);
    let whirls = |m: usize| -> Result<(Vec<f64>, Vec<f64>), AnalysisError> {
        let (f, b) = modes.reduced(m)?.periodic_system(speed).whirls()?;
        let keep = |v: Vec<f64>| v.into_iter().filter(|w| *w <= top).collect::<Vec<f64>>();
        Ok((keep(f), keep(b)))
    };
    let (rf, rb) = whirls(reference)?;
    let close =
        |a: &[f64], r: &[f64]| a.len() >= r.len() && r.iter().zip(a).all(|(r, a)| (a - r).abs() <= relative * r.abs());
    for m in start..reference {
        let (f, b) = whirls(m)?;
        if close(&f, &rf) && close(&b, &rb) {
            return Ok(m);
        }
    }
    Ok(reference)
}

/// An answer on a basis sized by convergence, with the system it was computed on.
#[derive(Debug, Clone)]
pub struct Sized<T> {
    /// The answer of the largest basis computed.
    pub answer: T,
    /// That basis's Floquet system.
    pub system: FloquetSystem,
    /// The basis and its convergence.
    pub basis: BasisReport,
}

/// The Floquet point at (φ (rad/s), β) with the configured method, on a basis of
/// `settings` sized by convergence at speed Ω (rad/s) for the window up to φ (or fixed by
/// them): its growth per period ln max|μ| compared between sizes ([`point_movement`]).
pub fn point_sized(
    rotor: &Rotor,
    settings: &Settings,
    speed: f64,
    phi: f64,
    beta: f64,
) -> Result<Sized<FloquetPoint>, AnalysisError> {
    let schedule = Schedule::new(rotor, settings, speed, phi)?;
    sized(rotor, settings, &schedule, speed, |fs| Ok(fs.point(phi, beta)), point_movement)
}

/// `answer` on the Floquet systems of `schedule`'s sizes (of `settings`' kind, at speed Ω
/// in rad/s) until one more size moves it, by `movement`, less than the tolerance.
pub fn sized<T>(
    rotor: &Rotor,
    settings: &Settings,
    schedule: &Schedule,
    speed: f64,
    answer: impl Fn(&FloquetSystem) -> Result<T, AnalysisError>,
    movement: impl Fn(&T, &T, &Tolerance) -> Movement,
) -> Result<Sized<T>, AnalysisError> {
    let tolerance = Tolerance::of(settings);
    // The basis modes are solved once for every size of the schedule.
    let set = ModeSet::new(rotor, speed, settings.basis)?;
    let ((answer, system), basis) = converge(
        schedule,
        settings.basis,
        |m| {
            let fs = FloquetSystem::from_mode_set(&set, settings, speed, m)?;
            Ok((answer(&fs)?, fs))
        },
        |a, b| movement(&a.0, &b.0, &tolerance),
    )?;
    Ok(Sized { answer, system, basis })
}

/// How far a point moved between two bases: its verdict (a change is a movement of +∞)
/// and its growth per period ln max|μ|, relative to itself (at least the path's floor
/// [`PATH_FLOOR`]: growths within the floor of zero are all "none").
pub fn point_movement(a: &FloquetPoint, b: &FloquetPoint, tolerance: &Tolerance) -> Movement {
    if a.summary.stable != b.summary.stable {
        return Movement::change("the verdict".into(), "relative", tolerance.relative);
    }
    let (x, y) = (a.summary.ln_max_multiplier, b.summary.ln_max_multiplier);
    relative_movement(x, y, tolerance.relative, PATH_FLOOR, "ln max|mu|")
}

/// Compute an answer on bases of increasing size until it moves less than its tolerance
/// (or the schedule ends): `answer(M)` computes it on M modes, `movement(a, b)` compares
/// the answers at two consecutive sizes. Returns the answer of the largest basis computed
/// and its [`BasisReport`]. A fixed schedule computes once.
pub fn converge<T>(
    schedule: &Schedule,
    basis: Basis,
    mut answer: impl FnMut(usize) -> Result<T, AnalysisError>,
    movement: impl Fn(&T, &T) -> Movement,
) -> Result<(T, BasisReport), AnalysisError> {
    let sizes = schedule.sizes();
    let mut current = answer(sizes[0])?;
    if schedule.fixed {
        return Ok((current, BasisReport::fixed(basis, sizes[0])));
    }
    let mut steps = vec![BasisStep { modes: sizes[0], movement: None }];
    for &m in &sizes[1..] {
        let next = answer(m)?;
        let moved = movement(&current, &next);
        let within = moved.within();
        steps.push(BasisStep { modes: m, movement: Some(moved) });
        current = next;
        if within {
            return Ok((current, BasisReport { basis, modes: m, sizing: Sizing::Converged, steps }));
        }
    }
    let modes = steps.last().map_or(sizes[0], |s| s.modes);
    Ok((current, BasisReport { basis, modes, sizing: Sizing::NotConverged, steps }))
}

/// The edges' movement between two intervals (rad/s), with the tolerance of the narrower
/// one's width: the larger of the two ends' movements.
pub fn interval_movement(a: Interval, b: Interval, tolerance: &Tolerance, what: &str) -> Movement {
    let tol = tolerance.edge(a.width().min(b.width()));
    let lo = (a.lo - b.lo).abs();
    let hi = (a.hi - b.hi).abs();
    let (value, end) = if lo >= hi { (lo, "lo") } else { (hi, "hi") };
    Movement::of(value, tol, "rad/s", format!("{what} {end}"))
}

/// The relative movement of a value (onset, growth) between two sizes, against the
/// relative tolerance `tolerance`; `floor` is the smallest magnitude a relative change is
/// taken of (a value nearer zero moves by its absolute change over `floor`).
pub fn relative_movement(a: f64, b: f64, tolerance: f64, floor: f64, what: &str) -> Movement {
    if !(a.is_finite() && b.is_finite()) {
        return Movement::change(format!("{what} not finite at one size"), "relative", tolerance);
    }
    let scale = a.abs().max(b.abs()).max(floor);
    Movement::of((a - b).abs() / scale, tolerance, "relative", what.into())
}
