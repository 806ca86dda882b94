//! The general-form problems of issue 16 through the binary: a plain bearing and a closed
//! ring (chart, regions labelled by ring and branch, a verified design on that ring), two
//! rings on different circuits against the symmetric case, bad general-form input, and
//! every bundled problem run twice with identical outputs.

use crate::common;
use rotorshunt::problem::{Problem, ProblemErrorKind};
use std::path::Path;
use std::process::{Command, Output};

fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rotorshunt"))
        .args(args)
        .current_dir(common::root())
        .env_remove("RUST_BACKTRACE")
        .output()
        .expect("run rotorshunt")
}

fn json(args: &[&str]) -> serde_json::Value {
    let out = run(args);
    assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("{args:?}: {e}"))
}

fn scratch(name: &str) -> std::path::PathBuf {
    common::tmp(&format!("general-{name}"))
}

/// (label, order, start) of a `regions --json` catalogue.
fn regions(v: &serde_json::Value) -> Vec<(String, u64, f64)> {
    v["regions"]
        .as_array()
        .expect("regions")
        .iter()
        .map(|r| {
            (
                r["label"].as_str().expect("label").to_string(),
                r["order"].as_u64().expect("order"),
                r["start"].as_f64().expect("start"),
            )
        })
        .collect()
}

const STEPPED: &str = "problems/stepped-bearing-ring.toml";
const TWO_RINGS: &str = "problems/two-rings-1-3.toml";

#[test]
fn bearing_and_ring_rotor_charts_and_catalogues_with_ring_labels() {
    let dir = scratch("chart");
    let out = run(&["chart", STEPPED, "--phi", "1600:2600:50", "--beta", "0:0.4:0.1", "--out", dir.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let chart: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("chart.json")).expect("chart.json")).expect("chart JSON");
    let points = chart["chart"]["points"].as_array().expect("points");
    assert_eq!(points.len(), 21 * 5);
    assert!(points.iter().all(|p| p["status"] == "ok"), "every point computed");
    // The first-order electrical regions (r1@drive + b1 near 1754, f1 + r1@drive near
    // 2002 rad/s) are unstable at β = 0.1 on this grid; β = 0 is stable everywhere.
    let unstable = |beta: f64| points.iter().filter(|p| p["beta"] == beta && p["stable"] == false).count();
    assert_eq!(unstable(0.0), 0);
    assert!(unstable(0.1) > 0);
    for f in ["chart.svg", "chart.png", "growth.svg", "chart.csv"] {
        assert!(dir.join(f).exists(), "{f}");
    }
    let _ = std::fs::remove_dir_all(&dir);
    // The catalogue: its electrical regions say which ring and branch (r = branch 1).
    let cat = json(&["regions", STEPPED, "--phi", "1600:2600", "--beta-max", "0.5", "--level", "0.3", "--json"]);
    let all = regions(&cat);
    let electrical: Vec<_> = all.iter().filter(|r| r.0.contains('r')).collect();
    println!("{} regions, {} with an electrical mode: {electrical:?}", all.len(), electrical.len());
    assert!(!electrical.is_empty());
    assert!(electrical.iter().all(|r| r.0.contains("r1@drive")), "{electrical:?}");
    // The first-order ω_b1 + ω_r and ω_f1 + ω_r regions start near the sums of the full
    // model's whirls: within 2 %, the regions' Floquet analysis running on the M = 8
    // modal reduction (its whirls differ by up to 1.5 % here, docs/model.md).
    let modes = json(&["modes", STEPPED, "--json"]);
    let freq = |tag: &str| {
        modes["modes"]
            .as_array()
            .expect("modes")
            .iter()
            .find(|m| format!("{}{}", &m["whirl"].as_str().unwrap()[..1], m["label"].as_str().unwrap()) == tag)
            .and_then(|m| m["frequency"].as_f64())
            .unwrap_or_else(|| panic!("no mode {tag}"))
    };
    for (label, sum) in
        [("r1@drive+b1", freq("br1@drive") + freq("b1")), ("f1+r1@drive", freq("f1") + freq("fr1@drive"))]
    {
        let r = all.iter().find(|r| r.0 == label && r.1 == 1).unwrap_or_else(|| panic!("no {label} in {all:?}"));
        println!("{label}: start {:.2} rad/s, whirl sum {sum:.2} rad/s", r.2);
        assert!((r.2 - sum).abs() < 2e-2 * sum, "{label}: {} vs {sum}", r.2);
    }
}

