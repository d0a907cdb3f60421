//! The ray–triangle family (seed 004): the exact oracle against plain rational arithmetic, every method
//! on clear cases, packets against single rays, the closed meshes of the stress rows, the watertight
//! claim held on them, and `tetwalk hit` and `count --family triangle` as a user runs them.

mod common;

use glam::Vec3;
use rand::RngExt;
use tetwalk::backend::{Backend, CPU};
use tetwalk::cases::HitCase;
use tetwalk::choice::Choice;
use tetwalk::engine::found::{Found, Replay, replay};
use tetwalk::engine::stress::{StressSettings, row_cases, run};
use tetwalk::exact::hit::{line_triangle, ray_triangle, ray_triangle_t};
use tetwalk::family::triangle::TriRows;
use tetwalk::family::{Family, Triangle};
use tetwalk::methods::Model;
use tetwalk::registry::Named;
use tetwalk::registry::TRIANGLE_METHODS;
use tetwalk::scenes::closed::{MeshShape, TriAim, TriPlace, case, mesh};
use tetwalk::scenes::rng;
use tetwalk::tet::{Ray, Tri, orientation};

/// A triangle of small lattice points and a ray through a lattice point of its plane or near it.
fn lattice_case(r: &mut tetwalk::scenes::Rng) -> (Tri, Ray) {
    let mut p = || {
        Vec3::new(
            r.random_range(-4..=4) as f32,
            r.random_range(-4..=4) as f32,
            r.random_range(-4..=4) as f32,
        )
    };
    let tri = [p(), p(), p()];
    let (org, dir) = (p() * 2.0, p());
    (tri, Ray { org, dir })
}

/// The filtered-sign oracle gives what plain rational Cramer's rule gives: a hit where the line crosses
/// the closed triangle at `t > 0` and is not parallel to it, on the boundary where a barycentric is 0.
#[test]
fn the_oracle_agrees_with_rational_arithmetic() {
    let mut r = rng(7);
    let (mut hits, mut boundary) = (0, 0);
    for _ in 0..20_000 {
        let (tri, ray) = lattice_case(&mut r);
        let Ok(h) = ray_triangle(tri, &ray) else {
            continue;
        };
        let want = line_triangle(tri, &ray).filter(|c| c.t.cmp0().is_gt());
        assert_eq!(h.hit, want.is_some(), "{tri:?} {ray:?}");
        assert_eq!(
            h.on_boundary,
            want.as_ref().is_some_and(|c| c.on_boundary),
            "{tri:?} {ray:?}"
        );
        assert_eq!(
            ray_triangle_t(tri, &ray).unwrap(),
            want.map(|c| c.t),
            "{tri:?} {ray:?}"
        );
        hits += h.hit as u32;
        boundary += h.on_boundary as u32;
    }
    assert!(
        hits > 200 && boundary > 50,
        "{hits} hits, {boundary} on a boundary"
    );
}

/// A random well-shaped triangle and a ray through a point well inside it (or well outside), from the
/// side its counterclockwise order faces (the only side `mt` sees).
fn clear_case(r: &mut tetwalk::scenes::Rng, inside: bool) -> (Tri, Ray) {
    let p = |r: &mut tetwalk::scenes::Rng| {
        Vec3::new(
            r.random_range(-1.0..1.0),
            r.random_range(-1.0..1.0),
            r.random_range(-1.0..1.0),
        )
    };
    loop {
        let tri = [p(r), p(r), p(r)];
        let n = (tri[1] - tri[0]).cross(tri[2] - tri[0]);
        if n.length() < 0.3 {
            continue;
        }
        let (u, v) = if inside {
            (r.random_range(0.1..0.4), r.random_range(0.1..0.4))
        } else {
            (r.random_range(0.7..1.0), r.random_range(0.7..1.0))
        };
        let target = tri[0] + (tri[1] - tri[0]) * u + (tri[2] - tri[0]) * v;
        let org = target + n.normalize() * r.random_range(0.5..3.0) + p(r) * 0.2;
        return (
            tri,
            Ray {
                org,
                dir: target - org,
            },
        );
    }
}

#[test]
fn every_method_is_right_on_clear_hits_and_misses() {
    let mut r = rng(3);
    for inside in [true, false] {
        for _ in 0..2_000 {
            let (tri, ray) = clear_case(&mut r, inside);
            assert!(ray_triangle(tri, &ray).unwrap().hit == inside);
            for m in TRIANGLE_METHODS {
                for model in Model::ALL {
                    let got = m.hit(model)(&tri, &ray);
                    assert_eq!(
                        got.is_some(),
                        inside,
                        "{} {model:?}: {tri:?} {ray:?}",
                        m.name()
                    );
                    if let Some(t) = got {
                        assert!((t - 1.0).abs() < 1e-4, "{}: t = {t}", m.name());
                    }
                }
            }
        }
    }
}

