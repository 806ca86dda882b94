//! Numerical honesty at the edge (issue 14): a model with a tiny inductance, the β = 0
//! sanity check of both Floquet paths, spurious damping of the whirl modes, and no `null`,
//! NaN or infinity in any JSON or CSV the commands write over a corpus of extreme inputs.
//! Run with `--nocapture` to see the figures.

use crate::common;
use common::{load, problem_path};
use rayon::prelude::*;
use rotorshunt::analysis::floquet::{FloquetSystem, PointIssue, PointStatus, ZERO_LOAD_TOLERANCE};
use rotorshunt::analysis::modes::whirl_modes;
use rotorshunt::analysis::Rotor;
use rotorshunt::problem::Problem;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Branch 1 of Fig. 11 tuned to 1e7 rad/s: L = 7.6e-9 H, a charge mass γL = 2.5e-7 kg
/// against kg-scale rotor masses; its mode sits at 1.1e7 rad/s.
const TINY_L: &str = "circuit.branches[0].tuning_frequency=1e7";

fn system(p: &Problem) -> FloquetSystem {
    let rotor = Rotor::new(&p.model).unwrap_or_else(|e| panic!("{e}"));
    FloquetSystem::new(&rotor, &p.settings, p.model.speed).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn tiny_inductance_gives_unit_multipliers_at_beta_zero_on_both_paths() {
    // Undamped (R = η = 0): at β = 0 every |μ| = 1. Before the DSTM took its
    // exponentials in frequency-scaled coordinates, a basis holding modes up to 3e6 rad/s
    // (M = 120) gave max|μ| = 1 + 5e-6 at any step count; M = 60 gave 1 + 6e-7, at
    // 256 as at 16 384 steps. Both paths must now give 1 to 1e-9 with status `ok` (the
    // β = 0 check passes), at the default M = 8 and at M = 60 (modes up to 1.1e6 rad/s).
    const UNIT: f64 = 1e-9;
    for (modes, phis, steps) in
        [(8, vec![100.0, 1000.0, 1230.0, 8000.0], vec![256, 4096]), (60, vec![1000.0], vec![256])]
    {
        let p = load("fig11-closed-2000.toml", &[TINY_L, &format!("analysis.reduced_modes={modes}")]);
        let fs = system(&p);
        for &phi in &phis {
            let fast = fs.point(phi, 0.0).summary;
            println!(
                "M = {modes}, phi = {phi}: fast max|mu| - 1 = {:.3e} ({:?})",
                fast.max_multiplier - 1.0,
                fast.status
            );
            assert_eq!(fast.status, PointStatus::Ok, "fast: {fast:?}");
            assert!((fast.max_multiplier - 1.0).abs() < UNIT, "fast: {fast:?}");
            for &n in &steps {
                let dstm = fs.point_dstm(phi, 0.0, n).summary;
                println!("  DSTM({n}) max|mu| - 1 = {:.3e} ({:?})", dstm.max_multiplier - 1.0, dstm.status);
                assert_eq!(dstm.status, PointStatus::Ok, "dstm({n}): {dstm:?}");
                assert!((dstm.max_multiplier - 1.0).abs() < UNIT, "dstm({n}): {dstm:?}");
                assert!((dstm.max_multiplier - fast.max_multiplier).abs() < UNIT);
            }
        }
    }
}

#[test]
fn beta_zero_check_flags_a_path_whose_unloaded_multipliers_drift() {
    // φ = 1e-4 rad/s: T = 6.3e4 s, and the DSTM's round-off over the period (~ε·T·ω_max)
    // leaves max|μ(0)| ≈ 1 + 4e-8 on an undamped model: above ZERO_LOAD_TOLERANCE, so every
    // point of that φ is `inaccurate`, with the deviation as its reason, on `point`,
    // `point_dstm` and `row` alike; at φ = 1000 rad/s the same path passes.
    let p = load("fig11-closed-2000.toml", &["analysis.method=dstm", "analysis.reference_steps=16"]);
    let fs = system(&p);
    let flagged = fs.point(1e-4, 0.0).summary;
    println!("DSTM at phi = 1e-4: {flagged:?}");
    assert_eq!(flagged.status, PointStatus::Inaccurate);
    match flagged.reason {
        Some(PointIssue::ZeroLoad { deviation }) => {
            assert!(deviation > ZERO_LOAD_TOLERANCE && deviation < 1e-6, "{deviation}")
        }
        other => panic!("expected the beta = 0 check, got {other:?}"),
    }
    assert!(flagged.stable, "the verdict is still computed");
    for point in fs.row(1e-4, &[0.1, 0.2]) {
        assert_eq!(point.summary.status, PointStatus::Inaccurate);
        assert!(matches!(point.summary.reason, Some(PointIssue::ZeroLoad { .. })));
    }
    let sound = fs.point(1000.0, 0.3).summary;
    assert_eq!((sound.status, sound.reason), (PointStatus::Ok, None));
    // The reason reaches the JSON and the text of `floquet`.
    let args =
        ["--phi", "1e-4", "--beta", "0", "--set", "analysis.method=dstm", "--set", "analysis.reference_steps=16"];
    let json = run(&["floquet", &problem_path("fig11-closed-2000.toml"), "--json"], &args);
    assert!(json.status.success());
    let v: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
    assert_eq!(v["status"], "inaccurate");
    assert!(
        v["reason"]["message"].as_str().unwrap().starts_with("beta = 0 check: the multipliers at beta = 0 deviate"),
        "{v}"
    );
    let text = run(&["floquet", &problem_path("fig11-closed-2000.toml")], &args);
    assert!(String::from_utf8_lossy(&text.stdout).contains("\nreason: beta = 0 check"));
}

#[test]
fn huge_beta_chart_never_calls_a_wrong_verdict_ok() {
    // β up to 1e10 on one per-φ table: the coupling per CFM4 exponential stays ~1e7 even
    // at 4096 steps, and the interpolant's value at β = 0 is not exp(τB0). (1230, 0) was
    // `ok` and UNSTABLE with ln μ = 617103; now every point of the row is `inaccurate`,
    // with the reason, and the summary says so.
    let dir = scratch("huge-beta-chart");
    let out = run(
        &["chart", &problem_path("fig11-closed-2000.toml")],
        &["--phi", "1230", "--beta", "0:1e10:1e9", "--out", &arg(&dir)],
    );
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stdout).contains("11 inaccurate"), "{}", String::from_utf8_lossy(&out.stdout));
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(dir.join("chart.json")).unwrap()).unwrap();
    let points = v["chart"]["points"].as_array().unwrap();
    assert_eq!(points.len(), 11);
    for p in points {
        assert_eq!(p["status"], "inaccurate", "{p}");
        assert!(p["reason"]["message"].as_str().unwrap().contains("parametric coupling"), "{p}");
    }
    // The same φ at the paper's loads is sound, and β = 0 stable with |μ| = 1.
    let fs = system(&load("fig11-closed-2000.toml", &[]));
    let row = fs.row(1230.0, &[0.0, 0.5, 1.0]);
    assert!(row.iter().all(|p| p.summary.status == PointStatus::Ok));
    assert!(row[0].summary.stable && (row[0].summary.max_multiplier - 1.0).abs() < 1e-9);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn undamped_modes_have_no_spurious_damping() {
    // R = η = 0: a conservative gyroscopic system, every whirl exactly undamped. The
    // shift-invert solve gave up to ±1.6e-3 on the high modes of the tiny-L model (and
    // ±1e-10 on the low ones); every mode must now have |ζ| < 1e-9 and no flag, for the
    // tiny inductance, for L = 0 (massless charges: condensed) and at Ω = 0 and 1e5 rad/s.
    for overrides in [vec![TINY_L], vec![], vec![TINY_L, "speed=0"], vec![TINY_L, "speed=1e5"]] {
        let p = load("fig11-closed-2000.toml", &overrides);
        let r = whirl_modes(&p.model, &p.settings, p.model.speed).unwrap();
        let worst = r.modes.iter().map(|m| m.damping_ratio.abs()).fold(0.0, f64::max);
        let residual = r.modes.iter().map(|m| m.residual).fold(0.0, f64::max);
        println!("{overrides:?}: {} modes, max |zeta| {worst:.2e}, max residual {residual:.2e}", r.modes.len());
        assert!(r.modes.len() >= 200);
        assert!(worst < 1e-9, "{overrides:?}: |zeta| up to {worst}");
        assert!(r.modes.iter().all(|m| m.flag.is_none()), "{overrides:?}: flagged modes");
        // The tiny-L branch's own modes are there, near √(γ/C_f·…/γL) ≈ 1.1e7 rad/s.
        if overrides.contains(&TINY_L) {
            assert!(r.modes.iter().any(|m| m.label.starts_with('r') && m.frequency > 1e7));
        }
    }
    let zero = Problem::from_text(
        &std::fs::read_to_string(problem_path("fig11-closed-2000.toml")).unwrap().replacen(
            "tuning_frequency = 900.0",
            "inductance = 0.0",
            1,
        ),
        "zero-l.toml",
        &[],
    )
    .unwrap();
    let r = whirl_modes(&zero.model, &zero.settings, 2000.0).unwrap();
    let worst = r.modes.iter().map(|m| m.damping_ratio.abs()).fold(0.0, f64::max);
    println!("L = 0: {} modes, max |zeta| {worst:.2e}", r.modes.len());
    assert!(worst < 1e-9 && r.modes.iter().all(|m| m.flag.is_none()));
}

