//! `rotorshunt import-ross` on the ROSS fixtures (`tests/fixtures/ross/`, made by
//! `scripts/ross/make_fixtures.py`; no Python here): every refusal names the right
//! element, and the converted files hold the values of ROSS's own files, read here
//! straight from ROSS's JSON.

mod common;
use rotorshunt::import::ross::{import_path, ElementRef, Options, Refusal, RossErrorKind};
use rotorshunt::Error;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

fn fixture(name: &str) -> PathBuf {
    common::root().join("tests/fixtures/ross").join(name)
}

fn refusal(path: &Path, speed: Option<f64>) -> (Option<ElementRef>, Refusal) {
    match import_path(path, Options { speed }) {
        Err(Error::Ross(e)) => match e.kind {
            RossErrorKind::Refused { element, reason } => (element.map(|e| *e), *reason),
            other => panic!("{}: not a refusal: {other}", path.display()),
        },
        Err(e) => panic!("{}: not a ROSS error: {e}", path.display()),
        Ok(_) => panic!("{}: imported", path.display()),
    }
}

fn element(class: &str, tag: &str, n: i64) -> Option<ElementRef> {
    Some(ElementRef { class: class.into(), tag: tag.into(), n: Some(n) })
}

/// A fixture, the element it must name, and a test of the reason.
type Case = (&'static str, Option<ElementRef>, fn(&Refusal) -> bool);

#[test]
fn every_refusal_fixture_names_its_element_and_reason() {
    let cases: [Case; 8] = [
        // ROSS's default: every element is Timoshenko; the first by n is named.
        ("refuse_timoshenko.toml", element("ShaftElement", "Shaft Element 0", 0), |r| matches!(r, Refusal::Timoshenko)),
        (
            "refuse_tapered_outer.toml",
            element("ShaftElement", "Refused tapered", 3),
            |r| matches!(r, Refusal::Tapered { left_key: "odl", left, right_key: "odr", right } if *left == 0.05 && *right == 0.06),
        ),
        (
            "refuse_tapered_bore.toml",
            element("ShaftElement", "Refused bore", 3),
            |r| matches!(r, Refusal::Tapered { left_key: "idl", left, right_key: "idr", right } if *left == 0.01 && *right == 0.02),
        ),
        (
            "refuse_anisotropic.toml",
            element("BearingElement", "Refused anisotropic", 6),
            |r| matches!(r, Refusal::Anisotropic { x_key: "kxx", x, y_key: "kyy", y, .. } if *x == 1e6 && *y == 0.8e6),
        ),
        (
            "refuse_anisotropic_damping.toml",
            element("BearingElement", "Refused anisotropic damping", 6),
            |r| matches!(r, Refusal::Anisotropic { x_key: "cxx", x, y_key: "cyy", y, .. } if *x == 100.0 && *y == 200.0),
        ),
        (
            "refuse_cross_coupled.toml",
            element("BearingElement", "Refused cross-coupled", 6),
            |r| matches!(r, Refusal::CrossCoupled { key: "kxy", value, .. } if *value == 2e5),
        ),
        ("refuse_linked_bearing.toml", element("BearingElement", "Refused linked", 6), |r| {
            matches!(r, Refusal::Linked(7))
        }),
        (
            "speed_dependent.toml",
            element("BearingElement", "Bearing 0", 0),
            |r| matches!(r, Refusal::SpeedDependent { points: 4, lo, hi } if *lo == 0.0 && *hi == 1500.0),
        ),
    ];
    for (name, expected, reason) in cases {
        let (found, why) = refusal(&fixture(name), None);
        assert_eq!(found, expected, "{name}: {why}");
        assert!(reason(&why), "{name}: wrong reason: {why}");
    }
    // Hand-edited (see the file's header): a free-free rotor is the rotor's refusal.
    let (found, why) = refusal(&fixture("refuse_no_bearing.toml"), None);
    assert_eq!((found, why), (None, Refusal::NoBearing));
    // A speed outside the table.
    let (found, why) = refusal(&fixture("speed_dependent.toml"), Some(2000.0));
    assert_eq!(found, element("BearingElement", "Bearing 0", 0));
    assert!(matches!(why, Refusal::OutsideTable { speed, .. } if speed == 2000.0), "{why}");
}

#[test]
fn other_element_classes_are_refused_by_class() {
    // ROSS saves a seal under its own class: the rotor example's second bearing as one.
    let text = std::fs::read_to_string(fixture("rotor_example_rayleigh.toml")).unwrap();
    assert!(text.contains("[\"BearingElement_Bearing 1\"]"));
    let text = text.replace("[\"BearingElement_Bearing 1\"]", "[\"SealElement_Seal 1\"]");
    let e = rotorshunt::import::ross::import_text(&text, "seal.toml", Options::default()).unwrap_err();
    let RossErrorKind::Refused { element: found, reason } = e.kind else { panic!("{e}") };
    assert_eq!(found.map(|e| *e), element("SealElement", "Seal 1", 6));
    assert_eq!(*reason, Refusal::UnknownClass("SealElement".into()));
}

/// ROSS's JSON file: its element tables by class prefix.
fn ross_json(name: &str) -> Vec<(String, Value)> {
    let text = std::fs::read_to_string(fixture(name)).unwrap();
    let doc: Value = serde_json::from_str(&text).unwrap();
    doc.as_object()
        .unwrap()
        .iter()
        .filter(|(k, _)| k.contains('_') && !k.starts_with('_'))
        .map(|(k, v)| (k.clone(), v.clone()))
        .collect()
}

fn f(v: &Value, key: &str) -> f64 {
    v[key].as_f64().unwrap_or_else(|| panic!("{key} in {v}"))
}

/// The first value of a ROSS bearing coefficient array.
fn coef(v: &Value, key: &str) -> f64 {
    v[key][0].as_f64().unwrap_or_else(|| panic!("{key} in {v}"))
}

fn imported(name: &str, speed: Option<f64>) -> toml::Table {
    let import = import_path(&fixture(name), Options { speed }).unwrap_or_else(|e| panic!("{name}: {e}"));
    toml::from_str(&import.text).unwrap_or_else(|e| panic!("{name}: the output is not TOML: {e}\n{}", import.text))
}

fn array<'a>(t: &'a toml::Table, key: &str) -> &'a Vec<toml::Value> {
    t.get(key).and_then(toml::Value::as_array).unwrap_or_else(|| panic!("no [[{key}]]"))
}