#[test]
fn design_on_the_ring_branch_ends_verified() {
    let dir = scratch("design");
    // 2 starts of 8 iterations (the file asks 4 of 30): what is checked holds for whatever
    // design the run returns.
    let out = run(&[
        "design",
        STEPPED,
        "--set",
        "design.starts=2",
        "--set",
        "design.max_iterations=8",
        "--set",
        common::COARSE_CHARTS[0],
        "--set",
        common::COARSE_CHARTS[1],
        "--out",
        dir.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    let report: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("report.json")).expect("report.json")).expect("report JSON");
    let text = report.to_string();
    let stdout = String::from_utf8_lossy(&out.stdout);
    println!("{stdout}");
    assert!(stdout.contains("verification: passed"), "{stdout}");
    assert!(stdout.contains("ring drive branch 1 tuning_frequency"), "{stdout}");
    assert!(text.contains("\"improved\"") || text.contains("\"unchanged\""), "status");
    // The tuned problem loads and keeps the general form, its ring's circuit changed.
    let tuned = Problem::from_path(dir.join("tuned.toml"), &[]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(tuned.model.rings.len(), 1);
    assert_eq!(tuned.model.rings[0].name, "drive");
    assert_eq!(tuned.model.shaft.sections.len(), 3);
    let base = common::load("stepped-bearing-ring.toml", &[]);
    assert_ne!(tuned.model.rings[0].circuit, base.model.rings[0].circuit);
    assert_eq!(tuned.model.shaft, base.model.shaft);
    assert_eq!(tuned.model.bearings, base.model.bearings);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The two-ring problem with the right ring's circuit made the same as the left's (one
/// branch tuned to 900 rad/s): the symmetric case.
fn symmetric_text() -> String {
    let text = std::fs::read_to_string(common::problem_path("two-rings-1-3.toml")).expect("two-rings-1-3.toml");
    let s_branch = text.find("[[rings.circuit.branches]]    # s@right").expect("s branch");
    let load = text.find("[load]").expect("[load]");
    format!("{}{}", &text[..s_branch], &text[load..]).replace("reduced_modes = 10", "reduced_modes = 8")
}

#[test]
fn two_rings_on_different_circuits_have_more_electrical_modes_and_regions() {
    // Each closed branch adds a charge DOF to its ring, and each charge an electrical
    // whirl pair: 1 + 3 = 4 per direction with different circuits, 2 (r1, r2: the rings'
    // r modes in and out of phase) in the symmetric case. Identical circuits keep the
    // paper's labels; different ones name the ring.
    let sym_path =
        common::generated("two-rings-symmetric.toml", |p| std::fs::write(p, symmetric_text()).expect("write"));
    let sym_path = sym_path.to_str().expect("path");
    let labels = |v: &serde_json::Value| -> Vec<String> {
        let mut l: Vec<String> = v["modes"]
            .as_array()
            .expect("modes")
            .iter()
            .filter(|m| m["kind"] == "electrical" && m["whirl"] == "forward")
            .map(|m| m["label"].as_str().expect("label").to_string())
            .collect();
        l.sort();
        l
    };
    let different = json(&["modes", TWO_RINGS, "--json", "--count", "20"]);
    let symmetric = json(&["modes", sym_path, "--json", "--count", "20"]);
    assert_eq!(labels(&different), ["r1@left", "r1@right", "s1@right", "t1@right"]);
    assert_eq!(labels(&symmetric), ["r1", "r2"]);
    // The rotor modes hardly move; the electrical whirls of the t branch (tuned to 1600
    // rad/s) exist only with the different circuits, and so do the first-order regions at
    // ω_b1 + ω_t and ω_f1 + ω_t.
    let freq = |v: &serde_json::Value, tag: &str| {
        v["modes"]
            .as_array()
            .expect("modes")
            .iter()
            .find(|m| format!("{}{}", &m["whirl"].as_str().unwrap()[..1], m["label"].as_str().unwrap()) == tag)
            .and_then(|m| m["frequency"].as_f64())
    };
    // Table 3 of the paper (closed circuit, Ω = 2000 rad/s): 1: 398.5 / 300.1, 2: 1903.8 /
    // 1654.5 rad/s; its circuit differs, so within 0.25 %.
    for (tag, table3) in [("f1", 398.5), ("b1", 300.1), ("f2", 1903.8), ("b2", 1654.5)] {
        let w = freq(&different, tag).expect(tag);
        assert!(common::rel(w, table3) < 2.5e-3, "{tag}: {w} vs Table 3 {table3}");
    }
    let (b1, f1) = (freq(&different, "b1").expect("b1"), freq(&different, "f1").expect("f1"));
    assert!((b1 - freq(&symmetric, "b1").expect("b1")).abs() < 1e-2 * b1);
    let (bt, ft) = (freq(&different, "bt1@right").expect("bt1"), freq(&different, "ft1@right").expect("ft1"));
    let window = ["--phi", "1800:2100", "--beta-max", "0.5", "--level", "0.3", "--json"];
    let d = regions(&json(&[&["regions", TWO_RINGS][..], &window[..]].concat()));
    let s = regions(&json(&[&["regions", sym_path][..], &window[..]].concat()));
    println!("different circuits: {d:?}\nsymmetric: {s:?}");
    for (label, sum) in [("t1@right+b1", bt + b1), ("f1+t1@right", f1 + ft)] {
        let r = d.iter().find(|r| r.0 == label && r.1 == 1).unwrap_or_else(|| panic!("no {label}: {d:?}"));
        assert!((r.2 - sum).abs() < 1e-3 * sum, "{label} starts at {}, whirls sum to {sum}", r.2);
        assert!(
            !s.iter().any(|r| r.1 == 1 && (r.2 - sum).abs() < 5e-3 * sum),
            "the symmetric rotor has a first-order region near {sum}: {s:?}"
        );
    }
    assert!(s.iter().all(|r| !r.0.contains('@')), "{s:?}");
}

/// Whether an error kind is the one expected.
type KindTest = fn(&ProblemErrorKind) -> bool;

#[test]
fn general_form_errors_are_typed_with_line_and_key() {
    use ProblemErrorKind as K;
    let dir = common::root().join("tests/fixtures/bad");
    let cases: [(&str, KindTest, &str); 9] = [
        ("general_free_free", |k| matches!(k, K::RigidBody { supports: 0 }), "sections"),
        ("general_one_support", |k| matches!(k, K::RigidBody { supports: 1 }), "bearings[0]"),
        ("general_two_supports_one_node", |k| matches!(k, K::SupportsShareNode { node: 4, .. }), "rings[1].position"),
        ("general_inner_not_below_outer", |k| matches!(k, K::InnerNotBelowOuter { .. }), "sections[1].inner_diameter"),
        ("general_sections_zero_length", |k| matches!(k, K::ShaftLength { .. }), "sections"),
        ("general_section_length_zero", |k| matches!(k, K::NotPositive(_)), "sections[0].length"),
        ("general_disk_off_shaft", |k| matches!(k, K::DiskOffShaft { .. }), "disks[0].position"),
        ("general_unknown_material", |k| matches!(k, K::UnknownName { .. }), "sections[1].material"),
        ("general_mixed_shaft_sections", |k| matches!(k, K::MixedForms(..)), "sections"),
    ];
    for (name, kind, key) in cases {
        let path = dir.join(format!("{name}.toml"));
        let e = Problem::from_path(&path, &[]).expect_err(name);
        assert!(kind(&e.kind), "{name}: {e}");
        assert_eq!(e.key, key, "{name}: {e}");
        assert!(e.line().is_some(), "{name}: no line: {e}");
        let out = run(&["check", path.to_str().unwrap()]);
        assert_eq!(out.status.code(), Some(2), "{name}");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!stderr.contains("panicked"), "{name}: {stderr}");
        assert!(stderr.contains(&format!("line {}: key `{key}`", e.line().unwrap())), "{name}: {stderr}");
    }
    // Design variables on rings with different circuits must name the ring.
    let two = std::fs::read_to_string(common::problem_path("two-rings-1-3.toml")).expect("two-rings");
    let design = |ring: &str| {
        format!(
            "{two}\n[design]\nobjective = \"widest-stable-band\"\nlevel = 0.3\nphi_op = 1230.0\n\n[[design.variables]]\n{ring}branch = 1\nparameter = \"resistance\"\nmin = 0.0\nmax = 20.0\n"
        )
    };
    let e = Problem::from_text(&design(""), "d.toml", &[]).expect_err("ring required");
    assert_eq!(e.key, "design.variables[0].ring");
    assert!(e.to_string().contains("the rings' circuits differ"), "{e}");
    assert!(e.line().is_some(), "{e}");
    let e = Problem::from_text(&design("ring = \"middle\"\n"), "d.toml", &[]).expect_err("unknown ring");
    assert!(matches!(e.kind, K::UnknownName { .. }), "{e}");
    assert!(e.to_string().contains("unknown ring `middle` (the file defines: left, right)"), "{e}");
    let ok = Problem::from_text(&design("ring = \"right\"\n"), "d.toml", &[]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(ok.design.expect("design").variables[0].ring, Some(1));
    // Branch 3 exists on the right ring only.
    let e = Problem::from_text(&design("ring = \"left\"\n").replace("branch = 1", "branch = 3"), "d.toml", &[])
        .expect_err("no branch 3 on the left");
    assert_eq!(e.key, "design.variables[0].branch");
    // `--set` reaches a ring's branch, and a bad value there is blamed on the command line.
    let p = common::load("two-rings-1-3.toml", &["rings[1].circuit.branches[2].resistance=50"]);
    assert_eq!(p.model.rings[1].circuit.branches[2].resistance, 50.0);
    let o = vec!["rings[1].circuit.branches[2].resistance=-1".to_string()];
    let e = Problem::from_path(common::problem_path("two-rings-1-3.toml"), &o).expect_err("negative R");
    assert_eq!(e.key, "rings[1].circuit.branches[2].resistance");
    assert!(e.to_string().contains("--set"), "{e}");
    // A rotor left with one support is blamed at the bearing that lost its stiffness.
    let o = vec!["bearings[1].stiffness=0".to_string()];
    let e = Problem::from_path(common::problem_path("ross-rotor-example.toml"), &o).expect_err("one support");
    assert!(matches!(e.kind, K::RigidBody { supports: 1 }), "{e}");
    assert_eq!(e.key, "bearings[1].stiffness", "{e}");
    let p =
        common::load("stepped-bearing-ring.toml", &["sections[1].inner_diameter=0.03", "bearings[0].stiffness=2e7"]);
    assert_eq!(p.model.shaft.sections[1].inner_diameter, 0.03);
    assert_eq!(p.model.bearings[0].stiffness(), 2e7);
}

/// Every bundled problem through `check`, `modes --json`, `floquet --json` and a small
/// `chart`, twice: the outputs must be byte-identical (wall times excepted).
#[test]
fn every_problem_gives_the_same_outputs_twice() {
    let mut files: Vec<_> = std::fs::read_dir(common::root().join("problems"))
        .expect("problems/")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    assert!(files.len() >= 13, "{} problems", files.len());
    let dir = scratch("twice");
    let out_dir = dir.to_str().unwrap().to_string();
    let once = |f: &Path| -> Vec<Vec<u8>> {
        let f = f.to_str().unwrap();
        let mut outs = Vec::new();
        for args in [
            vec!["check", f],
            vec!["modes", f, "--json"],
            vec!["floquet", f, "--phi", "1230", "--beta", "0.3", "--json"],
            vec!["chart", f, "--phi", "1100:1400:100", "--beta", "0:0.3:0.15", "--out", &out_dir],
        ] {
            let o = run(&args);
            assert!(o.status.success(), "{args:?}: {}", String::from_utf8_lossy(&o.stderr));
            outs.push(o.stdout);
        }
        let chart = std::fs::read(dir.join("chart.json")).expect("chart.json");
        let text = String::from_utf8(chart).expect("UTF-8");
        outs.push(text.lines().filter(|l| !l.trim_start().starts_with("\"seconds\"")).collect::<String>().into_bytes());
        outs.push(std::fs::read(dir.join("chart.png")).expect("chart.png"));
        outs
    };
    for f in &files {
        let (a, b) = (once(f), once(f));
        assert!(a == b, "{}: outputs differ between two runs", f.display());
    }
    println!("{} problems, {} outputs each, identical twice", files.len(), 6);
    let _ = std::fs::remove_dir_all(&dir);
}
