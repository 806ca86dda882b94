//! `rotorshunt import-ross` on the ROSS fixtures (`tests/fixtures/ross/`, made by
//! `scripts/ross/make_fixtures.py`; no Python here): every refusal names the right
//! element, and the converted files hold the values of ROSS's own files, read here
//! straight from ROSS's JSON.

use crate::common;
use rotorshunt::import::ross::{import_path, ElementRef, ImportError, Options, Refusal, RossErrorKind};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

fn fixture(name: &str) -> PathBuf {
    common::root().join("tests/fixtures/ross").join(name)
}

/// Every refusal of a file: (element, reason), in the order of the message.
fn refusals(path: &Path) -> Vec<(Option<ElementRef>, Refusal)> {
    match import_path(path, Options::default()) {
        Err(ImportError::Ross(e)) => match e.kind {
            RossErrorKind::Refused { element, reason, more } => std::iter::once((element.map(|e| *e), *reason))
                .chain(more.iter().map(|r| (r.element.clone().map(|e| *e), (*r.reason).clone())))
                .collect(),
            other => panic!("{}: not a refusal: {other}", path.display()),
        },
        Err(e) => panic!("{}: not a ROSS error: {e}", path.display()),
        Ok(_) => panic!("{}: imported", path.display()),
    }
}

/// The line of `["<class>_<tag>"]` in a fixture, found here by reading its text.
fn header_line(name: &str, class: &str, tag: &str) -> Option<usize> {
    let text = std::fs::read_to_string(fixture(name)).unwrap();
    let header = format!("[\"{class}_{tag}\"]");
    text.lines().position(|l| l.trim() == header).map(|i| i + 1)
}

fn element(name: &str, class: &str, tag: &str, n: i64) -> Option<ElementRef> {
    let line = header_line(name, class, tag);
    assert!(line.is_some(), "{name}: no table {class}_{tag}");
    Some(ElementRef { class: class.into(), tag: tag.into(), n: Some(n), line })
}

#[test]
fn every_refusal_of_a_file_is_listed_with_its_element_and_line() {
    // refuse_several (made by ROSS): five refusals, in the order shaft elements, point
    // masses, bearings.
    let name = "refuse_several.toml";
    let found = refusals(&fixture(name));
    let elements: Vec<_> = found.iter().map(|(e, _)| e.clone()).collect();
    assert_eq!(
        elements,
        [
            element(name, "ShaftElement", "Refused damped", 2),
            element(name, "ShaftElement", "Refused no rotary inertia", 4),
            element(name, "PointMass", "Refused pedestal", 7),
            element(name, "BearingElement", "Refused linked", 6),
            element(name, "BearingElement", "Refused pedestal support", 7),
        ]
    );
    assert!(matches!(found[0].1, Refusal::ShaftDamping { key: "alpha", value } if value == 2.0), "{}", found[0].1);
    assert_eq!(found[1].1, Refusal::EffectOff("rotary_inertia"));
    assert_eq!(found[2].1, Refusal::Pedestal { node: 7, last: 6 });
    assert_eq!(found[3].1, Refusal::Linked(7));
    assert_eq!(found[4].1, Refusal::NodeOffShaft { node: 7, last: 6 });
    // The command line prints each on its own `error:` line, and exits 2.
    let o = bin()
        .arg("import-ross")
        .arg(fixture(name))
        .arg("--out")
        .arg(common::tmp("ross-import-several").join("several.toml"))
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(stderr.lines().filter(|l| l.starts_with("error: ")).count(), 5, "{stderr}");
    // A magnetic bearing (saved by ROSS under BearingElement with its controller).
    let name = "refuse_magnetic.toml";
    assert_eq!(refusals(&fixture(name)), [(element(name, "BearingElement", "Refused magnetic", 6), Refusal::Magnetic)]);
    // A bearing on a pedestal: the bearing, the pedestal and the pedestal's bearing.
    let name = "refuse_linked_bearing.toml";
    let found: Vec<_> = refusals(&fixture(name)).into_iter().map(|(_, r)| r).collect();
    assert_eq!(
        found,
        [Refusal::Pedestal { node: 7, last: 6 }, Refusal::Linked(7), Refusal::NodeOffShaft { node: 7, last: 6 }]
    );
    // Hand-edited (see the file's header): a free-free rotor is the rotor's refusal.
    assert_eq!(refusals(&fixture("refuse_no_bearing.toml")), [(None, Refusal::NoBearing)]);
    // Hand-edited: a negative kxx on one bearing and a damping matrix [[0, 500], [0, 0]]
    // N·s/m on the other, whose symmetric part has the eigenvalue −250 N·s/m.
    let name = "refuse_coefficients.toml";
    let found = refusals(&fixture(name));
    assert_eq!(found.len(), 2);
    assert_eq!(found[0].0, element(name, "BearingElement", "Bearing 0", 0));
    assert_eq!(found[0].1, Refusal::NegativeStiffness { key: "kxx", value: -1e6, frequency: None });
    assert_eq!(found[1].0, element(name, "BearingElement", "Bearing 1", 6));
    let Refusal::DampingNotSemiDefinite { c, eigenvalue, frequency: None } = found[1].1 else {
        panic!("{}", found[1].1)
    };
    assert_eq!((c, eigenvalue), ([[0.0, 500.0], [0.0, 0.0]], -250.0));
}

