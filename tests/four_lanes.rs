//! The exit-face methods computed in four lanes (`ray-plane` and `halfspace`: the four faces at once;
//! `plucker`, `stp`, and `ms06` in a starting tetrahedron: the six edges in eight lanes; `aman20` and
//! `aman20-scaled`: the four vertices' projections) answer as their formulas written face by face,
//! edge by edge and vertex by vertex in scalar f32, bit for bit: in the plain, fused and flushed
//! models, on tetrahedra and rays from every exponent regime (subnormal to overflow, mixed scales
//! inside one case, near-edge cases scaled), with and without an entry face; and every exit-face method
//! answers alike compiled for AVX2 (as the walks run: the plain model's eight lanes one AVX register)
//! and for SSE2 alone (eight lanes two SSE registers).

use glam::Vec3;
use tetwalk::engine::filters::{Regime, draw};
use tetwalk::methods::aman20::{Frame, get_exit_face, start_exit_face};
use tetwalk::methods::{
    Aman20, Aman20Scaled, Arith, Certified, ExitMethod, Flushed, Fused, FusedFlushed, HalfSpace,
    Maria17, Model, MomentFirst, Ms06, OriginFirst, Plain, Plucker, RayPlane, Stp,
};
use tetwalk::registry::{METHODS, by_name};
use tetwalk::tet::{EDGES, FACE_VERTICES, Ray, Tet, edge_index};

/// `a·b + c` as the model rounds it.
fn mad(fused: bool, a: f32, b: f32, c: f32) -> f32 {
    if fused { a.mul_add(b, c) } else { a * b + c }
}

fn dot(m: bool, a: Vec3, b: Vec3) -> f32 {
    mad(m, a.z, b.z, mad(m, a.y, b.y, a.x * b.x))
}

fn cross(m: bool, a: Vec3, b: Vec3) -> Vec3 {
    Vec3::new(
        mad(m, a.y, b.z, -(a.z * b.y)),
        mad(m, a.z, b.x, -(a.x * b.z)),
        mad(m, a.x, b.y, -(a.y * b.x)),
    )
}

/// Face `f`'s outward normal and `n · d`.
fn plane(m: bool, t: &Tet, f: usize, d: Vec3) -> (Vec3, f32) {
    let [a, b, c] = FACE_VERTICES[f].map(|i| t[i]);
    let n = cross(m, b - a, c - a);
    (n, dot(m, n, d))
}

/// Lagae & Dutré's ray-plane method, one face at a time.
fn ray_plane(m: bool, t: &Tet, r: &Ray) -> Option<usize> {
    let mut best: Option<(usize, f32)> = None;
    for f in 0..4 {
        let (n, nd) = plane(m, t, f, r.dir);
        if nd > 0.0 {
            let tf = dot(m, n, t[FACE_VERTICES[f][0]] - r.org) / nd;
            if best.is_none_or(|(_, bt)| tf < bt) {
                best = Some((f, tf));
            }
        }
    }
    best.map(|(f, _)| f)
}

/// Their half-space method, one candidate and one half-space at a time.
fn halfspace(m: bool, t: &Tet, r: &Ray) -> Option<usize> {
    let planes: Vec<(Vec3, f32)> = (0..4).map(|f| plane(m, t, f, r.dir)).collect();
    let leaving: Vec<usize> = (0..4).filter(|&f| planes[f].1 > 0.0).collect();
    if leaving.len() == 1 {
        return Some(leaving[0]);
    }
    let anchor = |f: usize| t[FACE_VERTICES[f][0]];
    leaving.iter().copied().find(|&f| {
        let (n, nd) = planes[f];
        let tf = dot(m, n, anchor(f) - r.org) / nd;
        let p = Vec3::new(
            mad(m, r.dir.x, tf, r.org.x),
            mad(m, r.dir.y, tf, r.org.y),
            mad(m, r.dir.z, tf, r.org.z),
        );
        leaving
            .iter()
            .filter(|&&g| g != f)
            .all(|&g| dot(m, planes[g].0, p - anchor(g)) <= 0.0)
    })
}

/// Platis & Theoharis' six side products, one edge at a time, and the first face left.
fn plucker(m: bool, t: &Tet, r: &Ray) -> Option<usize> {
    let v = cross(m, r.org, r.dir);
    let sides = EDGES.map(|[a, b]| {
        let (moment, dir) = (cross(m, t[a], t[b]), t[b] - t[a]);
        mad(
            m,
            v.z,
            dir.z,
            mad(m, v.y, dir.y, mad(m, v.x, dir.x, dot(m, r.dir, moment))),
        )
    });
    (0..4).find(|&f| {
        let c = FACE_VERTICES[f];
        let s = [0, 1, 2].map(|k| {
            let (e, rev) = edge_index(c[k], c[(k + 1) % 3]);
            if rev { -sides[e] } else { sides[e] }
        });
        s.iter().all(|&x| x >= 0.0) && s.iter().any(|&x| x != 0.0)
    })
}