#[test]
fn damped_modes_are_never_negatively_damped() {
    // A passive model (η, R ≥ 0) has Re λ ≤ 0: shift-invert gave ζ = −2.9e-3 on the high
    // modes of the Fig. 11 rotor with η = 200 N·s/m. Every mode must have ζ > −1e-9, and
    // the resistance must still damp the electrical modes.
    for overrides in [vec!["ring.eta=200"], vec!["circuit.branches[0].resistance=50", TINY_L]] {
        let p = load("fig11-closed-2000.toml", &overrides);
        let r = whirl_modes(&p.model, &p.settings, 2000.0).unwrap();
        let lowest = r.modes.iter().map(|m| m.damping_ratio).fold(f64::INFINITY, f64::min);
        println!("{overrides:?}: min zeta {lowest:.3e}");
        assert!(lowest > -1e-9, "{overrides:?}: zeta down to {lowest}");
        assert!(r.modes.iter().all(|m| m.flag.is_none()));
    }
    let p = load("fig11-closed-2000.toml", &["circuit.branches[0].resistance=50"]);
    let r = whirl_modes(&p.model, &p.settings, 2000.0).unwrap();
    assert!(r.modes.iter().find(|m| m.tag() == "fr1").unwrap().damping_ratio > 1e-3);
}