#[test]
fn seals_are_imported_as_seals_and_other_classes_are_refused_by_class() {
    // ROSS saves a seal under its own class: the rotor example's second bearing as one.
    let text = std::fs::read_to_string(fixture("rotor_example_rayleigh.toml")).unwrap();
    assert!(text.contains("[\"BearingElement_Bearing 1\"]"));
    let seal = text.replace("[\"BearingElement_Bearing 1\"]", "[\"SealElement_Seal 1\"]");
    let out = rotorshunt::import::ross::import_text(&seal, "seal.toml", Options::default()).unwrap();
    let t: toml::Table = toml::from_str(&out.text).unwrap();
    assert_eq!(array(&t, "bearings").len(), 1);
    assert_eq!(int(&array(&t, "seals")[0], "node"), 6);
    // A class the importer does not read is refused by its class, naming it.
    let other = text.replace("[\"BearingElement_Bearing 1\"]", "[\"LabyrinthSeal_Seal 1\"]");
    let e = rotorshunt::import::ross::import_text(&other, "other.toml", Options::default()).unwrap_err();
    let RossErrorKind::Refused { element: found, reason, more } = e.kind else { panic!("{e}") };
    let line = other.lines().position(|l| l == "[\"LabyrinthSeal_Seal 1\"]").map(|i| i + 1);
    let expected = ElementRef { class: "LabyrinthSeal".into(), tag: "Seal 1".into(), n: Some(6), line };
    assert_eq!(found.map(|e| *e), Some(expected));
    assert_eq!(*reason, Refusal::UnknownClass("LabyrinthSeal".into()));
    // And the rotor has one bearing left: that is the general form's refusal, not ROSS's.
    assert!(more.is_empty());
}

#[test]
fn anisotropic_and_cross_coupled_bearings_keep_rosss_coefficients() {
    // Fixtures once refused (their names say so), now imported with the eight
    // coefficients as ROSS saved them: kxx = 1e6, kyy = 0.8e6 N/m; cxx = 100, cyy = 200
    // N·s/m; kxy = 2e5, kyx = −2e5 N/m (docs/ross-format.md, the fixtures' table).
    let cases: [(&str, [f64; 8]); 3] = [
        ("refuse_anisotropic.toml", [1e6, 0.0, 0.0, 0.8e6, 0.0, 0.0, 0.0, 0.0]),
        ("refuse_anisotropic_damping.toml", [1e6, 0.0, 0.0, 1e6, 100.0, 0.0, 0.0, 200.0]),
        ("refuse_cross_coupled.toml", [1e6, 2e5, -2e5, 1e6, 0.0, 0.0, 0.0, 0.0]),
    ];
    for (name, want) in cases {
        let out = imported(name, None);
        let b = array(&out, "bearings").iter().find(|b| int(b, "node") == 6).expect("bearing at node 6");
        let got: Vec<f64> = rotorshunt::model::COEFFICIENT_NAMES.iter().map(|k| num(b, k)).collect();
        assert_eq!(got, want, "{name}");
        assert!(b.get("speeds").is_none(), "{name}: constant coefficients");
    }
}

