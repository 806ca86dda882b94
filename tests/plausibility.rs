//! Units and plausibility (issue 18): speeds in rpm give the results of the same speed
//! in rad/s, and each unit mistake of the issue (mm for m, E in MPa, radians in
//! `angle_deg`, rpm in `speed`) gets a warning or an error naming its key; the bundled
//! problems get none.

use crate::common;
use common::{load, problem_path, rel, root};
use rotorshunt::problem::units::RAD_PER_S_PER_RPM;
use rotorshunt::problem::WarningKind;
use rotorshunt::problem::{Location, Problem, ProblemErrorKind, Warning};
use rotorshunt::problem::{MAX_SUPPORT_DAMPING_RATIO, MAX_SUPPORT_STIFFNESS_RATIO};
use std::f64::consts::PI;
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_rotorshunt");

fn warnings(name: &str, overrides: &[&str]) -> Vec<Warning> {
    load(name, overrides).warnings
}

fn run(args: &[&str]) -> std::process::Output {
    Command::new(BIN).args(args).current_dir(root()).output().expect("run rotorshunt")
}

/// The paper's file with `speed = 2000.0` written as `speed_rpm = …`.
fn rpm_text(rpm: f64) -> String {
    let text = std::fs::read_to_string(problem_path("paper-closed.toml")).unwrap();
    assert!(text.contains("\nspeed = 2000.0 "));
    text.replace("\nspeed = 2000.0 ", &format!("\nspeed_rpm = {rpm:?} "))
}

#[test]
fn a_speed_in_rpm_gives_the_results_of_the_same_speed_in_rad_per_s() {
    let rpm = 2000.0 / RAD_PER_S_PER_RPM;
    let by_rpm = Problem::from_text(&rpm_text(rpm), "rpm.toml", &[]).unwrap();
    let by_rad = load("paper-closed.toml", &[]);
    assert!(rel(by_rpm.model.speed, 2000.0) < 1e-15, "{}", by_rpm.model.speed);
    let (a, b) = (by_rpm.operating_point().unwrap(), by_rad.operating_point().unwrap());
    assert_eq!(a.modes.modes.len(), b.modes.modes.len());
    for (x, y) in a.modes.modes.iter().zip(&b.modes.modes) {
        assert_eq!(x.tag(), y.tag());
        assert!(rel(x.frequency, y.frequency) < 1e-12, "{}: {} vs {}", x.tag(), x.frequency, y.frequency);
    }
    let (p, q) = (a.floquet.point(1230.0, 0.3), b.floquet.point(1230.0, 0.3));
    assert!(rel(p.summary.max_multiplier, q.summary.max_multiplier) < 1e-12);
    // The same by --set, which replaces the file's `speed`.
    let set = load("paper-closed.toml", &[&format!("speed_rpm={rpm:?}")]);
    assert_eq!(set.model.speed, by_rpm.model.speed);
    // And the design speeds.
    let d = load("design-widest-band.toml", &["design.speeds_rpm=[9549.296585513721, 19098.593171027442]"]);
    let speeds = &d.design.as_ref().unwrap().speeds;
    assert!(rel(speeds[0], 1000.0) < 1e-15 && rel(speeds[1], 2000.0) < 1e-15, "{speeds:?}");
    // And the response's speed range of a design.
    let rpm_range =
        format!("design.response.speeds_rpm=[{:?}, {:?}]", 250.0 / RAD_PER_S_PER_RPM, 500.0 / RAD_PER_S_PER_RPM);
    let r = load("design-min-peak-at-speed.toml", &[&rpm_range]);
    let r = r.design.as_ref().unwrap().response().unwrap().speeds;
    assert!(rel(r.lo, 250.0) < 1e-15 && rel(r.hi, 500.0) < 1e-15, "{r:?}");
}

