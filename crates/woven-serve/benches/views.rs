//! The explorer's view update: every view of `/api/views` (in-plane curve, the three hemisphere
//! maps, the goniometer curves) for one material and incidence, on all cores, as the server
//! computes them after a slider moves (without HTTP). The target: ≤ 200 ms for a
//! single-orientation yarn (the polyester-sateen preset) on two cores.
//!
//!   cargo bench -p woven-serve --bench views

// criterion_group! and criterion_main! generate undocumented items.
#![allow(missing_docs)]

use criterion::{criterion_group, criterion_main, Criterion};
use std::time::Duration;
use tokio::sync::mpsc;
use woven::material::Material;
use woven_serve::job::{Channels, Emitter};
use woven_serve::views::{compute, Which};

fn views(c: &mut Criterion) {
    let mut group = c.benchmark_group("views");
    group
        .sample_size(20)
        .measurement_time(Duration::from_secs(8));
    let channels = Channels::default();
    let all = Which {
        hemisphere: true,
        plane: true,
        gonio: true,
    };
    let model = Material::preset("polyester-sateen")
        .unwrap()
        .build(550.0)
        .unwrap();
    for (name, which) in [
        ("polyester-sateen/all", all),
        (
            "polyester-sateen/click (hemisphere + plane)",
            Which {
                gonio: false,
                ..all
            },
        ),
    ] {
        group.bench_function(name, |b| {
            b.iter(|| {
                let (tx, mut rx) = mpsc::channel(1024);
                let out = Emitter::new(tx, channels.begin(None));
                compute(&model, 45f64.to_radians(), 0.0, which, &out);
                drop(out);
                let mut lines = 0;
                while rx.try_recv().is_ok() {
                    lines += 1;
                }
                assert!(lines >= 2);
            })
        });
    }
    group.finish();
}

criterion_group!(benches, views);
criterion_main!(benches);
