//! Fuzz of the command layer's flags and study fields (run by `cargo test`, in the
//! binary's tests: the layer is not part of the library): hostile numbers (NaN, ±inf,
//! signed zeros, the extremes of f64, integers beyond 2⁶³) as `floquet`, `regions`,
//! `band`, `modes` and `response` flags and as a study file's fields, each call run
//! in-process on `problems/fig9-open-2000.toml` with the default limits. Asserted for
//! every case: no panic; within [`CASE_HANG_TIMEOUT`] (plus its counted operations, for a
//! long response); an error of the documented input kinds (a rule, a cost refusal, a form
//! error) or an analysis error; a result's JSON without nulls.
//! `ROTORSHUNT_FUZZ_CASES=N` scales the run.

use proptest::prelude::*;
use proptest::test_runner::{Config, TestCaseError, TestRunner};
use rotorshunt::analysis::floquet::FloquetSystem;
use rotorshunt::problem::Problem;
use std::path::Path;
use std::time::{Duration, Instant};

/// Against hangs only, not a timing: no single case may take longer than this (a hang or
/// a runaway computation is orders of magnitude beyond it; cases take milliseconds, and a
/// loaded shared machine must not trip it). Timings belong to the benches.
const CASE_HANG_TIMEOUT: Duration = Duration::from_secs(30);
/// A long response's hang timeout adds this many times its counted operations at
/// [`SLOW_RATE`]: the tests run at once on two shared cores (four periods at φ = 1 rad/s,
/// counted at 7.4e9 operations: 1.3-2.5 s wall on the reference host at load 2, 8.7 s at
/// load 8, 10.8 s at load 7 beside two compilers).
const HANG_ESTIMATE_FACTOR: f64 = 5.0;
/// Operations a second a loaded core does at least (the quiet reference host did 3e9 to
/// 3e10 of the counted operations a second): what turns a count into a hang timeout.
const SLOW_RATE: f64 = 1.0e9;
/// Responses counted beyond this (floating-point operations) are not run: a few seconds
/// of RK4 on the reference host.
const LONG_RESPONSE: f64 = 2.0e10;

/// Hostile flag values: non-finite, signed zeros, negative, tiny and huge, subnormal, and
/// integers at and beyond 2⁶³ and 2⁶⁴ as f64.
const HOSTILE: [f64; 19] = [
    f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
    0.0,
    -0.0,
    -1.0,
    -1e3,
    1.0,
    2.0,
    1e9,
    1e-9,
    1e308,
    -1e308,
    f64::MAX,
    1e-308,
    5e-324,
    9.223_372_036_854_776e18,
    -9.223_372_036_854_776e18,
    1.844_674_407_370_955_2e19,
];

/// Cases of the command-line and study fuzz (CI run); `ROTORSHUNT_FUZZ_CASES` scales it.
const FLAG_CASES_DEFAULT: u32 = 400;

/// A hostile number: one of [`HOSTILE`], any f64, or an extreme.
fn hostile() -> impl Strategy<Value = f64> {
    prop_oneof![
        3 => (0..HOSTILE.len()).prop_map(|i| HOSTILE[i]),
        1 => any::<f64>(),
        1 => prop_oneof![Just(1e-300), Just(1e300), Just(5e-324), Just(-5e-324), Just(f64::MAX), Just(f64::MIN_POSITIVE)],
    ]
}

/// Nulls in a JSON document outside the documented optional `containing`.
fn json_nulls(v: &serde_json::Value) -> usize {
    match v {
        serde_json::Value::Null => 1,
        serde_json::Value::Array(a) => a.iter().map(json_nulls).sum(),
        serde_json::Value::Object(o) => {
            o.iter().filter(|(k, x)| !(k.as_str() == "containing" && x.is_null())).map(|(_, x)| json_nulls(x)).sum()
        }
        _ => 0,
    }
}

/// One fuzzed call: which command, and its hostile values.
#[derive(Debug, Clone)]
enum FlagCase {
    Floquet(f64, f64),
    Regions(f64, f64, f64, f64),
    Band(f64, f64, f64, f64),
    Modes(f64, u64),
    Response(f64, f64, u64),
    Study(f64, f64, f64, f64, f64),
}

fn flag_case() -> impl Strategy<Value = FlagCase> {
    let count = prop_oneof![Just(0u64), Just(1), Just(4), Just(u64::MAX), Just(1 << 40), 0u64..100_000];
    prop_oneof![
        (hostile(), hostile()).prop_map(|(p, b)| FlagCase::Floquet(p, b)),
        (hostile(), hostile(), hostile(), hostile()).prop_map(|(a, b, m, l)| FlagCase::Regions(a, b, m, l)),
        (hostile(), hostile(), hostile(), hostile()).prop_map(|(p, l, a, b)| FlagCase::Band(p, l, a, b)),
        (hostile(), count.clone()).prop_map(|(w, c)| FlagCase::Modes(w, c)),
        (hostile(), hostile(), count).prop_map(|(p, b, n)| FlagCase::Response(p, b, n)),
        (hostile(), hostile(), hostile(), hostile(), hostile())
            .prop_map(|(a, b, m, l, o)| FlagCase::Study(a, b, m, l, o)),
    ]
}

/// A hostile value written as TOML (TOML has `nan` and `inf`, and no other spelling).
fn toml_number(x: f64) -> String {
    if x.is_nan() {
        "nan".into()
    } else if x.is_infinite() {
        if x > 0.0 {
            "inf".into()
        } else {
            "-inf".into()
        }
    } else {
        format!("{x:e}")
    }
}

