//! The margins of a stable band (issue 27, point 1): how far the load may rise before a
//! counted tongue is born inside the band, how far φ_op lies from each edge, the largest
//! max|μ| sampled inside it, and the band by the strict criterion beside the declared one
//! ([`Criterion::strict`]).
//!
//! **Load margin.** A tongue that is not there at β_op enters the band when the load rises
//! to its onset: the tongues with a tip inside the band and an onset above β_op. Its
//! measure is the lowest such onset as β/β_op − 1, with the tongue's name as the catalogue
//! gives it, found among the regions of a catalogue at β_op ([`super::catalogue`]: the
//! seeds' starts and onsets up to its β_max, `regions.max_order`), the same regions
//! `rotorshunt regions` lists. The tongues bounding the band widen into it as soon as the
//! load rises; how far they may widen before reaching φ_op is the frequency margin
//! (φ_op − lo, hi − φ_op), and the band at a margin level (1 + m)·β_op is the band that
//! holds up to that load (`[design.margins]`, [`crate::design`]).

use super::{band_around, catalogue_with, Band, CatalogueRequest, Level, Probe, Region, RegionSettings, Seed};
use crate::analysis::criterion::Threshold;
use crate::analysis::floquet::FloquetSystem;
use crate::analysis::limits;
use crate::analysis::modes::ModesResult;
use crate::analysis::{AnalysisError, Criterion, Interval};
use crate::progress::Progress;
use serde::Serialize;

/// How far above β_op the onsets of a band's load margin are searched when no β_max is
/// given (`rotorshunt band`): up to (1 + this)·β_op, i.e. a load margin up to 100 %; a
/// larger one is reported as "more than" it.
pub const LOAD_MARGIN_REACH: f64 = 1.0;

/// The load a band's margin searches onsets up to, for a band at `level` (−):
/// (1 + [`LOAD_MARGIN_REACH`])·`level`, at most the largest load.
pub fn load_margin_reach(level: f64) -> f64 {
    ((1.0 + LOAD_MARGIN_REACH) * level).min(limits::MAX_BETA)
}

/// The lowest onset of a counted tongue born inside a band.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
pub struct LoadMargin {
    /// onset/β_op − 1 (−).
    pub margin: f64,
    /// The onset β_min (−, relative to P_cr).
    pub onset: f64,
    /// The region's label as the catalogue gives it (`f1+b1`, …).
    pub label: String,
    /// Its order k (−).
    pub order: usize,
    /// Its start φ_s inside the band (rad/s).
    pub start: f64,
    /// Whether its tip was located (false: `onset` is β_c at a point of the region, an
    /// upper bound of the onset, as the catalogue says).
    pub resolved: bool,
}

/// The margins of a stable band at β_op around φ_op.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
pub struct Margins {
    /// β_op (−).
    pub level: f64,
    /// The load margin, or None when no counted tongue is born inside the band up to
    /// `searched_to`: the margin is then more than `searched_to`/β_op − 1.
    pub load: Option<LoadMargin>,
    /// The load (−) up to which onsets were searched.
    pub searched_to: f64,
    /// φ_op − lo (rad/s).
    pub phi_below: f64,
    /// hi − φ_op (rad/s).
    pub phi_above: f64,
    /// The largest max|μ| (−) among the band search's points inside the band
    /// ([`Band::max_multiplier`]).
    pub max_multiplier: Option<f64>,
    /// How many points that is.
    pub sampled: usize,
    /// The strict criterion's threshold ([`Criterion::strict`]).
    pub strict: Threshold,
    /// The band around φ_op by the strict criterion (rad/s); None when φ_op is unstable by it.
    pub strict_band: Option<Interval>,
}

impl Margins {
    /// The load margin as a number (−): the lowest onset's, or `searched_to`/β_op − 1
    /// as a lower bound when none was found.
    pub fn load_margin(&self) -> f64 {
        self.load.as_ref().map_or(self.searched_to / self.level - 1.0, |l| l.margin)
    }

    /// The load margin in words, e.g. `+12.3 % (f1+b1 (k = 2), onset 0.3369)`.
    pub fn load_text(&self) -> String {
        match &self.load {
            Some(l) => format!(
                "{:+.2} % ({} (k = {}) born at {:.2} rad/s, onset {:.4}{})",
                100.0 * l.margin,
                l.label,
                l.order,
                l.start,
                l.onset,
                if l.resolved { "" } else { ", an upper bound: the tongue's lowest point was not found" }
            ),
            None => format!(
                "more than {:.1} % (no counted tongue born inside the band up to beta = {})",
                100.0 * (self.searched_to / self.level - 1.0),
                self.searched_to
            ),
        }
    }

