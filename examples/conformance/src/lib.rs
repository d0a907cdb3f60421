//! A user's traversal code, as it would live in their own crate: two exit-face methods, two
//! ray–triangle tests and two octree cell tests, written against tetwalk's kit prelude only (it
//! builds with tetwalk's `default-features = false`). `tests/conformance.rs` judges them with
//! `tetwalk::kit`: the exact ones pass, the f32 ones are caught.

use rug::Rational;
use std::cmp::Ordering;
use tetwalk::kit::prelude::*;

/// A vector of exact rationals (every f32 is one).
fn exact(v: Vec3) -> [Rational; 3] {
    v.to_array()
        .map(|x| Rational::from_f32(x).expect("finite coordinates"))
}

fn sub(a: &[Rational; 3], b: &[Rational; 3]) -> [Rational; 3] {
    std::array::from_fn(|i| Rational::from(&a[i] - &b[i]))
}

fn cross(a: &[Rational; 3], b: &[Rational; 3]) -> [Rational; 3] {
    std::array::from_fn(|i| {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        Rational::from(&a[j] * &b[k]) - Rational::from(&a[k] * &b[j])
    })
}

fn dot(a: &[Rational; 3], b: &[Rational; 3]) -> Rational {
    (0..3).map(|i| Rational::from(&a[i] * &b[i])).sum()
}

/// The sign of the side product `det[a - o, b - o, d] = d · ((a - o) × (b - o))`, exactly.
pub fn side_sign(a: Vec3, b: Vec3, o: Vec3, d: Vec3) -> Ordering {
    let o = exact(o);
    let (a, b) = (sub(&exact(a), &o), sub(&exact(b), &o));
    dot(&exact(d), &cross(&a, &b)).cmp0()
}

/// The side sign under Simulation of Simplicity: the origin moved to `o + ε·x + ε²·y + ε³·z`, so a
/// zero side takes the first nonzero component of `-((b - a) × d)`.
fn perturbed_side(a: Vec3, b: Vec3, o: Vec3, d: Vec3) -> Ordering {
    match side_sign(a, b, o, d) {
        Ordering::Equal => cross(&sub(&exact(b), &exact(a)), &exact(d))
            .iter()
            .map(|c| c.cmp0().reverse())
            .find(|c| c.is_ne())
            .unwrap_or(Ordering::Equal),
        s => s,
    }
}

/// Plücker exit test with exact, perturbed side signs: face `f` is left when the three sides along
/// its outward cycle are positive. Consistent between neighbours, so walks neither cycle nor stop.
/// Where the perturbed line misses (the line only touches the tetrahedron), Platis & Theoharis' rule
/// on the exact signs: `≥ 0` and not all zero.
pub struct ExactPlucker;

impl ExitMethod for ExactPlucker {
    type RayData = Ray;

    fn prepare<A: Arith>(ray: &Ray) -> Ray {
        *ray
    }

    fn exit_face<A: Arith>(tet: &Tet, ray: &Ray, _entry: Option<usize>) -> Option<usize> {
        let sides = |f: usize, side: fn(Vec3, Vec3, Vec3, Vec3) -> Ordering| {
            let v = FACE_VERTICES[f].map(|i| tet[i]);
            [0, 1, 2].map(|k| side(v[k], v[(k + 1) % 3], ray.org, ray.dir))
        };
        (0..4)
            .find(|&f| sides(f, perturbed_side).iter().all(|s| s.is_gt()))
            .or_else(|| {
                (0..4).find(|&f| {
                    let s = sides(f, side_sign);
                    s.iter().all(|s| s.is_ge()) && s.iter().any(|s| s.is_ne())
                })
            })
    }
}

/// The textbook f32 Plücker test (side products, Platis & Theoharis' `≥ 0, not all zero`), in the
/// operation order of tetwalk's `plucker`: rounding decides the sign of side products near zero, so it
/// picks wrong faces and walks cycle.
pub struct F32Plucker;

impl ExitMethod for F32Plucker {
    type RayData = (Vec3, Vec3);

    fn prepare<A: Arith>(ray: &Ray) -> (Vec3, Vec3) {
        (ray.dir, A::cross(ray.org, ray.dir))
    }

    fn exit_face<A: Arith>(
        tet: &Tet,
        &(u, v): &(Vec3, Vec3),
        _entry: Option<usize>,
    ) -> Option<usize> {
        // u·(a × b) + v·(b - a), summed left to right as tetwalk's `plucker` sums it.
        let side = |a: Vec3, b: Vec3| {
            let e = b - a;
            A::mad(
                v.z,
                e.z,
                A::mad(v.y, e.y, A::mad(v.x, e.x, A::dot(u, A::cross(a, b)))),
            )
        };
        (0..4).find(|&f| {
            let p = FACE_VERTICES[f].map(|i| tet[i]);
            let s = [side(p[0], p[1]), side(p[1], p[2]), side(p[2], p[0])];
            s.iter().all(|&x| x >= 0.0) && s.iter().any(|&x| x != 0.0)
        })
    }
}

