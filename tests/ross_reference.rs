//! Against ROSS itself (issues 16 and 28): rotors saved by ROSS, imported with
//! `rotorshunt import-ross`, give ROSS's own `run_modal` frequencies, at rest and as
//! forward and backward whirls at two speeds. ROSS's results are the committed fixtures
//! `tests/fixtures/ross/*.modal.json` (made by `scripts/ross/make_fixtures.py`; no Python
//! here). ROSS's Rayleigh, Timoshenko and tapered elements are rotorshunt's (the script
//! checks their matrices), so the two agree to round-off; the acceptance is 0.05 %.
//!
//! Compared: ROSS's damped natural frequencies `wd` = Im λ of its lateral modes (axial
//! and torsional ones are not in a lateral model), split into forward and backward by
//! the fixture's `whirl_from_orbit`, against `rotorshunt modes --json`'s whirl
//! frequencies |Im λ| by whirl. At rest every lateral frequency appears twice in ROSS
//! (forward and backward coincide) and once per whirl in rotorshunt.

use crate::common;
use serde_json::Value;
use std::path::PathBuf;
use std::process::Command;

/// The acceptance of issue 16: 0.05 % relative to ROSS.
const ACCEPTANCE_RTOL: f64 = 5e-4;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rotorshunt"))
}

fn fixture(name: &str) -> PathBuf {
    common::root().join("tests/fixtures/ross").join(name)
}

/// `rotorshunt import-ross` of a fixture into `NAME` in this binary's temporary folder.
fn import(rotor: &str, speed: Option<f64>, name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rotorshunt-ross-reference-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join(name);
    let mut c = bin();
    c.arg("import-ross").arg(fixture(&format!("{rotor}.toml"))).arg("--out").arg(&out).arg("--force");
    if let Some(w) = speed {
        c.arg("--speed").arg(w.to_string());
    }
    let o = c.output().unwrap();
    assert!(o.status.success(), "import-ross {rotor}: {}", String::from_utf8_lossy(&o.stderr));
    out
}

/// Forward and backward whirl frequencies (rad/s, ascending) of `rotorshunt modes`.
fn whirls(file: &PathBuf, speed: f64, count: usize) -> (Vec<f64>, Vec<f64>) {
    let o = bin()
        .arg("modes")
        .arg(file)
        .args(["--speed", &speed.to_string(), "--count", &count.to_string(), "--json"])
        .output()
        .unwrap();
    assert!(o.status.success(), "modes {}: {}", file.display(), String::from_utf8_lossy(&o.stderr));
    let json: Value = serde_json::from_slice(&o.stdout).unwrap();
    let of = |whirl: &str| {
        let mut f: Vec<f64> = json["modes"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|m| m["whirl"] == whirl)
            .map(|m| m["frequency"].as_f64().unwrap())
            .collect();
        f.sort_by(f64::total_cmp);
        f
    };
    (of("forward"), of("backward"))
}

fn list(v: &Value) -> Vec<f64> {
    v.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect()
}

/// The largest relative deviation of `ours` from `ross` (both ascending), over ROSS's
/// values; `ours` must have at least as many.
fn deviation(what: &str, ours: &[f64], ross: &[f64]) -> f64 {
    assert!(ours.len() >= ross.len(), "{what}: {} whirls, ROSS has {}", ours.len(), ross.len());
    ours.iter().zip(ross).map(|(a, b)| common::rel(*a, *b)).fold(0.0, f64::max)
}

/// Compare one rotor at every speed of its modal fixture; with `import_at_speed` it is
/// imported at each speed (`--speed`: tabulated bearings), else once. Returns (speed,
/// forward count, backward count, max deviation) per speed.
fn compare(rotor: &str, import_at_speed: bool) -> Vec<(f64, usize, usize, f64)> {
    let modal: Value =
        serde_json::from_str(&std::fs::read_to_string(fixture(&format!("{rotor}.modal.json"))).unwrap()).unwrap();
    let once = (!import_at_speed).then(|| import(rotor, None, &format!("{rotor}.toml")));
    let mut rows = Vec::new();
    for r in modal["results"].as_array().unwrap() {
        let speed = r["speed"].as_f64().unwrap();
        let file = once.clone().unwrap_or_else(|| import(rotor, Some(speed), &format!("{rotor}-{speed}.toml")));
        let (ross_f, ross_b) = if speed == 0.0 {
            // Each lateral frequency twice: one of each pair, for both whirls.
            let pairs: Vec<f64> = list(&r["lateral_wd"]).into_iter().step_by(2).collect();
            (pairs.clone(), pairs)
        } else {
            (list(&r["lateral_forward_wd"]), list(&r["lateral_backward_wd"]))
        };
        assert!(ross_f.len() >= 4 && ross_b.len() >= 4, "{rotor} at {speed}: too few ROSS whirls");
        let (f, b) = whirls(&file, speed, ross_f.len().max(ross_b.len()));
        let dev = deviation(&format!("{rotor} forward at {speed}"), &f, &ross_f).max(deviation(
            &format!("{rotor} backward at {speed}"),
            &b,
            &ross_b,
        ));
        eprintln!(
            "ROSS {rotor}, Ω = {speed} rad/s: {} forward and {} backward whirls, max relative deviation {dev:.3e}",
            ross_f.len(),
            ross_b.len()
        );
        rows.push((speed, ross_f.len(), ross_b.len(), dev));
    }
    rows
}