fn num(v: &toml::Value, key: &str) -> f64 {
    match &v[key] {
        toml::Value::Float(x) => *x,
        toml::Value::Integer(i) => *i as f64,
        other => panic!("{key} = {other}"),
    }
}

fn int(v: &toml::Value, key: &str) -> i64 {
    v[key].as_integer().unwrap_or_else(|| panic!("{key} in {v}"))
}

/// Check the converted file of `toml_name` against ROSS's JSON `json_name`.
fn check_against_ross(json_name: &str, toml_name: &str) {
    let ross = ross_json(json_name);
    let out = imported(toml_name, None);
    assert_eq!(out["version"].as_integer(), Some(1));
    assert_eq!(num(&out["load"], "alpha"), 0.0);
    assert_eq!(num(&toml::Value::Table(out.clone()), "speed"), 0.0);
    // Shaft: the sections, expanded into elements, are ROSS's elements in order of n.
    let mut shafts: Vec<&Value> = ross.iter().filter(|(k, _)| k.starts_with("ShaftElement_")).map(|(_, v)| v).collect();
    shafts.sort_by_key(|v| v["n"].as_i64().unwrap());
    let materials = array(&out, "materials");
    let mut expanded = Vec::new();
    for s in array(&out, "sections") {
        let name = s["material"].as_str().unwrap();
        let m = materials.iter().find(|m| m["name"].as_str() == Some(name)).expect("material defined");
        let n = int(s, "elements");
        for _ in 0..n {
            let l = num(s, "length") / n as f64;
            let d = (num(s, "outer_diameter"), num(s, "inner_diameter"));
            expanded.push((l, d, num(m, "youngs_modulus"), num(m, "density")));
        }
    }
    assert_eq!(expanded.len(), shafts.len(), "{toml_name}: element count");
    for (s, (l, (od, id), e, rho)) in shafts.iter().zip(&expanded) {
        assert!(common::rel(*l, f(s, "L")) < 1e-12, "{toml_name}: L {l} vs {}", f(s, "L"));
        assert_eq!((*od, *id), (f(s, "odl"), f(s, "idl")), "{toml_name}: diameters of {}", s["tag"]);
        assert_eq!((*od, *id), (f(s, "odr"), f(s, "idr")));
        assert_eq!((*e, *rho), (f(&s["material"], "E"), f(&s["material"], "rho")));
    }
    // Disks and bearings: the same sets as ROSS's, value for value.
    let key = |v: (i64, f64, f64, f64)| (v.0, v.1.to_bits(), v.2.to_bits(), v.3.to_bits());
    let mut ross_disks: Vec<_> = ross
        .iter()
        .filter(|(k, _)| k.starts_with("DiskElement_"))
        .map(|(_, d)| key((d["n"].as_i64().unwrap(), f(d, "m"), f(d, "Ip"), f(d, "Id"))))
        .collect();
    let mut disks: Vec<_> = array(&out, "disks")
        .iter()
        .map(|d| key((int(d, "node"), num(d, "mass"), num(d, "polar_inertia"), num(d, "diametral_inertia"))))
        .collect();
    ross_disks.sort();
    disks.sort();
    assert_eq!(disks, ross_disks, "{toml_name}: disks");
    let mut ross_bearings: Vec<_> = ross
        .iter()
        .filter(|(k, _)| k.starts_with("BearingElement_"))
        .map(|(_, b)| key((b["n"].as_i64().unwrap(), coef(b, "kxx"), coef(b, "cxx"), coef(b, "mxx"))))
        .collect();
    let mut bearings: Vec<_> = array(&out, "bearings")
        .iter()
        .map(|b| key((int(b, "node"), num(b, "stiffness"), num(b, "damping"), num(b, "mass"))))
        .collect();
    ross_bearings.sort();
    bearings.sort();
    assert_eq!(bearings, ross_bearings, "{toml_name}: bearings");
}