#[test]
fn garbage_modes_are_flagged_and_no_whirl_is_an_error() {
    // Ω = 1e300 rad/s: the gyroscopic terms swamp everything; residuals reach ~1 and every
    // such mode carries a flag (JSON `flag`, a note under the table).
    let out = run(&["modes", &problem_path("fig11-closed-2000.toml")], &["--set", "speed=1e300", "--json"]);
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let modes = v["modes"].as_array().unwrap();
    assert!(modes.iter().any(|m| m["flag"]["message"].as_str().is_some_and(|f| f.starts_with("QEP residual"))), "{v}");
    for m in modes {
        let residual = m["residual"].as_f64().unwrap();
        assert_eq!(
            residual > 1e-6,
            m["flag"]["message"].as_str().is_some_and(|f| f.starts_with("QEP residual")),
            "{m}"
        );
    }
    let text = run(&["modes", &problem_path("fig11-closed-2000.toml")], &["--set", "speed=1e300"]);
    assert!(String::from_utf8_lossy(&text.stdout).contains("note: mode "));
    // No whirl at all (every mode counted non-oscillatory): exit 1, not an empty list.
    let out = run(
        &["modes", &problem_path("fig8-eta4000.toml")],
        &["--set", "analysis.oscillation_tolerance=0.999999999999999", "--json"],
    );
    assert_eq!(out.status.code(), Some(1));
    assert!(out.stdout.is_empty());
    assert!(String::from_utf8_lossy(&out.stderr).starts_with("error: analysis failed: no whirl mode at speed 0 rad/s"));
}

