//! What a design costs, and where (issue 27, point 8): run by hand with
//! `cargo bench --bench design` (a plain harness: whole design runs are seconds to
//! minutes, too long for criterion's samples).
//!
//! 1. The cost of one Floquet evaluation over φ on the design problems' reference
//!    designs: the fast path's steps per period (`FloquetSystem::steps_for`: the alias
//!    guard 2·ω_max/φ of the reduced basis, and the phase step on its lowest mode) and
//!    the time of one point, one thread.
//! 2. `rotorshunt design` end to end on `problems/design-widest-band.toml` and
//!    `problems/design-compressor.toml`, alternating, three times each, in the same run:
//!    wall time, the ratio, candidates and evaluations, and the time share of each phase
//!    (optimising, verification, report) from report.json.
//! 3. Issue 47: the paper's widest-band design as the paper's settings judge it (its basis
//!    of M = 8 unloaded modes, max|μ| > 1.0001, no refined-basis check: what the design
//!    was before) and with the defaults (a loaded basis sized by convergence, the growth
//!    criterion, the refined check), alternating, three times each in the same run: wall
//!    and CPU time and the ratio of the medians. (`scripts/speed-compare.sh` measures the
//!    binary of before the issue against the working tree the same way.)
//! 4. Issue 49: the paper's widest-band design with its starts from the map over the box
//!    (the default) and from the first Halton points (`design.map = false`, as before the
//!    map), side by side in the same run: the map's candidate evaluations against those of
//!    the two Halton starts it replaces, the optimiser's candidates and Floquet
//!    evaluations, and the bands. `ROTORSHUNT_BENCH_MAP=only` runs this section alone.
//! 5. Issue 51, point 4: design runs on rotor families no design was tuned on, each
//!    beside a run of the paper's widest-band design in the same run (alternating): wall
//!    times and their ratio, the status, candidates and evaluations per candidate. The
//!    families: Friswell's two-disk rotor (Example 5.9.1, `design-friswell-widest-band.toml`),
//!    his overhung rotor (Example 5.9.9, `families/friswell-overhung.toml`), both widest
//!    band, and ROSS's compressor with a ring (`ross/design-compressor-example.toml`, least
//!    peak response). With `ROTORSHUNT_BENCH_LONG=1` also the widest-band families' robust
//!    variants (`[design.margins] beta = 0.2`, L ±5 %, R ±10 %).
//!    `ROTORSHUNT_BENCH_FAMILIES=only` runs this section alone.
//! 6. With `ROTORSHUNT_BENCH_LONG=1`, also the robust variant with a speed range
//!    (`problems/design-robust-speed-range.toml`) and a 5-point Pareto front of
//!    `problems/design-min-peak-at-speed.toml`, once each.

