//! Steady-state unbalance response (issue 17): against the time response run to steady
//! state, against the closed form of a one-DOF (Jeffcott) rotor, the shunt's effect on
//! the paper's rotor, thread-count independence and the typed errors of bad input.

use crate::common;
use common::load;
use faer::{c64, Mat};
use rotorshunt::analysis::floquet::FloquetSystem;
use rotorshunt::analysis::response::response;
use rotorshunt::analysis::unbalance::{
    check_speeds, node_probe, peak_at_node, probes, response_with, unbalance_response, DynamicStiffness, Matrices,
    Probe, ProbeKind, UnbalanceResult, UNBOUNDED_BANDWIDTH,
};
use rotorshunt::analysis::{AnalysisError, Rotor};
use std::process::Command;

fn rotor(name: &str, overrides: &[&str]) -> (Rotor, rotorshunt::problem::Problem) {
    let p = load(name, overrides);
    (Rotor::new(&p.model).unwrap(), p)
}

fn grid(lo: f64, hi: f64, step: f64) -> Vec<f64> {
    let n = ((hi - lo) / step).round() as usize;
    (0..=n).map(|i| lo + i as f64 * step).collect()
}

/// The disk's response of a result (its first probe).
fn disk(r: &UnbalanceResult) -> &rotorshunt::analysis::unbalance::ProbeResponse {
    let p = &r.probes[0];
    assert_eq!(p.probe.kind, ProbeKind::Disk);
    p
}

/// The shunt tuned to the first critical speed and damped (R = 100 Ω), η = 4000 N·s/m at
/// the rings (Fig. 8c), reduced to M = 4 modes: every mode of the basis is damped, so the
/// time response from rest reaches its steady state.
const DAMPED: [&str; 3] =
    ["circuit.state=closed", "circuit.branches[0].tuning_frequency=360", "circuit.branches[0].resistance=100"];

#[test]
fn time_response_reaches_the_frequency_domain_amplitude() {
    let (rotor, p) = rotor("fig8-eta4000.toml", &DAMPED);
    let reduced = FloquetSystem::new(&rotor, &p.settings, 0.0).unwrap().reduced;
    let m = reduced.size();
    let identity = Mat::<f64>::identity(m, m);
    let system = Matrices {
        m: identity.as_ref(),
        c: reduced.c.as_ref(),
        k: reduced.k.as_ref(),
        s: reduced.s.as_ref(),
        g: reduced.g.as_ref(),
        unbalance: &reduced.unbalance,
    };
    let a = DynamicStiffness::new(system, reduced.alpha * reduced.critical_load).unwrap();
    // The resonance of the first modal coordinate on a 0.5 rad/s grid, refined.
    let q1 = Probe { name: "q1".into(), kind: ProbeKind::Node, node: None, dof: 0 };
    let near = grid(300.0, 420.0, 0.5);
    let r = response_with(&a, &near, std::slice::from_ref(&q1), &rotorshunt::progress::Silent).unwrap();
    let (resonance, _, unbounded) = r[0].largest(&near);
    assert!(!unbounded && resonance > 300.0 && resonance < 420.0, "resonance {resonance}");
    let mut work = Default::default();
    for speed in [150.0, 0.97 * resonance, resonance, 600.0] {
        let expected = a.solve(speed, &mut work).unwrap()[0];
        let fs = FloquetSystem::new(&rotor, &p.settings, speed).unwrap();
        assert_eq!(fs.reduced.size(), m);
        // β = 0: φ only sets the step and the period count; φ = Ω makes a period a turn.
        let periods = 3000;
        let t = response(&fs, speed, 0.0, periods).finite().unwrap();
        // In steady state q1(t) = Q1·e^{jΩt}: compare Q1 over the last samples.
        let n = t.time.len();
        let mut worst: f64 = 0.0;
        for i in n - 10..n {
            let q = c64::new(t.q1[i][0], t.q1[i][1]) * c64::from_polar(1.0, -speed * t.time[i]);
            worst = worst.max((q - expected).norm() / expected.norm());
        }
        println!(
            "speed {speed:.3} rad/s: |Q1| = {:.6e} (frequency domain), worst relative deviation of the time response {worst:.2e}",
            expected.norm()
        );
        assert!(worst < 1e-3, "speed {speed}: time response deviates by {worst:.3e}");
    }
}

