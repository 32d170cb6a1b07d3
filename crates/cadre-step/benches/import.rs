//! Import (parse + B-Rep + assembly, no tessellation) of every corpus file, as one
//! throughput figure: the cadre half of `scripts/bench_import.sh`, which times OCCT on the same
//! files in the same run. Skips with a message when `../shared/corpus` is absent.

#![allow(
    missing_docs,
    reason = "criterion_group! generates an undocumented function"
)]

use std::hint::black_box;
use std::path::PathBuf;
use std::time::Duration;

use cadre_step::syntax::StepFile;
use criterion::{Criterion, Throughput, criterion_group, criterion_main};

fn corpus() -> Vec<(PathBuf, Vec<u8>)> {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/corpus/step");
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut files: Vec<(PathBuf, Vec<u8>)> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter_map(|p| std::fs::read(&p).ok().map(|b| (p, b)))
        .collect();
    files.sort();
    files
}

fn import(c: &mut Criterion) {
    let files = corpus();
    if files.is_empty() {
        println!("skipping: ../shared/corpus not found");
        return;
    }
    let bytes: usize = files.iter().map(|(_, b)| b.len()).sum();
    let mut group = c.benchmark_group("import");
    group.throughput(Throughput::Bytes(bytes as u64));
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(20));
    group.bench_function("corpus", |b| {
        b.iter(|| {
            for (_, data) in &files {
                if let Ok(file) = StepFile::parse(data.clone()) {
                    black_box(cadre_step::map_file(&file));
                }
            }
        })
    });
    group.finish();
}

criterion_group!(benches, import);
criterion_main!(benches);