/// Lagae & Dutré's scalar triple products, faces 3 to 0, each face's products taken until one is
/// negative (the published early outs).
fn stp(m: bool, t: &Tet, r: &Ray) -> Option<usize> {
    let rel = t.map(|v| v - r.org);
    let product = |i: usize, j: usize| {
        let (e, rev) = edge_index(i, j);
        let [a, b] = EDGES[e];
        let s = dot(m, r.dir, cross(m, rel[a], rel[b]));
        if rev { -s } else { s }
    };
    (0..4).rev().find(|&f| {
        let v = FACE_VERTICES[f];
        let mut nonzero = false;
        for k in 0..3 {
            let s = product(v[k], v[(k + 1) % 3]);
            if s < 0.0 {
                return false;
            }
            nonzero |= s != 0.0;
        }
        nonzero
    })
}

/// Aman et al.'s Algorithm 1 over the vertices projected one at a time (the projection the layout
/// walks use).
fn projected<M: ExitMethod, A: Arith>(t: &Tet, r: &Ray, entry: Option<usize>) -> Option<usize>
where
    M::RayData: Frame,
{
    let frame = M::prepare::<A>(r);
    let p = t.map(|v| frame.project::<A>(v));
    match entry {
        Some(e) => {
            let [a0, a1, a2] = FACE_VERTICES[e];
            let idx = [a0, a2, a1, e];
            Some(idx[get_exit_face::<A>(&idx.map(|i| p[i]))])
        }
        None => start_exit_face::<A>(&p),
    }
}

/// [`projected`] in `model`'s arithmetic and environment.
fn projected_in<M: ExitMethod>(model: Model, t: &Tet, r: &Ray, e: Option<usize>) -> Option<usize>
where
    M::RayData: Frame,
{
    match model {
        Model::Plain => projected::<M, Plain>(t, r, e),
        Model::Fused => projected::<M, Fused>(t, r, e),
        Model::Flushed => tetwalk::fpenv::flushed((), |_| projected::<M, Flushed>(t, r, e)),
        Model::FusedFlushed => {
            tetwalk::fpenv::flushed((), |_| projected::<M, FusedFlushed>(t, r, e))
        }
    }
}

#[test]
fn four_lane_projections_answer_as_one_vertex_at_a_time() {
    let mut rng = tetwalk::scenes::rng(25);
    let mut differ = 0;
    for regime in Regime::ALL {
        for i in 0..4000 {
            let (x, y) = (draw(regime, &mut rng), draw(regime, &mut rng));
            let tet: Tet = [x.a, x.b, x.c, y.a];
            let ray = Ray {
                org: x.org,
                dir: x.dir,
            };
            for entry in [None, Some(i % 4)] {
                for model in Model::ALL {
                    for (name, want) in [
                        ("aman20", projected_in::<Aman20>(model, &tet, &ray, entry)),
                        (
                            "aman20-scaled",
                            projected_in::<Aman20Scaled>(model, &tet, &ray, entry),
                        ),
                    ] {
                        let got = by_name(name).unwrap().exit(model)(&tet, &ray, entry);
                        assert_eq!(
                            got, want,
                            "{name} {model:?} {regime:?} entry {entry:?}: {tet:?}, {ray:?}"
                        );
                        differ += (got != projected_in::<Aman20>(model, &tet, &ray, entry)) as u32;
                    }
                }
            }
        }
    }
    // Not vacuous: the two frames answer differently somewhere.
    assert!(differ > 0);
}