/// A one-DOF rotor (mass m, stiffness k, damping c, unbalance m·e) through the same solver:
/// the closed form m e Ω²/|k − mΩ² + jcΩ|, its peak and its half-power points.
#[test]
fn one_dof_rotor_matches_the_closed_form_with_its_peak_and_amplification_factor() {
    let (m, k, c, e) = (10.0, 1e7, 2000.0, 1e-4);
    let one = |v: f64| Mat::<f64>::from_fn(1, 1, |_, _| v);
    let (mm, cc, kk, zero) = (one(m), one(c), one(k), one(0.0));
    let q = [c64::new(m * e, 0.0)];
    let system =
        Matrices { m: mm.as_ref(), c: cc.as_ref(), k: kk.as_ref(), s: zero.as_ref(), g: zero.as_ref(), unbalance: &q };
    let a = DynamicStiffness::new(system, 0.0).unwrap();
    let exact = |w: f64| m * e * w * w / c64::new(k - m * w * w, c * w).norm();
    let speeds = grid(100.0, 3000.0, 10.0);
    let probe = Probe { name: "disk".into(), kind: ProbeKind::Disk, node: None, dof: 0 };
    let r = &response_with(&a, &speeds, std::slice::from_ref(&probe), &rotorshunt::progress::Silent).unwrap()[0];
    for (w, amp) in speeds.iter().zip(&r.amplitude) {
        assert!((amp / exact(*w) - 1.0).abs() < 1e-12, "{w}: {amp} vs {}", exact(*w));
    }
    // The peak of m e Ω²/|k − mΩ² + jcΩ|: Ω_p = ω_n/√(1 − 2ζ²), A_p = e/(2ζ√(1 − ζ²)).
    let (wn, zeta) = ((k / m).sqrt(), c / (2.0 * (k * m).sqrt()));
    let (wp, ap) = (wn / (1.0 - 2.0 * zeta * zeta).sqrt(), e / (2.0 * zeta * (1.0 - zeta * zeta).sqrt()));
    assert_eq!(r.peaks.len(), 1);
    let peak = &r.peaks[0];
    assert!((peak.speed / wp - 1.0).abs() < 1e-6, "peak speed {} vs {wp}", peak.speed);
    assert!((peak.amplitude / ap - 1.0).abs() < 1e-10, "peak {} vs {ap}", peak.amplitude);
    // Half-power points of the closed form, by its own bisection.
    let half = ap / std::f64::consts::SQRT_2;
    let crossing = |mut inside: f64, mut outside: f64| {
        for _ in 0..200 {
            let mid = 0.5 * (inside + outside);
            if exact(mid) >= half {
                inside = mid
            } else {
                outside = mid
            }
        }
        inside
    };
    let (w1, w2) = (crossing(wp, 100.0), crossing(wp, 3000.0));
    let [l, h] = peak.half_power.unwrap();
    assert!((l / w1 - 1.0).abs() < 1e-9 && (h / w2 - 1.0).abs() < 1e-9, "[{l}, {h}] vs [{w1}, {w2}]");
    let af = peak.amplification_factor.unwrap();
    assert!((af / (peak.speed / (w2 - w1)) - 1.0).abs() < 1e-8);
    // ζ = 0.1: the half-power factor is near 1/(2ζ) = 5.
    assert!((af - 5.0).abs() < 0.3, "AF {af}");
    assert!(!peak.unbounded);
    // Phase: −π/2 at ω_n (the deflection lags the heavy spot by a quarter turn).
    let u = a.solve(wn, &mut Default::default()).unwrap()[0];
    assert!((u.arg() + std::f64::consts::FRAC_PI_2).abs() < 1e-12, "phase {}", u.arg());
    // Undamped: the peak is a pole, reported unbounded; exactly at ω_n the system is
    // singular.
    let system = Matrices { c: zero.as_ref(), ..system };
    let a = DynamicStiffness::new(system, 0.0).unwrap();
    assert_eq!(a.solve(wn, &mut Default::default()), Err(AnalysisError::SingularAtSpeed { speed: wn }));
    let speeds = grid(100.0, 2998.0, 7.0);
    let r = &response_with(&a, &speeds, std::slice::from_ref(&probe), &rotorshunt::progress::Silent).unwrap()[0];
    assert_eq!(r.peaks.len(), 1);
    assert!(r.peaks[0].unbounded, "{:?}", r.peaks[0]);
    assert!((r.peaks[0].speed / wn - 1.0).abs() < 1e-8);
    let width = r.peaks[0].half_power.map(|[l, h]| h - l).unwrap();
    assert!(width < UNBOUNDED_BANDWIDTH * wn);
}

