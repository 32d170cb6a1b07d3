//! The atlas of the base characters (ASCII, Latin-1, GD&T and engineering signs) built from
//! the bundled fonts on all cores (issue 20's target: ≤ 150 ms on 2 cores, then cached), the
//! same read back from the disk cache, and the layout of 3,000 labels (≤ 1 ms target).

// `criterion_group!` generates an undocumented function.
#![allow(missing_docs)]

use cadre_text::{Align, Baseline, FontChain, MsdfAtlas, Shaper, cache, layout};
use criterion::{Criterion, criterion_group, criterion_main};

fn atlas(c: &mut Criterion) {
    let chain = FontChain::bundled();
    let (keys, _) = chain.resolve_all(FontChain::base_characters());
    let mut group = c.benchmark_group("msdf atlas");
    group.sample_size(10);
    group.bench_function(format!("build {} base glyphs", keys.len()), |b| {
        b.iter(|| MsdfAtlas::build(chain, &keys).expect("atlas"));
    });
    let dir = std::env::temp_dir().join("cadre-text-bench-cache");
    let _ = cache::load_or_build(chain, &keys, Some(&dir));
    group.bench_function("read from the disk cache", |b| {
        b.iter(|| cache::load_or_build(chain, &keys, Some(&dir)));
    });
    group.finish();
}

fn labels(c: &mut Criterion) {
    let chain = FontChain::bundled();
    let shaper = Shaper::bundled();
    let names: Vec<String> = (0..3000).map(|i| format!("Bolt M8×30 #{i}")).collect();
    c.bench_function("layout 3,000 labels", |b| {
        b.iter(|| {
            names
                .iter()
                .map(|n| {
                    layout(chain, shaper, n, (Align::Left, Baseline::Middle), 1.0)
                        .glyphs
                        .len()
                })
                .sum::<usize>()
        });
    });
}

criterion_group!(benches, atlas, labels);
criterion_main!(benches);
