//! The `[design]` table, checked against the rest of the file: objective, level, range,
//! speeds, bands, and the variables (a branch of one ring's circuit, or of every ring's
//! while they carry an identical circuit).

use super::file::*;
use super::validate::{finite, non_negative, positive, range_rule, rule, Failure};
use super::{NameOf, ProblemErrorKind as K};
use crate::analysis::limits::{self, ParamError, Quantity};
use crate::analysis::Interval;
use crate::design::objective::{FileKeys, Objective, ObjectiveKind, OPTIONS_KEY};
use crate::design::spec::{
    Band, BandWidth, Constraints, DampingFloor, DesignSpec, MarginSpec, Parameter, Response, Variable, WarningLevels,
    CHART_GRID, DEFAULT_ITERATIONS, DEFAULT_STARTS, MAX_CHART_BETA_POINTS, MAX_CHART_PHI_POINTS, MAX_ITERATIONS,
    MAX_RESPONSE_POINTS, MAX_STARTS, MIN_CHART_POINTS, MIN_RESPONSE_POINTS,
};
use crate::design::tolerance::Tolerances;
use crate::model::{CircuitState, Model};

/// The circuit file of each ring, in model order (the shorthand: `[circuit]` for both).
fn circuits(f: &ProblemFile) -> Vec<&CircuitFile> {
    match &f.circuit {
        Some(c) => vec![c, c],
        None => f.rings.iter().map(|r| &r.circuit).collect(),
    }
}

/// Key of the circuit a variable without `ring` changes.
fn circuits_key(f: &ProblemFile) -> String {
    if f.circuit.is_some() {
        "circuit".into()
    } else {
        "rings[0].circuit".into()
    }
}

/// The name of ring `r` as the model names it (the shorthand's: `left`, `right`).
fn ring_name(f: &ProblemFile, r: usize) -> String {
    if f.circuit.is_some() {
        return if r == 0 { "left" } else { "right" }.to_string();
    }
    f.rings.get(r).and_then(|x| x.name.clone()).unwrap_or_else(|| format!("ring{}", r + 1))
}

/// The ring a variable names (`None`: every ring, valid while their circuits are
/// identical). A file without rings has no branch to design.
fn ring_of(
    f: &ProblemFile,
    circuits: &[&CircuitFile],
    key: &str,
    name: Option<&str>,
) -> Result<Option<usize>, Failure> {
    if circuits.is_empty() {
        let message = "a design changes the shunt branches: the file has no [[rings]]";
        return Err(("design.variables".into(), K::Schema(message.into())));
    }
    let names: Vec<String> = (0..circuits.len()).map(|r| ring_name(f, r)).collect();
    match name {
        Some(name) => match names.iter().position(|n| n == name) {
            Some(r) => Ok(Some(r)),
            None => {
                let known = names.into_boxed_slice();
                Err((format!("{key}.ring"), K::UnknownName { what: NameOf::Ring, name: name.into(), known }))
            }
        },
        None if circuits.iter().all(|c| *c == circuits[0]) => Ok(None),
        None => Err((
            format!("{key}.ring"),
            K::Schema(format!(
                "the rings' circuits differ: name the ring whose branch this is, `ring = \"…\"` (rings: {})",
                names.join(", ")
            )),
        )),
    }
}

/// Default φ range of a design's catalogues and band searches (rad/s): the paper's charts
/// ([`crate::analysis::DEFAULT_BAND_RANGE`]).
const DEFAULT_PHI_RANGE: [f64; 2] = [crate::analysis::DEFAULT_BAND_RANGE.lo, crate::analysis::DEFAULT_BAND_RANGE.hi];

/// Default grid speeds of a `[design.response]`.
const DEFAULT_RESPONSE_POINTS: i64 = 201;

/// `[design.response]` against the model: a node on the shaft, a speed range lo < hi of
/// admitted speeds, and a grid of at least [`MIN_RESPONSE_POINTS`] speeds.
fn response(r: &ResponseFile, model: &Model) -> Result<Response, Failure> {
    let last = model.shaft.last_node();
    let node = usize::try_from(r.node).ok().filter(|&n| n <= last);
    let Some(node) = node else {
        return Err(("design.response.node".into(), K::NodeOffShaft { node: r.node, last }));
    };
    let speeds = speed_pair("design.response.speeds", &r.speeds, limits::response_speed)?;
    let points = r.points.unwrap_or(DEFAULT_RESPONSE_POINTS);
    let n = u64::try_from(points).unwrap_or(0);
    let points = rule(
        "design.response.points",
        limits::count(n, MIN_RESPONSE_POINTS, MAX_RESPONSE_POINTS)
            .map_err(|e| ParamError { value: points as f64, ..e }),
    )?;
    Ok(Response { node, speeds, points: points as usize })
}