#[test]
fn converted_files_hold_the_values_of_ross_files() {
    check_against_ross("rotor_example_rayleigh.json", "rotor_example_rayleigh.toml");
    check_against_ross("stepped_hollow.json", "stepped_hollow.toml");
    // Runs of equal elements are one section each: 1 for the uniform rotor, 4 for the
    // stepped one (2, 6, 3 and 2 elements; docs/ross-format.md).
    let counts = |name| array(&imported(name, None), "sections").iter().map(|s| int(s, "elements")).collect::<Vec<_>>();
    assert_eq!(counts("rotor_example_rayleigh.toml"), [6]);
    assert_eq!(counts("stepped_hollow.toml"), [2, 6, 3, 2]);
    assert_eq!(array(&imported("stepped_hollow.toml", None), "materials").len(), 2);
}

#[test]
fn json_and_toml_of_one_rotor_give_the_same_problem() {
    for rotor in ["rotor_example_rayleigh", "stepped_hollow"] {
        let mut a = imported(&format!("{rotor}.toml"), None);
        let mut b = imported(&format!("{rotor}.json"), None);
        for t in [&mut a, &mut b] {
            t.remove("source");
        }
        assert_eq!(a, b, "{rotor}");
    }
}

#[test]
fn tabulated_bearings_are_evaluated_at_the_chosen_speed() {
    // The fixture's table is k = 1e6 + 200·ω N/m and c = 100 + 0.1·ω N·s/m
    // (docs/ross-format.md): at a tabulated speed and between two.
    for (speed, k, c) in [(1000.0, 1.2e6, 200.0), (750.0, 1.0e6 + 200.0 * 750.0, 100.0 + 0.1 * 750.0)] {
        let out = imported("speed_dependent.toml", Some(speed));
        assert_eq!(num(&toml::Value::Table(out.clone()), "speed"), speed);
        for b in array(&out, "bearings") {
            assert!(common::rel(num(b, "stiffness"), k) < 1e-12, "{speed}: k = {}", num(b, "stiffness"));
            assert!(common::rel(num(b, "damping"), c) < 1e-12, "{speed}: c = {}", num(b, "damping"));
        }
    }
}

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rotorshunt"))
}