/// Run one fuzzed call in-process with the default limits: no panic, within
/// `CASE_HANG_TIMEOUT`, an error of the documented input kinds (a rule, a cost refusal, a form
/// error) or an analysis error, and a result's JSON without nulls.
fn run_flag_case(
    c: &FlagCase,
    problem: &Problem,
    fs: &std::sync::OnceLock<FloquetSystem>,
    dir: &Path,
) -> Result<(), String> {
    use crate::commands::{self, StudyOptions};
    use rotorshunt::progress::Silent as Quiet;
    use rotorshunt::run::Budget;
    let budget = Budget::default();
    // A response asked for many periods of a low φ is long work the cost check admits,
    // not a hang: it is held to its own estimate, and not run at all beyond
    // `LONG_RESPONSE` (the estimate is what this test checks, not hours of RK4).
    let estimated = match c {
        FlagCase::Response(p, b, n) if *p > 0.0 && p.is_finite() && b.is_finite() => {
            let fs = fs.get_or_init(|| problem.operating_point().expect("fig9 reduces").floquet);
            rotorshunt::analysis::cost::response_of(fs, *p, *b, *n as usize).work.amount
        }
        _ => 0.0,
    };
    if estimated > LONG_RESPONSE {
        return Ok(());
    }
    let start = Instant::now();
    let out = dir.join("out");
    let _ = std::fs::remove_dir_all(&out);
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| match c {
        FlagCase::Floquet(p, b) => commands::floquet_cmd(problem, *p, *b, true, budget),
        FlagCase::Regions(a, b, m, l) => {
            let phi = format!("{a}:{b}");
            let args = commands::RegionsArgs { phi: &phi, beta_max: *m, level: Some(*l), json: true, out: None };
            commands::regions_cmd(problem, args, &Quiet, budget)
        }
        FlagCase::Band(p, l, a, b) => {
            commands::band_cmd(problem, *p, *l, Some(&format!("{a}:{b}")), true, &Quiet, budget)
        }
        FlagCase::Modes(w, n) => commands::modes(problem, Some(*w), *n as usize, true, budget),
        FlagCase::Response(p, b, n) => commands::response_cmd(problem, *p, *b, *n as usize, &out, &Quiet, budget),
        FlagCase::Study(a, b, m, l, o) => {
            let text = format!(
                "base = \"base.toml\"\nkind = \"regions\"\nphi = [{}, {}]\nbeta_max = {}\nlevel = {}\nphi_op = {}\n[[cases]]\nname = \"a\"\n",
                toml_number(*a),
                toml_number(*b),
                toml_number(*m),
                toml_number(*l),
                toml_number(*o)
            );
            let file = dir.join("study.toml");
            std::fs::write(&file, text)
                .map_err(|e| crate::commands::Error::Output { path: "study.toml".into(), message: e.to_string() })?;
            let options = StudyOptions { force: false, allow_non_empty: false, budget, ..Default::default() };
            commands::study_cmd(&file, &out, options, &Quiet).map(|(t, _)| t)
        }
    }));
    let elapsed = start.elapsed();
    let hang_timeout =
        CASE_HANG_TIMEOUT + Duration::from_secs_f64((HANG_ESTIMATE_FACTOR * estimated / SLOW_RATE).min(3600.0));
    if elapsed > hang_timeout {
        return Err(format!(
            "{c:?}: took {elapsed:?}, a hang (timeout {hang_timeout:?}, counted {estimated:.3e} operations)"
        ));
    }
    match result {
        Err(_) => Err(format!("{c:?}: panicked")),
        Ok(Ok(text)) => match serde_json::from_str::<serde_json::Value>(&text) {
            Ok(v) if json_nulls(&v) > 0 => Err(format!("{c:?}: {} nulls in the JSON", json_nulls(&v))),
            _ => Ok(()),
        },
        Ok(Err(e)) => {
            use crate::commands::Error as E;
            match &e {
                E::Parameter { .. } | E::Argument { .. } | E::Cost(_) | E::Problem(_) | E::Analysis(_) => Ok(()),
                other => Err(format!("{c:?}: unexpected error kind: {other}")),
            }
        }
    }
}

/// Command-line flags and study fields with hostile numbers (the routes of `tests/routes.rs`
/// at random): refused cleanly or answered quickly, never a panic or a hang.
#[test]
fn hostile_flags_and_study_fields_are_refused_cleanly() {
    let cases = std::env::var("ROTORSHUNT_FUZZ_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(FLAG_CASES_DEFAULT);
    let dir = std::env::temp_dir().join(format!("rotorshunt-fuzz-flags-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("create fuzz folder");
    let base = Path::new(env!("CARGO_MANIFEST_DIR")).join("problems/fig9-open-2000.toml");
    std::fs::copy(&base, dir.join("base.toml")).expect("copy base");
    let problem = Problem::from_path(&base, &[]).expect("fig9 loads");
    let fs = std::sync::OnceLock::new();
    // Found by this test: four periods at φ = 1 rad/s are 1.6 million admitted RK4 steps.
    let floquet = fs.get_or_init(|| problem.operating_point().expect("fig9 reduces").floquet);
    let estimate = rotorshunt::analysis::cost::response_of(floquet, 1.0, 1e-308, 4).work.amount;
    println!("response at phi = 1 rad/s, 4 periods: counted {estimate:.2e} operations");
    assert!(estimate <= LONG_RESPONSE, "the replayed case would not run: {estimate:e} operations");
    run_flag_case(&FlagCase::Response(1.0, 1e-308, 4), &problem, &fs, &dir).unwrap_or_else(|e| panic!("{e}"));
    let mut runner = TestRunner::new(Config { cases, failure_persistence: None, ..Config::default() });
    let result = runner.run(&flag_case(), |c| run_flag_case(&c, &problem, &fs, &dir).map_err(TestCaseError::fail));
    let _ = std::fs::remove_dir_all(&dir);
    result.unwrap_or_else(|e| panic!("{e}"));
}
