//! The `[design]` table, checked against the rest of the file: objective, level, range,
//! speeds, bands, and the variables (a branch of one ring's circuit, or of every ring's
//! while they carry an identical circuit).

use super::file::*;
use super::validate::{finite, non_negative, positive, range_rule, rule, Failure};
use super::{NameOf, ProblemErrorKind as K};
use crate::analysis::limits::{self, ParamError, Quantity};
use crate::analysis::Interval;
use crate::design::spec::{Band, DesignSpec, Objective, Parameter, Variable, MAX_ITERATIONS, MAX_STARTS};
use crate::model::CircuitState;

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

/// Default φ range of a design's catalogues and band searches (rad/s): the paper's charts.
const DEFAULT_PHI_RANGE: [f64; 2] = [100.0, 8000.0];
/// Default Nelder–Mead starts and iterations.
const DEFAULT_STARTS: i64 = 4;
const DEFAULT_ITERATIONS: i64 = 40;

/// Check `[design]` against the rest of the file.
pub fn design(f: &ProblemFile) -> Result<Option<DesignSpec>, Failure> {
    let Some(d) = &f.design else { return Ok(None) };
    let range = d.phi_range.unwrap_or(DEFAULT_PHI_RANGE);
    let range = range_rule("design.phi_range", range[0], range[1])?;
    // The level is a load coefficient up to β_max, whose default follows it.
    let level = rule("design.level", limits::level(d.level, limits::MAX_BETA))?;
    let beta_max = rule("design.beta_max", limits::beta_max(d.beta_max.unwrap_or(1.0_f64.max(level))))?;
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
    let phi_op = d.phi_op.map(|p| rule("design.phi_op", limits::phi_op(p, range))).transpose()?;
    if d.objective == Objective::WidestStableBand && phi_op.is_none() {
        return Err((
            "design.phi_op".into(),
            K::Schema("the widest-stable-band objective needs `phi_op` (rad/s)".into()),
        ));
    }
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
    if d.objective == Objective::ClearBands && bands.is_empty() {
        return Err(("design.bands".into(), K::Schema("the clear-bands objective needs [[design.bands]]".into())));
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
    let count = |key: &str, v: Option<i64>, default: i64, hi: u64| -> Result<usize, Failure> {
        let v = v.unwrap_or(default);
        let n = u64::try_from(v).unwrap_or(0);
        rule(key, limits::count(n, 1, hi).map_err(|e| ParamError { value: v as f64, ..e })).map(|n| n as usize)
    };
    Ok(Some(DesignSpec {
        objective: d.objective,
        level,
        phi_op,
        phi_range: (range.lo, range.hi),
        beta_max,
        speeds,
        bands,
        variables,
        starts: count("design.starts", d.starts, DEFAULT_STARTS, MAX_STARTS)?,
        max_iterations: count("design.max_iterations", d.max_iterations, DEFAULT_ITERATIONS, MAX_ITERATIONS)?,
    }))
}