/// Packets share work, never answers: each method's nearest hits over a view of rays sharing an origin
/// are the same taken 1, 4, 16 or 64 rays at a time, and equal its single-ray test's.
#[test]
fn packets_answer_as_single_rays_do() {
    let mut r = rng(11);
    let tris: Vec<Tri> = (0..64).map(|_| clear_case(&mut r, true).0).collect();
    let org = Vec3::new(0.1, 0.2, 3.0);
    let rays: Vec<Ray> = (0..256)
        .map(|i| Ray {
            org,
            dir: Vec3::new(
                (i % 16) as f32 / 8.0 - 1.0,
                (i / 16) as f32 / 8.0 - 1.0,
                -1.5,
            ) - Vec3::new(0.1, 0.2, 0.0),
        })
        .collect();
    let every = tetwalk::methods::triangle::Among::all(tris.len(), rays.len(), rays.len());
    let (ids, groups) = (&every.ids, &every.groups);
    for m in TRIANGLE_METHODS {
        for model in Model::ALL {
            let one = m.trace(model)(&tris, ids, groups, &rays, 1);
            assert!(
                one.iter().filter(|h| h.is_some()).count() > 20,
                "{}",
                m.name()
            );
            for p in [4, 16, 64] {
                assert_eq!(
                    m.trace(model)(&tris, ids, groups, &rays, p),
                    one,
                    "{} packets of {p}",
                    m.name()
                );
            }
            for (ray, h) in rays.iter().zip(&one) {
                let single = tris
                    .iter()
                    .enumerate()
                    .filter_map(|(i, t)| m.hit(model)(t, ray).map(|t| (i as u32, t)))
                    .fold(None, |b: Option<(u32, f32)>, (i, t)| match b {
                        Some((_, bt)) if bt <= t => b,
                        _ => Some((i, t)),
                    });
                assert_eq!(*h, single, "{}", m.name());
            }
        }
    }
}

/// Every stress shape is closed (each edge run once each way), convex with outward faces, and has its
/// face count; its vertices are integers or halves.
#[test]
fn the_stress_meshes_are_closed_and_outward() {
    let mut r = rng(5);
    for shape in MeshShape::ALL.iter().copied() {
        for _ in 0..20 {
            let m = mesh(shape, 1e-3, &mut r);
            let want = match shape {
                MeshShape::Octahedron => 8,
                MeshShape::Icosahedron => 20,
                _ => 4,
            };
            assert_eq!(m.len(), want, "{shape:?}");
            HitCase::closed(
                &m,
                Ray {
                    org: Vec3::ZERO,
                    dir: Vec3::X,
                },
            )
            .unwrap();
            let c: Vec3 = m.iter().flatten().sum::<Vec3>() / (3 * m.len()) as f32;
            for t in &m {
                assert!(
                    orientation(&[t[0], t[1], t[2], c]) > 0,
                    "{shape:?}: an inward face"
                );
                assert!(t.iter().all(|p| (*p * 2.0).round() == *p * 2.0));
            }
        }
    }
}

/// The rays aimed exactly through an edge or vertex meet it exactly, and most of them cross the
/// surface there (the others touch it).
#[test]
fn exact_rays_meet_their_edge_or_vertex() {
    let mut r = rng(9);
    for aim in [TriAim::Edge, TriAim::Vertex, TriAim::Grazing] {
        let (mut crossing, mut boundary) = (0, 0);
        for place in TriPlace::ALL.iter().copied() {
            for _ in 0..100 {
                let (m, ray) = case(MeshShape::Icosahedron, aim, place, 1e-3, 4, &mut r);
                let truth = Triangle::truth(&HitCase::closed(&m, ray).unwrap()).unwrap();
                let first = truth.first().expect("aimed at the surface");
                boundary += first
                    .holding
                    .iter()
                    .all(|&i| truth.each[i as usize].on_boundary)
                    as u32;
                crossing += first.crosses as u32;
            }
        }
        assert_eq!(
            boundary, 300,
            "{aim:?}: every first point is an edge or a vertex"
        );
        assert!(crossing > 150, "{aim:?}: {crossing} of 300 cross");
    }
}

fn stress_settings(cases: usize) -> StressSettings<Triangle> {
    StressSettings {
        contract: Default::default(),
        cases,
        rows: TriRows::default(),
        seed: 1,
        backend: CPU.ran(),
        scale: Default::default(),
    }
}

