//! The file layer reads, checks and builds types; it never runs an analysis. A design's
//! damping constraints name whirls, which need an eigensolve: that check belongs to the
//! design run (after the command line's cost guard), not to reading the file.
//!
//! The witness is a model too large for the guard: the paper's design rotor with 2 000
//! shaft elements (8 000 degrees of freedom, a dense quadratic eigenproblem of order
//! 16 000 that would take hours) and a damping constraint. Reading it must return at
//! once, and `check` and `design` must refuse it by its cost before any solve. A hang
//! timeout (not a duration assertion) stops the test if a solve does start.

use crate::common;

use common::{bin, problem_path, scratch};
use rotorshunt::Problem;
use std::sync::mpsc;
use std::time::Duration;

/// Generous limit against a hang: a read takes milliseconds; the eigensolve it must not
/// run takes hours.
const HANG_TIMEOUT: Duration = Duration::from_secs(120);

/// design-min-peak-at-speed.toml with a damping constraint on `f1` and 2 000 shaft elements.
fn too_large_with_damping_constraint() -> String {
    let text = std::fs::read_to_string(problem_path("design-min-peak-at-speed.toml")).unwrap();
    let text = text.replacen("elements = 64 ", "elements = 2000 ", 1);
    assert!(text.contains("elements = 2000 "));
    assert!(text.contains("[[design.variables]]"));
    text.replacen(
        "[[design.variables]]",
        "[[design.constraints.damping]]\nmode = \"f1\"\nmin = 0.01\n\n[[design.variables]]",
        1,
    )
}

#[test]
fn reading_a_file_with_damping_constraints_solves_nothing() {
    let text = too_large_with_damping_constraint();
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(Problem::from_text(&text, "big.toml", &[]).map(|p| {
            let spec = p.design.expect("[design]");
            (p.model.shaft.elements(), spec.constraints.damping.len())
        }));
    });
    let read = rx.recv_timeout(HANG_TIMEOUT).expect("Problem::from_text hangs: it runs a solve");
    let (elements, constraints) = read.unwrap_or_else(|e| panic!("{e}"));
    assert_eq!((elements, constraints), (2000, 1));
}

#[test]
fn the_cost_guard_refuses_the_model_before_any_solve() {
    let dir = scratch("file-layer");
    let file = dir.join("big.toml");
    std::fs::write(&file, too_large_with_damping_constraint()).unwrap();
    for command in ["check", "design"] {
        let out_dir = dir.join(format!("out-{command}"));
        let mut cmd = bin();
        cmd.arg(command).arg(&file);
        if command == "design" {
            cmd.arg("--out").arg(&out_dir);
        }
        let measured = common::run_measured(
            &cmd.get_args().map(|a| a.to_string_lossy().into_owned()).collect::<Vec<_>>(),
            &dir,
            HANG_TIMEOUT,
        );
        assert!(!measured.timed_out, "`{command}` hangs: a solve ran before the guard");
        assert_ne!(measured.code, Some(0), "`{command}` accepted a model beyond the guard");
        assert!(measured.stderr.contains("--max-cost"), "`{command}`: {}", measured.stderr);
        assert!(!out_dir.exists(), "`{command}` made a folder for a refused run");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `[design.objective_options]` holds the keys of one objective alone (docs/design.md,
/// "Adding an objective"); every bundled objective takes none and refuses the table at
/// its key path, whichever objective the file names.
#[test]
fn an_objective_without_options_refuses_the_table() {
    use rotorshunt::design::objective::{ObjectiveKind, OPTIONS_KEY};
    let mut seen = Vec::new();
    for file in ["design-widest-band.toml", "design-clear-bands.toml", "design-min-peak-at-speed.toml"] {
        let set = vec!["design.objective_options.min_width=150".to_string()];
        let e = Problem::from_path(problem_path(file), &set).unwrap_err().to_string();
        assert!(e.contains(OPTIONS_KEY) && e.contains("takes no options"), "{file}: {e}");
        let plain = Problem::from_path(problem_path(file), &[]).unwrap();
        seen.push(plain.design.unwrap().objective.kind());
    }
    assert_eq!(seen, ObjectiveKind::all(), "one problem of each objective");
}

/// A spec built in code (`DesignSpec::builder`) with the keys a file gives is the spec the
/// file reads to: the builder's defaults are the `[design]` table's. A rule the table
/// obeys is refused by the builder at the same key.
#[test]
fn a_spec_built_in_code_is_the_files_spec() {
    use rotorshunt::analysis::Interval;
    use rotorshunt::design::objective::widest_band::WidestStableBand;
    use rotorshunt::design::spec::{DesignSpec, Tolerances};
    let p = Problem::from_path(problem_path("design-robust-speed-range.toml"), &[]).unwrap();
    let read = p.design.clone().unwrap();
    let branches: Vec<usize> = p.model.rings.iter().map(|r| r.circuit.branches.len()).collect();
    let tolerances = Tolerances { inductance: 0.05, resistance: 0.2, c_f: 0.0, cp_t: 0.0, samples: 200 };
    let built =
        DesignSpec::builder(WidestStableBand { phi_op: 1230.0 }, 0.3, vec![p.model.speed], read.variables.clone())
            .max_iterations(25)
            .speed_range(Interval::new(1900.0, 2100.0))
            .tolerances(tolerances)
            .build(&branches)
            .unwrap();
    assert_eq!(built, read);
    let plain = Problem::from_path(problem_path("design-widest-band.toml"), &[]).unwrap();
    let built = DesignSpec::builder(WidestStableBand { phi_op: 1230.0 }, 0.3, vec![plain.model.speed], read.variables)
        .max_iterations(25);
    assert_eq!(built.clone().build(&branches).unwrap(), plain.design.unwrap());
    // β_op above β_max, and no start: refused at the key the file would name.
    assert_eq!(built.clone().beta_max(0.2).build(&branches).unwrap_err().0, "level");
    assert_eq!(built.starts(0).build(&branches).unwrap_err().0, "starts");
}
