//! Issue 49, "Global": the widest-band design answers with the widest band of its box, not
//! with the basin nearest its starts. The reference is independent of the optimiser: a
//! grid of `rotorshunt band` queries over the file's own box (the variables' bounds, the
//! tuning frequency on the log scale the design uses), each on a problem file whose branch
//! is set by `--set`. The design's band must be at least [`SHARE`] of the grid's best.
//!
//! In CI: on the paper's file, a 7 × 5 grid on a fixed basis of 8 modes over 800–1800
//! rad/s (the design judged on the same model and window, without its refined check). By
//! hand (`-- --ignored`): 21 × 11 grids on the default model (a basis sized by
//! convergence), against the design as the file asks it, on the paper's file and on a
//! rotor family no design was tuned on (Friswell et al.'s two-disk rotor). The box, φ_op,
//! β_op and window are read from each file's `[design]` table.

use crate::common;
use common::{bin, json, problem_path, run_ok, tmp};
use rayon::prelude::*;

/// The share of the grid's best band the design's band must reach (−): a grid point lies
/// inside the design's box, so the optimiser must find at least as wide a band, less what
/// the band search's own resolution (edges bisected to 0.2 rad/s, a width of 0.4 rad/s at
/// worst on a band of hundreds) and the simplex's tolerance (0.1 rad/s) can lose.
const SHARE: f64 = 0.99;

/// A widest-band file with two variables, branch 1's tuning frequency (log scale) and
/// resistance (linear), read from its `[design]` table: φ_op (rad/s), β_op, the φ range
/// (rad/s) and the box. `prefix` is the key path of the branch for `--set`.
struct Case {
    file: &'static str,
    prefix: &'static str,
    phi_op: f64,
    level: f64,
    window: String,
    tuning: (f64, f64),
    resistance: (f64, f64),
}

impl Case {
    fn of(file: &'static str, prefix: &'static str) -> Case {
        use rotorshunt::design::spec::Parameter;
        let p = rotorshunt::problem::Problem::from_path(problem_path(file), &[]).unwrap();
        let d = p.design.unwrap();
        let bounds = |param: Parameter| {
            let v = d.variables.iter().find(|v| v.parameter == param).expect("the variable");
            (v.min, v.max)
        };
        assert_eq!(d.variables.len(), 2, "{file}: the grid covers two variables");
        Case {
            file,
            prefix,
            phi_op: d.phi_op().unwrap(),
            level: d.level,
            window: format!("{}:{}", d.phi_range.0, d.phi_range.1),
            tuning: bounds(Parameter::TuningFrequency),
            resistance: bounds(Parameter::Resistance),
        }
    }
}

/// The paper's widest-band file.
fn paper() -> Case {
    Case::of("design-widest-band.toml", "circuit.branches[0]")
}

/// The band width (rad/s) of `rotorshunt band` at (tuning, resistance), with `extra` sets;
/// 0 when φ_op is unstable there.
fn band_width(c: &Case, tuning: f64, resistance: f64, extra: &[&str], window: &str) -> f64 {
    let t = format!("{}.tuning_frequency={tuning}", c.prefix);
    let r = format!("{}.resistance={resistance}", c.prefix);
    let mut cmd = bin();
    cmd.arg("band").arg(problem_path(c.file)).args(["--set", &t, "--set", &r]);
    for e in extra {
        cmd.args(["--set", e]);
    }
    let phi_op = c.phi_op.to_string();
    let level = c.level.to_string();
    let text = run_ok(cmd.args(["--phi-op", &phi_op, "--level", &level, "--phi", window, "--json", "--quiet"]));
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    match (v["band"]["lo"].as_f64(), v["band"]["hi"].as_f64()) {
        (Some(lo), Some(hi)) => hi - lo,
        _ => 0.0,
    }
}

/// The grid's best band: (width, tuning, resistance).
fn grid_best(c: &Case, n_tuning: usize, n_resistance: usize, extra: &[&str], window: &str) -> (f64, f64, f64) {
    let (t0, t1) = c.tuning;
    let (r0, r1) = c.resistance;
    let points: Vec<(f64, f64)> = (0..n_tuning)
        .flat_map(|i| {
            let t = t0 * (t1 / t0).powf(i as f64 / (n_tuning - 1) as f64);
            (0..n_resistance).map(move |j| (t, r0 + (r1 - r0) * j as f64 / (n_resistance - 1) as f64))
        })
        .collect();
    let widths: Vec<(f64, f64, f64)> =
        points.par_iter().map(|&(t, r)| (band_width(c, t, r, extra, window), t, r)).collect();
    widths.into_iter().fold((f64::NEG_INFINITY, 0.0, 0.0), |a, b| if b.0 > a.0 { b } else { a })
}