/// A two-sided ray–triangle test whose hit decision is exact (the three edge sides of the same sign,
/// not all zero), so it never leaks through a shared edge or vertex; `t` in f32.
pub struct ExactEdges;

impl SingleRay for ExactEdges {
    fn test<A: Arith>(tri: &Tri, ray: &Ray) -> Option<f32> {
        let s = [0, 1, 2].map(|k| side_sign(tri[k], tri[(k + 1) % 3], ray.org, ray.dir));
        let all = |p: fn(Ordering) -> bool| s.iter().all(|&x| p(x));
        if !(all(Ordering::is_ge) || all(Ordering::is_le)) || all(Ordering::is_eq) {
            return None;
        }
        let n = (tri[1] - tri[0]).cross(tri[2] - tri[0]);
        let t = n.dot(tri[0] - ray.org) / n.dot(ray.dir);
        t.is_finite().then_some(t)
    }
}

/// Möller & Trumbore 1997 as it is usually copied: two-sided, f32, no epsilon. Rounding can reject a
/// ray through a shared edge on both sides: a leak.
pub struct F32MollerTrumbore;

impl SingleRay for F32MollerTrumbore {
    fn test<A: Arith>(tri: &Tri, ray: &Ray) -> Option<f32> {
        let (e1, e2) = (tri[1] - tri[0], tri[2] - tri[0]);
        let p = ray.dir.cross(e2);
        let det = e1.dot(p);
        if det == 0.0 {
            return None;
        }
        let inv = 1.0 / det;
        let s = ray.org - tri[0];
        let u = s.dot(p) * inv;
        if !(0.0..=1.0).contains(&u) {
            return None;
        }
        let q = s.cross(e1);
        let v = ray.dir.dot(q) * inv;
        if v < 0.0 || u + v > 1.0 {
            return None;
        }
        Some(e2.dot(q) * inv)
    }
}

/// An octree cell's exit by slabs, as ray tracers write it: the smallest exit parameter over the axes,
/// then the exit point against the face centre, in f32. Rounding moves the point off an edge or a
/// centre line: wrong faces and wrong neighbours.
pub struct F32Slabs;

/// An octree cell's exit by slabs in exact rationals: the first axis whose exit parameter is the
/// smallest, and the quarter the exact exit point lies in (the lower one on a centre line).
pub struct ExactSlabs;

/// Face numbering of tetwalk's octree cells (seed 001's Figure 4, `tetwalk::kit::prelude::cell`).
fn face(axis: usize, high: bool) -> usize {
    cell::face_of(axis, high)
}

impl CellMethod for F32Slabs {
    type RayData = Ray;

    fn prepare<A: Arith>(ray: &Ray) -> Ray {
        *ray
    }

    fn exit<A: Arith>(lo: Vec3, hi: Vec3, r: &Ray) -> Option<(usize, usize)> {
        let (axis, t) = (0..3)
            .filter(|&a| r.dir[a] != 0.0)
            .map(|a| {
                let plane = if r.dir[a] > 0.0 { hi[a] } else { lo[a] };
                (a, (plane - r.org[a]) / r.dir[a])
            })
            .min_by(|x, y| x.1.total_cmp(&y.1))?;
        let p = r.org + r.dir * t;
        let c = (lo + hi) * 0.5;
        let [u, v] = cell::face_axes(axis);
        let q = (p[u] < c[u]) as usize | ((p[v] < c[v]) as usize) << 1;
        Some((face(axis, r.dir[axis] > 0.0), q))
    }
}

impl CellMethod for ExactSlabs {
    type RayData = Ray;

    fn prepare<A: Arith>(ray: &Ray) -> Ray {
        *ray
    }

    fn exit<A: Arith>(lo: Vec3, hi: Vec3, r: &Ray) -> Option<(usize, usize)> {
        let (o, d, l, h) = (exact(r.org), exact(r.dir), exact(lo), exact(hi));
        let (axis, t) = (0..3)
            .filter(|&a| d[a].cmp0().is_ne())
            .map(|a| {
                let plane = if d[a].cmp0().is_gt() { &h[a] } else { &l[a] };
                (a, Rational::from(plane - &o[a]) / &d[a])
            })
            .min_by(|x, y| x.1.cmp(&y.1))?;
        let p: [Rational; 3] = std::array::from_fn(|a| Rational::from(&d[a] * &t) + &o[a]);
        let c: [Rational; 3] = std::array::from_fn(|a| Rational::from(&l[a] + &h[a]) / 2u32);
        let [u, v] = cell::face_axes(axis);
        let q = (p[u] < c[u]) as usize | ((p[v] < c[v]) as usize) << 1;
        Some((face(axis, d[axis].cmp0().is_gt()), q))
    }
}

/// What the crate's fuzz target (`fuzz/fuzz_targets/exact_plucker.rs`) runs on each input: the case
/// cargo-fuzz decodes through tetwalk's own decoder (`Case: arbitrary::Arbitrary`), judged exactly;
/// a panic with the kit's report where `ExactPlucker` is wrong.
pub fn fuzz_exact_plucker(case: Case) {
    if let Err(failed) = judge_exit_face::<ExactPlucker>(&case, &Settings::default()) {
        panic!("{failed}");
    }
}
