//! The generated WGSL methods and walk on whatever adapter there is, through the backend seam; on
//! llvmpipe every method equals the CPU, and `certified` equals it on every adapter. Without
//! one these tests skip with a notice, unless TETWALK_REQUIRE_GPU=1 (as CI sets, with lavapipe
//! installed), where they fail.

mod common;

use glam::Vec3;
use tetwalk::backend::BackendKind;
use tetwalk::backend::{Against, Backend};
use tetwalk::cases::classify;
use tetwalk::engine::count::Shard;
use tetwalk::exact::edge_margin;
use tetwalk::family::{ExitFace, Family, Verdict};
use tetwalk::methods::Model;
use tetwalk::registry::Named;
use tetwalk::registry::{GpuVersion as GpuSupport, METHODS, Method};
use tetwalk::scenes::tets::{Target, TetShape, near, stabbing_ray, tet};
use tetwalk::scenes::{self, Generated, rng};
use tetwalk::tet::{Case, Ray};
use tetwalk::walk::{OutcomeKind, default_max_steps, locate};

/// llvmpipe and lavapipe compile without contracting multiply-adds: their answers equal the CPU's.
fn contracts(g: &Backend) -> bool {
    !g.describe().to_lowercase().contains("llvmpipe")
}

fn gpu_methods() -> impl Iterator<Item = &'static Method> {
    METHODS
        .iter()
        .filter(|m| matches!(m.info.gpu, GpuSupport::Wgsl(_)))
}

/// Near-edge and near-vertex cases of every family; every other one carries its exact entry face.
fn near_cases(seed: u64, n: usize) -> Vec<Case> {
    let mut r = rng(seed);
    (0..n)
        .filter_map(|i| {
            let target = if i % 2 == 0 {
                Target::Edge
            } else {
                Target::Vertex
            };
            let (t, ray) = near(TetShape::ALL[i % 5], 1e-3, target, 4, &mut r)?;
            let mut c = Case {
                tet: t,
                org: ray.org,
                dir: ray.dir,
                entry: None,
            };
            if (i / 2) % 2 == 0 {
                c.entry = classify(&c).ok()?.entry.first().map(|f| f as u8);
            }
            Some(c)
        })
        .collect()
}