#[test]
fn four_lane_methods_answer_as_their_scalar_formulas() {
    type Scalar = fn(bool, &Tet, &Ray) -> Option<usize>;
    let methods: [(&str, Scalar); 5] = [
        ("ray-plane", ray_plane),
        ("halfspace", halfspace),
        ("plucker", plucker),
        ("stp", stp),
        ("ms06", plucker),
    ];
    let mut rng = tetwalk::scenes::rng(24);
    let mut asked = 0;
    let mut answered = [0u32; 5];
    for regime in Regime::ALL {
        for _ in 0..4000 {
            let (x, y) = (draw(regime, &mut rng), draw(regime, &mut rng));
            let tet: Tet = [x.a, x.b, x.c, y.a];
            let ray = Ray {
                org: x.org,
                dir: x.dir,
            };
            for (name, scalar) in methods {
                let m = by_name(name).unwrap();
                for model in Model::ALL {
                    let lanes = m.exit(model)(&tet, &ray, None);
                    let fused = model == Model::Fused;
                    let want = match model {
                        Model::Flushed => {
                            tetwalk::fpenv::flushed((), |_| scalar(false, &tet, &ray))
                        }
                        Model::FusedFlushed => {
                            tetwalk::fpenv::flushed((), |_| scalar(true, &tet, &ray))
                        }
                        _ => scalar(fused, &tet, &ray),
                    };
                    assert_eq!(
                        lanes, want,
                        "{name} {model:?} {regime:?}: tetrahedron {tet:?}, ray {ray:?}"
                    );
                    asked += 1;
                    answered[lanes.unwrap_or(4)] += 1;
                    // The entry face is not used by these (ms06 uses it: its own scalar steps).
                    if name != "ms06" {
                        assert_eq!(m.exit(model)(&tet, &ray, Some(asked % 4)), lanes);
                    }
                }
            }
        }
    }
    // Not vacuous: every face answered, and none.
    assert!(answered.iter().all(|&n| n > 100), "{answered:?} of {asked}");
}

/// `M`'s exit face for one case (tetrahedron, ray, entry face) in model `A`.
#[inline(always)]
fn answer<M: ExitMethod, A: Arith>((t, r, e): &(Tet, Ray, Option<usize>)) -> Option<usize> {
    M::exit_face::<A>(t, &M::prepare::<A>(r), *e)
}

/// How many of `cases` registered method `name` (of type `M`) answers differently in `model` (of
/// type `A`) through the registry, as counts and walks run it (compiled for AVX2 where the processor
/// has it, `tetwalk::fpenv::wide`; the plain model's eight lanes then one AVX register), and called straight from here (this test's own code, compiled for
/// SSE2 alone, in the model's environment).
fn wide_differs<M: ExitMethod, A: Arith>(
    name: &str,
    model: Model,
    cases: &[(Tet, Ray, Option<usize>)],
) -> usize {
    let wide = by_name(name).unwrap().exit(model);
    cases
        .iter()
        .filter(|c| {
            let narrow = if A::FLUSHES {
                tetwalk::fpenv::flushed(*c, answer::<M, A>)
            } else {
                answer::<M, A>(c)
            };
            wide(&c.0, &c.1, c.2) != narrow
        })
        .count()
}

/// [`wide_differs`] in the plain and the flushed model.
fn differs<M: ExitMethod>(
    name: &'static str,
    cases: &[(Tet, Ray, Option<usize>)],
) -> (&'static str, usize) {
    let n = wide_differs::<M, Plain>(name, Model::Plain, cases)
        + wide_differs::<M, Flushed>(name, Model::Flushed, cases);
    (name, n)
}

/// Every exit-face method but the exact reference answers alike through the registry, compiled for
/// AVX2 (as the plain and flushed models run where the processor has it, the plain model's eight lanes
/// one AVX register), and compiled for SSE2
/// alone, on cases from every exponent regime, with and without an entry face; the list below holds
/// every such registered method.
#[test]
fn methods_answer_alike_compiled_for_avx2_and_for_sse2() {
    eprintln!(
        "AVX2 here: {} (where it is not, both sides are SSE2 code)",
        tetwalk::fpenv::has_avx2()
    );
    let mut rng = tetwalk::scenes::rng(26);
    let mut cases = Vec::new();
    for regime in Regime::ALL {
        for i in 0..2000 {
            let (x, y) = (draw(regime, &mut rng), draw(regime, &mut rng));
            let ray = Ray {
                org: x.org,
                dir: x.dir,
            };
            for entry in [None, Some(i % 4)] {
                cases.push(([x.a, x.b, x.c, y.a], ray, entry));
            }
        }
    }
    let differ = [
        differs::<Certified>("certified", &cases),
        differs::<RayPlane>("ray-plane", &cases),
        differs::<HalfSpace>("halfspace", &cases),
        differs::<Plucker>("plucker", &cases),
        differs::<Stp>("stp", &cases),
        differs::<Ms06>("ms06", &cases),
        differs::<Maria17<MomentFirst>>("maria17", &cases),
        differs::<Maria17<OriginFirst>>("maria17-translated", &cases),
        differs::<Aman20>("aman20", &cases),
        differs::<Aman20Scaled>("aman20-scaled", &cases),
    ];
    assert!(differ.iter().all(|(_, n)| *n == 0), "{differ:?}");
    for m in METHODS {
        assert!(
            m.info.reference
                || !m.info.runs_on_cpu
                || differ.iter().any(|(n, _)| *n == m.info.name),
            "{} is registered but not compared here",
            m.info.name
        );
    }
}
