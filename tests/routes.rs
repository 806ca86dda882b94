//! One validation layer: the same bad value fed through every route that can carry it —
//! the problem file, `--set`, a command-line flag, a study field, a study's `set` and a
//! sweep value — is refused with the same rule (the same kind
//! and words), naming the key and line (or the flag), with exit 2, and within 200 MB of
//! peak memory (the child's own `ru_maxrss`). Issue 14 asks for a refusal in under 1 s:
//! the slowest route's time is printed, not asserted (tests hold on any machine,
//! docs/development.md); a route still running after [`HANG_TIMEOUT`] is killed and fails
//! as a hang.

mod common;
use std::path::{Path, PathBuf};
use std::time::Duration;

/// A refusal still running after this is killed and reported as a hang (issue 14 asks for
/// under 1 s; that figure is printed, never asserted).
const HANG_TIMEOUT: Duration = Duration::from_secs(60);
/// Routes slower than this are listed in the output (issue 14: "in under 1 s").
const REPORTED_SECONDS: f64 = 1.0;
/// And use at most this much memory (kB; issue 14: "memory under 200 MB").
const MEMORY_LIMIT_KB: i64 = 200 * 1000;

/// The base problem of every route: the widest-band design (it has a `[design]` table).
const BASE: &str = "design-widest-band.toml";

/// A route: how the value comes in, the command line, and what the message must name.
struct Route {
    name: &'static str,
    args: Vec<String>,
    names: String,
}

/// A bad value: the rule's words every route must print, and its routes.
struct Bad {
    what: &'static str,
    rule: &'static str,
    routes: Vec<Route>,
}

struct Dir(PathBuf);

impl Dir {
    fn new(name: &str) -> Dir {
        let d = common::tmp(&format!("routes-{name}"));
        std::fs::create_dir_all(&d).expect("create test folder");
        std::fs::copy(common::problem_path(BASE), d.join("base.toml")).expect("copy base");
        Dir(d)
    }

    fn path(&self) -> &Path {
        &self.0
    }

    /// The base with line `from` replaced by `to` (whole lines, so the edit is exact).
    fn problem(&self, name: &str, edits: &[(&str, &str)]) -> String {
        let mut text = std::fs::read_to_string(self.0.join("base.toml")).expect("read base");
        for (from, to) in edits {
            let line = text.lines().find(|l| l.starts_with(from)).unwrap_or_else(|| panic!("no line {from}"));
            text = text.replacen(line, to, 1);
        }
        std::fs::write(self.0.join(name), text).expect("write problem");
        name.to_string()
    }

    /// A study file on the base with `body` (fields, cases, sweep).
    fn study(&self, name: &str, body: &str) -> String {
        std::fs::write(self.0.join(name), format!("base = \"base.toml\"\n{body}")).expect("write study");
        name.to_string()
    }
}

impl Drop for Dir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn args(a: &[&str]) -> Vec<String> {
    a.iter().map(|s| s.to_string()).collect()
}

fn route(name: &'static str, a: Vec<String>, names: &str) -> Route {
    Route { name, args: a, names: names.to_string() }
}

/// The design's default range and operating point, and the cases of a regions study.
const REGIONS: &str = "kind = \"regions\"\nphi = [1000.0, 1500.0]\nbeta_max = 0.5\nlevel = 0.3\n";
const ONE_CASE: &str = "\n[[cases]]\nname = \"a\"\n";