#[test]
fn response_that_outgrows_f64_fails_without_writing() {
    // β = 1e300 (and a strongly unstable point over many periods) overflow the state: the
    // integration stops there, the command exits 1 with the time, and writes nothing.
    for (beta, periods) in [("1e300", "50"), ("1", "2000")] {
        let dir = scratch(&format!("response-{beta}"));
        let out = run(
            &["response", &problem_path("fig9-open-2000.toml")],
            &["--phi", "704", "--beta", beta, "--periods", periods, "--out", &arg(&dir)],
        );
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{stderr}");
        assert!(stderr.contains("is not finite from t = ") && stderr.contains("lower --beta or --periods"), "{stderr}");
        assert!(!dir.exists(), "{} was created", dir.display());
    }
    // The library says where it stopped.
    let fs = system(&load("fig9-open-2000.toml", &[]));
    let r = rotorshunt::analysis::response::response(&fs, 704.0, 1e300, 5);
    let t = r.stopped_at.expect("stopped");
    assert!(t > 0.0 && r.time.iter().all(|s| *s < t) && r.q1.iter().flatten().all(|x| x.is_finite()));
    assert!(r.finite().is_err());
}

#[test]
fn check_refuses_an_inductance_that_overflows_and_accepts_zero() {
    let fig11 = problem_path("fig11-closed-2000.toml");
    // tuning_frequency = 1e-300 rad/s: L = inf (was "valid").
    let out = run(&["check", &fig11], &["--set", "circuit.branches[0].tuning_frequency=1e-300"]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("--set: key `circuit.branches[0].tuning_frequency`: must be one that gives a finite L"),
        "{stderr}"
    );
    // inductance = 1e308 H: finite L, infinite charge mass γL.
    let dir = scratch("huge-l");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("l.toml");
    let text = std::fs::read_to_string(&fig11).unwrap().replacen("tuning_frequency = 900.0", "inductance = 1e308", 1);
    std::fs::write(&file, text).unwrap();
    let out = run(&["check", file.to_str().unwrap()], &[]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("line 38: key `circuit.branches[0].inductance`: must be one that gives a finite charge mass gamma L (gamma = 32.9998)"),
        "{stderr}"
    );
    std::fs::remove_dir_all(&dir).ok();
    // L = 7.6e285 H (tuning 1e-140 rad/s) is finite, and so are its coefficients: valid,
    // and the full-model commands run on it, but the reduced model's modal solve cannot
    // resolve a basis spanning ω from 1e-140 to 1e6 rad/s: Floquet commands refuse it.
    let huge = ["--set", "circuit.branches[0].tuning_frequency=1e-140"];
    assert!(run(&["check", &fig11], &huge).status.success());
    let modes = run(&["modes", &fig11, "--json"], &huge);
    assert!(modes.status.success(), "{}", String::from_utf8_lossy(&modes.stderr));
    let out = run(&["floquet", &fig11, "--phi", "704", "--beta", "0.25"], &huge);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("not resolved by the modal solve"));
    // L = 0 from a tuning frequency so large that L underflows: valid, a massless charge.
    let out = run(&["check", &fig11], &["--set", "circuit.branches[0].tuning_frequency=1e300"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(
        String::from_utf8_lossy(&out.stdout).contains("L = 0.0000 H, R = 0 ohm, not tuned (L = 0: a massless charge)")
    );
}

/// One entry of the extreme-input corpus: a problem and its overrides, and whether its
/// time response is refused as stiff (a documented analysis error, exit 1).
struct Case {
    name: &'static str,
    file: &'static str,
    set: Vec<&'static str>,
    stiff: bool,
}

fn corpus() -> Vec<Case> {
    let case = |name, file, set: &[&'static str]| Case { name, file, set: set.to_vec(), stiff: name == "huge eta" };
    vec![
        case("tiny L", "fig11-closed-2000.toml", &[TINY_L]),
        case("tiny L, M = 40", "fig11-closed-2000.toml", &[TINY_L, "analysis.reduced_modes=40"]),
        case("huge L", "fig11-closed-2000.toml", &["circuit.branches[0].tuning_frequency=1e-2"]),
        case("L = 0", "fig11-closed-2000.toml", &["circuit.branches[0].tuning_frequency=1e300"]),
        case("speed 0", "fig9-open-2000.toml", &["speed=0"]),
        case("speed 1e5", "fig9-open-2000.toml", &["speed=1e5"]),
        case(
            "dstm, huge R",
            "fig13-r50.toml",
            &["analysis.method=dstm", "analysis.reference_steps=256", "circuit.branches[0].resistance=1e6"],
        ),
        case("huge eta", "fig8-eta4000.toml", &["ring.eta=1e12"]),
    ]
}

/// Every JSON value: no `null` anywhere (serde_json writes NaN and ±inf as null).
fn assert_no_null(v: &serde_json::Value, path: &str, what: &str) {
    match v {
        serde_json::Value::Null => panic!("{what}: null at {path}"),
        serde_json::Value::Array(a) => {
            a.iter().enumerate().for_each(|(i, x)| assert_no_null(x, &format!("{path}[{i}]"), what))
        }
        serde_json::Value::Object(o) => o.iter().for_each(|(k, x)| assert_no_null(x, &format!("{path}.{k}"), what)),
        _ => {}
    }
}

/// Every CSV field: no NaN or infinity; an empty field only where the chart documents one
/// (the numbers of a `failed` point).
fn assert_csv_finite(text: &str, what: &str) {
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    assert!(!header.is_empty(), "{what}: no header");
    for (row, line) in lines.enumerate() {
        let fields: Vec<&str> = line.split(',').collect();
        assert_eq!(fields.len(), header.len(), "{what}: row {row}: {line}");
        let failed = fields.contains(&"failed");
        for (name, field) in header.iter().zip(&fields) {
            let lower = field.to_ascii_lowercase();
            assert!(!lower.contains("nan") && !lower.contains("inf"), "{what}: row {row} {name} = {field}");
            assert!(!field.is_empty() || failed, "{what}: row {row} {name} is empty");
            if let Ok(x) = field.parse::<f64>() {
                assert!(x.is_finite(), "{what}: row {row} {name} = {field}");
            }
        }
    }
}

/// The `floquet` points of every corpus case: inside a region, far beyond the paper's
/// loads, and at extreme φ: 50 rad/s, an order of magnitude below the paper's range (a
/// point's cost grows as the fastest mode over φ: at 1 rad/s the tiny-L cases alone took
/// several minutes of CPU, at 10 rad/s 44 s), and 1e6 rad/s.
const FLOQUET_POINTS: [(&str, &str); 5] =
    [("704", "0.25"), ("1230", "1e300"), ("50", "0.5"), ("1e6", "0.5"), ("3000", "0")];

/// One unit of the corpus's work: a case's `floquet` point, or the rest of its commands.
enum Job<'a> {
    Floquet(&'a Case, &'static str, &'static str),
    Commands(&'a Case),
}

#[test]
fn no_null_nan_or_inf_in_any_json_or_csv_over_the_extreme_corpus() {
    // The cases and their floquet points are independent: two at a time (the machine's
    // two cores; most commands run on one thread), each point a job of its own, since a
    // few of them (M = 40 at φ = 50 rad/s and at β = 1e300) take most of the time.
    let cases = corpus();
    let mut jobs: Vec<Job> = Vec::new();
    for case in &cases {
        jobs.extend(FLOQUET_POINTS.iter().map(|&(phi, beta)| Job::Floquet(case, phi, beta)));
        jobs.push(Job::Commands(case));
    }
    let checked: usize = jobs
        .par_iter()
        .with_max_len(1)
        .map(|job| match job {
            Job::Floquet(case, phi, beta) => check_floquet_point(case, phi, beta),
            Job::Commands(case) => check_corpus_case(case),
        })
        .sum();
    println!("{checked} outputs checked");
}

/// `--set` arguments of a corpus case.
fn set_args(case: &Case) -> Vec<String> {
    case.set.iter().flat_map(|s| ["--set".to_string(), s.to_string()]).collect()
}

/// One `floquet --json` point of a corpus case: no null in its JSON; the outputs checked.
fn check_floquet_point(case: &Case, phi: &str, beta: &str) -> usize {
    let file = problem_path(case.file);
    let set = set_args(case);
    let set: Vec<&str> = set.iter().map(String::as_str).collect();
    let what = format!("{} (floquet {phi} {beta})", case.name);
    let out = run(&["floquet", &file, "--json", "--phi", phi, "--beta", beta], &set);
    assert!(out.status.success(), "{what}: {}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("{what}: {e}"));
    assert_no_null(&json, "", &what);
    1
}

/// The commands of one corpus case but its `floquet` points, and the checks of their
/// outputs; the outputs checked.
fn check_corpus_case(case: &Case) -> usize {
    let mut checked = 0;
    {
        let file = problem_path(case.file);
        let set = set_args(case);
        let set: Vec<&str> = set.iter().map(String::as_str).collect();
        let what = |cmd: &str| format!("{} ({cmd})", case.name);
        let json_of = |out: &Output, cmd: &str| -> serde_json::Value {
            assert!(out.status.success(), "{}: {}", what(cmd), String::from_utf8_lossy(&out.stderr));
            serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("{}: {e}", what(cmd)))
        };
        let out = run(&["modes", &file, "--json", "--count", "50"], &set);
        assert_no_null(&json_of(&out, "modes"), "", &what("modes"));
        let out = run(&["check", &file], &set);
        let text = String::from_utf8_lossy(&out.stdout).to_ascii_lowercase();
        assert!(out.status.success(), "{}: {}", what("check"), String::from_utf8_lossy(&out.stderr));
        assert!(!text.contains("nan") && !text.contains(" inf "), "{}: {text}", what("check"));
        let dir = scratch(&format!("corpus-{}", case.name.replace([' ', ','], "-")));
        let out = run(
            &["chart", &file, "--phi", "300:1500:600", "--beta", "0:20:10", "--out", &arg(&dir.join("chart"))],
            &set,
        );
        assert!(out.status.success(), "{}: {}", what("chart"), String::from_utf8_lossy(&out.stderr));
        assert_no_null(&read_json(&dir.join("chart/chart.json")), "", &what("chart.json"));
        assert_csv_finite(&std::fs::read_to_string(dir.join("chart/chart.csv")).unwrap(), &what("chart.csv"));
        let out = run(&["campbell", &file, "--speeds", "0:1e5:5e4", "--out", &arg(&dir.join("campbell"))], &set);
        assert!(out.status.success(), "{}: {}", what("campbell"), String::from_utf8_lossy(&out.stderr));
        assert_no_null(&read_json(&dir.join("campbell/campbell.json")), "", &what("campbell.json"));
        assert_csv_finite(&std::fs::read_to_string(dir.join("campbell/campbell.csv")).unwrap(), &what("campbell.csv"));
        let response = arg(&dir.join("response"));
        let args = ["response", &file, "--phi", "1000", "--beta", "0.25", "--periods", "2", "--out", &response];
        let out = run(&args, &set);
        if case.stiff {
            assert_eq!(out.status.code(), Some(1), "{}", what("response"));
            assert!(String::from_utf8_lossy(&out.stderr).contains("is stiff"), "{}", what("response"));
            assert!(!dir.join("response").exists());
        } else {
            assert!(out.status.success(), "{}: {}", what("response"), String::from_utf8_lossy(&out.stderr));
            assert_no_null(&read_json(&dir.join("response/response.json")), "", &what("response.json"));
            assert_csv_finite(
                &std::fs::read_to_string(dir.join("response/response.csv")).unwrap(),
                &what("response.csv"),
            );
        }
        checked += 7;
        std::fs::remove_dir_all(&dir).ok();
    }
    checked
}

fn read_json(path: &Path) -> serde_json::Value {
    serde_json::from_slice(&std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display())))
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn scratch(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("rotorshunt-numerics-{}-{name}", std::process::id()))
}

/// The binary with `args` then `more`.
fn run(args: &[&str], more: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rotorshunt"))
        .args(args.iter().chain(more))
        .env_remove("RUST_BACKTRACE")
        .output()
        .unwrap()
}

/// A path as a command-line argument.
fn arg(path: &Path) -> String {
    path.to_str().expect("temporary paths are UTF-8").to_string()
}
