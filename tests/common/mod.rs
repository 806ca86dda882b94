//! Shared helpers for the integration tests: the problem catalogue lives in problems/.
#![allow(dead_code)]

use rotorshunt::problem::Problem;

/// Path of a catalogue problem.
pub fn problem_path(name: &str) -> String {
    format!("{}/problems/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// Load a catalogue problem with overrides.
pub fn load(name: &str, overrides: &[&str]) -> Problem {
    let o: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    Problem::from_path(problem_path(name), &o).unwrap_or_else(|e| panic!("{e}"))
}

/// Relative difference.
pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}