/// Woop et al.'s claim, held exactly: on every stress row, in f32 as written, no ray leaks through a
/// closed mesh; the methods without the claim do leak through exact edges and vertices, and Woop's
/// does once its 2x2 determinants are fused (as a GPU compiler may).
#[test]
fn woop_watertight_never_leaks_and_the_others_do() {
    let s = stress_settings(150);
    let methods: Vec<_> = TRIANGLE_METHODS.iter().collect();
    for (backend, fma) in [
        (&CPU, false),
        (
            &Backend::Cpu {
                model: Model::Fused,
            },
            true,
        ),
    ] {
        let r = run(
            &s,
            &tetwalk::engine::stress::Who::methods(&methods),
            backend,
            &|_| {},
            &mut |_| {},
        )
        .unwrap();
        for (k, m) in methods.iter().enumerate() {
            let leaks: u64 = r.rows.iter().map(|row| row.tallies[k].counts.leaks).sum();
            if m.info.claim.is_some() && !fma {
                assert_eq!(leaks, 0, "{} leaks", m.name());
            } else if m.name() != "plucker-packet" || fma {
                assert!(leaks > 0, "{} (fma {fma}) never leaks here", m.name());
            }
        }
        assert!(r.rows.iter().all(|row| row.facts.crossing > 0));
    }
}

