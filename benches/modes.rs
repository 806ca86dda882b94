//! Whirl frequencies of the paper's problems (issue: `modes` well under a second).
//! Reads problems/ like the tests.

use criterion::{criterion_group, criterion_main, Criterion};
use rotorshunt::analysis::modes::{whirl_modes, whirl_modes_of};
use rotorshunt::analysis::Rotor;
use rotorshunt::problem::Problem;

fn load(name: &str) -> Problem {
    Problem::from_path(format!("{}/problems/{name}", env!("CARGO_MANIFEST_DIR")), &[]).unwrap()
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("modes");
    g.sample_size(10);
    for name in ["paper-open.toml", "paper-closed.toml"] {
        let p = load(name);
        // The whole `modes` command: assembly, P_cr (open-circuit supports) and the QEP.
        g.bench_function(format!("{name} full"), |b| b.iter(|| whirl_modes(&p.model, &p.settings, 2000.0).unwrap()));
        // One speed of a Campbell diagram: the QEP on a prepared rotor.
        let rotor = Rotor::new(&p.model).unwrap();
        g.bench_function(format!("{name} qep"), |b| b.iter(|| whirl_modes_of(&rotor, &p.settings, 2000.0).unwrap()));
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
