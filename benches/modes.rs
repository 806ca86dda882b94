//! Whirl frequencies of the paper's problems (issue: `modes` well under a second), and of
//! a 200-element anisotropic rotor (issue 28: under 1 s), where the shift-invert Krylov
//! solve of the lowest whirls is measured against the dense solve it replaces, in the
//! same run; and (group `krylov-vs-faer`, issue 48) the block Krylov solver of the
//! lowest whirls against faer's partial eigensolver on the same operator. Reads
//! problems/ and tests/fixtures/ like the tests.

use criterion::{criterion_group, criterion_main, Criterion};
use rotorshunt::analysis::modes::{
    lowest_whirls_of, whirl_modes, whirl_modes_nearest_by, whirl_modes_of, NearestSolver, WHIRL_WINDOW,
};
use rotorshunt::analysis::Rotor;
use rotorshunt::problem::Problem;

fn load(path: &str) -> Problem {
    Problem::from_path(format!("{}/{path}", env!("CARGO_MANIFEST_DIR")), &[]).unwrap()
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("modes");
    g.sample_size(10);
    for name in ["paper-open.toml", "paper-closed.toml"] {
        let p = load(&format!("problems/{name}"));
        // The whole `modes` command: assembly, P_cr (open-circuit supports) and the QEP.
        g.bench_function(format!("{name} full"), |b| b.iter(|| whirl_modes(&p.model, &p.settings, 2000.0).unwrap()));
        // One speed of a Campbell diagram: the QEP on a prepared rotor.
        let rotor = Rotor::new(&p.model).unwrap();
        g.bench_function(format!("{name} qep"), |b| b.iter(|| whirl_modes_of(&rotor, &p.settings, 2000.0).unwrap()));
    }
    // tests/fixtures/aniso/stepped-aniso-200.toml: the stepped rotor on a cross-coupled
    // tabulated bearing and a seal, refined to 200 elements (a first-order state of 1616).
    let p = load("tests/fixtures/aniso/stepped-aniso-200.toml");
    let speed = p.model.speed;
    // `modes FILE` (count 4): assembly, P_cr and the Krylov solve of the window.
    g.bench_function("stepped-aniso-200 modes krylov", |b| {
        b.iter(|| lowest_whirls_of(&Rotor::new(&p.model).unwrap(), &p.settings, speed, 4).unwrap())
    });
    // The same with the dense solve of every whirl, as `modes` did before.
    g.bench_function("stepped-aniso-200 modes dense", |b| {
        b.iter(|| whirl_modes_of(&Rotor::new(&p.model).unwrap(), &p.settings, speed).unwrap())
    });
    g.finish();
}

/// `modes --count 4`'s window (16 whirls) nearest λ = 0 on the real path, by the block
/// Krylov solver and by faer's partial eigensolver on the same shift-invert operator,
/// each problem's two solvers one after the other in the same run: assembly at the speed, the factorisations, the
/// solve and the whirls' QEP residuals. `cargo bench --bench modes -- krylov-vs-faer`.
fn krylov_vs_faer(c: &mut Criterion) {
    let mut g = c.benchmark_group("krylov-vs-faer");
    g.sample_size(10);
    let cases: [(&str, &[&str]); 4] = [
        ("tests/fixtures/aniso/stepped-aniso-200.toml", &[]),
        ("tests/fixtures/aniso/stepped-aniso.toml", &[]),
        ("problems/ross/compressor_example.toml", &[]),
        ("problems/paper-closed.toml", &["analysis.coordinates=\"real\""]),
    ];
    for (path, set) in cases {
        let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
        let p = Problem::from_path(format!("{}/{path}", env!("CARGO_MANIFEST_DIR")), &set).unwrap();
        let rotor = Rotor::new(&p.model).unwrap();
        // The whole state allowed, as tests/fast_modes.rs: `modes`' third of it
        // (KRYLOV_STATE_FRACTION) leaves the block solver short on the 240-state rotor.
        let (speed, limit) = (p.model.speed, 2 * rotor.general_size());
        let name = path.rsplit('/').next().unwrap_or(path);
        for (label, solver) in [("block", NearestSolver::Block), ("faer", NearestSolver::Faer)] {
            let run = || whirl_modes_nearest_by(&rotor, &p.settings, speed, WHIRL_WINDOW * 4, limit, solver).unwrap();
            // Timed only where it resolves the window (no fallback to the dense solve).
            assert!(run().is_some(), "{name} {label}: fell back");
            g.bench_function(format!("{name} {label}"), |b| b.iter(run));
        }
    }
    g.finish();
}

criterion_group!(benches, bench, krylov_vs_faer);
criterion_main!(benches);
