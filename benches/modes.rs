//! Whirl frequencies of the paper's problems (issue: `modes` well under a second), and of
//! a 200-element anisotropic rotor (issue 28: under 1 s), where the shift-invert Krylov
//! solve of the lowest whirls is measured against the dense solve it replaces, in the
//! same run. Reads problems/ and tests/fixtures/ like the tests.

use criterion::{criterion_group, criterion_main, Criterion};
use rotorshunt::analysis::modes::{lowest_whirls_of, whirl_modes, whirl_modes_of};
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

criterion_group!(benches, bench);
criterion_main!(benches);
