//! The map of the objective over the box (issue 49): its files (map.csv, map.json), its
//! paragraph in the details, and the answers that sit on an edge of the box or of a start.

use crate::design::optimise::{MapPoint, StartReport};
use crate::design::spec::DesignSpec;
use crate::design::DesignOutcome;
use serde::Serialize;
use std::fmt::Write;

/// A value this close to a bound, in the variable's scaled unit (1 % of its range, of its
/// logarithm's for a log-scaled one), sits on it: the simplex, pressed against a bound,
/// ends within its last step of it (the paper's design: 0.1 % of the range from its
/// tuning bound), and a designer widens the box either way.
pub const ON_BOUND: f64 = 1.0e-2;

/// The variables of `values` (SI units) that sit on a bound: (index, upper).
pub fn at_bounds(spec: &DesignSpec, values: &[f64]) -> Vec<(usize, bool)> {
    spec.variables
        .iter()
        .zip(values)
        .enumerate()
        .filter_map(|(i, (v, &x))| {
            let u = v.to_unit(x);
            if u <= ON_BOUND {
                Some((i, false))
            } else if u >= 1.0 - ON_BOUND {
                Some((i, true))
            } else {
                None
            }
        })
        .collect()
}

/// How a start ended, in words: `converged`, `iteration limit`, or what argmin said;
/// `, on a bound` when its best point sits on one.
pub fn ending(spec: &DesignSpec, start: &StartReport) -> String {
    let how = if hit_iteration_limit(start) {
        "iteration limit".to_string()
    } else if start.termination.contains("converged") {
        "converged".to_string()
    } else {
        start.termination.clone()
    };
    if at_bounds(spec, &start.best).is_empty() {
        how
    } else {
        format!("{how}, on a bound")
    }
}

/// Whether a start stopped at `design.max_iterations` (argmin's reason says so).
pub fn hit_iteration_limit(start: &StartReport) -> bool {
    start.termination.contains("iterations")
}

/// The variable's column header: name and unit.
fn header(spec: &DesignSpec, i: usize) -> String {
    let v = &spec.variables[i];
    format!("{} ({})", v.name(), v.parameter.unit())
}

/// map.json: the map with its variables named.
#[derive(Debug, Serialize)]
pub struct MapFile<'a> {
    /// The variables, in the order of each point's values: name (unit).
    pub variables: Vec<String>,
    /// What the objective is, with its unit.
    pub objective: &'a str,
    /// Whether larger is better.
    pub maximise: bool,
    /// The points of the Halton set over the box.
    pub points: &'a [MapPoint],
    /// The points the local searches started from (indices into `points`), best first.
    pub basins: &'a [usize],
    /// With more than two variables, the slices through the tuned design, one per pair.
    #[serde(skip_serializing_if = "<[_]>::is_empty")]
    pub slices: &'a [crate::design::optimise::MapSlice],
}

/// map.json's content, where the run made a map.
pub fn map_file(o: &DesignOutcome) -> Option<MapFile<'_>> {
    let m = o.map.as_ref()?;
    Some(MapFile {
        variables: (0..o.spec.variables.len()).map(|i| header(&o.spec, i)).collect(),
        objective: &m.objective,
        maximise: m.maximise,
        points: &m.points,
        basins: &m.basins,
        slices: &m.slices,
    })
}

/// map.csv: one row per point, the variables (SI units), the objective (empty where the
/// candidate failed) and the rank of the basin a start began from (empty for the rest).
pub fn map_csv(o: &DesignOutcome) -> Option<String> {
    let m = o.map.as_ref()?;
    let mut s = String::new();
    let names: Vec<String> = (0..o.spec.variables.len()).map(|i| header(&o.spec, i)).collect();
    let _ = writeln!(s, "{},objective,basin", names.join(","));
    for (k, p) in m.points.iter().enumerate() {
        let values: Vec<String> = p.values.iter().map(|x| format!("{x:e}")).collect();
        let rank = m.basins.iter().position(|&b| b == k).map_or(String::new(), |r| (r + 1).to_string());
        let _ = writeln!(s, "{},{},{rank}", values.join(","), p.objective.map_or(String::new(), |x| format!("{x:e}")));
    }
    Some(s)
}

