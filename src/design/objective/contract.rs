//! What an objective provides ([`Objective`]), and the keys it is built from.

use super::constraints;
use super::ObjectiveKind;
use crate::analysis::cost::{Estimate, PointCost};
use crate::analysis::regions::{RegionSettings, Seed};
use crate::analysis::{Criterion, Interval};
use crate::design::optimise::{Context, FindingsKind};
use crate::design::pareto::{NoTradeOff, TradeOff};
use crate::design::spec::{Band, DesignSpec, Response};
use crate::design::verify::DesignAtSpeed;
use crate::design::{DesignError, DesignOutcome};
use std::sync::Arc;

/// What the optimiser is asked to do, with the data it needs: one implementation per
/// objective (a module of [`crate::design::objective`]). The design and its report reach
/// everything that differs between objectives through these methods; the provided ones
/// are what the constraints any objective may carry ask for
/// ([`crate::design::spec::Constraints`]).
pub trait Objective: std::fmt::Debug + Send + Sync {
    // The name and the data.

    /// The kind: its name in the file and how it is built.
    fn kind(&self) -> ObjectiveKind;
    /// The objective's data as the flat keys of `[design]` and of the spec's JSON.
    fn keys(&self) -> ObjectiveKeys<'_>;
    /// φ_op (rad/s) when the objective carries one.
    fn phi_op(&self) -> Option<f64> {
        self.keys().phi_op
    }
    /// The operating bands the objective keeps clear (empty for an objective without
    /// bands of its own: its `[[design.bands]]` are then constraints).
    fn bands(&self) -> &[Band] {
        self.keys().bands.unwrap_or(&[])
    }
    /// The unbalance response the objective judges, when it carries one.
    fn response(&self) -> Option<&Response> {
        self.keys().response
    }

    // The run.

    /// The most candidates a design of `spec` builds (an optimiser that converges early
    /// builds fewer): the `optimise` phase's length and the cost estimate's count.
    fn most_candidates(&self, spec: &DesignSpec) -> usize;
    /// Optimise on the run's context: fill the starts, history, convex steps, tuned values
    /// (`out.after`), status and findings of `out`, whose verification follows.
    fn optimise(&self, ctx: &Context<'_>, out: &mut DesignOutcome) -> Result<(), DesignError>;
    /// Which findings the objective's outcome has (report.json's keys read back into it).
    fn findings(&self) -> FindingsKind;
    /// The trade-off of a Pareto front on `spec` ([`crate::design::pareto`]), or why
    /// there is none (by default none: a front trades the peak response against the band
    /// around φ_op).
    fn trade_off(&self, spec: &DesignSpec) -> Result<TradeOff, NoTradeOff> {
        let _ = spec;
        Err(NoTradeOff {
            key: "design.objective".into(),
            reason: format!(
                "{} has no trade-off: a front trades the peak unbalance response against the stable band around phi_op (min-peak-response with phi_op and constraints.min_band_width, or widest-stable-band with [design.response])",
                self.kind().key()
            ),
        })
    }

    // The verification and the cost estimate.

    /// The windows of the tuned design that must be free of instability at one speed
    /// (their catalogued tongues, tongue centres and grid are checked), with the number
    /// of comparisons made; a failure found on the way is added to `d.failures`. `band`
    /// is the optimiser's band around φ_op at that speed, if it searched one. By default
    /// the constraints' windows ([`constraints::verified_windows`]).
    fn verified_windows(
        &self,
        spec: &DesignSpec,
        band: Option<Interval>,
        d: &mut DesignAtSpeed,
    ) -> (Vec<Interval>, usize) {
        let _ = band;
        constraints::verified_windows(spec, d)
    }
    /// The φ window (rad/s) of the before/after charts, before it is clipped to the
    /// design's range ([`crate::design::content::chart_window`]). By default the bands
    /// kept clear, else φ_op's, else the whole range ([`constraints::chart_window`]).
    fn chart_window(&self, spec: &DesignSpec) -> (f64, f64) {
        constraints::chart_window(spec)
    }
    /// The work of one candidate at one speed beyond its dense stages, for the up-front
    /// cost estimate of a design. By default the constraints' searches
    /// ([`constraints::candidate_cost`]).
    fn candidate_cost(&self, spec: &DesignSpec, at: &CostAt<'_>) -> Estimate {
        constraints::candidate_cost(spec, at)
    }
    /// How many times one candidate's [`Objective::candidate_cost`] at one speed is spent
    /// per candidate, over its builds and speeds: by default every build (the nominal
    /// and each corner of `[design.tolerances]`) at every operating speed.
    fn searches_per_candidate(&self, spec: &DesignSpec) -> f64 {
        (spec.builds() * spec.speeds.len().max(1)) as f64
    }
    /// The windows the verification checks on grids, as the cost estimate counts them
    /// (the band taken as the charts' window). By default the constraints'
    /// ([`constraints::checked_windows`]).
    fn checked_windows(&self, spec: &DesignSpec) -> Vec<Interval> {
        constraints::checked_windows(spec)
    }

    // The report.

    /// The question the design answers, in one sentence: `variables` names them, `speeds`
    /// are the operating speeds in words, `constrained` says whether bands are kept clear
    /// or constraints judged.
    fn question(&self, spec: &DesignSpec, variables: &str, speeds: &str, constrained: bool) -> String;
    /// The objective's figures on page one of the report (Markdown).
    fn page_one(&self, s: &mut String, o: &DesignOutcome);
    /// The objective's lines of the command line's summary (each starting with a line
    /// break), after the status; by default none.
    fn summary(&self, o: &DesignOutcome) -> String {
        let _ = o;
        String::new()
    }
    /// The report's description of the optimiser from `starts` starts and the header of
    /// its table of starts (Markdown, ending in a line break).
    fn optimiser_method(&self, starts: usize) -> String;
    /// The axes of the report's history plot: (x, y).
    fn history_axes(&self) -> (&'static str, &'static str);
    /// The name of the `k`-th line of the history plot, when the objective names it
    /// (by default the start's origin).
    fn history_series(&self, k: usize) -> Option<&'static str> {
        let _ = k;
        None
    }
}