#[test]
fn the_shunt_tuned_to_the_first_critical_speed_lowers_its_peak() {
    // Fig. 8b's rotor (η = 200 N·s/m): open circuit, then closed with branch 1 tuned to the
    // open circuit's first critical speed, found here from its response.
    let speeds = grid(250.0, 500.0, 0.5);
    let (open, _) = rotor("fig8-eta200.toml", &[]);
    let r = unbalance_response(&open, &speeds, &probes(&open, &[]).unwrap(), &rotorshunt::progress::Silent).unwrap();
    let (critical, open_peak, unbounded) = disk(&r).largest(&speeds);
    assert!(!unbounded);
    println!("open circuit: disk peak {open_peak:.4e} m at {critical:.3} rad/s");
    let tuning = format!("circuit.branches[0].tuning_frequency={critical}");
    for resistance in [0.0, 10.0, 50.0, 100.0] {
        let set = [
            "circuit.state=closed".to_string(),
            tuning.clone(),
            format!("circuit.branches[0].resistance={resistance}"),
        ];
        let set: Vec<&str> = set.iter().map(String::as_str).collect();
        let (closed, _) = rotor("fig8-eta200.toml", &set);
        let r = unbalance_response(&closed, &speeds, &probes(&closed, &[]).unwrap(), &rotorshunt::progress::Silent)
            .unwrap();
        let d = disk(&r);
        let (speed, peak, _) = d.largest(&speeds);
        let near: Vec<_> = d.peaks.iter().filter(|k| (k.speed / critical - 1.0).abs() < 0.1).collect();
        println!(
            "closed, R = {resistance} ohm: disk peak {peak:.4e} m at {speed:.3} rad/s; peaks near {critical:.1}: {:?}",
            near.iter().map(|k| (k.speed, k.amplitude)).collect::<Vec<_>>()
        );
        if resistance == 0.0 {
            // R = 0: a tuned absorber without damping splits the peak in two, one on
            // each side of the critical speed; it does not damp it.
            assert_eq!(near.len(), 2, "{near:?}");
            assert!(near[0].speed < critical && near[1].speed > critical);
        } else {
            assert!(peak < 0.1 * open_peak, "R = {resistance}: {peak} vs open {open_peak}");
        }
    }
}

#[test]
fn peak_at_a_node_is_the_largest_of_its_response() {
    let (rotor, _) = rotor("fig8-eta4000.toml", &DAMPED);
    let speeds = grid(200.0, 600.0, 2.0);
    let (w, a, unbounded) = peak_at_node(&rotor, 16, &speeds).unwrap();
    let r =
        unbalance_response(&rotor, &speeds, &probes(&rotor, &[16]).unwrap(), &rotorshunt::progress::Silent).unwrap();
    let node = r.probes.last().unwrap();
    assert_eq!(node.probe.node, Some(16));
    assert_eq!(node.largest(&speeds), (w, a, unbounded));
    assert!(node.amplitude.iter().all(|x| *x <= a));
    // The disk sits at node 16: the same DOF.
    assert_eq!(disk(&r).amplitude, node.amplitude);
}

#[test]
fn results_are_identical_for_any_thread_count() {
    let (rotor, _) = rotor("fig13-r50.toml", &[]);
    let speeds = grid(0.0, 3000.0, 3.0);
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            unbalance_response(&rotor, &speeds, &probes(&rotor, &[5, 40]).unwrap(), &rotorshunt::progress::Silent)
                .unwrap()
        })
    };
    let one = run(1);
    assert_eq!(one, run(2));
    assert_eq!(one, run(5));
}