fn corpus(d: &Dir) -> Vec<Bad> {
    let check = |file: String, set: &[&str]| {
        let mut a = args(&["check", &file]);
        for s in set {
            a.extend(args(&["--set", s]));
        }
        a
    };
    let study = |file: String| args(&["study", &file, "--out", "study-out"]);
    vec![
        Bad {
            what: "a phi range ending at inf",
            rule: "must be a finite number, found inf",
            routes: vec![
                route(
                    "file",
                    check(d.problem("p1.toml", &[("phi_range", "phi_range = [1000.0, inf]")]), &[]),
                    "line 58: key `design.phi_range[1]`",
                ),
                route("--set", check("base.toml".into(), &["design.phi_range=[1000.0,inf]"]), "key `design.phi_range[1]`"),
                route("flag", args(&["regions", "base.toml", "--phi", "1000:inf"]), "argument `--phi`"),
                route(
                    "flag",
                    args(&["band", "base.toml", "--phi", "1000:inf", "--phi-op", "1230", "--level", "0.3"]),
                    "argument `--phi`",
                ),
                route(
                    "study field",
                    study(d.study("s1.toml", &format!("{}{ONE_CASE}", REGIONS.replace("1500.0]", "inf]")))),
                    "s1.toml, line 3: key `phi[1]`",
                ),
                route(
                    "sweep",
                    study(d.study("s2.toml", "kind = \"design\"\n[sweep]\n\"design.phi_range\" = [[1000.0, inf]]\n")),
                    "s2.toml, line 4: key `sweep.design.phi_range[0]`",
                ),
            ],
        },
        Bad {
            what: "beta_max = NaN",
            rule: "must be a finite number, found NaN",
            routes: vec![
                route(
                    "file",
                    check(d.problem("p2.toml", &[("level", "level = 0.3\nbeta_max = nan")]), &[]),
                    "line 57: key `design.beta_max`",
                ),
                route("--set", check("base.toml".into(), &["design.beta_max=nan"]), "key `design.beta_max`"),
                route(
                    "flag",
                    args(&["regions", "base.toml", "--phi", "1000:1500", "--beta-max", "nan"]),
                    "argument `--beta-max`",
                ),
                route(
                    "study field",
                    study(d.study("s3.toml", &format!("{}{ONE_CASE}", REGIONS.replace("= 0.5", "= nan")))),
                    "s3.toml, line 4: key `beta_max`",
                ),
                route(
                    "sweep",
                    study(d.study("s4.toml", "kind = \"design\"\n[sweep]\n\"design.beta_max\" = [1.0, nan]\n")),
                    "s4.toml, line 4: key `sweep.design.beta_max[1]`",
                ),
            ],
        },
        Bad {
            what: "a level above beta_max",
            rule: "must be at most beta_max = 0.5, found 0.9",
            routes: vec![
                route(
                    "file",
                    check(d.problem("p3.toml", &[("level", "level = 0.9\nbeta_max = 0.5")]), &[]),
                    "line 56: key `design.level`",
                ),
                route("--set", check("base.toml".into(), &["design.beta_max=0.5", "design.level=0.9"]), "key `design.level`"),
                route(
                    "flag",
                    args(&["regions", "base.toml", "--phi", "1000:1500", "--beta-max", "0.5", "--level", "0.9"]),
                    "argument `--level`",
                ),
                route(
                    "study field",
                    study(d.study("s5.toml", &format!("{}{ONE_CASE}", REGIONS.replace("= 0.3", "= 0.9")))),
                    "s5.toml, line 5: key `level`",
                ),
                route(
                    "sweep",
                    study(d.study(
                        "s6.toml",
                        "kind = \"design\"\nset = [\"design.beta_max=0.5\"]\n[sweep]\n\"design.level\" = [0.9]\n",
                    )),
                    "s6.toml, line 5: key `sweep.design.level[0]`",
                ),
            ],
        },
        Bad {
            what: "phi_op outside the phi range",
            rule: "must be inside the range [1000, 1500] rad/s, found 2000",
            routes: vec![
                route(
                    "file",
                    check(
                        d.problem(
                            "p4.toml",
                            &[("phi_op", "phi_op = 2000.0"), ("phi_range", "phi_range = [1000.0, 1500.0]")],
                        ),
                        &[],
                    ),
                    "line 57: key `design.phi_op`",
                ),
                route(
                    "--set",
                    check("base.toml".into(), &["design.phi_range=[1000.0,1500.0]", "design.phi_op=2000"]),
                    "key `design.phi_op`",
                ),
                route(
                    "flag",
                    args(&["band", "base.toml", "--phi", "1000:1500", "--phi-op", "2000", "--level", "0.3"]),
                    "argument `--phi-op`",
                ),
                route(
                    "study field",
                    study(d.study("s7.toml", &format!("{REGIONS}phi_op = 2000.0\n{ONE_CASE}"))),
                    "s7.toml, line 6: key `phi_op`",
                ),
                route(
                    "sweep",
                    study(d.study(
                        "s8.toml",
                        "kind = \"design\"\nset = [\"design.phi_range=[1000.0,1500.0]\"]\n[sweep]\n\"design.phi_op\" = [1230.0, 2000.0]\n",
                    )),
                    "s8.toml, line 5: key `sweep.design.phi_op[1]`",
                ),
            ],
        },
        Bad {
            what: "a negative speed",
            rule: "must not be negative, found -1",
            routes: vec![
                route("file", check(d.problem("p5.toml", &[("speed", "speed = -1.0")]), &[]), "line 8: key `speed`"),
                route("--set", check("base.toml".into(), &["speed=-1"]), "key `speed`"),
                route("flag", args(&["modes", "base.toml", "--speed=-1"]), "argument `--speed`"),
                route("flag", args(&["campbell", "base.toml", "--speeds=-1:1:1", "--out", "c"]), "argument `--speeds`"),
                route(
                    "study set",
                    study(d.study("s9.toml", &format!("{REGIONS}set = [\"speed=-1\"]\n{ONE_CASE}"))),
                    "--set: key `speed`",
                ),
                route(
                    "sweep",
                    study(d.study("s11.toml", &format!("{REGIONS}[sweep]\nspeed = [2000.0, -1.0]\n"))),
                    "s11.toml, line 7: key `sweep.speed[1]`",
                ),
            ],
        },
        Bad {
            what: "a negative phi",
            rule: "must be positive, found -1000",
            routes: vec![
                route(
                    "file",
                    check(d.problem("p6.toml", &[("phi_range", "phi_range = [-1000.0, 1500.0]")]), &[]),
                    "line 58: key `design.phi_range[0]`",
                ),
                route("--set", check("base.toml".into(), &["design.phi_range=[-1000.0,1500.0]"]), "key `design.phi_range[0]`"),
                route("flag", args(&["regions", "base.toml", "--phi=-1000:1500"]), "argument `--phi`"),
                route("flag", args(&["floquet", "base.toml", "--phi=-1000", "--beta", "0.3"]), "argument `--phi`"),
                route(
                    "study field",
                    study(d.study("s12.toml", &format!("{}{ONE_CASE}", REGIONS.replace("[1000.0", "[-1000.0")))),
                    "s12.toml, line 3: key `phi[0]`",
                ),
                route(
                    "sweep",
                    study(d.study("s13.toml", "kind = \"design\"\n[sweep]\n\"design.phi_range\" = [[-1000.0, 1500.0]]\n")),
                    "s13.toml, line 4: key `sweep.design.phi_range[0]`",
                ),
            ],
        },
        Bad {
            what: "a reversed phi range",
            rule: "must be above the range's low end, 1500 rad/s, found 1000",
            routes: vec![
                route(
                    "file",
                    check(d.problem("p7.toml", &[("phi_range", "phi_range = [1500.0, 1000.0]")]), &[]),
                    "line 58: key `design.phi_range[1]`",
                ),
                route("--set", check("base.toml".into(), &["design.phi_range=[1500.0,1000.0]"]), "key `design.phi_range[1]`"),
                route("flag", args(&["regions", "base.toml", "--phi", "1500:1000"]), "argument `--phi`"),
                route(
                    "study field",
                    study(d.study("s14.toml", &format!("{}{ONE_CASE}", REGIONS.replace("[1000.0, 1500.0]", "[1500.0, 1000.0]")))),
                    "s14.toml, line 3: key `phi[1]`",
                ),
            ],
        },
        Bad {
            what: "a phi range of 600 decades",
            rule: "must be at most 1e7 rad/s, found 1e300",
            routes: vec![
                route(
                    "file",
                    check(d.problem("p8.toml", &[("phi_range", "phi_range = [1e-300, 1e300]")]), &[]),
                    "line 58: key `design.phi_range[1]`",
                ),
                route("--set", check("base.toml".into(), &["design.phi_range=[1e-300,1e300]"]), "key `design.phi_range[1]`"),
                route("flag", args(&["regions", "base.toml", "--phi", "1e-300:1e300"]), "argument `--phi`"),
                route(
                    "study field",
                    study(d.study("s15.toml", &format!("{}{ONE_CASE}", REGIONS.replace("[1000.0, 1500.0]", "[1e-300, 1e300]")))),
                    "s15.toml, line 3: key `phi[1]`",
                ),
            ],
        },
    ]
}