/// `[design.constraints]` and the band constraints, each limit checked: a band width and
/// a peak positive, a damping ratio in [0, 1).
fn constraints(
    d: &DesignFile,
    bands: Vec<Band>,
    phi_op: Option<f64>,
    response: Option<&Response>,
) -> Result<Constraints, Failure> {
    let mut out = Constraints { bands, ..Constraints::default() };
    let Some(c) = &d.constraints else { return Ok(out) };
    if let Some(w) = c.min_band_width {
        let key = "design.constraints.min_band_width";
        let width = positive(key, w)?;
        let Some(phi_op) = phi_op else {
            let message = "the band-width constraint `design.constraints.min_band_width` needs `phi_op` (rad/s)";
            return Err(("design.phi_op".into(), K::Schema(message.into())));
        };
        out.min_band_width = Some(BandWidth { phi_op, width });
    }
    if let Some(p) = c.max_peak {
        let key = "design.constraints.max_peak";
        let peak = positive(key, p)?;
        if response.is_none() {
            let message = "a peak constraint needs [design.response] (node and speeds)";
            return Err((key.into(), K::Schema(message.into())));
        }
        out.max_peak = Some(peak);
    }
    for (i, z) in c.damping.iter().enumerate() {
        let key = format!("design.constraints.damping[{i}]");
        let min = non_negative(&format!("{key}.min"), z.min)?;
        if min >= 1.0 {
            return Err((format!("{key}.min"), K::OutOfRange { value: min, range: "below 1".into() }));
        }
        if z.mode.trim().is_empty() {
            return Err((format!("{key}.mode"), K::Schema("a whirl tag is needed, e.g. `f1`".into())));
        }
        out.damping.push(DampingFloor { mode: z.mode.clone(), min });
    }
    Ok(out)
}

