//! criterion benches for water (filled in as the modules land).

use criterion::{Criterion, criterion_group, criterion_main};

fn fbm(c: &mut Criterion) {
    let tex = water::noise::NoiseTexture::default_water();
    let fbm = water::noise::Fbm::new(&tex, water::noise::FbmParams::default()).unwrap();
    c.bench_function("fbm_height", |b| {
        b.iter(|| fbm.height(std::hint::black_box(glam::Vec2::new(1.5, 2.5))))
    });
}

criterion_group!(benches, fbm);
criterion_main!(benches);
