//! Steady-state unbalance response (issue 17: 1 000 speeds on the paper's model in under
//! 0.5 s). Reads problems/ like the tests.

use criterion::{criterion_group, criterion_main, Criterion};
use rotorshunt::analysis::unbalance::{probes, unbalance_response, DynamicStiffness, Workspace};
use rotorshunt::analysis::Rotor;
use rotorshunt::problem::Problem;

fn load(name: &str) -> Problem {
    Problem::from_path(format!("{}/problems/{name}", env!("CARGO_MANIFEST_DIR")), &[]).unwrap()
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("unbalance");
    g.sample_size(10);
    // The paper's rotor with damped branches (Fig. 13a, R = 10 ohm): 136 complex DOFs.
    let p = load("fig13-r10.toml");
    let rotor = Rotor::new(&p.model).unwrap();
    let speeds: Vec<f64> = (0..1000).map(|i| 3.0 * i as f64).collect();
    let at = probes(&rotor, &[]).unwrap();
    // The whole library call: 1 000 solves, the disk's and supports' peaks refined.
    g.bench_function("fig13-r10 1000 speeds, peaks refined", |b| {
        b.iter(|| unbalance_response(&rotor, &speeds, &at, &rotorshunt::progress::Silent).unwrap())
    });
    // One speed: one numeric sparse LU and solve.
    let a = DynamicStiffness::of(&rotor).unwrap();
    let mut work = Workspace::default();
    g.bench_function("fig13-r10 one solve", |b| b.iter(|| a.solve(1234.5, &mut work).unwrap()));
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