fn lines(out: &str) -> Vec<serde_json::Value> {
    out.lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

const TRI: &str = r#""tri": [[0,0,0],[1,0,0],[0,1,0]]"#;

#[test]
fn hit_answers_each_case_and_method_with_the_exact_fields() {
    let input = format!(
        "{{{TRI}, \"org\": [0.25,0.25,1], \"dir\": [0,0,-3]}}\n\
         {{{TRI}, \"org\": [0.5,0.5,1], \"dir\": [0,0,-1]}}\n\
         {{{TRI}, \"org\": [0.25,0.25,-1], \"dir\": [0,0,-1]}}\n\
         {{{TRI}, \"org\": [0.25,0.25,0], \"dir\": [0,0,-1]}}\n\
         {{{TRI}, \"org\": [-1,0.25,0], \"dir\": [1,0,0]}}\n\
         {{{TRI}, \"org\": [0.1,0.1,1], \"dir\": [0,0,-0.125]}}\n"
    );
    let (code, out, _) = common::run_tetwalk(&["hit", "--method", "all"], input.as_bytes());
    assert_eq!(code, 0);
    let v = lines(&out);
    let n = TRIANGLE_METHODS.len();
    assert_eq!(v.len(), 6 * n);
    let want = [
        (true, Some("1/3"), false),
        (true, Some("1/1"), true),
        (false, None, false),
        (false, None, false),
        (false, None, false),
        (true, Some("8/1"), false),
    ];
    for (line, (hit, t, boundary)) in want.iter().enumerate() {
        for x in &v[line * n..(line + 1) * n] {
            assert_eq!(x["line"], line + 1);
            assert_eq!(x["exact_hit"], *hit, "{x}");
            assert_eq!(x["exact_t"], serde_json::json!(t), "{x}");
            assert_eq!(x["on_boundary"], *boundary, "{x}");
            assert_eq!(x["correct"], *boundary || x["hit"] == *hit, "{x}");
        }
    }
    // Parallel in the plane, and an origin on the triangle: misses every method must see.
    for x in &v[3 * n..5 * n] {
        assert_eq!(x["correct"], true, "{x}");
    }
}

#[test]
fn hit_answers_bad_lines_with_an_error_and_the_others() {
    let input = format!(
        "{{{TRI}, \"org\": [0.25,0.25,1], \"dir\": [0,0,-1]}}\n\
         {{\"tri\": [[0,0,0],[1,1,1],[2,2,2]], \"org\": [0,0,1], \"dir\": [0,0,-1]}}\n\
         {{{TRI}, \"org\": [0.25,0.25,1], \"dir\": [0,0,0]}}\n\
         {{{TRI}, \"org\": [0.25,0.25,1e39], \"dir\": [0,0,-1]}}\n\
         {{\"tris\": [[[0,0,0],[1,0,0],[0,1,0]]], \"org\": [0,0,1], \"dir\": [0,0,-1]}}\n\
         {{\"tet\": [[0,0,0],[0,1,0],[1,0,0],[0,0,1]], \"org\": [0.2,0.2,-1], \"dir\": [0,0,1]}}\n\
         not json\n"
    );
    let (code, out, err) = common::run_tetwalk(&["hit", "--method", "mt"], input.as_bytes());
    assert_eq!(code, 1, "{err}");
    let v = lines(&out);
    assert_eq!(v.len(), 7);
    assert_eq!(v[0]["correct"], true);
    for (x, says) in v[1..].iter().zip([
        "degenerate",
        "direction is zero",
        "not finite",
        "tris",
        "tetwalk exit",
        "JSON",
    ]) {
        assert!(x["error"].as_str().unwrap().contains(says), "{x}");
    }
}

/// A closed mesh case: the first hit's triangles, whether the ray crosses there, and each method's
/// nearest hit; and a mesh that is not closed is refused, naming the edge.
#[test]
fn hit_judges_a_closed_mesh_by_its_first_crossing() {
    let tet = r#""tris": [[[0,0,0],[0,1,0],[1,0,0]],[[0,0,0],[1,0,0],[0,0,1]],[[0,0,0],[0,0,1],[0,1,0]],[[1,0,0],[0,1,0],[0,0,1]]]"#;
    let input = format!(
        "{{{tet}, \"org\": [2.5,-2,2.5], \"dir\": [-1,1,-1]}}\n\
         {{{tet}, \"org\": [0.5,0.5,3], \"dir\": [0,0,-1]}}\n\
         {{{tet}, \"org\": [0.25,0.25,3], \"dir\": [0,0,-1]}}\n\
         {{\"tris\": [[[0,0,0],[0,1,0],[1,0,0]],[[0,0,0],[1,0,0],[0,0,1]],[[0,0,0],[0,0,1],[0,1,0]],[[1,0,0],[0,0,1],[0,1,0]]], \"org\": [0,0,3], \"dir\": [0,0,-1]}}\n"
    );
    let (code, out, _) =
        common::run_tetwalk(&["hit", "--method", "woop-watertight"], input.as_bytes());
    assert_eq!(code, 1);
    let v = lines(&out);
    // Through the edge between faces 1 and 3, into the tetrahedron: a crossing.
    assert_eq!(v[0]["exact_tris"], serde_json::json!([1, 3]));
    assert_eq!(v[0]["exact_t"], "2/1");
    assert_eq!(v[0]["crosses"], true);
    assert_eq!(v[0]["on_boundary"], true);
    assert_eq!(v[0]["correct"], true);
    // Down onto the edge between faces 0 and 3, which face opposite ways along it: it only touches.
    assert_eq!(v[1]["exact_tris"], serde_json::json!([0, 3]));
    assert_eq!(v[1]["crosses"], false);
    assert_eq!(v[2]["exact_tris"], serde_json::json!([3]));
    assert_eq!(v[2]["tri"], 3);
    assert_eq!(v[2]["exact_t"], "5/2");
    let why = v[3]["error"].as_str().unwrap();
    assert!(why.contains("is run 2 times this way"), "{why}");
}

/// A ray that meets a triangle's back: `mt` (front faces only, as published) misses it and is judged
/// wrong, and the line and the summary say the ray met a back face; a closed mesh turned inside out is
/// named on its lines.
#[test]
fn hit_names_back_faces_and_inside_out_meshes() {
    let back = r#"{"tri": [[0,0,0],[0,1,0],[1,0,0]], "org": [0.25,0.25,1], "dir": [0,0,-1]}"#;
    let front = format!("{{{TRI}, \"org\": [0.25,0.25,1], \"dir\": [0,0,-1]}}");
    let (code, out, err) = common::run_tetwalk(
        &["hit", "--method", "mt,mt-two-sided"],
        format!("{back}\n{front}\n").as_bytes(),
    );
    assert_eq!(code, 0, "{err}");
    let v = lines(&out);
    assert_eq!(
        (v[0]["method"].as_str(), v[0]["hit"].as_bool()),
        (Some("mt"), Some(false))
    );
    assert_eq!(v[0]["back_face"], true);
    assert_eq!(v[0]["correct"], false);
    assert_eq!(v[1]["back_face"], true);
    assert_eq!(v[1]["correct"], true);
    assert!(v[2].get("back_face").is_none(), "{}", v[2]);
    assert!(
        err.contains("tetwalk hit: mt: 2 cases, 1 right, 1 wrong (of them 1 where the ray first meets a back face"),
        "{err}"
    );
    assert!(
        err.contains("tetwalk hit: mt-two-sided: 2 cases, 2 right, 0 wrong, 0 not judged"),
        "{err}"
    );

    let out_tet = r#"[[0,0,0],[0,1,0],[1,0,0]],[[0,0,0],[1,0,0],[0,0,1]],[[0,0,0],[0,0,1],[0,1,0]],[[1,0,0],[0,1,0],[0,0,1]]"#;
    let in_tet = r#"[[0,0,0],[1,0,0],[0,1,0]],[[0,0,0],[0,0,1],[1,0,0]],[[0,0,0],[0,1,0],[0,0,1]],[[1,0,0],[0,0,1],[0,1,0]]"#;
    let ray = r#""org": [0.25,0.25,3], "dir": [0,0,-1]"#;
    let input = format!("{{\"tris\": [{out_tet}], {ray}}}\n{{\"tris\": [{in_tet}], {ray}}}\n");
    let (_, out, _) = common::run_tetwalk(&["hit", "--method", "mt"], input.as_bytes());
    let v = lines(&out);
    assert!(v[0].get("inside_out").is_none(), "{}", v[0]);
    assert_eq!(v[0]["correct"], true);
    assert_eq!(v[1]["inside_out"], true);
    assert_eq!(v[1]["back_face"], true);
    assert_eq!(v[1]["correct"], false);
}

/// A triangle case in the case format reads back as the same f32 case, and a found case's recorded
/// nearest hit is compared on replay: changing it is noticed.
#[test]
fn a_triangle_case_reads_back_and_its_recorded_answer_is_compared() {
    let (m, ray) = case(
        MeshShape::Tetrahedron,
        TriAim::Edge,
        TriPlace::Embree,
        1e-3,
        4,
        &mut rng(2),
    );
    let case = HitCase::closed(&m, ray).unwrap();
    let line = serde_json::Value::Object(Triangle::case_json(&case)).to_string();
    assert_eq!(Found::<Triangle>::parse(&line).unwrap().case, case);
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/corpora/found/mt");
    let file = std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|f| std::fs::read_to_string(f.path()).unwrap())
        .find(|t| t.contains("\"tris\"") && t.contains("\"tri\":"))
        .expect("a wrong-triangle finding of mt");
    let r = Found::<Triangle>::parse(file.trim()).unwrap();
    assert_eq!(replay(&r).unwrap(), Replay::Holds);
    let mut other = r.clone();
    if let Some(f) = other.failure.as_mut()
        && let Some((i, t)) = f.answer.nearest()
    {
        f.answer = tetwalk::family::triangle::Hits::of(&[(i, t.next_up())]);
    }
    let other = Found::<Triangle>::parse(&other.to_json()).unwrap();
    assert!(matches!(replay(&other).unwrap(), Replay::OtherAnswer(_)));
}