/// A design spec's objective: any [`Objective`], shared (cloning a spec clones a pointer).
/// It derefs to the objective; two are equal when they are of the same kind with the same
/// data.
#[derive(Clone)]
pub struct AnyObjective(Arc<dyn Objective>);

impl AnyObjective {
    /// The objective `o`, e.g. `AnyObjective::new(WidestStableBand { phi_op: 1230.0 })`.
    pub fn new(o: impl Objective + 'static) -> AnyObjective {
        AnyObjective(Arc::new(o))
    }
}

impl<T: Objective + 'static> From<T> for AnyObjective {
    fn from(o: T) -> AnyObjective {
        AnyObjective::new(o)
    }
}

impl std::ops::Deref for AnyObjective {
    type Target = dyn Objective;
    fn deref(&self) -> &(dyn Objective + 'static) {
        &*self.0
    }
}

/// The objective's own form, e.g. `WidestStableBand { phi_op: 1230.0 }`.
impl std::fmt::Debug for AnyObjective {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.0.fmt(f)
    }
}

impl PartialEq for AnyObjective {
    fn eq(&self, other: &Self) -> bool {
        self.kind() == other.kind() && self.keys() == other.keys()
    }
}

/// An objective's data as the flat keys of `[design]` and of the spec's JSON (`phi_op`,
/// `bands`, `response`, `objective_options`); a key the objective does not carry is none.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ObjectiveKeys<'a> {
    /// φ_op (rad/s).
    pub phi_op: Option<f64>,
    /// The operating bands of the objective.
    pub bands: Option<&'a [Band]>,
    /// The unbalance response of the objective.
    pub response: Option<&'a Response>,
    /// `[design.objective_options]`: keys of the objective's own, which no other
    /// objective shares, as the objective reads them ([`read_options`]).
    pub options: Option<&'a serde_json::Value>,
}

/// The keys of a `[design]` table an objective is built from, checked by the file layer
/// one by one (each as [`ObjectiveKeys`]): what the objective takes of them is its own,
/// what it does not take ([`ObjectiveKeys`] none) is the constraints'.
#[derive(Debug, Clone, Copy)]
pub struct FileKeys<'a> {
    /// `design.phi_op` (rad/s).
    pub phi_op: Option<f64>,
    /// `[[design.bands]]`.
    pub bands: &'a [Band],
    /// `[design.response]`.
    pub response: Option<&'a Response>,
    /// Whether `design.constraints.min_band_width` is given (the constraint `phi_op`
    /// belongs to, when the objective does not take it).
    pub min_band_width: bool,
    /// `[design.objective_options]`, the objective's own keys (a TOML table read as
    /// JSON): refused for an objective that takes none
    /// ([`ObjectiveKind::build_from_file`]).
    pub options: Option<&'a serde_json::Value>,
}

/// The key path of an objective's own table in a problem file.
pub const OPTIONS_KEY: &str = "design.objective_options";

/// An objective's own keys (`[design.objective_options]`) read into its type `T`, which
/// names and checks them (with `#[serde(deny_unknown_fields)]` an unknown key is refused
/// by name); none when the table is not given. This is how an objective with data of a
/// kind no other objective has gets it, without a key of its own in the file format.
pub fn read_options<T: serde::de::DeserializeOwned>(
    options: Option<&serde_json::Value>,
) -> Result<Option<T>, KeyRefusal> {
    options.map(|v| T::deserialize(v).map_err(|e| KeyRefusal::new(OPTIONS_KEY, &e.to_string()))).transpose()
}

/// Why a `[design]` table's keys do not make the objective it names: the key to blame
/// and the reason.
#[derive(Debug, Clone, PartialEq)]
pub struct KeyRefusal {
    /// The key path in the problem file, e.g. `design.phi_op`.
    pub key: String,
    /// Why, in words, with what to add or drop.
    pub reason: String,
}

impl KeyRefusal {
    /// The refusal of `key` for `reason`.
    pub fn new(key: &str, reason: &str) -> KeyRefusal {
        KeyRefusal { key: key.into(), reason: reason.into() }
    }
}

/// What the cost of a candidate's searches at one speed is estimated from: the reference
/// candidate's point cost, region settings, criterion and seeds there.
#[derive(Debug, Clone, Copy)]
pub struct CostAt<'a> {
    /// The cost of one Floquet point of the speed's system.
    pub point: &'a PointCost<'a>,
    /// The region search's settings.
    pub regions: &'a RegionSettings,
    /// The instability criterion.
    pub criterion: &'a Criterion,
    /// The reference candidate's seeds at the speed.
    pub seeds: &'a [Seed],
}