#[test]
fn the_same_bad_value_gets_the_same_error_by_every_route() {
    let d = Dir::new("same");
    let mut failures = Vec::new();
    let mut worst = (0.0f64, 0i64);
    let mut slow = Vec::new();
    let mut count = 0;
    for bad in corpus(&d) {
        for r in &bad.routes {
            count += 1;
            let m = common::run_measured(&r.args, d.path(), HANG_TIMEOUT);
            let first = m.stderr.lines().next().unwrap_or_default().to_string();
            let what = format!("{} by {} (rotorshunt {})", bad.what, r.name, r.args.join(" "));
            worst = (worst.0.max(m.seconds), worst.1.max(m.peak_kb));
            if m.code != Some(2) {
                failures.push(format!("{what}: exit {:?} (signal {:?}), expected 2: {first}", m.code, m.signal));
            }
            // The same rule's words, after the key or flag it names.
            if !first.ends_with(&format!(": {}", bad.rule)) {
                failures.push(format!("{what}: `{first}` does not end with the rule `{}`", bad.rule));
            }
            if !first.contains(&r.names) {
                failures.push(format!("{what}: `{first}` does not name `{}`", r.names));
            }
            if m.timed_out {
                failures.push(format!("{what}: still running after {HANG_TIMEOUT:?}, killed (a hang)"));
            }
            if m.seconds > REPORTED_SECONDS {
                slow.push(format!("  {:.2} s: {what}", m.seconds));
            }
            if m.peak_kb > MEMORY_LIMIT_KB {
                failures.push(format!("{what}: peak {} kB", m.peak_kb));
            }
            if d.path().join("study-out").exists() {
                failures.push(format!("{what}: the refused study created its --out folder"));
                let _ = std::fs::remove_dir_all(d.path().join("study-out"));
            }
        }
    }
    println!("{count} routes; slowest {:.3} s, largest peak {} kB", worst.0, worst.1);
    println!("{} routes beyond the {REPORTED_SECONDS} s of issue 14 (printed, not asserted):", slow.len());
    for l in &slow {
        println!("{l}");
    }
    assert!(count >= 38, "only {count} routes");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The library's request constructors apply the same rules as the file and the flags.
#[test]
fn library_requests_obey_the_same_rules() {
    use rotorshunt::analysis::limits::{self, Quantity, Rule};
    use rotorshunt::analysis::regions::CatalogueRequest;
    use rotorshunt::analysis::Interval;
    use rotorshunt::problem::ProblemErrorKind;

    let near = CatalogueRequest::builder().range(Interval::new(1000.0, 1500.0));
    let ok = near.beta_max(0.5).level(0.3).build().expect("a valid request");
    assert_eq!((ok.beta_max, ok.level), (0.5, 0.3));
    let e = near.beta_max(f64::NAN).level(0.3).build().unwrap_err();
    assert_eq!(
        (e.quantity, ProblemErrorKind::from(&e).to_string()),
        (Quantity::BetaMax, "must be a finite number, found NaN".into())
    );
    let e = near.beta_max(0.5).level(0.9).build().unwrap_err();
    assert_eq!(near.beta_max(0.5).level(0.9).validate().unwrap_err(), e);
    // A required value not set is refused, never defaulted quietly, and said to be missing
    // (not a NaN the caller never wrote).
    let missing = CatalogueRequest::builder().level(0.3).build().unwrap_err();
    assert_eq!((&missing.rule, missing.to_string().as_str()), (&Rule::NotSet, "is required and was not set"));
    assert_eq!(missing.rule.kind(), "Schema");
    assert!(rotorshunt::BandRequest::builder().level(0.3).build().is_err());
    assert!(rotorshunt::ChartRequest::grid()
        .phi(Interval::new(1000.0, 1500.0))
        .beta_max(0.5)
        .beta_step(0.1)
        .build()
        .is_err());
    assert_eq!(e.rule, Rule::AboveBetaMax { beta_max: 0.5 });
    assert_eq!(e.to_string(), "must be at most beta_max = 0.5, found 0.9");
    // A request built field by field is checked by the catalogue itself.
    let built = CatalogueRequest { range: Interval::new(1500.0, 1000.0), beta_max: 0.5, level: 0.3, track: false };
    assert_eq!(built.check().unwrap_err().to_string(), "must be above the range's low end, 1500 rad/s, found 1000");
    assert!(limits::phi_op(2000.0, Interval::new(1000.0, 1500.0)).is_err());

    // A DesignSpec with public fields is checked by the design run, not trusted.
    let mut p = common::load(BASE, &[]);
    if let Some(spec) = p.design.as_mut() {
        spec.level = 1e300;
    }
    let e = rotorshunt::design::optimise::run(&p.machine(), p.design.as_ref().unwrap(), &|| {}).unwrap_err();
    assert_eq!(e.to_string(), "design.level: must be at most 100, found 1e300");
}

/// Settings built in code are held to the `[analysis]` rules by every analysis, with the
/// file layer's words: no silent use of a setting the file would refuse.
#[test]
fn settings_built_in_code_are_validated() {
    use rotorshunt::analysis::{floquet::FloquetSystem, modes::whirl_modes_of, SettingsRule};
    let p = common::load("paper-closed.toml", &[]);
    let rotor = p.rotor().unwrap();
    let bad = rotorshunt::Settings { steps_per_period: 1, ..p.settings.clone() };
    let e = bad.validate().unwrap_err();
    assert_eq!(e.field, "steps_per_period");
    assert!(matches!(e.rule, SettingsRule::OutOfRange { value, .. } if value == 1.0));
    assert_eq!(e.to_string(), "analysis.steps_per_period: must be a whole number from 2 to 65536, found 1");
    let Err(floquet) = FloquetSystem::new(&rotor, &bad, 2000.0) else { panic!("bad settings accepted by Floquet") };
    let Err(modes) = whirl_modes_of(&rotor, &bad, 2000.0) else { panic!("bad settings accepted by modes") };
    for err in [floquet, modes] {
        assert!(matches!(&err, rotorshunt::AnalysisError::Settings(s) if *s == e), "{err}");
    }
    let nan = rotorshunt::Settings { min_growth_rate: f64::NAN, ..p.settings.clone() };
    assert_eq!(nan.validate().unwrap_err().rule.to_string(), "must be a finite number, found NaN");
    // The same rule through the file: the same words at the key.
    let from_file = rotorshunt::Problem::from_path(
        common::problem_path("paper-closed.toml"),
        &["analysis.steps_per_period=1".into()],
    )
    .unwrap_err();
    assert!(
        from_file
            .to_string()
            .ends_with("key `analysis.steps_per_period`: must be a whole number from 2 to 65536, found 1"),
        "{from_file}"
    );
    p.settings.validate().unwrap();
}

/// A catalogue and a band read back from their JSON are the results written: the library's
/// results of the region search are Serialize and Deserialize, and round-trip exactly
/// (serde_json's `float_roundtrip`: every f64 bit for bit). The other results round-trip
/// in tests/round_trip.rs.
#[test]
fn catalogue_and_band_round_trip_through_json() {
    use rotorshunt::{Band, BandRequest, Catalogue, CatalogueRequest, Interval};
    let op = common::load("fig11-closed-2000.toml", &[]).operating_point().unwrap();
    let request = CatalogueRequest::builder().range(Interval::new(1100.0, 1350.0)).beta_max(0.5).level(0.3);
    let catalogue = op.catalogue(&request.build().unwrap()).unwrap();
    assert!(!catalogue.regions.is_empty());
    let back: Catalogue = serde_json::from_str(&serde_json::to_string(&catalogue).unwrap()).unwrap();
    assert_eq!(back, catalogue);
    let band = op.band(&BandRequest::builder().phi_op(1230.0).level(0.3).build().unwrap()).unwrap();
    assert!(band.band.is_some());
    let back: Band = serde_json::from_str(&serde_json::to_string(&band).unwrap()).unwrap();
    assert_eq!(back, band);
}