fn assert_within(rotor: &str, rows: &[(f64, usize, usize, f64)], speeds: usize) {
    assert!(rows.len() >= speeds, "{rotor}: {} speeds", rows.len());
    assert_eq!(rows[0].0, 0.0, "{rotor}: the first speed is rest");
    for (speed, _, _, dev) in rows {
        assert!(*dev < ACCEPTANCE_RTOL, "{rotor} at {speed} rad/s: deviation {dev:.3e} from ROSS");
    }
}

#[test]
fn rotor_example_matches_ross_at_rest_and_two_speeds() {
    // ROSS's rotor_example() geometry: uniform shaft, two disks, end bearings.
    let rows = compare("rotor_example_rayleigh", false);
    assert_within("rotor_example_rayleigh", &rows, 3);
}

#[test]
fn stepped_hollow_rotor_matches_ross_at_rest_and_two_speeds() {
    // Four sections (one hollow titanium), an overhung disk, bearings at interior nodes
    // 2 and 11, one of them damped.
    let rows = compare("stepped_hollow", false);
    assert_within("stepped_hollow", &rows, 3);
}

#[test]
fn speed_dependent_bearings_match_ross_at_the_chosen_speed() {
    // Imported at each speed: 1000 rad/s is in the table, 750 rad/s between two points.
    let rows = compare("speed_dependent", true);
    assert_eq!(rows.iter().map(|r| r.0).collect::<Vec<_>>(), [1000.0, 750.0]);
    for (speed, _, _, dev) in rows {
        assert!(dev < ACCEPTANCE_RTOL, "at {speed} rad/s: deviation {dev:.3e} from ROSS");
    }
}

#[test]
fn timoshenko_rotor_example_matches_ross_at_rest_and_two_speeds() {
    // ROSS's default elements (shear_effects = true, Cowper's κ) on rotor_example's
    // geometry and isotropic bearings: rotorshunt's Timoshenko elements are ROSS's (the
    // script checks ROSS's against the integral over Nelson's shape functions).
    let rows = compare("rotor_example_timoshenko", false);
    assert_within("rotor_example_timoshenko", &rows, 3);
}

#[test]
fn tapered_timoshenko_rotor_matches_ross_at_rest_and_two_speeds() {
    // A bulge of two tapered elements and a tapered bore with ROSS's hutchinson κ.
    let rows = compare("tapered", false);
    assert_within("tapered", &rows, 3);
}

#[test]
fn held_out_tapered_timoshenko_rotor_matches_ross() {
    // Written into scripts/ross/make_fixtures.py before this comparison existed, and not
    // looked at while the Timoshenko and taper code was written: three tapered elements
    // (one of both diameters, with hutchinson κ), two materials, hollow spans, two
    // overhung disks and damped bearings at interior nodes.
    let rows = compare("held_out", false);
    assert_within("held_out", &rows, 3);
}

#[test]
fn concentric_layers_match_ross_at_rest_and_two_speeds() {
    // rotor_example_timoshenko with sleeves (elements of one n): a stiffless one over two
    // elements, a Rayleigh steel one, a tapered one.
    let rows = compare("layered", false);
    assert_within("layered", &rows, 3);
}

#[test]
fn compressor_shaft_matches_ross_at_rest_and_two_speeds() {
    // ROSS's compressor example's 91 elements (36 concentric layers) and 7 disks, on
    // isotropic bearings at its bearings' nodes (its own bearings and seals are
    // anisotropic and cross-coupled).
    let rows = compare("compressor_shaft", false);
    assert_within("compressor_shaft", &rows, 3);
}

