//! `--set` of one key of a pair of alternatives replaces the other (issue 18): node or
//! position, inductance or tuning frequency, cp_s or k_eq2, a speed or its rpm form; a
//! file that gives both, or two `--set`s of both, are still refused. A study can sweep L
//! over a base file that tunes its branch by frequency.

use crate::common;
use common::{load, problem_path, rel, root};
use rotorshunt::analysis::floquet::FloquetSystem;
use rotorshunt::analysis::modes::whirl_modes_of;
use rotorshunt::analysis::regions::band;
use rotorshunt::analysis::{Interval, Rotor};
use rotorshunt::problem::{Location, Problem, ProblemErrorKind};
use std::process::Command;

fn set(name: &str, overrides: &[&str]) -> Result<Problem, rotorshunt::problem::ProblemError> {
    let o: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    Problem::from_path(problem_path(name), &o)
}

#[test]
fn a_position_replaces_the_files_node() {
    // paper-closed.toml places its disk by `node = 16`; 0.3 m is nearest node 27 of 64
    // elements of 0.7/64 m.
    let p = load("paper-closed.toml", &["disks[0].position=0.3"]);
    let h: f64 = 0.7 / 64.0;
    assert_eq!(p.model.disks[0].node, (0.3 / h).round() as usize);
    assert_eq!(p.model.disks[0].node, 27);
    assert_eq!((p.data.disks[0].node, p.data.disks[0].position), (None, Some(0.3)));
    // And back: a node replaces a position (the general form's supports).
    let p = load("stepped-bearing-ring.toml", &["bearings[0].node=5"]);
    assert_eq!(p.model.bearings[0].node, 5);
    let p = load("stepped-bearing-ring.toml", &["rings[0].node=27"]);
    assert_eq!(p.model.rings[0].node, 27);
}

#[test]
fn an_inductance_replaces_the_files_tuning_frequency() {
    let p = load("paper-closed.toml", &["circuit.branches[0].inductance=1.25"]);
    let b = &p.model.rings[0].circuit.branches[0];
    assert_eq!(b.inductance, 1.25);
    // The other branch keeps its tuning (2600 rad/s → 1.5615 H, Eq. 4).
    assert!(rel(p.model.rings[0].circuit.branches[1].inductance, 1.5615) < 1e-4);
    assert!(p.data.circuit.as_ref().unwrap().branches[0].tuning_frequency.is_none());
    // And the reverse on a file whose branch is given by L: the tuning frequency wins
    // (900 rad/s → the paper's L_1 = 0.9328 H, Eq. 4).
    let file = root().join("tests/fixtures/good/branch_inductance.toml");
    let p = Problem::from_path(&file, &["circuit.branches[0].tuning_frequency=900".into()]).unwrap();
    assert!(rel(p.model.rings[0].circuit.branches[0].inductance, 0.9328) < 1e-4);
}

#[test]
fn a_ring_cp_s_replaces_the_files_k_eq2_and_speed_rpm_the_speed() {
    let p = load("paper-closed.toml", &["ring.cp_s=1.35e-6"]);
    assert_eq!(p.model.rings[0].ring.cp_s, 1.35e-6);
    let p = load("two-rings-1-3.toml", &["rings[1].k_eq2=2.0e7"]);
    assert!(p.data.rings[1].cp_s.is_none());
    let p = load("paper-closed.toml", &["speed_rpm=9549.296585513721"]);
    assert!(rel(p.model.speed, 1000.0) < 1e-15);
}

#[test]
fn both_keys_of_a_pair_stay_refused() {
    // Two --sets of both keys: the user gave both, so nothing is replaced.
    let e = set("paper-closed.toml", &["disks[0].node=3", "disks[0].position=0.3"]).unwrap_err();
    assert_eq!(e.kind, ProblemErrorKind::BothGiven("node".into(), "position".into()));
    assert_eq!(e.location, Location::Override);
    let e =
        set("paper-closed.toml", &["circuit.branches[0].inductance=1.0", "circuit.branches[0].tuning_frequency=800"])
            .unwrap_err();
    assert_eq!(e.kind, ProblemErrorKind::BothGiven("inductance".into(), "tuning_frequency".into()));
    // A file that gives both is refused at its line, with or without an unrelated --set.
    let both = root().join("tests/fixtures/bad/disk_node_and_position.toml");
    for o in [vec![], vec!["speed=1000".to_string()]] {
        let e = Problem::from_path(&both, &o).unwrap_err();
        assert!(matches!(e.kind, ProblemErrorKind::BothGiven(..)), "{e}");
        assert!(matches!(e.location, Location::Line(_)), "{e}");
    }
}

