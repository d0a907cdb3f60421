//! Exit-face methods and walks, timed in the same run so that their ratios can be read off.
//! `cargo bench`; compare methods against each other, not against other machines.

use criterion::{Criterion, criterion_group, criterion_main};
use glam::Vec3;
use std::hint::black_box;
use tetwalk::exact::classify;
use tetwalk::mesh::layout::Layout;
use tetwalk::methods::Model;
use tetwalk::registry::METHODS;
use tetwalk::registry::Named;
use tetwalk::scenes::tets::{TetShape, stabbing_ray, tet};
use tetwalk::scenes::{self, Generated, rng};
use tetwalk::walk::layouts::{LayoutKind, Source};
use tetwalk::walk::{default_max_steps, locate};

fn exit_faces(c: &mut Criterion) {
    let mut r = rng(1);
    let cases: Vec<_> = (0..4096)
        .map(|_| {
            let t = tet(TetShape::Well, 1.0, &mut r);
            let ray = stabbing_ray(&t, &mut r);
            let entry = classify(&t, &ray).unwrap().entry.first();
            (t, ray, entry)
        })
        .collect();
    let mut g = c.benchmark_group("exit_face_4096_cases");
    for m in METHODS.iter().filter(|m| m.name() != "exact") {
        for model in [Model::Plain, Model::Fused] {
            let exit = m.exit(model);
            let name = if model == Model::Fused {
                format!("{} fma", m.name())
            } else {
                m.name().to_string()
            };
            g.bench_function(name, |b| {
                b.iter(|| {
                    cases
                        .iter()
                        .map(|(t, ray, e)| exit(t, ray, *e).unwrap_or(9))
                        .sum::<usize>()
                })
            });
        }
    }
    g.finish();
}

fn walks(c: &mut Criterion) {
    let mesh = tetwalk::mesh::reorder::hilbert_sorted(
        &scenes::generated_mesh(Generated::Jitter, 12, Vec3::ZERO, 1).unwrap(),
    );
    let layout = Layout::build(&mesh);
    let max = default_max_steps(&mesh);
    let rays: Vec<_> = scenes::rays(Generated::Jitter, &mesh, Vec3::ZERO, 2048, 1)
        .into_iter()
        .filter_map(|ray| Some((ray, locate(&mesh, ray.org, 0).ok()?)))
        .collect();
    let mut g = c.benchmark_group("walk_2048_rays_jitter12");
    for m in METHODS.iter().filter(|m| m.name() != "exact") {
        let walk = m.walk(Model::Plain);
        g.bench_function(m.name(), |b| {
            b.iter(|| {
                rays.iter()
                    .map(|(ray, s)| walk(&mesh, ray, *s, max).steps)
                    .sum::<u32>()
            })
        });
        if let Some(lw) = m.layout_walk(Model::Plain) {
            for kind in [LayoutKind::Tet32, LayoutKind::Tet20, LayoutKind::Tet16] {
                g.bench_function(format!("{} {kind:?}", m.name()), |b| {
                    b.iter(|| {
                        rays.iter()
                            .map(|(ray, s)| {
                                lw(
                                    kind,
                                    &layout,
                                    &mesh.points,
                                    ray,
                                    &Source::new(&layout, *s),
                                    max,
                                )
                                .1
                            })
                            .sum::<u32>()
                    })
                });
            }
        }
    }
    g.finish();
    black_box(&rays);
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).measurement_time(std::time::Duration::from_secs(2)).warm_up_time(std::time::Duration::from_millis(500));
    targets = exit_faces, walks
}
criterion_main!(benches);