/// The unbalance acceptance of issue 28: 0.5 % of ROSS's amplitude.
const UNBALANCE_RTOL: f64 = 5e-3;

/// Phases of the undamped rotor's response are 0 or π in both codes; a deviation beyond
/// round-off would be a sign or convention error (rad).
const PHASE_TOL: f64 = 1e-6;

#[test]
fn timoshenko_unbalance_response_matches_ross() {
    // ROSS's run_unbalance_response of rotor_example_timoshenko, 1e-3 kg·m on the disk at
    // node 2, against rotorshunt's with that disk's eccentricity 1e-3 kg·m / m. An
    // isotropic rotor under a forward force whirls in circles: x = Re(U e^{jΩt}) and
    // y = Im(U e^{jΩt}) of rotorshunt's u = v + jw, so |X| = |Y| = |U|, arg X = arg U and
    // arg Y = arg U − π/2.
    use rotorshunt::analysis::unbalance::{node_probe, unbalance_response};
    let fixture_json: Value =
        serde_json::from_str(&std::fs::read_to_string(fixture("rotor_example_timoshenko.unbalance.json")).unwrap())
            .unwrap();
    let file = import("rotor_example_timoshenko", None, "rotor_example_timoshenko.toml");
    let base = rotorshunt::problem::Problem::from_path(&file, &[]).unwrap();
    let unbalance = &fixture_json["unbalance"];
    let node = unbalance["node"].as_u64().unwrap() as usize;
    let disk = base.model.disks.iter().position(|d| d.node == node).expect("a disk at the unbalance's node");
    let e = unbalance["magnitude"].as_f64().unwrap() / base.model.disks[disk].mass;
    assert_eq!(unbalance["phase"].as_f64(), Some(0.0));
    let p = rotorshunt::problem::Problem::from_path(&file, &[format!("disks[{disk}].eccentricity={e:e}")]).unwrap();
    let rotor = rotorshunt::analysis::Rotor::new(&p.model).unwrap();
    let speeds = list(&fixture_json["speeds"]);
    let records = fixture_json["nodes"].as_array().unwrap();
    let probes: Vec<_> =
        records.iter().map(|r| node_probe(&rotor.system.dofs, r["node"].as_u64().unwrap() as usize).unwrap()).collect();
    let ours = unbalance_response(&rotor, &speeds, &probes, &rotorshunt::progress::Silent).unwrap();
    let wrap = |a: f64| (a + std::f64::consts::PI).rem_euclid(2.0 * std::f64::consts::PI) - std::f64::consts::PI;
    for (r, response) in records.iter().zip(&ours.probes) {
        let (mut amplitude, mut phase) = (0.0_f64, 0.0_f64);
        for (axis, shift) in [("x", 0.0), ("y", -std::f64::consts::FRAC_PI_2)] {
            let amp = list(&r[format!("{axis}_amplitude").as_str()]);
            let ph = list(&r[format!("{axis}_phase").as_str()]);
            for i in 0..speeds.len() {
                amplitude = amplitude.max(common::rel(response.amplitude[i], amp[i]));
                phase = phase.max(wrap(response.phase[i] + shift - ph[i]).abs());
            }
        }
        eprintln!(
            "ROSS unbalance, node {}: {} speeds, largest relative amplitude deviation {amplitude:.3e} (x and y), phase {phase:.3e} rad",
            r["node"],
            speeds.len()
        );
        assert!(amplitude < UNBALANCE_RTOL, "node {}: amplitude deviation {amplitude:.3e}", r["node"]);
        assert!(phase < PHASE_TOL, "node {}: phase deviation {phase:.3e} rad", r["node"]);
    }
}

#[test]
fn the_catalogue_rotor_is_the_imported_rotor_example() {
    // problems/ross-rotor-example.toml is `import-ross` of the fixture, unedited, so the
    // comparison above is its check (expected values: problems/README.md).
    let name = "tests/fixtures/ross/rotor_example_rayleigh.toml";
    let text = std::fs::read_to_string(common::root().join(name)).unwrap();
    let import = rotorshunt::import::ross::import_text(&text, name, Default::default()).unwrap();
    let fresh: toml::Table = toml::from_str(&import.text).unwrap();
    let catalogue: toml::Table =
        toml::from_str(&std::fs::read_to_string(common::problem_path("ross-rotor-example.toml")).unwrap()).unwrap();
    assert_eq!(catalogue, fresh);
    common::load("ross-rotor-example.toml", &[]);
}
