//! Campbell diagram: tracking, outputs, and parallel = sequential.

mod common;
use common::{load, rel};
use rotorshunt::analysis::campbell::campbell;
use rotorshunt::analysis::Rotor;
use rotorshunt::commands::{campbell_cmd, parse_range};
use rotorshunt::progress::Silent as Quiet;

#[test]
fn tracks_follow_modes_through_the_table_speeds() {
    let p = load("paper-closed.toml", &[]);
    let rotor = Rotor::new(&p.model).unwrap();
    let speeds = parse_range("0:2000:250", "speeds").unwrap();
    let r = campbell(&rotor, &p.settings, &speeds, 8, &|| {}).unwrap();
    assert_eq!(r.tracks.len(), 16);
    assert_eq!(r.flagged, 0, "no low-MAC step on this range");
    // At 2000 rad/s the tracks that started as f1 and b1 end on Table 3's values.
    let end = |tag: &str| r.tracks.iter().find(|t| t.tag == tag).unwrap().points.last().unwrap().frequency;
    assert!(rel(end("f1"), 398.5) < 1e-3 && rel(end("b1"), 300.1) < 1e-3);
    assert!(rel(end("f3"), 4901.8) < 1e-3 && rel(end("b3"), 2815.3) < 1e-3);
    for t in &r.tracks {
        assert_eq!(t.points.len(), speeds.len(), "{} ended early", t.tag);
    }
}

#[test]
fn parallel_equals_sequential() {
    let p = load("paper-open.toml", &[]);
    let rotor = Rotor::new(&p.model).unwrap();
    let speeds = parse_range("0:3000:500", "speeds").unwrap();
    let par = campbell(&rotor, &p.settings, &speeds, 4, &|| {}).unwrap();
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let seq = pool.install(|| campbell(&rotor, &p.settings, &speeds, 4, &|| {}).unwrap());
    assert_eq!(par, seq);
}

#[test]
fn command_writes_csv_json_svg_png() {
    let p = load("paper-open.toml", &[]);
    let dir = std::env::temp_dir().join(format!("rotorshunt-campbell-{}", std::process::id()));
    let text = campbell_cmd(&p, "0:2000:1000", 4, &dir, &Quiet, Default::default()).unwrap();
    assert!(text.contains("3 speeds"), "{text}");
    let csv = std::fs::read_to_string(dir.join("campbell.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 8 * 3);
    let json: serde_json::Value = serde_json::from_slice(&std::fs::read(dir.join("campbell.json")).unwrap()).unwrap();
    assert_eq!(json["campbell"]["tracks"].as_array().unwrap().len(), 8);
    assert!(std::fs::read_to_string(dir.join("campbell.svg")).unwrap().starts_with("<svg"));
    assert_eq!(&std::fs::read(dir.join("campbell.png")).unwrap()[1..4], b"PNG");
    std::fs::remove_dir_all(&dir).unwrap();
}