/// Check `[design]` against the rest of the file and the model built from it.
pub fn design(f: &ProblemFile, model: &Model) -> Result<Option<DesignSpec>, Failure> {
    let Some(d) = &f.design else { return Ok(None) };
    let range = d.phi_range.unwrap_or(DEFAULT_PHI_RANGE);
    let range = range_rule("design.phi_range", range[0], range[1])?;
    // The level is a load coefficient up to β_max, whose default follows it.
    let level = rule("design.level", limits::level(d.level, limits::MAX_BETA))?;
    let beta_max =
        rule("design.beta_max", limits::beta_max(d.beta_max.unwrap_or(crate::design::spec::default_beta_max(level))))?;
    rule("design.level", limits::level(level, beta_max))?;
    let speeds = match &d.speeds {
        Some(v) if v.is_empty() => return Err(("design.speeds".into(), K::Schema("needs at least one speed".into()))),
        Some(v) => v
            .iter()
            .enumerate()
            .map(|(i, &w)| rule(&format!("design.speeds[{i}]"), limits::speed(w)))
            .collect::<Result<Vec<_>, _>>()?,
        None => vec![f.speed],
    };
    let speed_range = match &d.speed_range {
        None => None,
        Some(_) if d.speeds.is_some() => {
            return Err(("design.speed_range".into(), K::BothGiven("speeds".into(), "speed_range".into())))
        }
        Some(v) => Some(speed_pair("design.speed_range", v, limits::speed)?),
    };
    let speeds = speed_range.map_or(speeds, crate::design::spec::range_speeds);
    let phi_op = d.phi_op.map(|p| rule("design.phi_op", limits::phi_op(p, range))).transpose()?;
    let bands = d
        .bands
        .iter()
        .enumerate()
        .map(|(i, b)| {
            let key = format!("design.bands[{i}]");
            let Interval { lo, hi } = limits::band(b.lo, b.hi).map_err(|e| {
                let end = if e.quantity == Quantity::RangeLow { "lo" } else { "hi" };
                (format!("{key}.{end}"), K::from(&e))
            })?;
            let clearance = rule(&format!("{key}.clearance"), limits::span(b.clearance))?;
            Ok(Band { lo, hi, clearance })
        })
        .collect::<Result<Vec<_>, Failure>>()?;
    let response = d.response.as_ref().map(|r| response(r, model)).transpose()?;
    let width_constraint = d.constraints.as_ref().is_some_and(|c| c.min_band_width.is_some());
    // Each objective takes its own data; a key of another one is a mistake, not a hint.
    let options = d.objective_options.as_ref().map(serde_json::to_value).transpose();
    let options = options.map_err(|e| (OPTIONS_KEY.to_string(), K::Schema(e.to_string())))?;
    let keys = FileKeys {
        phi_op,
        bands: &bands,
        response: response.as_ref(),
        min_band_width: width_constraint,
        options: options.as_ref(),
    };
    let objective = d.objective.build_from_file(&keys).map_err(|r| (r.key, K::Schema(r.reason)))?;
    // What the objective does not take is the constraints'.
    let bands = if objective.keys().bands.is_some() { Vec::new() } else { bands };
    let response = response.filter(|_| objective.response().is_none());
    let judged = objective.response().or(response.as_ref());
    let mut constraints = constraints(d, bands, phi_op, judged)?;
    if let Some(m) = &d.margins {
        non_negative("design.margins.beta", m.beta.unwrap_or(0.0))?;
        non_negative("design.margins.phi", m.phi.unwrap_or(0.0))?;
        let Some(phi_op) = phi_op else {
            let message = "margins judge the stable band around `design.phi_op` (rad/s): add `phi_op` (widest-stable-band, or with `constraints.min_band_width`)";
            return Err(("design.margins".into(), K::Schema(message.into())));
        };
        // A margin no band in the window can give is refused here, before any solve.
        let beta = rule("design.margins.beta", limits::load_margin(m.beta.unwrap_or(0.0), level))?;
        let phi = rule("design.margins.phi", limits::frequency_margin(m.phi.unwrap_or(0.0), phi_op, range))?;
        constraints.margins = Some(MarginSpec { beta, phi });
    }
    if d.variables.is_empty() {
        return Err(("design.variables".into(), K::Schema("a design needs at least one [[design.variables]]".into())));
    }
    let circuits = circuits(f);
    let mut variables: Vec<Variable> = Vec::new();
    for (i, v) in d.variables.iter().enumerate() {
        let key = format!("design.variables[{i}]");
        let ring = ring_of(f, &circuits, &key, v.ring.as_deref())?;
        let (circuit_key, circuit) = match ring {
            Some(r) => (format!("rings[{r}].circuit"), circuits[r]),
            None => (circuits_key(f), circuits[0]),
        };
        if circuit.state != CircuitState::Closed {
            return Err((
                format!("{circuit_key}.state"),
                K::Schema("a design changes the shunt branches: the circuit must be `closed`".into()),
            ));
        }
        let n = circuit.branches.len();
        if v.branch < 1 || v.branch as usize > n {
            return Err((
                format!("{key}.branch"),
                K::OutOfRange { value: v.branch as f64, range: format!("a branch number from 1 to {n}") },
            ));
        }
        let min = if v.parameter.logarithmic() {
            positive(&format!("{key}.min"), v.min)?
        } else {
            non_negative(&format!("{key}.min"), v.min)?
        };
        let max = finite(&format!("{key}.max"), v.max)?;
        if max <= min {
            return Err((format!("{key}.max"), K::OutOfRange { value: max, range: format!("above min = {min}") }));
        }
        let var = Variable {
            ring,
            ring_name: ring.map(|r| ring_name(f, r)),
            branch: v.branch as usize - 1,
            parameter: v.parameter,
            min,
            max,
        };
        let exclusive = |p: Parameter| matches!(p, Parameter::Inductance | Parameter::TuningFrequency);
        // A variable on every ring overlaps one on any ring.
        let overlap = |a: Option<usize>, b: Option<usize>| a.is_none() || b.is_none() || a == b;
        if variables.iter().any(|w| {
            overlap(w.ring, var.ring)
                && w.branch == var.branch
                && (w.parameter == var.parameter || (exclusive(w.parameter) && exclusive(var.parameter)))
        }) {
            return Err((
                format!("{key}.parameter"),
                K::Schema(format!(
                    "branch {} already has a variable for this parameter (inductance and tuning_frequency are one)",
                    v.branch
                )),
            ));
        }
        variables.push(var);
    }
    let tolerances = match &d.tolerances {
        None => None,
        Some(t) => Some(tolerances(t, &*objective)?),
    };
    Ok(Some(DesignSpec {
        speed_range,
        tolerances,
        objective,
        level,
        phi_range: (range.lo, range.hi),
        beta_max,
        speeds,
        variables,
        starts: count("design.starts", d.starts, DEFAULT_STARTS as i64, MAX_STARTS)?,
        max_iterations: count("design.max_iterations", d.max_iterations, DEFAULT_ITERATIONS as i64, MAX_ITERATIONS)?,
        response,
        constraints,
        speed_unit: Default::default(),
        chart_grid: (
            count_from(
                "design.chart_phi_points",
                d.chart_phi_points,
                CHART_GRID.0 as i64,
                MIN_CHART_POINTS,
                MAX_CHART_PHI_POINTS,
            )?,
            count_from(
                "design.chart_beta_points",
                d.chart_beta_points,
                CHART_GRID.1 as i64,
                MIN_CHART_POINTS,
                MAX_CHART_BETA_POINTS,
            )?,
        ),
        refined_check: d.refined_check.unwrap_or(true),
        map: d.map.unwrap_or(true),
        warnings: warning_levels(d.warnings.as_ref())?,
    }))
}