#[test]
fn bad_requests_are_typed_errors() {
    let (rotor, _) = rotor("paper-closed.toml", &[]);
    assert_eq!(check_speeds(&[]), Err(AnalysisError::NoSpeeds));
    assert!(matches!(check_speeds(&[10.0, 10.0]), Err(AnalysisError::SpeedsNotAscending { index: 1, .. })));
    assert!(matches!(check_speeds(&[-1.0]), Err(AnalysisError::Request(_))));
    assert_eq!(node_probe(&rotor.system.dofs, 65), Err(AnalysisError::ProbeNodeOffShaft { node: 65, last: 64 }));
    assert!(probes(&rotor, &[64]).is_ok());
    assert_eq!(probes(&rotor, &[3, 99]), Err(AnalysisError::ProbeNodeOffShaft { node: 99, last: 64 }));
    let a = DynamicStiffness::of(&rotor).unwrap();
    let off = Probe { name: "x".into(), kind: ProbeKind::Node, node: None, dof: a.size() };
    assert_eq!(
        response_with(&a, &[1.0], &[off], &rotorshunt::progress::Silent),
        Err(AnalysisError::ProbeOffSystem { dof: a.size(), dofs: a.size() })
    );
}

fn cli(args: &[&str]) -> (Option<i32>, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_rotorshunt"))
        .args(args)
        .current_dir(common::root())
        .env_remove("RUST_BACKTRACE")
        .output()
        .unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn bad_command_lines_name_the_flag_and_write_nothing() {
    let dir = std::env::temp_dir().join(format!("rotorshunt-unbalance-bad-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out = dir.to_str().unwrap();
    let file = "problems/paper-closed.toml";
    for (args, expected) in [
        (vec!["--speeds", "100:0:10"], "error: argument `--speeds`: `100:0:10` needs A <= B and STEP > 0"),
        (vec!["--speeds", "0:100:0"], "error: argument `--speeds`: `0:100:0` needs A <= B and STEP > 0"),
        (vec!["--speeds", "0:100:-5"], "error: argument `--speeds`: `0:100:-5` needs A <= B and STEP > 0"),
        (vec!["--speeds=-10:100:10"], "error: argument `--speeds`: must not be negative, found -10"),
        (
            vec!["--speeds", "0:100:10", "--nodes", "3,65"],
            "error: argument `--nodes`: node 65 is off the shaft: the shaft has nodes 0 to 64",
        ),
        (
            vec!["--speeds", "0:100:10", "--nodes", "3,x"],
            "error: argument `--nodes`: `x` in `3,x` is not a node index (expected e.g. 3,16)",
        ),
    ] {
        let mut all = vec!["unbalance", file, "--out", out];
        all.extend(args);
        let (code, _, stderr) = cli(&all);
        assert_eq!(code, Some(2), "{all:?}: {stderr}");
        assert_eq!(stderr.lines().next().unwrap_or_default(), expected, "{all:?}");
        assert!(!dir.exists(), "{all:?} created the output folder");
    }
    // A grid whose results would not fit the memory limit is refused before any work.
    let (code, _, stderr) = cli(&["unbalance", file, "--speeds", "0:100000:0.1", "--out", out]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(stderr.starts_with("error: the unbalance response would need about 1.2 GiB of memory"), "{stderr}");
    assert!(!dir.exists());
    let (code, _, stderr) = cli(&["damping", file, "--speeds", "0:100:50", "--modes", "f1,fq9"]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(
        stderr.starts_with("error: argument `--modes`: the model has no whirl mode `fq9` at speed 0 rad/s; its lowest modes there are f1, fr1,"),
        "{stderr}"
    );
}

#[test]
fn the_command_writes_its_files_and_compares_two_configurations() {
    let dir = std::env::temp_dir().join(format!("rotorshunt-unbalance-cmd-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out = dir.to_str().unwrap();
    let (code, stdout, stderr) = cli(&[
        "unbalance",
        "problems/fig13-r50.toml",
        "--speeds",
        "0:3000:10",
        "--nodes",
        "32",
        "--out",
        out,
        "--compare-set",
        "circuit.state=open",
    ]);
    assert_eq!(code, Some(0), "{stderr}");
    assert!(stdout.contains("compare (open circuit):"), "{stdout}");
    for f in [
        "unbalance.json",
        "unbalance.csv",
        "peaks.csv",
        "compare.json",
        "compare.csv",
        "compare-peaks.csv",
        "bode.svg",
        "bode.png",
    ] {
        assert!(dir.join(f).metadata().map(|m| m.len() > 0).unwrap_or(false), "{f} missing");
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("unbalance.json")).unwrap()).unwrap();
    let probes = json["unbalance"]["probes"].as_array().unwrap();
    let names: Vec<&str> = probes.iter().map(|p| p["name"].as_str().unwrap()).collect();
    assert_eq!(
        names,
        [
            "disk 1 (node 16)",
            "journal at ring left (node 0)",
            "ring left",
            "journal at ring right (node 64)",
            "ring right",
            "node 32"
        ]
    );
    assert_eq!(probes[0]["amplitude"].as_array().unwrap().len(), 301);
    let text = std::fs::read_to_string(dir.join("bode.svg")).unwrap();
    assert!(
        text.contains("amplitude |U| (m)") && text.contains("phase arg U (deg)") && text.contains("speed Ω (rad/s)")
    );
    assert!(text.contains("open circuit"), "the legend names the compared configuration");
    let csv = std::fs::read_to_string(dir.join("unbalance.csv")).unwrap();
    assert!(csv.starts_with("probe,kind,node,speed_rad_s,amplitude_m,phase_rad\n"));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The Jeffcott rotor in the general form (format16: `[[sections]]`, `[[bearings]]`): a
/// 10 kg disk at midspan of a nearly rigid, nearly massless shaft on two plain bearings,
/// k = 2 × 5e6 N/m and c = 2 × 1000 N·s/m (ζ = 0.1), no axial load. The disk does not tilt
/// (symmetry), so its translation is the one-DOF rotor m e Ω²/|k − mΩ² + jcΩ|.
const JEFFCOTT: &str = r#"
version = 1
title = "Jeffcott rotor on plain bearings"
speed = 0.0

[[sections]]
length = 0.5
outer_diameter = 0.05
youngs_modulus = 2.1e15
density = 1.0
elements = 8

[[disks]]
node = 4
mass = 10.0
polar_inertia = 0.02
eccentricity = 1e-4

[[bearings]]
node = 0
stiffness = 5e6
damping = 1000.0

[[bearings]]
node = 8
stiffness = 5e6
damping = 1000.0

[load]
alpha = 0.0
"#;

#[test]
fn jeffcott_rotor_on_plain_bearings_matches_the_closed_form() {
    let path = std::env::temp_dir().join(format!("rotorshunt-jeffcott-{}.toml", std::process::id()));
    std::fs::write(&path, JEFFCOTT).unwrap();
    let p = rotorshunt::problem::Problem::from_path(&path, &[]).unwrap_or_else(|e| panic!("{e}"));
    let rotor = Rotor::new(&p.model).unwrap();
    let (m, k, c, e) = (10.0, 1e7, 2000.0, 1e-4);
    let speeds = grid(100.0, 3000.0, 5.0);
    let r = unbalance_response(&rotor, &speeds, &probes(&rotor, &[]).unwrap(), &rotorshunt::progress::Silent).unwrap();
    let d = disk(&r);
    let mut worst: f64 = 0.0;
    for (w, amp) in speeds.iter().zip(&d.amplitude) {
        let exact = m * e * w * w / c64::new(k - m * w * w, c * w).norm();
        worst = worst.max((amp / exact - 1.0).abs());
    }
    println!("Jeffcott: worst relative deviation from m e w^2/|k - m w^2 + j c w| over 100..3000 rad/s: {worst:.3e}");
    assert!(worst < 5e-3, "{worst}");
    let _ = std::fs::remove_file(&path);
}