    /// The margins in words, one line per item, each starting with `prefix`.
    pub fn text(&self, prefix: &str) -> String {
        let mut s = format!("{prefix}load margin: {}\n", self.load_text());
        s += &format!(
            "{prefix}frequency margins: phi_op - lo = {:.2} rad/s, hi - phi_op = {:.2} rad/s\n",
            self.phi_below, self.phi_above
        );
        s += &match self.max_multiplier {
            Some(m) => format!(
                "{prefix}largest max|mu| inside the band: {m:.7} (over the {} points the band search evaluated inside it)\n",
                self.sampled
            ),
            None => format!("{prefix}largest max|mu| inside the band: not sampled\n"),
        };
        let rule = self.strict.describe();
        s + &match self.strict_band {
            Some(b) => format!(
                "{prefix}strict band (unstable when {rule}): [{:.2}, {:.2}] rad/s, width {:.2} rad/s\n",
                b.lo,
                b.hi,
                b.width()
            ),
            None => format!("{prefix}strict band (unstable when {rule}): none, phi_op is unstable by it\n"),
        }
    }
}

/// The lowest onset above `level` among `regions` whose start lies inside `band`
/// (strictly: a start on an edge is a bounding tongue's).
pub fn load_margin(regions: &[Region], band: Interval, level: f64) -> Option<LoadMargin> {
    regions
        .iter()
        .filter(|r| r.onset_beta > level && band.lo < r.start && r.start < band.hi)
        .min_by(|a, b| a.onset_beta.total_cmp(&b.onset_beta).then(a.order.cmp(&b.order)))
        .map(|r| LoadMargin {
            margin: r.onset_beta / level - 1.0,
            onset: r.onset_beta,
            label: r.label.clone(),
            order: r.order,
            start: r.start,
            resolved: r.resolved,
        })
}

/// The band around `band.phi_op` by the strict criterion in `window`, from `seeds` (the
/// window's, as the band took them); None when φ_op is unstable by it. When the declared
/// criterion is the strict one ([`Criterion::is_strict`]) that is `band` itself, found
/// again by no search. The search stops early when `progress` asks (its result is then
/// incomplete, for the caller to discard).
pub fn strict_band(
    fs: &FloquetSystem,
    s: &RegionSettings,
    seeds: &[Seed],
    band: &Band,
    window: Interval,
    progress: &dyn Progress,
) -> Option<Interval> {
    let declared = Criterion::of(&fs.settings);
    if declared.is_strict() {
        // The declared criterion is the strict one: its band is the declared band.
        return band.band;
    }
    // Stopped when `progress` asks, its steps not reported (the caller's band counted them).
    let ask = crate::progress::AskOnly(progress);
    let probe = Probe::reporting(fs, s, &ask);
    band_around(&Level::new(&probe, declared.strict(), band.level, window), seeds, band.phi_op).band
}

/// The margins of `band` from its parts: the strict band and the regions of a catalogue
/// at the band's level searched up to `searched_to`. None without a band.
pub fn assemble(
    band: &Band,
    strict_band: Option<Interval>,
    regions: &[Region],
    searched_to: f64,
    strict: Threshold,
) -> Option<Margins> {
    let b = band.band?;
    Some(Margins {
        level: band.level,
        load: load_margin(regions, b, band.level),
        searched_to,
        phi_below: band.phi_op - b.lo,
        phi_above: b.hi - band.phi_op,
        max_multiplier: band.max_multiplier,
        sampled: band.sampled,
        strict,
        strict_band,
    })
}

/// The margins of a band found in `window` (as `rotorshunt band` gives them): the strict
/// band, and the load margin from a catalogue of the band itself at its level with onsets
/// up to (1 + [`LOAD_MARGIN_REACH`])·β_op (at most the largest load). None without a band.
pub fn band_margins(
    fs: &FloquetSystem,
    full: &ModesResult,
    s: &RegionSettings,
    seeds: &[Seed],
    band: &Band,
    window: Interval,
    progress: &dyn Progress,
) -> Result<Option<Margins>, AnalysisError> {
    let Some(b) = band.band else { return Ok(None) };
    let strict = strict_band(fs, s, seeds, band, window, progress);
    let searched_to = load_margin_reach(band.level);
    let req = CatalogueRequest::new(b, searched_to, band.level, false)?;
    let cat = catalogue_with(fs, full, s, &req, progress)?;
    Ok(assemble(band, strict, &cat.regions, searched_to, Criterion::of(&fs.settings).strict().threshold))
}