#[test]
fn an_existing_out_file_is_kept_unless_force() {
    let dir = std::env::temp_dir().join(format!("rotorshunt-ross-import-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("existing.toml");
    std::fs::write(&out, "keep me\n").unwrap();
    let source = fixture("rotor_example_rayleigh.toml");
    let run = |force: bool| {
        let mut c = bin();
        c.arg("import-ross").arg(&source).arg("--out").arg(&out);
        if force {
            c.arg("--force");
        }
        c.output().unwrap()
    };
    let refused = run(false);
    assert_eq!(refused.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&refused.stderr).contains("exists and is not replaced"));
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "keep me\n");
    let forced = run(true);
    assert_eq!(forced.status.code(), Some(0), "{}", String::from_utf8_lossy(&forced.stderr));
    assert!(std::fs::read_to_string(&out).unwrap().contains("[[sections]]"));
    // A refused import writes nothing, even with --force.
    std::fs::write(&out, "keep me\n").unwrap();
    let mut c = bin();
    c.arg("import-ross").arg(fixture("refuse_timoshenko.toml")).arg("--out").arg(&out).arg("--force");
    let o = c.output().unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "keep me\n");
}

#[test]
fn mutated_ross_files_never_panic() {
    // Each line of each fixture deleted, or its value replaced by a bad one: the import
    // returns a result or a typed error (a panic fails the test). Values that ROSS never
    // writes but TOML allows (nan, inf, negative numbers, strings, arrays) included.
    let replacements = ["-1.0", "nan", "inf", "0", "\"x\"", "[]", "[ 1.0, 2.0,]", "true", "1e308"];
    let mut runs = 0;
    let mut refused = 0;
    for name in
        ["rotor_example_rayleigh.toml", "stepped_hollow.toml", "speed_dependent.toml", "refuse_linked_bearing.toml"]
    {
        let text = std::fs::read_to_string(fixture(name)).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        for i in 0..lines.len() {
            let mut variants =
                vec![lines.iter().enumerate().filter(|(j, _)| *j != i).map(|(_, l)| *l).collect::<Vec<_>>().join("\n")];
            if let Some((key, _)) = lines[i].split_once(" = ") {
                for r in replacements {
                    let mut edited = lines.clone();
                    let line = format!("{key} = {r}");
                    edited[i] = &line;
                    variants.push(edited.join("\n"));
                }
            }
            for v in variants {
                for speed in [None, Some(750.0)] {
                    runs += 1;
                    if rotorshunt::import::ross::import_text(&v, name, Options { speed }).is_err() {
                        refused += 1;
                    }
                }
            }
        }
    }
    assert!(runs > 5000 && refused > runs / 4, "{runs} runs, {refused} refused");
}

#[test]
fn a_rotor_the_general_form_refuses_is_not_written() {
    // The rotor example on its left bearing only: a rigid-body mode remains.
    let text = std::fs::read_to_string(fixture("rotor_example_rayleigh.toml")).unwrap();
    let start = text.find("[\"BearingElement_Bearing 1\"]").unwrap();
    let end = start + text[start..].find("\n\n").unwrap();
    let dir = std::env::temp_dir().join(format!("rotorshunt-ross-import-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let source = dir.join("one_bearing.toml");
    std::fs::write(&source, format!("{}{}", &text[..start], &text[end..])).unwrap();
    let out = dir.join("one_bearing.problem.toml");
    let _ = std::fs::remove_file(&out);
    let e = rotorshunt::commands::import_ross_cmd(&source, &out, None, false).unwrap_err();
    let Error::Problem(p) = &e else { panic!("{e}") };
    assert!(matches!(p.kind, rotorshunt::problem::ProblemErrorKind::RigidBody { .. }), "{e}");
    assert!(!out.exists());
}
