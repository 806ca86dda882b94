//! Campbell diagram: tracking, outputs, and parallel = sequential.

use crate::common;
use common::{load, rel};
use rotorshunt::analysis::campbell::campbell;
use rotorshunt::analysis::Interval;
use rotorshunt::analysis::Rotor;

#[test]
fn tracks_follow_modes_through_the_table_speeds() {
    let p = load("paper-closed.toml", &[]);
    let rotor = Rotor::new(&p.model).unwrap();
    let speeds = Interval::new(0.0, 2000.0).stepped(250.0, 1000).unwrap();
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
    let speeds = Interval::new(0.0, 3000.0).stepped(500.0, 1000).unwrap();
    let par = campbell(&rotor, &p.settings, &speeds, 4, &|| {}).unwrap();
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let seq = pool.install(|| campbell(&rotor, &p.settings, &speeds, 4, &|| {}).unwrap());
    assert_eq!(par, seq);
}

#[test]
fn command_writes_csv_json_svg_png() {
    let dir = common::tmp("campbell");
    let mut campbell = common::bin();
    campbell.args(["campbell", &common::problem_path("paper-open.toml")]);
    let text = common::run_ok(campbell.args(["--speeds", "0:2000:1000", "--count", "4", "--out"]).arg(&dir));
    assert!(text.contains("3 speeds"), "{text}");
    let csv = std::fs::read_to_string(dir.join("campbell.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 8 * 3);
    let json: serde_json::Value = serde_json::from_slice(&std::fs::read(dir.join("campbell.json")).unwrap()).unwrap();
    assert_eq!(json["campbell"]["tracks"].as_array().unwrap().len(), 8);
    assert!(std::fs::read_to_string(dir.join("campbell.svg")).unwrap().starts_with("<svg"));
    assert_eq!(&std::fs::read(dir.join("campbell.png")).unwrap()[1..4], b"PNG");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The Jeffcott rotor's shaft mass is 8e-8 of the disk's and its rotary inertia 1e-9 of
/// the disk's: the whirls move from the massless closed forms by about that.
const JEFFCOTT_TOLERANCE: f64 = 1e-6;

#[test]
fn anisotropic_jeffcott_whirls_are_tracked_through_their_change_of_direction() {
    use rotorshunt::analysis::modes::Whirl;
    use rotorshunt::problem::Problem;
    // Bearings of 1e6 N/m in x and 2e6 N/m in y; a 10 kg disk with J_d = 0.1 and
    // J_p = 0.2 kg·m² at mid-span. By symmetry its translation and its tilt decouple:
    // the translations whirl at √(k_x/m) and √(k_y/m) at every speed, planar (mixed);
    // the tilt (J_d ψ̈_x + ΩJ_p ψ̇_y + a_x ψ_x = 0, J_d ψ̈_y − ΩJ_p ψ̇_x + a_y ψ_y = 0)
    // at the roots ω² of J_d²ω⁴ − (J_d(a_x + a_y) + Ω²J_p²)ω² + a_x a_y = 0: planar at
    // rest, then a backward ellipse falling through both translations and a forward one
    // rising.
    let (kx, ky, m, jd, jp) = (1.0e6, 2.0e6, 10.0, 0.1, 0.2);
    let p = Problem::from_text(&common::jeffcott(kx, ky, jp, jd, 0.0), "jeffcott.toml", &[]).unwrap();
    let rotor = Rotor::new(&p.model).unwrap();
    assert!(rotor.real);
    let speeds: Vec<f64> = (0..=15).map(|i| 100.0 * i as f64).collect();
    let r = campbell(&rotor, &p.settings, &speeds, 4, &|| {}).unwrap();
    let (wx, wy) = ((common::jeffcott_translation(kx) / m).sqrt(), (common::jeffcott_translation(ky) / m).sqrt());
    let (ax, ay) = (common::jeffcott_tilt(kx), common::jeffcott_tilt(ky));
    let tilt = |speed: f64| {
        let (a, b, c) = (jd * jd, jd * (ax + ay) + (speed * jp).powi(2), ax * ay);
        let root = (b * b - 4.0 * a * c).sqrt();
        // The lower root without cancellation: ω²_low·ω²_high = c/a.
        let high = (b + root) / (2.0 * a);
        ((c / a / high).sqrt(), high.sqrt())
    };
    let starting = |w: f64| {
        r.tracks
            .iter()
            .find(|t| t.points[0].speed == 0.0 && rel(t.points[0].frequency, w) < JEFFCOTT_TOLERANCE)
            .unwrap_or_else(|| panic!("no track starts at {w} rad/s: {:#?}", r.tracks))
    };
    for w in [wx, wy] {
        let t = starting(w);
        assert_eq!(t.points.len(), speeds.len(), "{}", t.tag);
        for p in &t.points {
            assert!(rel(p.frequency, w) < JEFFCOTT_TOLERANCE, "{} at {}: {} vs {w}", t.tag, p.speed, p.frequency);
        }
        assert_eq!(t.points[0].whirl, Some(Whirl::Mixed));
        // Its critical speed, where the 1× line crosses it: √(k/m) (the track is flat).
        let cross = t.points.windows(2).find(|q| (q[0].frequency - q[0].speed) * (q[1].frequency - q[1].speed) <= 0.0);
        let q = cross.expect("the 1× line crosses the translation");
        let (d0, d1) = (q[0].frequency - q[0].speed, q[1].frequency - q[1].speed);
        let critical = q[0].speed + (q[1].speed - q[0].speed) * d0 / (d0 - d1);
        assert!(rel(critical, w) < JEFFCOTT_TOLERANCE, "critical {critical} vs {w}");
    }
    let (low0, high0) = tilt(0.0);
    for (w0, lower) in [(low0, true), (high0, false)] {
        let t = starting(w0);
        assert_eq!(t.points.len(), speeds.len(), "{}", t.tag);
        for p in &t.points {
            let (low, high) = tilt(p.speed);
            let w = if lower { low } else { high };
            assert!(rel(p.frequency, w) < JEFFCOTT_TOLERANCE, "{} at {}: {} vs {w}", t.tag, p.speed, p.frequency);
            let direction = match (p.speed > 0.0, lower) {
                (false, _) => Whirl::Mixed,
                (true, true) => Whirl::Backward,
                (true, false) => Whirl::Forward,
            };
            assert_eq!(p.whirl, Some(direction), "{} at {}", t.tag, p.speed);
        }
        assert_eq!(t.whirl, Whirl::Mixed, "the track's direction is its first point's");
    }
    // The backward tilt falls through both translations on the way: 319 rad/s at the end.
    assert!(tilt(1500.0).0 < wx.min(wy));
}
