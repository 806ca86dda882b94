//! The library's results read back from their JSON are the results written (issue 30:
//! "results that are Serialize and Deserialize and round-trip"): whirls, Campbell
//! diagrams, Floquet points (every reason a point is not trusted, an infinite β = 0
//! deviation included), charts, unbalance and time responses and damping ratios, in
//! complex and in real coordinates. serde_json's `float_roundtrip` keeps every f64 bit
//! for bit, so a result read back is equal to the one written and writes the same text.
//! What a result keeps out of its JSON (mode shapes, the modal coordinates of a time
//! response, the refined peaks' extra samples) is named at the field and comes back empty.
//! The catalogue and the band round-trip in tests/routes.rs.

use crate::common;
use rotorshunt::analysis::campbell::{campbell, CampbellResult};
use rotorshunt::analysis::damping::{mode_damping, ModeDamping};
use rotorshunt::analysis::floquet::{FloquetPoint, FloquetSystem, PointIssue, PointStatus};
use rotorshunt::analysis::modes::{whirl_modes_of, ModeFlag, ModesResult};
use rotorshunt::analysis::response::{response, ResponseResult};
use rotorshunt::analysis::unbalance::{node_probe, unbalance_response, UnbalanceResult};
use rotorshunt::analysis::{ChartRequest, Interval, Rotor};
use rotorshunt::problem::Problem;
use serde::de::DeserializeOwned;
use serde::Serialize;

/// `value` written as JSON and read back; the text the read-back value writes is the text
/// it was read from.
fn back<T: Serialize + DeserializeOwned>(value: &T) -> T {
    let text = serde_json::to_string(value).unwrap();
    let read: T = serde_json::from_str(&text).unwrap_or_else(|e| panic!("{e}: {text}"));
    assert_eq!(serde_json::to_string(&read).unwrap(), text);
    read
}

/// Whirls read back: every number and name of every mode, the speed and the loads.
fn same_modes(a: &ModesResult, b: &ModesResult) {
    assert_eq!((a.speed, a.critical_load, a.static_load, a.real), (b.speed, b.critical_load, b.static_load, b.real));
    assert_eq!(a.modes, b.modes);
    assert_eq!(b.shapes.nrows() * b.shapes.ncols(), 0, "shapes are not serialised");
}

/// The paper's rotor (complex coordinates) and an anisotropic, damped Jeffcott rotor (real
/// coordinates: whirl ellipticities, orbits).
fn rotors() -> Vec<(&'static str, Problem)> {
    let jeffcott = common::jeffcott_damped(1.0e6, 2.0e6, 0.05, 0.03, 20.0, 300.0);
    vec![
        ("fig11-closed-2000.toml", common::load("fig11-closed-2000.toml", &[])),
        ("anisotropic Jeffcott", Problem::from_text(&jeffcott, "jeffcott.toml", &[]).unwrap()),
    ]
}

#[test]
fn whirls_campbell_and_damping_round_trip() {
    for (name, p) in rotors() {
        let rotor = Rotor::new(&p.model).unwrap();
        let speeds = [0.5 * p.model.speed, 0.75 * p.model.speed, p.model.speed];
        let modes = whirl_modes_of(&rotor, &p.settings, speeds[0]).unwrap();
        assert!(!modes.modes.is_empty(), "{name}");
        assert_eq!(modes.real, modes.modes.iter().all(|m| m.ellipticity.is_some()), "{name}");
        same_modes(&modes, &back(&modes));
        let diagram = campbell(&rotor, &p.settings, &speeds, 2, &rotorshunt::progress::Silent).unwrap();
        assert!(!diagram.tracks.is_empty(), "{name}");
        assert_eq!(back::<CampbellResult>(&diagram), diagram, "{name}");
        let tags: Vec<String> = modes.modes.iter().take(2).map(|m| m.tag()).collect();
        let damping = mode_damping(&rotor, &p.settings, &speeds, &tags, &rotorshunt::progress::Silent).unwrap();
        assert_eq!(damping.len(), tags.len(), "{name}");
        assert_eq!(back::<Vec<ModeDamping>>(&damping), damping, "{name}");
    }
}