use rotorshunt::design::evaluate::{values_of, Candidate};
use rotorshunt::problem::Problem;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// The path of `problems/NAME`.
fn problem_file(name: &str) -> String {
    format!("{}/problems/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn problem(name: &str) -> Problem {
    Problem::from_path(problem_file(name), &[]).unwrap()
}

/// Repetitions of one point when timing it: enough for a stable median.
const POINT_REPEATS: usize = 15;

fn cost_over_phi(name: &str, level: f64, phis: &[f64]) {
    let p = problem(name);
    let spec = p.design.as_ref().expect("a [design] table");
    let m = p.machine();
    let c = Candidate::new(&m, spec, &values_of(&m, spec)).unwrap();
    let fs = &c.systems[0].1;
    let f = &fs.reduced.frequencies;
    let (lo, hi) = f.iter().fold((f64::INFINITY, 0.0f64), |(a, b), &w| (a.min(w), b.max(w)));
    println!("{name} at Ω = {:.1} rad/s: reduced basis of {} modes, {lo:.1} to {hi:.1} rad/s", c.systems[0].0, f.len());
    println!("  phi (rad/s)  steps/period  us/point (fast, 1 thread)");
    for &phi in phis {
        let mut times: Vec<f64> = (0..POINT_REPEATS)
            .map(|_| {
                let t = Instant::now();
                std::hint::black_box(fs.point_fast(&fs.table(phi, level), level));
                t.elapsed().as_secs_f64()
            })
            .collect();
        times.sort_by(f64::total_cmp);
        println!("  {phi:>10.0}  {:>12}  {:>10.1}", fs.steps_for(phi), 1e6 * times[POINT_REPEATS / 2]);
    }
}

/// One `design` run: wall time (s) and its report.json.
fn design(args: &[&str], out: &Path) -> (f64, serde_json::Value) {
    let _ = std::fs::remove_dir_all(out);
    let t = Instant::now();
    let status = Command::new(env!("CARGO_BIN_EXE_rotorshunt"))
        .arg("design")
        .args(args)
        .arg("--quiet")
        .arg("--out")
        .arg(out)
        .status()
        .unwrap();
    let wall = t.elapsed().as_secs_f64();
    assert!(status.success() || status.code() == Some(4), "{args:?}: {status}");
    let report = serde_json::from_slice(&std::fs::read(out.join("report.json")).unwrap()).unwrap();
    (wall, report)
}

fn phases(name: &str, wall: f64, r: &serde_json::Value) {
    let o = &r["outcome"];
    let optimise = o["seconds"].as_f64().unwrap_or(0.0);
    let verify = o["verification_cost"]["seconds"].as_f64().unwrap_or(0.0);
    let candidates = o["candidates"].as_u64().unwrap_or(0);
    let evaluations = o["floquet_evaluations"].as_u64().unwrap_or(0);
    println!(
        "{name}: {wall:.2} s end to end; optimising {optimise:.2} s ({:.0} %), verification {verify:.2} s ({:.0} %), report and the rest {:.2} s ({:.0} %); {candidates} candidates, {evaluations} evaluations ({:.0} per candidate), verification {} evaluations",
        100.0 * optimise / wall,
        100.0 * verify / wall,
        wall - optimise - verify,
        100.0 * (wall - optimise - verify) / wall,
        evaluations as f64 / candidates.max(1) as f64,
        o["verification_cost"]["evaluations"]
    );
}

/// Issue 49: the map's evaluations against the two Halton starts it replaces, on `paper`.
fn map_against_halton(paper: &str, dir: &Path) {
    let band = |r: &serde_json::Value| {
        let b = &r["outcome"]["after_bands"][0]["band"]["band"];
        b["hi"].as_f64().unwrap_or(f64::NAN) - b["lo"].as_f64().unwrap_or(f64::NAN)
    };
    let (wm, map) = design(&[paper], &dir.join("map"));
    let (wh, halton) = design(&[paper, "--set", "design.map=false"], &dir.join("halton"));
    let halton_evaluations: u64 = halton["outcome"]["starts"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|s| s["origin"].as_str().is_some_and(|o| o.starts_with("halton")))
        .map(|s| s["evaluations"].as_u64().unwrap())
        .sum();
    let map_points = map["outcome"]["map"]["points"].as_array().map_or(0, Vec::len);
    for (name, w, r) in [("map", wm, &map), ("Halton starts", wh, &halton)] {
        let o = &r["outcome"];
        println!(
            "paper widest band, starts from the {name}: {w:.2} s; {} candidates, {} Floquet evaluations optimising; band {:.2} rad/s; tuned {}",
            o["candidates"], o["floquet_evaluations"], band(r), o["after"]
        );
    }
    println!(
        "the map: {map_points} candidate evaluations; the two Halton starts it replaces: {halton_evaluations}; map / Halton = {:.2}",
        map_points as f64 / halton_evaluations.max(1) as f64
    );
}

/// The robust variant of a widest-band design (issue 51's acceptance): margins at
/// 1.2 β_op and the shunt's L within ±5 %, R within ±10 %.
const ROBUST: [&str; 6] = [
    "--set",
    "design.margins.beta=0.2",
    "--set",
    "design.tolerances.inductance=0.05",
    "--set",
    "design.tolerances.resistance=0.1",
];

/// Issue 51, point 4: each family's design beside a run of the paper's widest-band design
/// (`paper`), alternating in the same run; the robust variants with `robust`.
fn families(paper: &str, dir: &Path, robust: bool) {
    let files = problem_file;
    let cases = [
        ("Friswell two-disk (5.9.1), widest band", files("design-friswell-widest-band.toml"), true),
        ("Friswell overhung (5.9.9), widest band", files("families/friswell-overhung.toml"), true),
        ("ROSS compressor with a ring, least peak", files("ross/design-compressor-example.toml"), false),
    ];
    let per_candidate = |r: &serde_json::Value| {
        let o = &r["outcome"];
        o["floquet_evaluations"].as_f64().unwrap_or(0.0) / o["candidates"].as_f64().unwrap_or(1.0).max(1.0)
    };
    let mut rows = Vec::new();
    for (name, file, band) in &cases {
        let variants: &[(&str, &[&str])] =
            if robust && *band { &[("", &[]), (", robust", &ROBUST)] } else { &[("", &[])] };
        for (suffix, extra) in variants {
            let (wp, rp) = design(&[paper], &dir.join("family-paper"));
            phases("paper widest band (beside the family below)", wp, &rp);
            let mut args = vec![file.as_str()];
            args.extend_from_slice(extra);
            let (wf, rf) = design(&args, &dir.join("family"));
            let label = format!("{name}{suffix}");
            phases(&label, wf, &rf);
            rows.push((label, wf, wp, per_candidate(&rf), per_candidate(&rp), rf["outcome"]["status"].clone()));
        }
    }
    println!(
        "| family | status | wall (s) | the paper's beside it (s) | ratio | evaluations per candidate | the paper's |"
    );
    println!("|---|---|---|---|---|---|---|");
    for (label, wf, wp, ef, ep, status) in rows {
        println!("| {label} | {status} | {wf:.2} | {wp:.2} | {:.2} | {ef:.0} | {ep:.0} |", wf / wp);
    }
}

fn main() {
    // `cargo bench` passes --bench; nothing to parse.
    let dir: PathBuf = std::env::temp_dir().join(format!("rotorshunt-bench-design-{}", std::process::id()));
    let files = problem_file;
    let long = std::env::var("ROTORSHUNT_BENCH_LONG").is_ok_and(|v| v == "1");
    if std::env::var("ROTORSHUNT_BENCH_FAMILIES").is_ok_and(|v| v == "only") {
        families(&files("design-widest-band.toml"), &dir, long);
        let _ = std::fs::remove_dir_all(&dir);
        return;
    }
    if std::env::var("ROTORSHUNT_BENCH_MAP").is_ok_and(|v| v == "only") {
        map_against_halton(&files("design-widest-band.toml"), &dir);
        let _ = std::fs::remove_dir_all(&dir);
        return;
    }
    cost_over_phi("design-widest-band.toml", 0.3, &[250.0, 500.0, 1000.0, 1230.0, 2000.0, 4000.0, 8000.0]);
    cost_over_phi("design-compressor.toml", 0.1, &[250.0, 500.0, 1000.0, 2000.0, 4000.0, 6000.0]);
    let (paper, compressor) = (files("design-widest-band.toml"), files("design-compressor.toml"));
    let mut walls = (Vec::new(), Vec::new());
    for round in 0..3 {
        let (w, r) = design(&[&paper], &dir.join("paper"));
        phases(&format!("paper widest band, run {}", round + 1), w, &r);
        walls.0.push(w);
        let (w, r) = design(&[&compressor], &dir.join("compressor"));
        phases(&format!("compressor widest band, run {}", round + 1), w, &r);
        walls.1.push(w);
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let (p, c) = (median(&mut walls.0), median(&mut walls.1));
    println!("medians: paper {p:.2} s, compressor {c:.2} s: compressor / paper = {:.2}", c / p);
    // Issue 47: the paper's settings against the defaults, alternating.
    let old = [
        "--set",
        "analysis.reduced_modes=8",
        "--set",
        "analysis.basis=\"unloaded\"",
        "--set",
        "analysis.instability_tolerance=1.0001",
        "--set",
        "design.refined_check=false",
    ];
    let mut pairs = (Vec::new(), Vec::new());
    for round in 0..3 {
        let mut args = vec![paper.as_str()];
        args.extend(old);
        let (w, r) = design(&args, &dir.join("paper-settings"));
        phases(&format!("widest band, the paper's settings, run {}", round + 1), w, &r);
        pairs.0.push(w);
        let (w, r) = design(&[&paper], &dir.join("defaults"));
        phases(&format!("widest band, the defaults, run {}", round + 1), w, &r);
        pairs.1.push(w);
    }
    let (a, b) = (median(&mut pairs.0), median(&mut pairs.1));
    println!(
        "widest band, medians: the paper's settings {a:.2} s, the defaults {b:.2} s: defaults / paper's = {:.2}",
        b / a
    );
    map_against_halton(&paper, &dir);
    families(&paper, &dir, long);
    if long {
        let (w, r) = design(&[&files("design-robust-speed-range.toml")], &dir.join("robust"));
        phases("robust with a speed range", w, &r);
        let (w, r) = design(&[&files("design-min-peak-at-speed.toml"), "--pareto", "5"], &dir.join("pareto"));
        let f = &r["front"];
        println!(
            "Pareto front of design-min-peak-at-speed.toml, 5 points: {w:.2} s end to end; {} runs, {} candidates, {} evaluations; monotone {}",
            f["runs"], f["candidates"], f["evaluations"], f["monotone"]
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