/// `[design.warnings]`, each ≥ 0; the defaults where absent.
fn warning_levels(w: Option<&WarningsFile>) -> Result<WarningLevels, Failure> {
    let d = WarningLevels::default();
    let Some(w) = w else { return Ok(d) };
    Ok(WarningLevels {
        load_margin: non_negative("design.warnings.load_margin", w.load_margin.unwrap_or(d.load_margin))?,
        frequency_margin: non_negative(
            "design.warnings.frequency_margin",
            w.frequency_margin.unwrap_or(d.frequency_margin),
        )?,
    })
}

/// Default Monte Carlo samples of the tolerance check (`design.tolerances.samples`).
const DEFAULT_SAMPLES: i64 = 200;
/// Most Monte Carlo samples (one band search each, per speed).
const MAX_SAMPLES: u64 = 10_000;

/// `[design.tolerances]`, validated: each tolerance in [0, 1) (a part at −100 % is no
/// part), for an objective the optimiser judges at the tolerance box's corners
/// ([`ObjectiveKind::judges_tolerances`]: widest-stable-band, min-peak-response).
fn tolerances(t: &TolerancesFile, objective: &dyn Objective) -> Result<Tolerances, Failure> {
    let one = |name: &str, v: Option<f64>| -> Result<f64, Failure> {
        let key = format!("design.tolerances.{name}");
        let v = non_negative(&key, v.unwrap_or(0.0))?;
        if v >= 1.0 {
            return Err((
                key,
                K::OutOfRange { value: v, range: "a relative tolerance in [0, 1), e.g. 0.05 for ±5 %".into() },
            ));
        }
        Ok(v)
    };
    let out = Tolerances {
        inductance: one("inductance", t.inductance)?,
        resistance: one("resistance", t.resistance)?,
        c_f: one("c_f", t.c_f)?,
        cp_t: one("cp_t", t.cp_t)?,
        samples: count("design.tolerances.samples", t.samples, DEFAULT_SAMPLES, MAX_SAMPLES)?,
    };
    if !objective.kind().judges_tolerances() {
        let message = tolerances_refusal();
        return Err(("design.tolerances".into(), K::Schema(message)));
    }
    if !out.any() {
        let message = "every tolerance is 0: give at least one of inductance, resistance, c_f, cp_t above 0, or remove [design.tolerances]";
        return Err(("design.tolerances".into(), K::Schema(message.into())));
    }
    Ok(out)
}

/// Why `[design.tolerances]` is refused for an objective that does not judge them: the
/// objectives that do, by name.
fn tolerances_refusal() -> String {
    let judging: Vec<&str> = ObjectiveKind::all().iter().filter(|k| k.judges_tolerances()).map(|k| k.key()).collect();
    let names = judging.join(" or ");
    let uses: Vec<String> = judging.iter().map(|k| format!("`objective = \"{k}\"`")).collect();
    format!(
        "component tolerances are judged by the {names} objectives only (at the tolerance box's corners); remove [design.tolerances] or use {}",
        uses.join(" or ")
    )
}

/// A whole number at `key` from 1 to `hi`, `default` when absent.
fn count(key: &str, v: Option<i64>, default: i64, hi: u64) -> Result<usize, Failure> {
    count_from(key, v, default, 1, hi)
}

/// A whole number at `key` from `lo` to `hi`, `default` when absent.
fn count_from(key: &str, v: Option<i64>, default: i64, lo: u64, hi: u64) -> Result<usize, Failure> {
    let v = v.unwrap_or(default);
    let n = u64::try_from(v).unwrap_or(0);
    rule(key, limits::count(n, lo, hi).map_err(|e| ParamError { value: v as f64, ..e })).map(|n| n as usize)
}

/// A speed range [lo, hi] (rad/s) at `key`: two speeds, each by `speed_rule` at its own
/// index, lo < hi (`design.response.speeds`, `design.speed_range`; their rpm forms are
/// converted before).
fn speed_pair(key: &str, v: &[f64], speed_rule: fn(f64) -> Result<f64, ParamError>) -> Result<Interval, Failure> {
    let [lo, hi] = v[..] else {
        let message = format!("needs two speeds [lo, hi] (rad/s), found {}", v.len());
        return Err((key.into(), K::Schema(message)));
    };
    let lo = rule(&format!("{key}[0]"), speed_rule(lo))?;
    let hi = rule(&format!("{key}[1]"), speed_rule(hi))?;
    if hi <= lo {
        let range = format!("above the low end {} rad/s (an empty speed range)", limits::number(lo));
        return Err((format!("{key}[1]"), K::OutOfRange { value: hi, range }));
    }
    Ok(Interval::new(lo, hi))
}