/// The map's paragraph of the details: its size, its best point, and where the starts
/// began.
pub(super) fn map_section(s: &mut String, o: &DesignOutcome) {
    let Some(m) = &o.map else { return };
    let values = |v: &[f64]| o.spec.values_text(v);
    let failed = m.points.iter().filter(|p| p.objective.is_none()).count();
    let _ = write!(
        s,
        "\nBefore the local searches, a map of the objective ({}) over the whole box: {} points of a Halton set{}.",
        m.objective,
        m.points.len(),
        if failed > 0 { format!(", {failed} of them not analysable") } else { String::new() }
    );
    // A clear-bands run's map is its global pass, whose best point starts a convex run.
    let global_pass = o.starts.iter().any(|x| x.termination == crate::design::optimise::GLOBAL_PASS);
    for (r, &i) in m.basins.iter().enumerate() {
        let p = &m.points[i];
        let start = if global_pass {
            "the convex run from the best global point".to_string()
        } else {
            format!("start `map basin {}`", r + 1)
        };
        let _ = write!(
            s,
            " Basin {} ({start}): {} at {}.",
            r + 1,
            p.objective.map_or("–".into(), |x| format!("{x:.2}")),
            values(&p.values)
        );
    }
    if let Some(first) = m.slices.first() {
        let _ = write!(
            s,
            " With {} variables, the map is drawn as one slice per pair through the tuned design ({} pairs, {} points each on a {k} × {k} grid over the pair's box, the other variables at their tuned values; map-i-j.png).",
            o.spec.variables.len(),
            m.slices.len(),
            first.points.len(),
            k = crate::design::optimise::SLICE_POINTS
        );
    }
    let _ = writeln!(s, " Every point is in map.csv and map.json (the slices in map.json).");
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::design::objective::widest_band::WidestStableBand;
    use crate::design::spec::{Parameter, Variable};

    /// The paper's design box: branch 1's tuning frequency (600–1400 rad/s) and resistance
    /// (0–20 Ω), at φ_op = 1230 rad/s, β_op = 0.3, Ω = 2000 rad/s.
    pub(crate) fn spec() -> DesignSpec {
        let tuning = Variable {
            ring: None,
            ring_name: None,
            branch: 0,
            parameter: Parameter::TuningFrequency,
            min: 600.0,
            max: 1400.0,
        };
        let resistance = Variable { parameter: Parameter::Resistance, min: 0.0, max: 20.0, ..tuning.clone() };
        DesignSpec::builder(WidestStableBand { phi_op: 1230.0 }, 0.3, vec![2000.0], vec![tuning, resistance])
            .build(&[2])
            .unwrap()
    }

    #[test]
    fn a_value_on_its_bound_is_named_and_one_inside_is_not() {
        let s = spec();
        assert_eq!(at_bounds(&s, &[1400.0, 10.0]), vec![(0, true)]);
        assert_eq!(at_bounds(&s, &[900.0, 0.0]), vec![(1, false)]);
        assert!(at_bounds(&s, &[900.0, 10.0]).is_empty());
        // 0.5 % of the log range below the upper bound still sits on it; 2 % does not.
        let near = |u: f64| 600.0 * (1400.0f64 / 600.0).powf(u);
        assert_eq!(at_bounds(&s, &[near(0.995), 10.0]), vec![(0, true)]);
        assert!(at_bounds(&s, &[near(0.98), 10.0]).is_empty());
    }

    #[test]
    fn a_start_ends_converged_at_its_limit_or_on_a_bound() {
        let s = spec();
        let start = |termination: &str, best: Vec<f64>| StartReport {
            origin: "map basin 1".into(),
            initial: vec![900.0, 10.0],
            best,
            objective: 300.0,
            evaluations: 20,
            iterations: 10,
            termination: termination.into(),
        };
        assert_eq!(ending(&s, &start("Solver converged", vec![900.0, 10.0])), "converged");
        assert_eq!(
            ending(&s, &start("Maximum number of iterations reached", vec![1400.0, 10.0])),
            "iteration limit, on a bound"
        );
    }
}