/// `count --family triangle` on the bunny: every primary ray judged per method, the scene's 3,686
/// constrained faces as triangles.
#[test]
fn count_family_triangle_judges_every_ray() {
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("t.json");
    let (code, out, err) = common::run_tetwalk(
        &[
            "count",
            "--family",
            "triangle",
            "--views",
            "2",
            "--size",
            "32x32",
            "--methods",
            "mt,woop-watertight",
            "--json",
            json.to_str().unwrap(),
        ],
        b"",
    );
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("packets of 2x2"), "{out}");
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(r["rays"], 2 * 32 * 32);
    assert_eq!(r["triangles"], 3686);
    assert_eq!(r["methods"].as_array().unwrap().len(), 2);
}

/// The methods that divide before testing a hit (`1/det`, `-1/N·D`, Woop's shear).
const DIVIDE_BEFORE_TESTS: [&str; 4] = [
    "mt-two-sided",
    "mt-precomputed",
    "komatsu-packet",
    "woop-watertight",
];

/// The WGSL of every method answers as its CPU twin on the stress rows' cases (lavapipe, which does not
/// fuse), one (ray, triangle) pair per thread: bit for bit where the method does not divide before its
/// tests, on 97% of the cases at least where it does; `woop-watertight`'s WGSL, whose edge functions
/// fall back to exact f32 products where the CPU's use f64, never leaks there; and the nearest-hit
/// kernel, every triangle tried per ray, finds what the CPU's packets find.
#[test]
fn the_gpu_answers_as_the_cpu_does() {
    let Some(gpu) = common::gpu_or_skip() else {
        return;
    };
    let s = stress_settings(30);
    let judged: Vec<_> = Triangle::rows(&s.rows)
        .into_iter()
        .flat_map(|row| row_cases(&s, row).0)
        .collect();
    let cases: Vec<HitCase> = judged.iter().map(|(c, _)| *c).collect();
    for m in TRIANGLE_METHODS {
        let on_cpu = CPU.triangle_hits(m, &cases).unwrap();
        let on_gpu = gpu.triangle_hits(m, &cases).unwrap();
        let same = on_cpu.iter().zip(&on_gpu).filter(|(a, b)| a == b).count();
        if m.info.claim.is_some() {
            for ((_, truth), h) in judged.iter().zip(&on_gpu) {
                let ids: Vec<u32> = h.iter().map(|&(i, _)| i).collect();
                assert!(!truth.leaks(&ids), "{} leaks on the GPU", m.name());
            }
        }
        // lavapipe's f32 division is not correctly rounded (Vulkan allows 2.5 ulps): the methods that
        // divide before their tests differ from the CPU's on a few cases right at an edge; the others
        // are bit for bit the CPU's.
        if DIVIDE_BEFORE_TESTS.contains(&m.name()) {
            assert!(
                same * 100 >= cases.len() * 97,
                "{}: {same} of {}",
                m.name(),
                cases.len()
            );
        } else {
            assert_eq!(same, cases.len(), "{}", m.name());
        }
    }
    let tris: Vec<Tri> = cases
        .iter()
        .take(40)
        .flat_map(|c| c.tris().to_vec())
        .collect();
    let org = tris[0][0] + Vec3::new(3.0, 5.0, 7.0);
    let rays: Vec<Ray> = tris
        .iter()
        .map(|t| Ray {
            org,
            dir: (t[0] + t[1] + t[2]) / 3.0 - org,
        })
        .collect();
    let all = tetwalk::methods::triangle::Among::all(tris.len(), rays.len(), 64);
    for m in TRIANGLE_METHODS
        .iter()
        .filter(|m| !DIVIDE_BEFORE_TESTS.contains(&m.name()))
    {
        assert_eq!(
            CPU.trace_triangles(m, &tris, &rays, 4, &all).unwrap(),
            gpu.trace_triangles(m, &tris, &rays, 4, &all).unwrap(),
            "{}",
            m.name()
        );
    }
}