#[test]
fn the_binary_takes_the_alternative_keys() {
    let run = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_rotorshunt")).args(args).current_dir(root()).output().expect("run")
    };
    let out = run(&["check", "problems/paper-closed.toml", "--set", "disks[0].position=0.3"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stdout).contains("disk 1: node 27 (x = 0.2953 m)"));
    let out = run(&["check", "problems/paper-closed.toml", "--set", "circuit.branches[0].inductance=1.4"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stdout).contains("branch 1: C_f = 5.0000e-6 F, L = 1.4000 H"));
}

#[test]
fn a_study_sweeps_the_inductance_over_a_base_tuned_by_frequency() {
    let out_dir = common::tmp("overrides-study");
    let out = Command::new(env!("CARGO_BIN_EXE_rotorshunt"))
        .args(["--quiet", "study", "tests/fixtures/study/sweep-inductance.toml", "--out"])
        .arg(&out_dir)
        .current_dir(root())
        .output()
        .expect("run");
    assert!(out.status.success(), "{}\n{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out_dir.join("summary/summary.json")).unwrap()).unwrap();
    let cases = summary["cases"].as_array().expect("cases");
    assert_eq!(cases.len(), 2);
    for c in cases {
        assert_eq!(c["status"], "ok", "{c}");
    }
    // L = 0.9328 H is the base's own tuning (900 rad/s, to 1e-4): its case is the base's
    // band around 1230 rad/s, asked of the library on the base file itself (no override,
    // no study) over the study's range; 1.4 H moves the regions.
    let base = load("fig11-closed-2000.toml", &[]);
    let l_base = base.model.rings[0].circuit.branches[0].inductance;
    assert!(rel(l_base, 0.9328) < 1e-4, "{l_base}");
    let rotor = Rotor::new(&base.model).unwrap();
    let fs = FloquetSystem::new(&rotor, &base.settings, base.model.speed).unwrap();
    let full = whirl_modes_of(&rotor, &base.settings, base.model.speed).unwrap();
    let window = Interval::new(1150.0, 1250.0);
    let own = band(&fs, &full, &base.regions, window, 1230.0, 0.3).unwrap().band.expect("1230 rad/s is stable at 0.3");
    let band_of =
        |c: &serde_json::Value| (c["metrics"]["band_lo"].as_f64().unwrap(), c["metrics"]["band_hi"].as_f64().unwrap());
    let (lo, hi) = band_of(&cases[0]);
    assert!((lo - own.lo).abs() < 0.2 && (hi - own.hi).abs() < 0.2, "case [{lo}, {hi}], base {own:?}");
    assert_ne!(band_of(&cases[1]), band_of(&cases[0]));
}

#[test]
fn an_array_override_is_blamed_on_set_with_its_key() {
    // Issue 50, item 8: an array set by --set was blamed on a line of the file (the key's
    // own line, or its table's header when the file has no such key); scalars already
    // said --set. The key is the element that breaks the rule.
    for (given, key) in [
        ("design.phi_range=[8000.0, 100.0]", "design.phi_range[1]"),
        ("design.speeds=[-1.0]", "design.speeds[0]"),
        ("design.response.speeds=[-1.0, 5.0]", "design.response.speeds[0]"),
        ("design.speed_range=[-1.0, 5.0]", "design.speed_range[0]"),
    ] {
        let e = set("design-min-peak-at-speed.toml", &[given]).unwrap_err();
        assert_eq!((e.key.as_str(), e.location), (key, Location::Override), "{given}: {e}");
    }
    // The file's own array is still blamed at its line (design-min-peak-at-speed.toml, line 67).
    let text = std::fs::read_to_string(problem_path("design-min-peak-at-speed.toml")).unwrap();
    let text = text.replace("speeds = [250.0, 500.0]", "speeds = [-250.0, 500.0]");
    let e = Problem::from_text(&text, "f.toml", &[]).unwrap_err();
    assert_eq!((e.key.as_str(), e.location), ("design.response.speeds[0]", Location::Line(67)), "{e}");
    let out = Command::new(env!("CARGO_BIN_EXE_rotorshunt"))
        .args(["check", "problems/design-min-peak-at-speed.toml", "--set", "design.phi_range=[8000.0,100.0]"])
        .current_dir(root())
        .output()
        .expect("run");
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr).lines().next(),
        Some("error: problems/design-min-peak-at-speed.toml, --set: key `design.phi_range[1]`: must be above the range's low end, 8000 rad/s, found 100")
    );
}
