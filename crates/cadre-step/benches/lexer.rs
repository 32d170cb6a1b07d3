//! Throughput of the STEP syntax layer on the largest corpus file:
//! (a) tokenising with [`Lexer`], (b) [`StepFile::parse`] (structure + index),
//! (c) parse plus decoding every instance on one thread.
//!
//! Without `../shared/corpus` a synthetic ~5 MB file is generated instead, so the bench
//! always runs; `CADRE_STEP_BENCH_FILE=path` benchmarks any other file.

use std::hint::black_box;
use std::time::Duration;

use cadre_step::syntax::{Lexer, StepFile};
use criterion::{BatchSize, Criterion, Throughput, criterion_main};

const CORPUS_FILE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../../shared/corpus/step/trj9_ap209-mp.stp"
);

/// A plausible B-Rep-ish file of about `size` bytes.
fn synthetic(size: usize) -> Vec<u8> {
    let mut s = String::from(
        "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION(('synthetic'),'2;1');\n\
         FILE_NAME('synthetic.stp','2024-01-01T00:00:00',(''),(''),'','','');\n\
         FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));\nENDSEC;\nDATA;\n",
    );
    let mut id = 1u64;
    while s.len() < size {
        let x = id as f64 * 0.731;
        s.push_str(&format!(
            "#{id}=CARTESIAN_POINT('',({x:.6E},{:.6E},-{:.6E}));\n",
            x * 1.5,
            x / 3.0
        ));
        s.push_str(&format!(
            "#{}=DIRECTION('',(0.E0,1.E0,0.E0));\n#{}=AXIS2_PLACEMENT_3D('',#{id},#{},$);\n",
            id + 1,
            id + 2,
            id + 1
        ));
        s.push_str(&format!(
            "#{}=(GEOMETRIC_REPRESENTATION_CONTEXT(3) REPRESENTATION_CONTEXT('ctx {}',''));\n",
            id + 3,
            id
        ));
        id += 4;
    }
    s.push_str("ENDSEC;\nEND-ISO-10303-21;\n");
    s.into_bytes()
}

fn input() -> (String, Vec<u8>) {
    // `CADRE_STEP_BENCH_FILE` benchmarks another file instead.
    let path = std::env::var("CADRE_STEP_BENCH_FILE").unwrap_or_else(|_| CORPUS_FILE.to_owned());
    match std::fs::read(&path) {
        Ok(bytes) => {
            let name = path.rsplit('/').next().unwrap_or("input").to_owned();
            (name, bytes)
        }
        Err(_) => {
            println!("../shared/corpus not found: using a synthetic 5 MB file");
            ("synthetic".to_owned(), synthetic(5 << 20))
        }
    }
}

fn bench(c: &mut Criterion) {
    let (name, bytes) = input();
    let mut group = c.benchmark_group(format!("step/{name}"));
    group.throughput(Throughput::Bytes(bytes.len() as u64));
    group.sample_size(30);
    group.measurement_time(Duration::from_secs(4));

    group.bench_function("lexer", |b| {
        b.iter(|| {
            let mut lexer = Lexer::new(black_box(&bytes));
            let mut tokens = 0usize;
            while let Ok(Some(token)) = lexer.next_token() {
                black_box(token);
                tokens += 1;
            }
            tokens
        })
    });

    group.bench_function("index", |b| {
        b.iter_batched(
            || bytes.clone(),
            |bytes| StepFile::parse(bytes).map(|f| f.len()),
            BatchSize::LargeInput,
        )
    });

    group.bench_function("index+decode", |b| {
        b.iter_batched(
            || bytes.clone(),
            |bytes| {
                let Ok(file) = StepFile::parse(bytes) else {
                    return 0;
                };
                let mut records = 0usize;
                for id in file.ids() {
                    if let Ok(instance) = file.instance(id) {
                        records += instance.records.len();
                        black_box(&instance);
                    }
                }
                records
            },
            BatchSize::LargeInput,
        )
    });
    group.finish();
}

// `criterion_group!` expands to an undocumented `pub fn`; there is nothing to document.
#[allow(missing_docs)]
mod group {
    criterion::criterion_group!(benches, super::bench);
}
use group::benches;
criterion_main!(benches);
