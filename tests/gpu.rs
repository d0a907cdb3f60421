//! The WGSL methods and walk on whatever adapter there is. Without one these tests skip with a notice,
//! unless TETWALK_REQUIRE_GPU=1 (as CI sets, with lavapipe installed), where they fail.

mod common;

use glam::Vec3;
use tetwalk::cases::{Case, answer, answers_gpu, classify, judged};
use tetwalk::exact::edge_margin;
use tetwalk::gpu::{GPU_METHODS, Gpu};
use tetwalk::methods::by_name;
use tetwalk::report::count::{Backend, Cpu, Gpu as GpuBackend};
use tetwalk::scenes::tets::{Family, Target, near, stabbing_ray, tet};
use tetwalk::scenes::{self, Generated, rng};
use tetwalk::walk::{default_max_steps, locate};

/// llvmpipe and lavapipe compile without contracting multiply-adds: their answers equal the CPU's.
fn contracts(g: &Gpu) -> bool {
    !g.describe().to_lowercase().contains("llvmpipe")
}

#[test]
fn every_gpu_method_is_exact_with_margin() {
    let Some(g) = common::gpu_or_skip() else {
        return;
    };
    let mut r = rng(11);
    let mut cases = Vec::new();
    while cases.len() < 3000 {
        let t = tet(Family::Well, 1.0, &mut r);
        let ray = stabbing_ray(&t, &mut r);
        if edge_margin(&t, &ray) < 1e-4 {
            continue;
        }
        let mut c = Case {
            tet: t,
            org: ray.org,
            dir: ray.dir,
            entry: None,
        };
        let x = classify(&c).unwrap();
        if cases.len() % 2 == 0 {
            c.entry = x.entry.first().map(|f| f as u8);
        }
        cases.push((c, x));
    }
    let plain: Vec<Case> = cases.iter().map(|(c, _)| *c).collect();
    for name in GPU_METHODS {
        let faces = answers_gpu(&g, &plain, by_name(name).unwrap()).unwrap();
        for ((c, x), f) in cases.iter().zip(faces) {
            assert_eq!(
                judged(x, f).correct,
                Some(true),
                "{name} on the GPU: {f:?} for {c:?}"
            );
        }
    }
}

#[test]
fn gpu_answers_equal_the_cpu_where_the_adapter_does_not_contract() {
    let Some(g) = common::gpu_or_skip() else {
        return;
    };
    let mut r = rng(12);
    let cases: Vec<Case> = (0..4000)
        .filter_map(|i| {
            let (t, ray) = near(
                Family::ALL[i % 5],
                1e-3,
                if i % 2 == 0 {
                    Target::Edge
                } else {
                    Target::Vertex
                },
                4,
                &mut r,
            )?;
            Some(Case {
                tet: t,
                org: ray.org,
                dir: ray.dir,
                entry: None,
            })
        })
        .collect();
    for name in GPU_METHODS {
        let m = by_name(name).unwrap();
        let gpu = answers_gpu(&g, &cases, m).unwrap();
        let cpu: Vec<_> = cases.iter().map(|c| answer(c, m, false)).collect();
        let differ = gpu.iter().zip(&cpu).filter(|(a, b)| a != b).count();
        println!(
            "{name}: GPU and CPU differ on {differ} of {} near-edge/vertex cases",
            cases.len()
        );
        if !contracts(&g) {
            assert_eq!(differ, 0, "{name}");
        }
    }
}

#[test]
fn gpu_walks_run_end_to_end_and_match_the_cpu_on_llvmpipe() {
    let Some(g) = common::gpu_or_skip() else {
        return;
    };
    let llvmpipe = !contracts(&g);
    let mesh = scenes::generated_mesh(Generated::Jitter, 6, Vec3::ZERO, 4).unwrap();
    let rays = scenes::rays(Generated::Jitter, &mesh, Vec3::ZERO, 2000, 4);
    let start = locate(&mesh, Vec3::splat(3.0), 0).unwrap();
    // Rays from one start: re-aim the generated ones from that tetrahedron's origin point.
    let org = Vec3::splat(3.0);
    let rays: Vec<_> = rays
        .iter()
        .map(|r| tetwalk::tet::Ray { org, dir: r.dir })
        .collect();
    let backend = GpuBackend::new(g, &mesh);
    let max = default_max_steps(&mesh);
    for name in GPU_METHODS {
        let m = by_name(name).unwrap();
        let on_gpu = backend.walks(&mesh, m, &rays, start, max).unwrap();
        let on_cpu = Cpu { fma: false }
            .walks(&mesh, m, &rays, start, max)
            .unwrap();
        assert_eq!(on_gpu.len(), rays.len());
        let differ = on_gpu.iter().zip(&on_cpu).filter(|(a, b)| a != b).count();
        println!(
            "{name}: {differ} of {} walks differ between GPU and CPU",
            rays.len()
        );
        if llvmpipe {
            assert_eq!(on_gpu, on_cpu, "{name}");
        }
        assert!(on_gpu.iter().all(|w| w.steps >= 1 && w.steps <= max));
    }
}