/// ROSS's file (JSON, or TOML read here by the toml crate): its element tables by class
/// prefix.
fn ross_json(name: &str) -> Vec<(String, Value)> {
    let text = std::fs::read_to_string(fixture(name)).unwrap();
    let doc: Value =
        if name.ends_with(".json") { serde_json::from_str(&text).unwrap() } else { toml::from_str(&text).unwrap() };
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
    // Shaft: the sections and their layers, expanded into elements, are ROSS's elements
    // in order of n (the layers of one n innermost first).
    let mut shafts: Vec<&Value> = ross.iter().filter(|(k, _)| k.starts_with("ShaftElement_")).map(|(_, v)| v).collect();
    shafts.sort_by(|a, b| (a["n"].as_i64(), f(a, "idl")).partial_cmp(&(b["n"].as_i64(), f(b, "idl"))).unwrap());
    let materials = array(&out, "materials");
    let mut expanded = Vec::new();
    for s in array(&out, "sections") {
        let n = int(s, "elements");
        let l = num(s, "length") / n as f64;
        let tubes: Vec<&toml::Value> =
            std::iter::once(s).chain(s.get("layers").and_then(toml::Value::as_array).into_iter().flatten()).collect();
        let mut per_element = Vec::new();
        for t in tubes {
            let name = t["material"].as_str().unwrap();
            let m = materials.iter().find(|m| m["name"].as_str() == Some(name)).expect("material defined");
            let opt = |key: &str, default: f64| if t.get(key).is_some() { num(t, key) } else { default };
            let left = (num(t, "outer_diameter"), opt("inner_diameter", 0.0));
            let right = (opt("outer_diameter_right", left.0), opt("inner_diameter_right", left.1));
            // A tapered ROSS element is a section of its own (docs/ross-format.md).
            assert!(left == right || n == 1, "{toml_name}: a tapered section of {n} elements");
            let timoshenko = t.get("beam").and_then(toml::Value::as_str) == Some("timoshenko");
            let g = timoshenko.then(|| num(m, "shear_modulus"));
            let kappa = t.get("shear_coefficient").map(|_| num(t, "shear_coefficient"));
            per_element.push((l, left, right, num(m, "youngs_modulus"), num(m, "density"), g, kappa));
        }
        for _ in 0..n {
            expanded.extend(per_element.iter().cloned());
        }
    }
    assert_eq!(expanded.len(), shafts.len(), "{toml_name}: element count");
    for (s, (l, left, right, e, rho, g, kappa)) in shafts.iter().zip(&expanded) {
        assert!(common::rel(*l, f(s, "L")) < 1e-12, "{toml_name}: L {l} vs {}", f(s, "L"));
        assert_eq!(*left, (f(s, "odl"), f(s, "idl")), "{toml_name}: diameters of {}", s["tag"]);
        assert_eq!(*right, (f(s, "odr"), f(s, "idr")));
        assert_eq!((*e, *rho), (f(&s["material"], "E"), f(&s["material"], "rho")));
        let shear = s["shear_effects"].as_bool().unwrap();
        assert_eq!(g.is_some(), shear, "{toml_name}: beam theory of {}", s["tag"]);
        if let Some(g) = g {
            assert_eq!(*g, f(&s["material"], "G_s"));
            // Cowper's coefficient is rotorshunt's default; ROSS's hutchinson value is
            // written as a number (checked against ROSS's expression below).
            let method = s["shear_method_calc"].as_str().unwrap();
            assert_eq!(kappa.is_some(), method == "hutchinson", "{toml_name}: κ of {}", s["tag"]);
        }
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
fn timoshenko_and_tapered_elements_are_imported_with_their_shear_and_taper() {
    // rotor_example_timoshenko: ROSS's default elements, one uniform section; tapered:
    // a bulge of two tapered elements and a tapered bore with ROSS's hutchinson κ, each
    // tapered element a section of its own between the uniform runs.
    check_against_ross("rotor_example_timoshenko.toml", "rotor_example_timoshenko.toml");
    check_against_ross("tapered.toml", "tapered.toml");
    let counts = |name| array(&imported(name, None), "sections").iter().map(|s| int(s, "elements")).collect::<Vec<_>>();
    assert_eq!(counts("rotor_example_timoshenko.toml"), [6]);
    assert_eq!(counts("tapered.toml"), [1, 1, 1, 1, 1, 1]);
    // ROSS's hutchinson expression (shaft_element.py), written out here: r = 0.015/0.05
    // (the mean bore over the mean outer diameter), ν = E/(2G) − 1 of ROSS's steel.
    let out = imported("tapered.toml", None);
    let bore = &array(&out, "sections")[4];
    let (r, nu) = (0.015_f64 / 0.05, 2.11e11 / (2.0 * 8.12e10) - 1.0);
    let r12 = (1.0 + r * r).powi(2);
    let kappa = 6.0 * r12 * (1.0 + nu)
        / (r12 * (7.0 + 12.0 * nu + 4.0 * nu * nu) + 4.0 * r * r * (5.0 + 6.0 * nu + 2.0 * nu * nu));
    assert!(common::rel(num(bore, "shear_coefficient"), kappa) < 1e-15, "{bore}");
}

#[test]
fn concentric_layers_are_imported_as_layers_of_their_section() {
    // layered: core elements 0 to 5, a sleeve over 1 and 2 (one section of two elements
    // with one layer), a Rayleigh steel sleeve over 4, a tapered sleeve over 5 (a section
    // of its own). compressor_shaft: ROSS's compressor shaft, 91 elements on 55 nodes.
    check_against_ross("layered.toml", "layered.toml");
    check_against_ross("compressor_shaft.toml", "compressor_shaft.toml");
    let out = imported("layered.toml", None);
    let shape: Vec<(i64, usize)> = array(&out, "sections")
        .iter()
        .map(|s| (int(s, "elements"), s.get("layers").and_then(toml::Value::as_array).map_or(0, Vec::len)))
        .collect();
    assert_eq!(shape, [(1, 0), (2, 1), (1, 0), (1, 1), (1, 1)]);
    let compressor = imported("compressor_shaft.toml", None);
    let nodes: i64 = array(&compressor, "sections").iter().map(|s| int(s, "elements")).sum();
    assert_eq!(nodes, 55);
    // A layer of another length than its element is refused, naming it.
    let text = std::fs::read_to_string(fixture("layered.toml")).unwrap();
    let start = text.find("[\"ShaftElement_Sleeve 1\"]").unwrap();
    let at = start + text[start..].find("L = 0.25").unwrap();
    let text = format!("{}L = 0.2{}", &text[..at], &text[at + "L = 0.25".len()..]);
    let e = rotorshunt::import::ross::import_text(&text, "layered.toml", Options::default()).unwrap_err();
    let RossErrorKind::Refused { element: found, reason, .. } = e.kind else { panic!("{e}") };
    assert_eq!(found.map(|e| *e), element("layered.toml", "ShaftElement", "Sleeve 1", 1));
    assert!(matches!(*reason, Refusal::Numbering(ref m) if m.contains("concentric layer")), "{reason}");
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
fn tabulated_bearings_keep_their_table_and_are_evaluated_at_the_speed() {
    // The fixture's table is k = 1e6 + 200·ω N/m and c = 100 + 0.1·ω N·s/m at 0, 500,
    // 1000 and 1500 rad/s (docs/ross-format.md): written whole, with or without --speed,
    // and evaluated by the model at any speed, at a tabulated one and between two.
    let ross = ross_json("speed_dependent.toml");
    let (_, b0) = ross.iter().find(|(k, _)| k.as_str() == "BearingElement_Bearing 0").unwrap();
    let list = |v: &Value| v.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect::<Vec<_>>();
    for speed in [None, Some(750.0)] {
        let out = imported("speed_dependent.toml", speed);
        assert_eq!(num(&toml::Value::Table(out.clone()), "speed"), speed.unwrap_or(0.0));
        let b = &array(&out, "bearings")[0];
        let values = |key: &str| b[key].as_array().unwrap().iter().map(|x| x.as_float().unwrap()).collect::<Vec<_>>();
        assert_eq!(values("speeds"), list(&b0["frequency"]));
        assert_eq!(values("kxx"), list(&b0["kxx"]));
        assert_eq!(values("cyy"), list(&b0["cyy"]));
    }
    let text = import_path(&fixture("speed_dependent.toml"), Options::default()).unwrap().text;
    let p = rotorshunt::problem::Problem::from_text(&text, "speed_dependent", &[]).unwrap();
    for (speed, k, c) in [(1000.0, 1.2e6, 200.0), (750.0, 1.0e6 + 200.0 * 750.0, 100.0 + 0.1 * 750.0)] {
        for b in &p.model.bearings {
            let m = b.matrices_at(speed);
            assert!(common::rel(m.k[0][0], k) < 1e-12 && common::rel(m.k[1][1], k) < 1e-12, "{speed}: {:?}", m.k);
            assert!(common::rel(m.c[0][0], c) < 1e-12, "{speed}: {:?}", m.c);
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
    c.arg("import-ross").arg(fixture("refuse_magnetic.toml")).arg("--out").arg(&out).arg("--force");
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
    for name in [
        "rotor_example_rayleigh.toml",
        "stepped_hollow.toml",
        "speed_dependent.toml",
        "refuse_linked_bearing.toml",
        "tapered.toml",
        "layered.toml",
        "refuse_several.toml",
    ] {
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
    let (run, stderr) = import_ross(&source, &out);
    // Exit code 2: bad input (docs/errors.md); the file layer's rigid-body refusal.
    assert_eq!(run.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("rigid-body mode(s)"), "{stderr}");
    assert!(!out.exists());
}

#[test]
fn a_ross_coefficient_far_beyond_the_shafts_scale_is_not_written() {
    // Issue 50, item 6: `kxx = 1e308` was imported, and the rotor's whirls came out
    // wrong with tiny residuals. The general form refuses it at its key (OutOfScale).
    let text = std::fs::read_to_string(fixture("rotor_example_rayleigh.toml")).unwrap();
    let start = text.find("[\"BearingElement_Bearing 0\"]").unwrap();
    let at = start + text[start..].find("kxx = [ 1000000.0,]").unwrap();
    let dir = crate::common::tmp("ross-import-scale");
    std::fs::create_dir_all(&dir).unwrap();
    let source = dir.join("stiff.toml");
    std::fs::write(&source, format!("{}kxx = [ 1e308,]{}", &text[..at], &text[at + "kxx = [ 1000000.0,]".len()..]))
        .unwrap();
    let out = dir.join("stiff.problem.toml");
    let (run, stderr) = import_ross(&source, &out);
    assert_eq!(run.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("key `bearings[0].kxx`: kxx = 1e308 N/m is 1.0057e300 times the shaft's own stiffness scale"),
        "{stderr}"
    );
    assert!(!out.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_number_that_is_not_finite_is_named_by_its_key() {
    // Issue 50, item 10: `L = nan` read as "invalid type: null", a huge integer as "JSON
    // number out of range"; each is now named by its key and line.
    let text = std::fs::read_to_string(fixture("rotor_example_rayleigh.toml")).unwrap();
    let first_l = text.find("\nL = 0.25").unwrap() + 1;
    let line = text[..first_l].lines().count() + 1;
    let key = "[\"ShaftElement_Shaft Element 0\"].L";
    for value in ["nan", "inf", "-inf", "1e400", "99999999999999999999999"] {
        let edited = format!("{}L = {value}{}", &text[..first_l], &text[first_l + "L = 0.25".len()..]);
        match rotorshunt::import::ross::import_text(&edited, "r.toml", Options::default()).unwrap_err().kind {
            RossErrorKind::Schema { key: k, line: l, message } => {
                assert_eq!((k.as_str(), l), (key, Some(line)), "{value}");
                assert!(message.starts_with(&format!("`{value}` is not a finite number")), "{value}: {message}");
            }
            other => panic!("{value}: {other}"),
        }
    }
    // In a table of a bearing, and in JSON (where serde_json stops on 1e400 itself).
    let at = text.find("kxx = [ 1000000.0,]").unwrap();
    let edited = format!("{}kxx = [ nan,]{}", &text[..at], &text[at + "kxx = [ 1000000.0,]".len()..]);
    let e = rotorshunt::import::ross::import_text(&edited, "r.toml", Options::default()).unwrap_err();
    assert!(e.to_string().contains("`[\"BearingElement_Bearing 0\"].kxx[0]`: `nan` is not a finite number"), "{e}");
    let json = std::fs::read_to_string(fixture("rotor_example_rayleigh.json")).unwrap();
    let edited = json.replacen("\"L\": 0.25", "\"L\": 1e400", 1);
    let e = rotorshunt::import::ross::import_text(&edited, "r.json", Options::default()).unwrap_err();
    assert!(e.to_string().contains("`[\"ShaftElement_Shaft Element 0\"].L`: `1e400` is not a finite number"), "{e}");
}

#[test]
fn an_out_folder_is_bad_input() {
    // Issue 50, item 10: `--out EXISTING_DIR` was exit 1 ("cannot write"); a folder
    // given where the one problem file goes is bad input (exit 2), refused before work.
    let dir = crate::common::tmp("ross-import-out-folder");
    std::fs::create_dir_all(&dir).unwrap();
    let o =
        bin().arg("import-ross").arg(fixture("rotor_example_rayleigh.toml")).arg("--out").arg(&dir).output().unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    assert!(stderr.starts_with("error: argument `--out`: ") && stderr.contains("is a folder"), "{stderr}");
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `rotorshunt import-ross SOURCE --out OUT`: its output and standard error.
fn import_ross(source: &std::path::Path, out: &std::path::Path) -> (std::process::Output, String) {
    let run = crate::common::bin()
        .args(["import-ross", source.to_str().unwrap(), "--out", out.to_str().unwrap()])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr).into_owned();
    (run, stderr)
}