#[test]
fn speed_flags_in_rpm_give_the_results_of_the_same_speeds_in_rad_per_s() {
    let out = common::tmp("rpm-flags");
    let campbell = |speeds: &str, dir: &str| {
        let o = run(&["campbell", "problems/paper-closed.toml", "--speeds", speeds, "--count", "2", "--out", dir]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        common::json(&std::path::Path::new(dir).join("campbell.json"))
    };
    let (a, b) = (out.join("rad"), out.join("rpm"));
    let by_rad = campbell(&format!("0:{:?}:{:?}", 3000.0, 500.0), a.to_str().unwrap());
    let by_rpm = campbell(
        &format!("0:{:?}:{:?} rpm", 3000.0 / RAD_PER_S_PER_RPM, 500.0 / RAD_PER_S_PER_RPM),
        b.to_str().unwrap(),
    );
    let speeds = |v: &serde_json::Value| -> Vec<f64> {
        v["campbell"]["speeds"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect()
    };
    let (sa, sb) = (speeds(&by_rad), speeds(&by_rpm));
    assert_eq!(sa.len(), 7);
    assert_eq!(sa.len(), sb.len());
    for (x, y) in sa.iter().zip(&sb) {
        assert!((x - y).abs() <= 1e-12 * x.max(1.0), "{x} vs {y}");
    }
    let o = run(&["unbalance", "problems/paper-closed.toml", "--speeds", "1:2:1 rpms", "--out", "/nonexistent/x"]);
    assert_eq!(o.status.code(), Some(2), "a bad unit is bad input");
    std::fs::remove_dir_all(&out).unwrap();
}

#[test]
fn a_speed_given_both_ways_is_refused_at_its_line() {
    let mut text = rpm_text(19098.6);
    text = text.replacen("\nspeed_rpm", "\nspeed = 2000.0\nspeed_rpm", 1);
    let e = Problem::from_text(&text, "both.toml", &[]).unwrap_err();
    assert_eq!(e.key, "speed_rpm");
    assert_eq!(e.kind, ProblemErrorKind::BothGiven("speed".into(), "speed_rpm".into()));
    assert_eq!(e.location, Location::Line(7));
    let e = Problem::from_text(&rpm_text(-5.0), "neg.toml", &[]).unwrap_err();
    assert_eq!((e.key.as_str(), e.kind), ("speed_rpm", ProblemErrorKind::Negative(-5.0)));
}

#[test]
fn the_bundled_problems_and_good_fixtures_have_no_warning() {
    let mut files: Vec<_> = ["problems", "tests/fixtures/good"]
        .iter()
        .flat_map(|d| std::fs::read_dir(root().join(d)).unwrap())
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    assert!(files.len() >= 17);
    for f in files {
        let p = Problem::from_path(&f, &[]).unwrap();
        assert!(p.warnings.is_empty(), "{}: {:?}", f.display(), p.warnings);
    }
    // Nor the speeds of the bundled study (up to 3000 rad/s).
    assert!(warnings("fig11-closed-2000.toml", &["speed=3000"]).is_empty());
}

#[test]
fn lengths_in_mm_are_warned_of() {
    // The paper's shaft (L = 0.7 m, r = 15 mm) with both typed in mm.
    let w = warnings("paper-closed.toml", &["shaft.length=700", "shaft.radius=15"]);
    let mass = w.iter().find(|w| w.key == "shaft").expect("a mass warning");
    match &mass.kind {
        WarningKind::Mass { mass, .. } => assert!(rel(*mass, 7900.0 * std::f64::consts::PI * 225.0 * 700.0) < 1e-12),
        other => panic!("{other:?}"),
    }
    assert!(mass.to_string().contains("3.9089e9 kg"), "{mass}");
    // The length alone in mm: a 700 m shaft of 30 mm.
    let w = warnings("paper-closed.toml", &["shaft.length=700"]);
    assert!(
        w.iter().any(|w| w.key == "shaft.length" && matches!(w.kind, WarningKind::Slenderness { ratio, .. } if ratio > 2e4)),
        "{w:?}"
    );
    // The general form: sections in mm.
    let w = warnings("stepped-bearing-ring.toml", &["sections[2].length=150", "rings[0].node=28"]);
    assert!(w.iter().any(|w| w.key == "sections" && matches!(w.kind, WarningKind::Slenderness { .. })), "{w:?}");
}

#[test]
fn a_modulus_in_mpa_is_warned_of() {
    let p = load("paper-open.toml", &["shaft.youngs_modulus=206e3"]);
    let w = &p.warnings;
    assert_eq!(w.len(), 1, "{w:?}");
    assert_eq!(w[0].key, "shaft.youngs_modulus");
    assert!(matches!(w[0].kind, WarningKind::YoungsModulus { value, .. } if value == 206e3));
    assert_eq!(w[0].location, Location::Override);
    // What it does: P_cr of 0.16 N instead of 1.65e5 N.
    let p_cr = p.rotor().unwrap().critical_load;
    assert!(p_cr < 0.2, "{p_cr}");
    let w = warnings("stepped-bearing-ring.toml", &["materials[0].youngs_modulus=211"]);
    assert!(w.iter().any(|w| w.key == "materials[0].youngs_modulus"), "{w:?}");
}

#[test]
// 1.0472 is 60° as a user types it in radians (4 digits), not π/3 itself.
#[allow(clippy::approx_constant)]
fn radians_in_angle_deg_are_refused_or_warned_of() {
    // From k_eq2, a 60° angle typed as 1.0472 makes C_p^S 9 000 times C_p^T's order:
    // physically impossible, refused at the angle's line.
    let path = root().join("tests/fixtures/bad/ring_angle_in_radians.toml");
    let e = Problem::from_path(&path, &[]).unwrap_err();
    assert_eq!(e.key, "ring.angle_deg");
    assert_eq!(e.location, Location::Line(29));
    match e.kind {
        ProblemErrorKind::ClampedCapacitance { cp_s, cp_t, angle_deg, from_k_eq2 } => {
            assert!(cp_s > 1000.0 * cp_t, "{cp_s} vs {cp_t}");
            assert_eq!((angle_deg, from_k_eq2), (1.0472, Some(2.444e7)));
        }
        other => panic!("{other:?}"),
    }
    // C_p^S given directly: nothing impossible, but the angle is warned of.
    let w = warnings("paper-closed.toml", &["ring.angle_deg=1.0472", "ring.cp_s=1.35e-6"]);
    assert!(
        w.iter().any(|w| w.key == "ring.angle_deg" && w.kind == WarningKind::AngleInRadians { angle_deg: 1.0472 }),
        "{w:?}"
    );
    // C_p^S at or above C_p^T, given, is refused at cp_s.
    let e = Problem::from_path(problem_path("paper-closed.toml"), &["ring.cp_s=1.8e-6".into()]).unwrap_err();
    assert_eq!(e.key, "ring.cp_s");
    assert!(matches!(e.kind, ProblemErrorKind::ClampedCapacitance { from_k_eq2: None, .. }), "{e}");
}

#[test]
fn rpm_in_speed_is_warned_of_naming_speed_rpm() {
    // 2000 rad/s is 19 099 rpm; typed into `speed`, the disk's rim (r = √(2J_p/m) ≈ 0.101 m)
    // would run at 1 930 m/s.
    let w = warnings("paper-closed.toml", &["speed=19099"]);
    assert_eq!(w.len(), 1, "{w:?}");
    assert_eq!(w[0].key, "speed");
    match &w[0].kind {
        WarningKind::PeripheralSpeed { peripheral, radius, rpm_key, .. } => {
            assert!(rel(*radius, (2.0 * 0.0248f64 / 4.85).sqrt()) < 1e-12);
            assert!(rel(*peripheral, 19099.0 * radius) < 1e-12);
            assert_eq!(rpm_key, "speed_rpm");
        }
        other => panic!("{other:?}"),
    }
    assert!(w[0].to_string().contains("`speed_rpm`"), "{}", w[0]);
    let w = warnings("design-widest-band.toml", &["design.speeds=[2000.0, 19099.0]"]);
    assert!(w.iter().any(|w| w.key == "design.speeds[1]"), "{w:?}");
    // The binary prints it on stderr and puts it in the JSON; the result is unchanged.
    let out = run(&["modes", "problems/paper-closed.toml", "--set", "speed=19099", "--json", "--count", "1"]);
    assert!(out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.starts_with("warning: problems/paper-closed.toml, --set: key `speed`: 19099 rad/s"), "{stderr}");
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let w = &json["warnings"][0];
    assert_eq!(
        (w["kind"].as_str(), w["key"].as_str(), w["set"].as_bool()),
        (Some("PeripheralSpeed"), Some("speed"), Some(true))
    );
    // A plausible run has no `warnings` field at all.
    let out = run(&["modes", "problems/paper-closed.toml", "--json", "--count", "1"]);
    assert!(out.stderr.is_empty());
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(json.get("warnings").is_none());
}

#[test]
fn a_phi_range_no_region_can_reach_is_warned_of() {
    let dir = common::tmp("plausibility");
    // paper-open at rest (M = 8): whirl sums from 2·350.5 to 2·ω_8; none reaches 1e5 rad/s.
    let out_dir = dir.join("above");
    let args = ["chart", "problems/paper-open.toml", "--phi", "100000:100010:10", "--beta", "0:0.1:0.1"];
    let out = run(&[&args[..], &["--out", out_dir.to_str().unwrap()]].concat());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("argument `--phi`: the phi range [100000, 100010] rad/s lies above every whirl sum"),
        "{stderr}"
    );
    let json: serde_json::Value = serde_json::from_slice(&std::fs::read(out_dir.join("chart.json")).unwrap()).unwrap();
    assert_eq!(json["warnings"][0]["kind"], "RangeAboveWhirls");
    // Below: the smallest sum 701 rad/s over order 8 is 87.6 rad/s.
    let out = run(&["regions", "problems/paper-open.toml", "--phi", "10:80", "--beta-max", "0.1", "--json"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["warnings"][0]["kind"], "RangeBelowWhirls", "{json}");
    assert!(String::from_utf8_lossy(&out.stderr).contains("lies below every instability tongue of order <= 8"));
    // A range with regions in it has none.
    let out = run(&["regions", "problems/paper-open.toml", "--phi", "600:800", "--beta-max", "0.1", "--json"]);
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(json.get("warnings").is_none());
    assert!(out.stderr.is_empty(), "{}", String::from_utf8_lossy(&out.stderr));
}

/// problems/ross-rotor-example.toml's shaft scales from its geometry, on `elements`
/// uniform Rayleigh elements of the 1.5 m shaft (D = 0.05 m, E = 2.11e11 Pa, ρ = 7810
/// kg/m³): at an inner node two elements meet, so K_s = 2·12EI/l³ and
/// M_s = 2·(156ρAl/420 + 36ρI/(30l)) (the consistent and rotary masses' k_uu).
fn ross_example_scales(elements: usize) -> (f64, f64) {
    let (d, e, rho) = (0.05f64, 2.11e11, 7810.0);
    let l = 1.5 / elements as f64;
    let (a, i) = (PI * d * d / 4.0, PI * d.powi(4) / 64.0);
    (2.0 * 12.0 * e * i / l.powi(3), 2.0 * (156.0 * rho * a * l / 420.0 + 36.0 * rho * i / (30.0 * l)))
}

fn out_of_scale(overrides: &[String]) -> (String, Location, f64, f64, &'static str) {
    let e = Problem::from_path(problem_path("ross-rotor-example.toml"), overrides).unwrap_err();
    match e.kind {
        ProblemErrorKind::OutOfScale { value, scale, coefficient, speed: None } => {
            (e.key, e.location, value, scale, coefficient)
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_support_far_beyond_the_shafts_own_scale_is_refused_at_its_key() {
    // Issue 50, item 6: bearings of 1e65 N/m gave f1 = 1936.60 rad/s for the pinned
    // 123.89, with residuals of 1e-29 and no warning; 1e100 gave 4.27e20 rad/s.
    let (k_s, m_s) = ross_example_scales(6);
    for k in ["1e65", "1e100"] {
        let (key, location, value, scale, coefficient) = out_of_scale(&[format!("bearings[0].stiffness={k}")]);
        assert_eq!((key.as_str(), location), ("bearings[0].stiffness", Location::Override));
        assert_eq!((value, coefficient), (k.parse().unwrap(), "stiffness"));
        assert!(rel(scale, k_s) < 1e-12, "{scale} vs {k_s}");
    }
    // The ratio is the bound: just inside is admitted, just outside refused.
    let set = |key: &str, v: f64| vec![format!("{key}={v:e}")];
    load("ross-rotor-example.toml", &[&set("bearings[1].stiffness", 0.99 * MAX_SUPPORT_STIFFNESS_RATIO * k_s)[0]]);
    let (key, ..) = out_of_scale(&set("bearings[1].stiffness", 1.01 * MAX_SUPPORT_STIFFNESS_RATIO * k_s));
    assert_eq!(key, "bearings[1].stiffness");
    // A damping against √(K_s·M_s).
    let c_s = (k_s * m_s).sqrt();
    load("ross-rotor-example.toml", &[&set("bearings[0].damping", 0.99 * MAX_SUPPORT_DAMPING_RATIO * c_s)[0]]);
    let (key, _, _, scale, coefficient) =
        out_of_scale(&set("bearings[0].damping", 1.01 * MAX_SUPPORT_DAMPING_RATIO * c_s));
    assert_eq!((key.as_str(), coefficient), ("bearings[0].damping", "damping"));
    assert!(rel(scale, c_s) < 1e-12, "{scale} vs {c_s}");
}

#[test]
fn the_stiffest_support_admitted_still_gives_the_pinned_whirls() {
    // On 3 shaft elements, the worst case measured (docs/decisions.md, issue 50), the
    // lowest four forward whirls with both bearings at the largest stiffness admitted
    // agree with those at 1e6·K_s (pinned to ~1e-6 of K_s/K) to 1e-6; at 1e16·K_s they
    // left it by 1e-4.
    let (k_s, _) = ross_example_scales(3);
    let whirls = |k: f64| -> Vec<f64> {
        let p = load(
            "ross-rotor-example.toml",
            &[
                "sections[0].elements=3",
                "disks[0].node=1",
                "disks[1].node=2",
                "bearings[1].node=3",
                &format!("bearings[0].stiffness={k:e}"),
                &format!("bearings[1].stiffness={k:e}"),
            ],
        );
        let m = rotorshunt::analysis::modes::whirl_modes(&p.model, &p.settings, 0.0).unwrap();
        m.forward().take(4).map(|w| w.frequency).collect()
    };
    let (pinned, stiffest) = (whirls(1e6 * k_s), whirls(0.99 * MAX_SUPPORT_STIFFNESS_RATIO * k_s));
    assert_eq!(pinned.len(), 4);
    for (a, b) in stiffest.iter().zip(&pinned) {
        assert!(rel(*a, *b) < 1e-6, "{stiffest:?} vs {pinned:?}");
    }
    // f1 is the pinned limit the issue quotes, 123.89 rad/s (its K = 1e20 N/m on 6 elements).
    assert!((pinned[0] - 123.89).abs() < 0.01, "{pinned:?}");
}