#[test]
fn every_gpu_method_is_exact_with_margin() {
    let Some(g) = common::gpu_or_skip() else {
        return;
    };
    let mut r = rng(11);
    let mut cases = Vec::new();
    while cases.len() < 3000 {
        let t = tet(TetShape::Well, 1.0, &mut r);
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
    for m in gpu_methods() {
        let faces = g.exit_faces(m, &plain).unwrap();
        for ((c, x), f) in cases.iter().zip(faces) {
            assert_eq!(
                ExitFace::verdict(c, x, &f.map(|f| f as u8)),
                Verdict::Right,
                "{} on the GPU: {f:?} for {c:?}",
                m.name()
            );
        }
    }
}

#[test]
fn gpu_answers_equal_the_cpu_from_entry_faces_and_starts_where_the_adapter_does_not_contract() {
    let Some(g) = common::gpu_or_skip() else {
        return;
    };
    let cases = near_cases(12, 4000);
    let with_entry = cases.iter().filter(|c| c.entry.is_some()).count();
    assert!(
        with_entry > 1000 && cases.len() - with_entry > 1000,
        "both kinds of case: {with_entry} with an entry face of {}",
        cases.len()
    );
    for m in gpu_methods() {
        let gpu = g.exit_faces(m, &cases).unwrap();
        let cpu = Backend::Cpu {
            model: Model::Plain,
        }
        .exit_faces(m, &cases)
        .unwrap();
        let differ = gpu.iter().zip(&cpu).filter(|(a, b)| a != b).count();
        println!(
            "{}: GPU and CPU differ on {differ} of {} near-edge/vertex cases",
            m.name(),
            cases.len()
        );
        // tetwalk's own method is exact on every adapter: what the GPU cannot settle, the CPU does.
        if !contracts(&g) || !m.info.published {
            assert_eq!(differ, 0, "{}", m.name());
        }
    }
}

#[test]
fn a_method_without_a_gpu_version_is_refused_on_the_gpu_with_its_reason() {
    let Some(Backend::Gpu(g)) = common::gpu_or_skip() else {
        return;
    };
    for m in METHODS {
        if let GpuSupport::CpuOnly(why) = m.info.gpu {
            let err = g.exit_faces(m, &[]).unwrap_err().to_string();
            assert!(err.contains(why) && err.contains(m.name()), "{err}");
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
    // Each ray from the tetrahedron holding its origin, as one batch.
    let rays: Vec<(Ray, u32)> = scenes::rays(Generated::Jitter, &mesh, Vec3::ZERO, 2000, 4)
        .into_iter()
        .filter_map(|r| Some((r, locate(&mesh, r.org, 0).ok()?)))
        .collect();
    assert!(rays.len() > 1500);
    let on_gpu_mesh = g.mesh(&mesh);
    let cpu = Backend::Cpu {
        model: Model::Plain,
    };
    let on_cpu_mesh = cpu.mesh(&mesh);
    let max = default_max_steps(&mesh);
    for m in gpu_methods() {
        let on_gpu = g.walks_from(m, &on_gpu_mesh, &rays, max).unwrap();
        let on_cpu = cpu.walks_from(m, &on_cpu_mesh, &rays, max).unwrap().walks;
        if g.kind() == tetwalk::backend::BackendKind::Gpu
            && let Backend::Gpu(gpu) = &g
            && gpu.measures_kernels()
        {
            assert!(
                on_gpu.kernel_seconds.is_some_and(|s| s > 0.0),
                "{}",
                m.name()
            );
        }
        let on_gpu = on_gpu.walks;
        assert_eq!(on_gpu.len(), rays.len());
        let differ = on_gpu.iter().zip(&on_cpu).filter(|(a, b)| a != b).count();
        println!(
            "{}: {differ} of {} walks differ between GPU and CPU",
            m.name(),
            rays.len()
        );
        if llvmpipe || !m.info.published {
            assert_eq!(on_gpu, on_cpu, "{}", m.name());
        }
        assert!(on_gpu.iter().all(|w| w.steps >= 1 && w.steps <= max));
    }
}

/// `bench` on the GPU beside the CPU, over the same rays of several views in one batch (each ray
/// from its own view's starting tetrahedron): every ray is walked, the kernel time is reported when the
/// adapter measures one, and `certified` traverses exactly the tetrahedra it traverses on the CPU
/// (its flagged rays finished there).
#[test]
fn bench_on_the_gpu_walks_every_ray_of_every_view_as_the_cpu_does() {
    let Some(g) = common::gpu_or_skip() else {
        return;
    };
    let measures = g.measures_kernels();
    let scene = scenes::load("kuhn", tetwalk::mesh::Faces::Required).unwrap();
    let views = tetwalk::scenes::camera::Views::new(4, 24, 24, 1);
    let certified = tetwalk::registry::by_name("certified").unwrap();
    let backends = [
        Backend::Cpu {
            model: Model::Plain,
        },
        g,
    ];
    let r = tetwalk::engine::bench::run(
        &scene,
        false,
        &views,
        &[certified],
        &[&backends[0], &backends[1]],
        (1 << 20, false, 1),
        &|| {},
    )
    .unwrap();
    assert!(r.views_timed >= 2, "several views in one batch");
    let [cpu, gpu] = [&r.rows[0], &r.rows[1]];
    assert_eq!(gpu.backend, BackendKind::Gpu);
    assert_eq!(gpu.rays, cpu.rays);
    assert_eq!(gpu.rays, r.views_timed as u64 * 24 * 24);
    assert_eq!(gpu.tetrahedra, cpu.tetrahedra);
    assert_eq!(gpu.kernel_seconds.is_some(), measures);
    assert!(cpu.kernel_seconds.is_none());
}

/// Seed 003 on the GPU: `aman20` and `aman20-scaled` walk Tet32, Tet20 and Tet16 in WGSL, on a plain
/// and a Hilbert-ordered mesh, each ray from its own source tetrahedron; on an adapter that does not
/// contract multiply-adds every walk equals the CPU layout walk (outcome, tetrahedron, vertex across
/// the face, steps), elsewhere the differences are counted and shown, and every walk ends on the same
/// kind of stop with at least one step.
#[test]
fn layout_walks_on_the_gpu_equal_the_cpu_ones() {
    let Some(g) = common::gpu_or_skip() else {
        return;
    };
    let exact_adapter = !contracts(&g);
    let plain = scenes::generated_mesh(Generated::Jitter, 8, Vec3::ZERO, 2).unwrap();
    let cpu = Backend::Cpu {
        model: Model::Plain,
    };
    for mesh in [
        plain.clone(),
        tetwalk::mesh::reorder::hilbert_sorted(&plain),
    ] {
        let layout = tetwalk::mesh::layout::Layout::build(&mesh);
        let rays: Vec<(Ray, tetwalk::walk::layouts::Source)> =
            scenes::rays(Generated::Jitter, &mesh, Vec3::ZERO, 1500, 5)
                .into_iter()
                .filter_map(|r| {
                    let s = locate(&mesh, r.org, 0).ok()?;
                    Some((r, tetwalk::walk::layouts::Source::new(&layout, s)))
                })
                .collect();
        assert!(rays.len() > 1000);
        let max = default_max_steps(&mesh);
        let on_gpu = g.layout(&layout, &mesh.points);
        let on_cpu = cpu.layout(&layout, &mesh.points);
        for m in METHODS
            .iter()
            .filter(|m| m.layout_walk(Model::Plain).is_some())
        {
            for kind in <tetwalk::walk::layouts::LayoutKind as tetwalk::choice::Choice>::ALL {
                let a = g.layout_walks(m, *kind, &on_gpu, &rays, max).unwrap();
                let b = cpu.layout_walks(m, *kind, &on_cpu, &rays, max).unwrap();
                assert_eq!(a.walks.len(), rays.len());
                let differ = a.walks.iter().zip(&b.walks).filter(|(x, y)| x != y).count();
                println!("{} {kind:?}: {differ} of {} differ", m.name(), rays.len());
                if exact_adapter {
                    assert_eq!(a.walks, b.walks, "{} {kind:?}", m.name());
                } else {
                    assert!(differ * 20 < rays.len(), "{} {kind:?}: {differ}", m.name());
                }
                assert!(a.walks.iter().all(|(_, steps)| *steps >= 1));
            }
        }
        // A method without a layout walk is refused with its name.
        let maria17 = tetwalk::registry::by_name("maria17").unwrap();
        let err = g
            .layout_walks(
                maria17,
                tetwalk::walk::layouts::LayoutKind::Tet20,
                &on_gpu,
                &rays,
                max,
            )
            .err()
            .unwrap()
            .to_string();
        assert!(err.contains("maria17") && err.contains("layout"), "{err}");
    }
}

/// A batch larger than one dispatch ([`tetwalk::gpu::DISPATCH_RUN`] items) is split into several:
/// the answers come back complete and in order — `certified`'s equal the CPU's case for case on any adapter (what the GPU cannot settle,
/// the CPU answers).
#[test]
fn batches_larger_than_one_dispatch_come_back_whole_and_in_order() {
    let Some(g) = common::gpu_or_skip() else {
        return;
    };
    let base = near_cases(21, 4000);
    let n = tetwalk::gpu::DISPATCH_RUN + 12_345;
    let cases: Vec<Case> = (0..n).map(|i| base[(i * 7919) % base.len()]).collect();
    let certified = tetwalk::registry::by_name("certified").unwrap();
    let on_gpu = g.exit_faces(certified, &cases).unwrap();
    let on_cpu = Backend::Cpu {
        model: Model::Plain,
    }
    .exit_faces(certified, &cases)
    .unwrap();
    assert_eq!(on_gpu.len(), n);
    assert!(
        on_gpu == on_cpu,
        "certified answers differ between the GPU and the CPU"
    );
}

/// `tetwalk paper` with a GPU backend: its column of Table 4 is a count like the CPU's, Table 5 gains
/// the GPU's kernel time per query for every method with a GPU version (where the adapter measures
/// kernel times), seed 003's structures are walked on it, and the adapter and driver are written once
/// at the top.
#[test]
fn paper_gives_a_gpu_its_columns_with_its_adapter() {
    let Some(g) = common::gpu_or_skip() else {
        return;
    };
    let scene = scenes::load("kuhn", tetwalk::mesh::Faces::Required).unwrap();
    let size = tetwalk::engine::paper::Size {
        views: 2,
        side: 16,
        tets: 20,
        rays: 8,
        triangle_side: 8,
        bench_views: 2,
    };
    let measures = g.measures_kernels();
    let adapter = g.ran();
    let backends = [
        Backend::Cpu {
            model: Model::Plain,
        },
        g,
    ];
    let r = tetwalk::engine::paper::run(&scene, size, Shard::ALL, &backends, &|| ()).unwrap();
    assert_eq!(r.counts.len(), 2);
    assert_eq!(r.counts[1].backend, adapter);
    assert_eq!(r.counts[1].rays, r.counts[0].rays);
    assert_eq!(r.octrees[1].backend, adapter);
    assert_eq!(r.octrees[1].rays, r.octrees[0].rays);
    let timed = r.timings.as_ref().expect("a whole run is timed");
    assert_eq!(timed.table5_gpu.len(), usize::from(measures));
    for t in &timed.table5_gpu {
        assert_eq!(t.backend, adapter);
        assert_eq!(
            t.times.len(),
            gpu_methods().filter(|m| !m.is_reference()).count()
        );
        assert!(t.times.iter().all(|q| q.ns_per_query > 0.0), "{t:?}");
    }
    let on_gpu: Vec<_> = timed
        .speed
        .rows
        .iter()
        .filter(|x| x.backend == BackendKind::Gpu)
        .collect();
    for (method, layout) in [("stp", "cells"), ("maria17", "cells"), ("aman20", "tet20")] {
        assert!(
            on_gpu
                .iter()
                .any(|x| x.method == method && x.layout == layout && x.rays > 0),
            "{method} over {layout} walked on the GPU"
        );
    }
    let text = r.markdown();
    assert_eq!(text.matches(&format!("- {adapter}")).count(), 1, "{text}");
    assert!(text.contains("| ours, cpu | ours, gpu |"), "{text}");
    assert_eq!(text.contains("ours, gpu: ns/query"), measures, "{text}");
}

/// The methods that divide before their tests: Vulkan lets f32 division be 2.5 ulps off (lavapipe's
/// is), so on a case right at an edge their GPU answer may differ from the CPU's (and
/// `woop-watertight`'s WGSL falls back to f32 products where its CPU version uses f64).
const DIVIDE: [&str; 6] = [
    "mt-two-sided",
    "mt-precomputed",
    "komatsu-packet",
    "woop-watertight",
    "portalez16",
    "portalez16-direction",
];

/// One family's generated stress cases (`per_row` a row) on cpu, cpu-fma and the GPU, through the
/// engine's one differential check: where the adapter does not contract, every method answers every
/// case as the CPU does but for the ones that divide, which must still agree on 95% of the cases.
fn gpu_agrees_with_the_cpu<F: Family>(g: &Backend, per_row: usize) {
    let s = tetwalk::engine::stress::StressSettings::<F> {
        contract: Default::default(),
        cases: per_row,
        rows: F::Rows::default(),
        seed: 7,
        backend: g.ran(),
        scale: Default::default(),
    };
    let methods: Vec<&F::Method> = F::methods()
        .iter()
        .filter(|m| matches!(m.info().gpu, GpuSupport::Wgsl(_)))
        .collect();
    let d = tetwalk::engine::stress::compare(&s, &methods, g).unwrap();
    assert!(!d.rows.is_empty() && !d.methods.is_empty(), "{}", F::NAME);
    for (i, name) in d.methods.iter().enumerate() {
        let (differ, cases) = d.rows.iter().fold((0, 0), |(n, all), r| {
            let vs = &r.methods[i].gpu_vs;
            assert_eq!(vs.len(), Model::ALL.len());
            assert!(
                vs.iter()
                    .zip(Model::ALL)
                    .all(|((k, _), m)| *k == m.backend())
            );
            (n + vs[0].1, all + r.cases as u64)
        });
        println!(
            "{} {name}: the GPU differs from the CPU on {differ} of {cases}",
            F::NAME
        );
        if contracts(g) {
            continue;
        }
        if DIVIDE.contains(&name.as_str()) {
            assert!(
                differ * 20 <= cases,
                "{} {name}: {differ} of {cases}",
                F::NAME
            );
        } else {
            assert_eq!(differ, 0, "{} {name}", F::NAME);
        }
    }
}

#[test]
fn every_family_answers_on_the_gpu_as_on_the_cpu_through_one_differential_check() {
    let Some(g) = common::gpu_or_skip() else {
        return;
    };
    gpu_agrees_with_the_cpu::<ExitFace>(&g, 300);
    gpu_agrees_with_the_cpu::<tetwalk::family::Walks>(&g, 100);
    gpu_agrees_with_the_cpu::<tetwalk::family::Triangle>(&g, 100);
    gpu_agrees_with_the_cpu::<tetwalk::family::OctreeCells>(&g, 200);
}

/// A count on the GPU keeps the reference walk's rays and endings there and compares each method's
/// answers with them where they are made, in every family. The reference walk writes the rays (32
/// bytes a ray, and 16 for each ray it flagged, walked on the CPU and written over its ending) and
/// reads back only its counters (32 bytes a dispatch, with the timestamps), the audited rays'
/// endings (16 bytes each) and the rays it flagged (32 bytes each): in the walk family that is the
/// reference row's. Every method row writes only its dispatches' uniforms (and the first octree
/// walk of a view, each ray with its entry cell, 32 bytes, for every octree method) and reads back
/// only its counters and the answers not settled there (32 bytes each, with the reference's ending:
/// every wrong ray, and few right ones), the first of them (one for every 64 rays, and 16) read with
/// the counters, the reference walk and every method row of a view in one wait (counted on the
/// reference walk's), the rest in a second (a row whose records the next row sent over before the
/// wait dispatched again). The counts, wrong rays by kind and steps, equal the CPU's
/// where the adapter does not contract, but the octree walk's (seed 001's cell methods divide, and
/// lavapipe's f32 division is not correctly rounded: its answers are held to the GPU's own read back
/// in `octree_walks_are_compared_on_the_gpu_as_they_read_back`); a CPU count reports no transfer.
/// On `kuhn-far`, where most walk and octree methods fail often.
#[test]
fn a_gpu_count_compares_on_the_gpu_reads_back_little_and_counts_as_the_cpu() {
    let Some(g) = common::gpu_or_skip() else {
        return;
    };
    // Family, bytes written per ray by all its method rows beside their uniforms, the wrong rays
    // the scene makes at least, and whether the counts are the CPU's.
    for (family, written, least, as_cpu) in [
        ("walk", 0, 1000, true),
        ("octree", 32, 1000, false),
        ("triangle", 0, 0, true),
    ] {
        count_compared(&g, family, written, least, as_cpu);
    }
}

/// [`a_gpu_count_compares_on_the_gpu_reads_back_little_and_counts_as_the_cpu`] for one family.
fn count_compared(g: &Backend, family: &str, written: u64, least: u64, as_cpu: bool) {
    let count = |backend: &str| {
        let dir = tempfile::tempdir().unwrap();
        let json = dir.path().join("count.json");
        let dump = dir.path().join("dump.jsonl");
        let (code, _, err) = common::run_tetwalk(
            &[
                "count",
                "--family",
                family,
                "--backend",
                backend,
                "--scene",
                "kuhn-far",
                "--views",
                "2",
                "--size",
                "48x48",
                "--json",
                json.to_str().unwrap(),
                "--dump",
                dump.to_str().unwrap(),
            ],
            b"",
        );
        assert_eq!(code, 0, "{family}: {err}");
        let r: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
        // Each wrong ray's view, pixel, method and kind, in the order written.
        let wrong: Vec<_> = std::fs::read_to_string(&dump)
            .unwrap()
            .lines()
            .map(|l| {
                let d: serde_json::Value = serde_json::from_str(l).unwrap();
                ["view", "pixel", "method", "kind"].map(|k| d[k].clone())
            })
            .collect();
        (r, wrong)
    };
    let ((cpu, cpu_wrong), (gpu, gpu_wrong)) = (count("cpu"), count("gpu"));
    // A GPU count judges a view's answers while the next view's are made: every wrong ray is
    // still written, view by view in order.
    if as_cpu && !contracts(g) {
        assert_eq!(cpu_wrong, gpu_wrong, "{family}");
    }
    assert!(
        gpu_wrong
            .windows(2)
            .all(|w| w[0][0].as_u64() <= w[1][0].as_u64()),
        "{family}: views in order"
    );
    let rays = gpu["rays"].as_u64().unwrap();
    let views = gpu["views_counted"].as_u64().unwrap();
    // The method rows' waits, and whether each row read nothing beyond its counters.
    let (mut method_waits, mut all_ahead) = (0, true);
    assert_eq!(cpu["rays"], gpu["rays"]);
    let (mut wrong, mut sent_back, mut rows, mut rays_written) = (0, 0, 0, 0);
    let pairs = cpu["methods"]
        .as_array()
        .unwrap()
        .iter()
        .zip(gpu["methods"].as_array().unwrap());
    for (k, (c, m)) in pairs.enumerate() {
        assert_eq!(c["method"], m["method"]);
        assert!(c.get("transfer").is_none(), "{c}");
        let t = &m["transfer"];
        let int = |k: &str| t[k].as_u64().unwrap();
        // Only the walk family's reference row reads every ending back.
        let reference_row = family == "walk" && k == 0;
        let (dispatches, sent) = (int("dispatches"), int("sent_back"));
        let beside = int("bytes_written") - 16 * dispatches;
        // Per dispatch (one a view, and one again for a view where the next row's records were
        // sent over this row's before they were read), the counters and timestamps, the records
        // read with them (one for every 64 rays of a view and 16 more), and those sent back beyond
        // them in a second wait.
        let ahead = rays / views / 64 + 16;
        let read = int("bytes_read") - dispatches * (32 + 32 * ahead);
        let beyond = sent.saturating_sub(views * ahead);
        let again = dispatches - views;
        if reference_row {
            let waits = int("waits") - dispatches;
            // Each flagged ray sent back, then written over its ending; a view's wait (the methods'
            // answers read in it too), and one more for the upload.
            let flagged = (beside - 32 * rays) / 16;
            assert_eq!((beside, sent), (32 * rays + 16 * flagged, flagged), "{t}");
            let audited = gpu["audited"].as_u64().unwrap();
            assert!(
                (16 * audited..=16 * audited + 32 * sent).contains(&read),
                "{t}"
            );
            assert!(flagged <= rays / 100, "{flagged} flagged");
            // One at least here: each method's answer to it, sent back in the same wait as the
            // reference's flag, is judged against the CPU's walk (the counts are the CPU's).
            assert!(flagged >= 1, "{t}");
            assert!((dispatches..=2 * dispatches).contains(&waits), "{t}");
        } else {
            // A view's method rows are read back in the reference walk's wait (counted on it);
            // a row waits a second time for records beyond those read ahead, two more for a
            // dispatch again.
            let waits = int("waits");
            assert!((32 * beyond..=32 * sent).contains(&read), "{t}");
            assert!(waits <= views + 2 * again, "{t}");
            if sent == 0 {
                assert_eq!((read, waits, again), (0, 0, 0), "{t}");
            }
            method_waits += waits;
            all_ahead &= read == 0 && again == 0;
            let w = match m.get("wrong_total") {
                Some(w) => w.as_u64().unwrap(),
                None => m["wrong_triangle"].as_u64().unwrap() + m["false_miss"].as_u64().unwrap(),
            };
            assert!(
                sent >= w && sent - w <= rays / 100,
                "{family} {}: {sent} sent back, {w} wrong",
                m["method"]
            );
            wrong += w;
            sent_back += sent;
            rows += 1;
            rays_written += beside;
        }
        assert_eq!(t.get("kernel_share").is_some(), g.measures_kernels(), "{t}");
        if as_cpu && !contracts(g) {
            let timed = ["seconds", "mrays_per_second", "transfer"];
            for (key, v) in c.as_object().unwrap() {
                if !timed.contains(&key.as_str()) {
                    assert_eq!(v, &m[key], "{family} {}: {key} as on the CPU", m["method"]);
                }
            }
        }
    }
    assert_eq!(rays_written, written * rays, "{family}");
    if all_ahead {
        assert_eq!(
            method_waits, 0,
            "{family}: read in the reference walk's wait"
        );
    }
    assert!(
        wrong >= least,
        "{family}: the scene makes wrong rays to send back: {wrong}"
    );
    assert!(
        sent_back < rays * 3,
        "{family}: most rows read back almost nothing: {sent_back} of {rows} rows of {rays}"
    );
}

/// The reference walk of `rays` kept on the GPU (`walks_keeping`), which reads back only the steps
/// summed and the picked rays' endings (lone ones and a run), then every ending read back
/// (`kept_walks`): the endings as the CPU walks them (where the adapter does not contract), the
/// steps as their sum, the picked ones as read whole.
fn kept_reference(
    g: &Backend,
    reference: &Method,
    on: &tetwalk::backend::MeshOn,
    rays: &[Ray],
    start: u32,
    max: u32,
) -> Vec<tetwalk::walk::Walk> {
    // Lone picks and a run of consecutive ones (read back in one copy).
    let picked: Vec<usize> = (0..rays.len())
        .filter(|i| i % 7 == 0 || (100..300).contains(i))
        .collect();
    let kept = g
        .walks_keeping(reference, on, rays, start, max, &picked)
        .unwrap();
    assert!(kept.all.is_none(), "kept on the GPU");
    let all = g.kept_walks(rays, start).unwrap();
    assert_eq!(
        kept.steps,
        all.iter().map(|w| u64::from(w.steps)).sum::<u64>()
    );
    let picked_all: Vec<_> = picked.iter().map(|&i| all[i]).collect();
    assert_eq!(kept.picked, picked_all);
    if !contracts(g) {
        let cpu = Backend::Cpu {
            model: Model::Plain,
        };
        let on_cpu = cpu.mesh(on.mesh);
        assert_eq!(
            all,
            cpu.walks(reference, &on_cpu, rays, start, max).unwrap()
        );
    }
    all
}

/// A Kuhn grid's mesh moved by `offset`, seen from a point inside it outside its inner box (the
/// tetrahedron holding it), the inner box's faces as the scene's triangles (each face from both
/// sides), rays aimed at each triangle's first vertex, an edge's middle and its centre; `mt` and the
/// reference walk.
struct Aimed {
    mesh: tetwalk::mesh::Mesh,
    start: u32,
    tris: Vec<tetwalk::tet::Tri>,
    sides: Vec<[(u32, u8); 2]>,
    rays: Vec<Ray>,
    mt: &'static tetwalk::registry::TriangleMethod,
    reference: &'static Method,
}

fn aimed(offset: Vec3) -> Aimed {
    use tetwalk::mesh::surface::{both_sides, region_of, scene_triangles};
    let mesh = scenes::generated_mesh(Generated::Kuhn, 6, offset, 0).unwrap();
    let org = offset + Vec3::new(0.4, 0.55, 0.35);
    let start = locate(&mesh, org, 0).unwrap();
    let (tris, from) = scene_triangles(&mesh, &region_of(&mesh, start));
    assert!(tris.len() > 100, "{}", tris.len());
    let rays = tris
        .iter()
        .flat_map(|t| [t[0], (t[0] + t[1]) * 0.5, (t[0] + t[1] + t[2]) / 3.0])
        .map(|p| Ray { org, dir: p - org })
        .collect();
    Aimed {
        sides: both_sides(&mesh, &from),
        mesh,
        start,
        tris,
        rays,
        mt: tetwalk::registry::TRIANGLE_METHODS
            .iter()
            .find(|m| m.name() == "mt")
            .unwrap(),
        reference: tetwalk::registry::by_name("certified").unwrap(),
    }
}

/// Nearest hits compared on the GPU ([`Backend::triangles_against`]) take a hit on a triangle as the
/// constrained face it came from, named from either side as the reference walk names it: on rays
/// aimed at the vertices, edges and centres of a Kuhn grid's inner box seen from inside the mesh,
/// every ray sent back is as the CPU answers it (`mt`, which divides after its tests, bit for bit
/// where the adapter does not contract), in pixel order, and every ray settled there hits the
/// reference's face (from either side) or both miss; other rays are refused, and so are triangles
/// made ready without their faces; the CPU compares nothing (`None`).
#[test]
fn nearest_hits_are_compared_on_the_gpu_on_either_side_of_their_face() {
    use tetwalk::methods::triangle::Among;
    let Some(g) = common::gpu_or_skip() else {
        return;
    };
    let a = aimed(Vec3::ZERO);
    let (on, max) = (g.mesh(&a.mesh), default_max_steps(&a.mesh));
    let walked = kept_reference(&g, a.reference, &on, &a.rays, a.start, max);
    let against = gathered(
        &g,
        g.triangles_against(a.mt, &g.triangles(&a.tris, &a.sides), &a.rays, a.start)
            .unwrap()
            .unwrap(),
    );
    let cpu = Backend::Cpu {
        model: Model::Plain,
    };
    let mine = cpu
        .trace_triangles(
            a.mt,
            &a.tris,
            &a.rays,
            1,
            &Among::all(a.tris.len(), a.rays.len(), 1),
        )
        .unwrap();
    let face = |hit: Option<(u32, f32)>| hit.map(|(k, _)| a.sides[k as usize]);
    let settled = a.rays.len() - against.sent.len();
    assert!(
        !against.sent.is_empty() && settled > a.rays.len() / 2,
        "{} of {} sent back",
        against.sent.len(),
        a.rays.len()
    );
    if !contracts(&g) {
        for (i, hit) in mine.iter().enumerate() {
            match against.sent.iter().find(|(j, ..)| *j == i) {
                Some((_, sent, reference)) => {
                    assert_eq!(sent, hit, "ray {i}");
                    assert_eq!(reference.outcome, walked[i].outcome, "ray {i}");
                }
                None => match (face(*hit), walked[i].outcome) {
                    (None, o) => assert_eq!(o.kind(), OutcomeKind::LeftMesh, "ray {i}"),
                    (Some(both), tetwalk::walk::Outcome::Hit { tet, face }) => {
                        assert!(both.contains(&(tet, face)), "ray {i}: {both:?}")
                    }
                    (Some(both), o) => panic!("ray {i} settled: {both:?} against {o:?}"),
                },
            }
        }
    }
    assert!(
        against.sent.windows(2).all(|p| p[0].0 < p[1].0),
        "in pixel order"
    );
    let others: Vec<Ray> = a.rays.iter().map(|r| Ray { dir: -r.dir, ..*r }).collect();
    let ready = g.triangles(&a.tris, &a.sides);
    assert!(g.triangles_against(a.mt, &ready, &others, a.start).is_err());
    assert!(
        g.triangles_against(a.mt, &g.triangles(&a.tris, &[]), &a.rays, a.start)
            .is_err()
    );
    let on_cpu = cpu.mesh(&a.mesh);
    cpu.walks_keeping(a.reference, &on_cpu, &a.rays, a.start, max, &[])
        .unwrap();
    let ready = cpu.triangles(&a.tris, &a.sides);
    assert!(
        cpu.triangles_against(a.mt, &ready, &a.rays, a.start)
            .unwrap()
            .is_none()
    );
}

/// Octree walks compared on the GPU ([`Backend::octree_walks_against`]) are the walks the GPU
/// reads back ([`Backend::octree_walks`]), ray for ray: on a Kuhn grid moved far (2^12), rays from
/// inside the mesh aimed at the vertices, edges and centres of its inner box's faces, every walk sent
/// back is the one read back, in pixel order, every walk settled there hits the reference's face
/// (from either side) or both leave, and the cells summed are the cells read back; other rays are
/// refused.
#[test]
fn octree_walks_are_compared_on_the_gpu_as_they_read_back() {
    use tetwalk::walk::octree::End;
    let Some(g) = common::gpu_or_skip() else {
        return;
    };
    let a = aimed(Vec3::splat(4096.0));
    let octree = tetwalk::octree::Octree::build(
        &a.tris,
        tetwalk::octree::Settings {
            depth: 6,
            capacity: 1,
        },
    )
    .unwrap();
    let on_octree = g.octree(&octree, &a.tris, &a.sides);
    let cap = tetwalk::walk::octree::default_max_steps(&octree);
    let (on, max) = (g.mesh(&a.mesh), default_max_steps(&a.mesh));
    let mut sent_back = 0;
    // The a.reference octree walk runs on the CPU, where nothing is compared.
    for m in tetwalk::registry::OCTREE_METHODS
        .iter()
        .filter(|m| !m.is_reference())
    {
        let read = g
            .octree_walks(m, a.mt, &octree, &a.tris, &on_octree, &a.rays, cap)
            .unwrap();
        let walked = kept_reference(&g, a.reference, &on, &a.rays, a.start, max);
        let against = gathered(
            &g,
            g.octree_walks_against(m, a.mt, &octree, &on_octree, &a.rays, a.start, cap)
                .unwrap()
                .unwrap(),
        );
        assert_eq!(
            against.steps,
            read.iter().map(|w| w.cells as u64).sum::<u64>(),
            "{}",
            m.name()
        );
        for (i, w) in read.iter().enumerate() {
            match against.sent.iter().find(|(j, ..)| *j == i) {
                Some((_, sent, reference)) => {
                    assert_eq!(sent, w, "{} ray {i}", m.name());
                    assert_eq!(reference.outcome, walked[i].outcome, "ray {i}");
                }
                None => match (w.end, walked[i].outcome) {
                    (End::Miss, o) => assert_eq!(o.kind(), OutcomeKind::LeftMesh, "ray {i}"),
                    (End::Hit { tri, .. }, tetwalk::walk::Outcome::Hit { tet, face }) => {
                        assert!(a.sides[tri as usize].contains(&(tet, face)), "ray {i}")
                    }
                    (end, o) => panic!("{} ray {i} settled: {end:?} against {o:?}", m.name()),
                },
            }
        }
        assert!(
            against.sent.windows(2).all(|p| p[0].0 < p[1].0),
            "in pixel order"
        );
        sent_back += against.sent.len();
        let others: Vec<Ray> = a.rays.iter().map(|r| Ray { dir: -r.dir, ..*r }).collect();
        assert!(
            g.octree_walks_against(m, a.mt, &octree, &on_octree, &others, a.start, cap)
                .is_err()
        );
    }
    assert!(
        sent_back > 0 && sent_back < a.rays.len(),
        "{sent_back} of {} a.rays sent back by two methods",
        a.rays.len()
    );
}

/// A jittered grid and 3,000 rays fanned out from a point inside it, with the tetrahedron holding
/// that point.
fn fanned() -> (tetwalk::mesh::Mesh, u32, Vec<Ray>) {
    let mesh = scenes::generated_mesh(Generated::Jitter, 6, Vec3::ZERO, 4).unwrap();
    let start = locate(&mesh, Vec3::splat(2.9), 0).unwrap();
    let rays: Vec<Ray> = (0..3000)
        .map(|i| {
            let a = i as f32 * 0.618;
            Ray {
                org: Vec3::splat(2.9),
                dir: Vec3::new(a.cos(), a.sin(), (a * 0.3).sin()),
            }
        })
        .collect();
    (mesh, start, rays)
}

/// Answers queued on the GPU ([`Backend::triangles_against`] and the like), read back alone.
fn gathered<T>(g: &Backend, pending: tetwalk::backend::Pending<Against<T>>) -> Against<T> {
    g.gather(vec![pending]).unwrap().remove(0).0
}

/// Walks of several methods queued on the GPU are read back in one wait, each as it is read back
/// alone: with the reference kept two steps long, nearly every walk comes back, more than a
/// dispatch reads with its counters, so the first one's records are sent over by the second's
/// before the wait, and it is queued again alone (a second dispatch on its traffic).
#[test]
fn walks_queued_together_are_read_back_in_one_wait_as_each_alone() {
    let Some(g) = common::gpu_or_skip() else {
        return;
    };
    let (mesh, start, rays) = fanned();
    let (on, max) = (g.mesh(&mesh), default_max_steps(&mesh));
    let reference = tetwalk::registry::by_name("certified").unwrap();
    let methods = ["maria17", "plucker"].map(|m| tetwalk::registry::by_name(m).unwrap());
    g.walks_keeping(reference, &on, &rays, start, 2, &[])
        .unwrap();
    let queue = |m| g.walks_against(m, &on, &rays, start, max).unwrap().unwrap();
    let alone: Vec<Against> = methods.iter().map(|&m| gathered(&g, queue(m))).collect();
    let waits = g.traffic().unwrap().waits;
    let together = g
        .gather(methods.iter().map(|&m| queue(m)).collect())
        .unwrap();
    // One wait for both; the second's records beyond those read ahead in a second; the first's
    // were sent over: it was dispatched again alone, and read whole in two more.
    assert_eq!(g.traffic().unwrap().waits - waits, 4);
    let [(first, t1), (second, t2)] = <[_; 2]>::try_from(together).ok().unwrap();
    assert_eq!((t1.dispatches, t1.waits), (2, 3));
    assert_eq!((t2.dispatches, t2.waits), (1, 1));
    for ((a, t), b) in [(first, t1), (second, t2)].into_iter().zip(&alone) {
        // More than a dispatch of 3,000 rays reads with its counters (3000 / 64 + 16).
        assert!(a.sent.len() > 3000 / 64 + 16, "{}", a.sent.len());
        assert_eq!(a.steps, b.steps);
        assert_eq!(t.sent_back, a.sent.len() as u64);
        assert_eq!(a.sent, b.sent);
    }
}

/// Walks compared on the GPU are compared with the reference walk of the same rays only: after
/// `walks_keeping`, `walks_against` of the same rays sends back at least every walk that is not the
/// reference's (each as the CPU walks it, in pixel order) and sums the steps as the CPU does; of other
/// rays it is refused; the CPU compares nothing there (`None`).
#[test]
fn walks_are_compared_on_the_gpu_only_with_the_reference_of_the_same_rays() {
    let Some(g) = common::gpu_or_skip() else {
        return;
    };
    let (mesh, start, rays) = fanned();
    let (on, max) = (g.mesh(&mesh), default_max_steps(&mesh));
    let cpu = Backend::Cpu {
        model: Model::Plain,
    };
    let on_cpu = cpu.mesh(&mesh);
    let reference = tetwalk::registry::by_name("certified").unwrap();
    let maria17 = tetwalk::registry::by_name("maria17").unwrap();
    let walked = kept_reference(&g, reference, &on, &rays, start, max);
    let against = gathered(
        &g,
        g.walks_against(maria17, &on, &rays, start, max)
            .unwrap()
            .unwrap(),
    );
    let mine = cpu.walks(maria17, &on_cpu, &rays, start, max).unwrap();
    if !contracts(&g) {
        assert_eq!(
            against.steps,
            mine.iter().map(|w| w.steps as u64).sum::<u64>()
        );
        for (i, w) in mine.iter().enumerate() {
            match against.sent.iter().find(|(j, ..)| *j == i) {
                Some((_, sent, reference)) => {
                    assert_eq!(sent, w, "ray {i}");
                    assert_eq!(reference.outcome, walked[i].outcome, "ray {i}");
                }
                // Settled: both left the mesh, or both hit the same face.
                None => assert!(
                    w.outcome.kind() == walked[i].outcome.kind()
                        && (w.outcome.kind() != OutcomeKind::Hit || w.outcome == walked[i].outcome),
                    "ray {i} settled on the GPU"
                ),
            }
        }
    }
    assert!(
        against.sent.windows(2).all(|p| p[0].0 < p[1].0),
        "in pixel order"
    );
    let others: Vec<Ray> = rays.iter().map(|r| Ray { dir: -r.dir, ..*r }).collect();
    assert!(g.walks_against(maria17, &on, &others, start, max).is_err());
    let kept = cpu
        .walks_keeping(reference, &on_cpu, &rays, start, max, &[])
        .unwrap();
    assert!(kept.all.is_some());
    assert!(cpu.kept_walks(&rays, start).is_err());
    assert!(
        cpu.walks_against(maria17, &on_cpu, &rays, start, max)
            .unwrap()
            .is_none()
    );
}
