//! Loading time against file size (issue: linear-time loading): problem files of 10³,
//! 10⁴ and 10⁵ `[[disks]]`, parsed, checked and translated into the model. Linear loading
//! shows as the same time per disk at every size. Reads problems/ like the tests.

#[path = "../tests/common/mod.rs"]
mod common;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use rotorshunt::problem::Problem;

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("loading");
    g.sample_size(10);
    for n in [1_000, 10_000, 100_000] {
        let text = common::many_disks_text(n);
        g.throughput(Throughput::Elements(n as u64));
        g.bench_function(format!("{n} disks ({} bytes)", text.len()), |b| {
            b.iter(|| Problem::from_text(&text, "disks.toml", &[]).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