/// The design's band width (rad/s), the tuned values, the map and page one of report.md.
fn design(c: &Case, extra: &[&str], name: &str) -> (f64, Vec<f64>, serde_json::Value, String) {
    let dir = tmp(name);
    let mut cmd = bin();
    cmd.arg("design").arg(problem_path(c.file));
    for e in extra {
        cmd.args(["--set", e]);
    }
    run_ok(cmd.arg("--out").arg(&dir).arg("--quiet"));
    let report = json(&dir.join("report.json"));
    let o = &report["outcome"];
    let b = &o["after_bands"][0]["band"]["band"];
    let width = b["hi"].as_f64().unwrap() - b["lo"].as_f64().unwrap();
    let after: Vec<f64> = o["after"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
    let map = o["map"].clone();
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    let page_one = md.split("\n---\n").next().unwrap().to_string();
    for f in ["map.csv", "map.json", "map.png", "map.svg"] {
        assert!(dir.join(f).is_file(), "{f} missing");
    }
    // The map drawn over the two variables, each axis with its unit, and shown in the report.
    let svg = std::fs::read_to_string(dir.join("map.svg")).unwrap();
    assert!(svg.contains("tuning_frequency (rad/s)") && svg.contains("resistance (Ω)"), "map.svg axes");
    assert!(md.contains("](map.png)"), "report.md does not show map.png");
    let _ = std::fs::remove_dir_all(&dir);
    (width, after, map, page_one)
}

/// The design with `extra` sets against the grid on the same model and φ window (rad/s,
/// `lo:hi`, the design's `design.phi_range`).
fn check(c: &Case, extra: &[&str], grid: (usize, usize), window: &str, name: &str) {
    let (width, after, map, page_one) = design(c, extra, name);
    // Page one warns of a tuned value on a bound of the box exactly when there is one (1 %
    // of the range: the tuning frequency's log range, the resistance's linear one).
    let log_u = (after[0] / c.tuning.0).ln() / (c.tuning.1 / c.tuning.0).ln();
    let lin_u = (after[1] - c.resistance.0) / (c.resistance.1 - c.resistance.0);
    let on_bound = [log_u, lin_u].iter().any(|u| *u <= 1e-2 || *u >= 1.0 - 1e-2);
    assert_eq!(page_one.contains("bound (`design.variables["), on_bound, "{after:?}:\n{page_one}");
    let (best, t, r) = grid_best(c, grid.0, grid.1, extra, window);
    let points = map["points"].as_array().map_or(0, Vec::len);
    let top = map["basins"].as_array().and_then(|b| b.first()).and_then(|i| i.as_u64());
    let top = top.map(|i| &map["points"][i as usize]);
    println!(
        "{}: design band {width:.2} rad/s at {after:?}; the map: {points} points, best {}; the {}×{} grid of `band`: best {best:.2} rad/s at tuning {t:.2} rad/s, R {r:.3} Ω; design / grid = {:.4}",
        c.file,
        top.map_or("none".into(), |p| p.to_string()),
        grid.0,
        grid.1,
        width / best
    );
    assert!(points > 0, "the design made no map");
    assert!(
        width >= SHARE * best,
        "the design's band {width:.2} rad/s is under {SHARE} of the grid's best {best:.2} rad/s"
    );
}

#[test]
fn the_widest_band_design_finds_the_best_band_of_a_grid_over_its_box() {
    // The design's catalogues and the grid's band searches over 800–1800 rad/s, around
    // every band the box holds (the widest reaches from about 1075 to 1462 rad/s).
    let extra = [
        common::QUICK_BASIS[0],
        common::QUICK_BASIS[1],
        common::COARSE_CHARTS[0],
        common::COARSE_CHARTS[1],
        "design.phi_range=[800.0, 1800.0]",
    ];
    check(&paper(), &extra, (7, 5), "800:1800", "global-quick");
}

#[test]
#[ignore = "a 21 × 11 grid of `band` on the converged model and the design as the file asks it (several minutes on 2 cores); run with `cargo test --release --test suite global_map:: -- --ignored`"]
fn the_widest_band_design_finds_the_best_band_of_a_fine_grid_on_the_converged_model() {
    check(&paper(), &[], (21, 11), "100:8000", "global-fine");
}

#[test]
#[ignore = "a 21 × 11 grid of `band` on a rotor no design was tuned on (about 12 minutes on 2 cores); run with `cargo test --release --test suite global_map:: -- --ignored`"]
fn on_a_textbook_rotor_the_design_finds_the_best_band_of_a_fine_grid() {
    // Friswell et al.'s two-disk rotor (Example 5.9.1) on the paper's ring, scaled: a
    // rotor family the project had not designed on (problems/README.md).
    let c = Case::of("design-friswell-widest-band.toml", "rings[0].circuit.branches[0]");
    let window = c.window.clone();
    check(&c, &[], (21, 11), &window, "global-friswell");
}