/// The README's register of claims, `woop-watertight`'s row, on the case as it was found (the found
/// case's `original`; the file holds it shrunk): in f32 as written it hits one of the two triangles
/// sharing the edge the ray crosses; fused, it leaks through the edge and first reports the triangle
/// where the ray leaves.
#[test]
fn the_claims_register_woop_counterexample_replays() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/corpora/found/woop-watertight/stress-tetrahedron-edge-origin-wrong_face-15054ba8dc6ab2ef.json"
    ))
    .unwrap();
    let found = Found::<Triangle>::parse(text.trim()).unwrap();
    let case = found.original.unwrap_or(found.case);
    let truth = Triangle::truth(&case).unwrap();
    let first = truth.first_crossing().unwrap();
    assert_eq!(first.holding, vec![0, 2]);
    assert_eq!(first.t, rug::Rational::from(1));
    let woop = tetwalk::family::by_name::<tetwalk::family::Triangle>("woop-watertight").unwrap();
    let hits = |model| {
        Backend::Cpu { model }
            .triangle_hits(woop, std::slice::from_ref(&case))
            .unwrap()
            .remove(0)
    };
    let ids = |h: &[(u32, f32)]| h.iter().map(|&(i, _)| i).collect::<Vec<_>>();
    let plain = hits(Model::Plain);
    assert!(!truth.leaks(&ids(&plain)), "{plain:?}");
    let fused = hits(Model::Fused);
    assert!(truth.leaks(&ids(&fused)), "{fused:?}");
    assert_eq!(
        tetwalk::methods::triangle::nearest_of(&fused),
        Some((3, 1.589068)),
        "as the register writes it"
    );
}

/// `gen-cases --shape` writes closed-mesh cases that `hit` reads back, every one answered; the rays
/// aimed exactly at edges meet the surface first at an edge (two triangles hold the point, or, where
/// the ray runs along one, that one), and woop-watertight is right on all of them here.
#[test]
fn gen_cases_writes_closed_meshes_that_hit_reads() {
    let (code, cases, err) = common::run_tetwalk(
        &[
            "gen-cases",
            "--shape",
            "icosahedron",
            "--aim",
            "edge",
            "--place",
            "embree",
            "--count",
            "50",
        ],
        b"",
    );
    assert_eq!(code, 0, "{err}");
    assert_eq!(cases.lines().count(), 50);
    let (code, out, err) =
        common::run_tetwalk(&["hit", "--method", "woop-watertight"], cases.as_bytes());
    assert_eq!(code, 0, "{err}");
    let v = lines(&out);
    assert_eq!(v.len(), 50);
    for x in &v {
        assert_eq!(x["on_boundary"], true, "{x}");
        assert_eq!(x["correct"], true, "{x}");
    }
}

