//! The atlas of ASCII and the GD&T symbols built from the bundled fonts on all cores (issue
//! 20's target: ≤ 150 ms on 2 cores, then cached), the whole base atlas (Latin-1 and the
//! engineering signs too) built and read back from the disk cache, and the layout of 3,000
//! labels.

// `criterion_group!` generates an undocumented function.
#![allow(missing_docs)]

use cadre_text::{Align, Baseline, FontChain, GDT_SYMBOLS, MsdfAtlas, Shaper, cache, layout};
use criterion::{Criterion, criterion_group, criterion_main};

fn atlas(c: &mut Criterion) {
    let chain = FontChain::bundled();
    let (keys, _) = chain.resolve_all(FontChain::base_characters());
    let mut group = c.benchmark_group("msdf atlas");
    group.sample_size(10);
    // The set: ASCII and the 27 GD&T symbols.
    let (ascii_gdt, _) = chain.resolve_all((' '..='~').chain(GDT_SYMBOLS.iter().copied()));
    group.bench_function(
        format!("build ASCII + GD&T, {} glyphs", ascii_gdt.len()),
        |b| {
            b.iter(|| MsdfAtlas::build(chain, &ascii_gdt).expect("atlas"));
        },
    );
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