#[test]
fn floquet_points_and_charts_round_trip() {
    let p = common::load("fig11-closed-2000.toml", &[]);
    let op = p.operating_point().unwrap();
    // Around ω_b1 + ω_r (Fig. 11): stable and unstable points.
    let request = ChartRequest::grid()
        .phi(Interval::new(1190.0, 1240.0))
        .phi_step(5.0)
        .beta_max(0.5)
        .beta_step(0.25)
        .build()
        .unwrap();
    let chart = op.chart(&request);
    assert!(chart.unstable() > 0 && chart.unstable() < chart.points.len());
    assert_eq!(back(&chart), chart);
    let fs: &FloquetSystem = &op.floquet;
    for point in [fs.point_fast(&fs.table(1210.0, 0.5), 0.5), fs.point_dstm(1210.0, 0.5, p.settings.reference_steps)] {
        assert_eq!(point.multipliers.len(), fs.system.b0.nrows());
        assert_eq!(back::<FloquetPoint>(&point), point);
    }
}

#[test]
fn every_reason_a_point_or_mode_is_not_trusted_round_trips_with_its_message() {
    let issues = [
        PointIssue::Interpolant { terms: 33 },
        PointIssue::Coupling { coupling: 2.345678901234567, steps: 4096 },
        PointIssue::ZeroLoad { deviation: 1.234567890123e-3 },
        PointIssue::ZeroLoad { deviation: f64::INFINITY },
        PointIssue::NoZeroLoadReference,
        PointIssue::Eigenvalues,
        PointIssue::NotFinite,
    ];
    for issue in issues {
        let json = serde_json::to_value(issue).unwrap();
        assert_eq!(json["message"], issue.to_string(), "{json}");
        assert_eq!(back(&issue), issue, "{json}");
    }
    // The infinite deviation is `null` in JSON, which has no infinity.
    assert!(serde_json::to_value(issues[3]).unwrap()["deviation"].is_null());
    // A point that carries one, as the analysis builds it.
    let p = common::load("fig11-closed-2000.toml", &[]);
    let fs = p.operating_point().unwrap().floquet;
    let mut point = fs.point_fast(&fs.table(1210.0, 0.3), 0.3);
    point.summary.flag(Some(issues[2]));
    assert_eq!(point.summary.status, PointStatus::Inaccurate);
    assert_eq!(back(&point), point);
    for flag in [ModeFlag::Residual { residual: 3.3e-5 }, ModeFlag::NegativeDamping { damping_ratio: -2.5e-8 }] {
        let json = serde_json::to_value(flag).unwrap();
        assert_eq!(json["message"], flag.to_string(), "{json}");
        assert_eq!(back(&flag), flag, "{json}");
    }
    // A reason with a name the library does not know, or without its number, is refused.
    for bad in [r#"{"issue":"gremlins","message":""}"#, r#"{"issue":"coupling","steps":3,"message":""}"#] {
        assert!(serde_json::from_str::<PointIssue>(bad).is_err(), "{bad}");
    }
}

#[test]
fn unbalance_and_time_responses_round_trip() {
    for (name, p) in rotors() {
        let rotor = Rotor::new(&p.model).unwrap();
        let node = p.model.disks[0].node;
        let probe = node_probe(&rotor.system.dofs, node).unwrap();
        let speeds: Vec<f64> = (1..=40).map(|i| f64::from(i) * 20.0).collect();
        let mut r = unbalance_response(&rotor, &speeds, &[probe], &rotorshunt::progress::Silent).unwrap();
        assert_eq!(r.probes[0].orbit.is_some(), rotor.real, "{name}");
        let read: UnbalanceResult = back(&r);
        // The refined peaks' extra samples are for plots, not the JSON.
        r.probes.iter_mut().for_each(|pr| pr.refined.clear());
        assert_eq!(read, r, "{name}");
    }
    let p = common::load("fig11-closed-2000.toml", &[]);
    let fs = p.operating_point().unwrap().floquet;
    let mut r = response(&fs, 1210.0, 0.3, 3);
    assert!(!r.modal.is_empty());
    let read: ResponseResult = back(&r);
    r.modal.clear(); // the modal coordinates are not serialised
    assert_eq!(read, r);
}