/// "Near" is measured at the case's scale: a near row's origin moves by 1 to 4 ulps of the case's
/// largest coordinate, so a zero coordinate moves as far as the others, never by a subnormal (before,
/// 741 of 2,000 octahedron near-vertex origins did), for closed meshes, tetrahedra and octree cells.
#[test]
fn near_rows_move_their_origin_at_the_cases_scale() {
    let runs: [&[&str]; 3] = [
        &["--shape", "octahedron", "--aim", "near-vertex"],
        &[
            "--tet-shape",
            "cap",
            "--rays",
            "near-edge",
            "--flatness",
            "0.001",
        ],
        &["--cell-aim", "near-corner"],
    ];
    for args in runs {
        let mut all = vec!["gen-cases", "--count", "300"];
        all.extend(args);
        let (code, out, err) = common::run_tetwalk(&all, b"");
        assert_eq!(code, 0, "{args:?}: {err}");
        for l in lines(&out) {
            let org: Vec<f64> = l["org"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect();
            assert!(
                org.iter().all(|x| *x == 0.0 || x.abs() > 1e-30),
                "{args:?}: an origin coordinate moved by a subnormal: {l}"
            );
        }
    }
}

/// The 4-wide versions (seed 004's SIMD packets) answer bit for bit as the scalar ones in the plain
/// model: every triangle alone and the nearest over all, in packets of 1 to 64 rays sharing an origin,
/// and every hit of each ray alone (`hit --wide`), on cases from every exponent regime (subnormal to near overflow, mixed in one case), degenerate
/// triangles, rays parallel to a triangle's plane, through its vertices, and with zero components.
#[test]
fn wide_packets_answer_bit_for_bit_as_the_scalar_ones() {
    let mut r = rng(29);
    let mut compared = 0usize;
    let mut hits = 0usize;
    for round in 0..60 {
        let e = r.random_range(-140..100);
        let scale = |r: &mut tetwalk::scenes::Rng| 2f32.powi(e + r.random_range(-8..=8));
        let p = |r: &mut tetwalk::scenes::Rng| {
            let s = scale(r);
            Vec3::new(
                r.random_range(-4..=4) as f32,
                r.random_range(-4..=4) as f32,
                r.random_range(-4..=4) as f32,
            ) * s
                + Vec3::new(r.random_range(-1.0..1.0), r.random_range(-1.0..1.0), 0.0) * s
        };
        let mut tris: Vec<Tri> = (0..24).map(|_| [p(&mut r), p(&mut r), p(&mut r)]).collect();
        // Degenerate: a point, a segment.
        let a = p(&mut r);
        tris.push([a, a, a]);
        let b = p(&mut r);
        tris.push([a, b, (a + b) * 0.5]);
        let org = p(&mut r) * 2.0;
        let mut rays: Vec<Ray> = Vec::new();
        for k in 0..64 {
            let dir = match k % 4 {
                // Towards a vertex, or in a triangle's plane, or along an axis, or anywhere.
                0 => tris[k % tris.len()][k % 3] - org,
                1 => {
                    let t = tris[k % 24];
                    (t[1] - t[0]) + (t[2] - t[0]) * 0.5
                }
                2 => Vec3::new(0.0, 0.0, if k % 8 == 2 { 1.0 } else { -1.0 }),
                _ => p(&mut r) - org,
            };
            rays.push(Ray { org, dir });
        }
        let every = tetwalk::methods::triangle::Among::all(tris.len(), rays.len(), rays.len());
        let whole = [(0..rays.len(), 0..1)];
        for m in TRIANGLE_METHODS {
            let Some(four) = m.wide else { continue };
            let (wide, scalar) = (four.trace, m.trace(Model::Plain));
            let bits = |v: Vec<Option<(u32, f32)>>| -> Vec<_> {
                v.into_iter()
                    .map(|h| h.map(|(i, t)| (i, t.to_bits())))
                    .collect()
            };
            for packet in [1, 4, 16, 64] {
                assert_eq!(
                    bits(wide(&tris, &every.ids, &every.groups, &rays, packet)),
                    bits(scalar(&tris, &every.ids, &every.groups, &rays, packet)),
                    "{} nearest, packets of {packet}, round {round} at 2^{e}",
                    m.name()
                );
                for i in 0..tris.len() as u32 {
                    let (w, s) = (
                        wide(&tris, &[i], &whole, &rays, packet),
                        scalar(&tris, &[i], &whole, &rays, packet),
                    );
                    hits += s.iter().filter(|h| h.is_some()).count();
                    compared += s.len();
                    assert_eq!(bits(w), bits(s), "{} triangle {i}, round {round}", m.name());
                }
            }
            // Every hit of one ray, as `tetwalk hit --wide` compares them.
            let every_hit = |v: Vec<(u32, f32)>| -> Vec<_> {
                v.into_iter().map(|(i, t)| (i, t.to_bits())).collect()
            };
            for ray in &rays {
                assert_eq!(
                    every_hit((four.hits)(&tris, ray)),
                    every_hit(m.hits(Model::Plain)(&tris, ray)),
                    "{} every hit of {ray:?}, round {round}",
                    m.name()
                );
            }
        }
    }
    assert!(
        hits > 1000 && compared > 100_000,
        "{hits} hits of {compared}"
    );
}

/// `hit --wide`: each method with a 4-wide version answers every case through it too, and says so on
/// each line and in its summary (stress cases of every aim, near and far from the origin, one
/// triangle and closed meshes); the run is refused where the comparison means nothing.
#[test]
fn hit_wide_compares_the_4_wide_versions_case_by_case() {
    let mut input = Vec::new();
    for (aim, place, one) in [
        ("near-edge", "far", false),
        ("near-vertex", "origin", true),
        ("grazing", "embree", false),
        ("edge", "origin", true),
    ] {
        let mut args = vec![
            "gen-cases",
            "--shape",
            "icosahedron",
            "--aim",
            aim,
            "--place",
            place,
            "--count",
            "150",
        ];
        if one {
            args.push("--single");
        }
        let (code, out, err) = common::run_tetwalk(&args, b"");
        assert_eq!(code, 0, "{err}");
        input.extend_from_slice(out.as_bytes());
    }
    let cases = input.iter().filter(|&&b| b == b'\n').count();
    assert!(cases > 550, "{cases} cases");
    let (code, out, err) = common::run_tetwalk(&["hit", "--wide"], &input);
    assert_eq!(code, 0, "{err}");
    let v = lines(&out);
    assert_eq!(v.len(), cases * TRIANGLE_METHODS.len());
    for m in TRIANGLE_METHODS {
        let mine: Vec<_> = v.iter().filter(|x| x["method"] == m.name()).collect();
        assert_eq!(mine.len(), cases);
        for x in mine {
            assert_eq!(
                x.get("wide_same"),
                m.wide.is_some().then_some(&serde_json::Value::Bool(true)),
                "{x}"
            );
        }
        if m.wide.is_some() {
            assert!(
                err.contains(&format!(
                    "{}: {cases} cases, {} right",
                    m.name(),
                    v.iter()
                        .filter(|x| x["method"] == m.name() && x["correct"] == true)
                        .count()
                )) && err.contains(&format!(
                    "its 4-wide version answered all {cases} the same, bit for bit"
                )),
                "{err}"
            );
        }
    }
    let (code, _, err) = common::run_tetwalk(&["hit", "--wide", "--method", "mt"], &input);
    assert_eq!(code, 2);
    assert!(
        err.contains("none of the methods asked for has a 4-wide version"),
        "{err}"
    );
    let (code, _, err) = common::run_tetwalk(&["hit", "--wide", "--backend", "cpu-fma"], &input);
    assert_eq!(code, 2);
    assert!(err.contains("give --backend cpu"), "{err}");
}

/// A hit at `t = 0` (or `-0.0`) is never right, even where the exact first hit lies within the
/// ulps a `t` may be off: a ray from just before a triangle (the exact `t` the smallest subnormal)
/// answered "hit at 0" is wrong; the same triangle at the smallest positive `t` is right.
#[test]
fn a_hit_at_t_zero_is_wrong_even_next_to_the_exact_hit() {
    use tetwalk::exact::hit::{T_ULPS, judge_hit};
    let tri = [
        Vec3::new(-1.0, -1.0, 0.0),
        Vec3::new(1.0, -1.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
    ];
    let ray = tetwalk::tet::Ray {
        org: Vec3::new(0.0, 0.0, -f32::from_bits(1)),
        dir: Vec3::Z,
    };
    let truth = judge_hit(&[tri], false, &ray).unwrap();
    assert!(truth.judge(Some((0, f32::from_bits(1))), T_ULPS).right);
    for t in [0.0f32, -0.0] {
        let judged = truth.judge(Some((0, t)), T_ULPS);
        assert!(judged.triangle && !judged.right, "t = {t:?}: {judged:?}");
        assert!(
            judged.t.unwrap().ulps.is_some_and(|u| u <= T_ULPS),
            "t = {t:?} is near"
        );
    }
}
