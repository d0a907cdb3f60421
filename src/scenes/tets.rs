//! Single tetrahedra — well-shaped, sliver, cap, needle, wedge — and rays that stab them: random, aimed
//! exactly through an edge or a vertex, or within k ulps of one.

use super::Rng;
use crate::tet::{EDGES, FACE_VERTICES, Ray, Tet, normalize, orientation};
use glam::{Mat3, Quat, Vec3};
use rand::RngExt;

/// Shape families (Cheng et al.'s taxonomy of badly shaped tetrahedra), plus the well-shaped one.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum TetShape {
    /// Near-regular.
    Well,
    /// Four well-separated vertices near one plane, no short edge.
    Sliver,
    /// One vertex just above the inside of the opposite face.
    Cap,
    /// Three vertices close together, the fourth far away.
    Needle,
    /// One short edge.
    Wedge,
}

crate::choice!(TetShape { Well => "well", Sliver => "sliver", Cap => "cap", Needle => "needle", Wedge => "wedge" });

impl TetShape {
    pub const ALL: [TetShape; 5] = [
        TetShape::Well,
        TetShape::Sliver,
        TetShape::Cap,
        TetShape::Needle,
        TetShape::Wedge,
    ];

    /// The shape in its own frame; `flatness` in (0, 1], smaller is flatter.
    fn canonical(self, flatness: f32, rng: &mut Rng) -> [Vec3; 4] {
        let h = flatness;
        let mut j = |s: f32| {
            Vec3::new(
                rng.random_range(-s..s),
                rng.random_range(-s..s),
                rng.random_range(-s..s),
            )
        };
        match self {
            TetShape::Well => [
                Vec3::new(1.0, 1.0, 1.0) + j(0.15),
                Vec3::new(1.0, -1.0, -1.0) + j(0.15),
                Vec3::new(-1.0, 1.0, -1.0) + j(0.15),
                Vec3::new(-1.0, -1.0, 1.0) + j(0.15),
            ],
            TetShape::Sliver => [
                Vec3::new(1.0, 0.0, h) + j(0.1) * Vec3::new(1.0, 1.0, h),
                Vec3::new(-1.0, 0.0, h) + j(0.1) * Vec3::new(1.0, 1.0, h),
                Vec3::new(0.0, 1.0, -h) + j(0.1) * Vec3::new(1.0, 1.0, h),
                Vec3::new(0.0, -1.0, -h) + j(0.1) * Vec3::new(1.0, 1.0, h),
            ],
            TetShape::Cap => {
                let apex = j(0.3) * Vec3::new(1.0, 1.0, 0.0) + Vec3::new(0.0, 0.0, h);
                [
                    Vec3::new(1.0, 0.0, 0.0),
                    Vec3::new(-0.5, 0.866, 0.0),
                    Vec3::new(-0.5, -0.866, 0.0),
                    apex,
                ]
            }
            TetShape::Needle => [
                Vec3::new(h, 0.0, 0.0) + j(0.2 * h),
                Vec3::new(-0.5 * h, 0.866 * h, 0.0) + j(0.2 * h),
                Vec3::new(-0.5 * h, -0.866 * h, 0.0) + j(0.2 * h),
                Vec3::new(0.0, 0.0, 2.0) + j(0.3),
            ],
            TetShape::Wedge => [
                Vec3::new(-0.5 * h, 0.0, 0.0),
                Vec3::new(0.5 * h, 0.0, 0.0),
                Vec3::new(0.3, 1.0, 0.0) + j(0.2),
                Vec3::new(-0.2, 0.0, 1.0) + j(0.2),
            ],
        }
    }
}

/// A random rotation.
pub(crate) fn rotation(rng: &mut Rng) -> Mat3 {
    let q = Quat::from_xyzw(
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
    );
    Mat3::from_quat(if q.length() > 1e-3 {
        q.normalize()
    } else {
        Quat::IDENTITY
    })
}

/// A positively oriented, non-flat tetrahedron of `shape`, randomly rotated, of size about 1 near the
/// origin; `flatness` in (0, 1].
pub fn tet(shape: TetShape, flatness: f32, rng: &mut Rng) -> Tet {
    loop {
        let r = rotation(rng);
        let c = shape.canonical(flatness, rng).map(|v| r * v);
        let (t, _) = normalize(&c);
        if orientation(&t) != 0 {
            return t;
        }
    }
}

/// A point inside the tetrahedron (random barycentric weights, kept away from the faces).
pub(crate) fn interior_point(t: &Tet, rng: &mut Rng) -> Vec3 {
    let w: [f32; 4] = std::array::from_fn(|_| rng.random_range(0.2..1.0));
    let s: f32 = w.iter().sum();
    (0..4).map(|i| t[i] * (w[i] / s)).sum()
}

/// A random point of face `f` (uniform barycentric weights, so near its edges too).
fn face_point(t: &Tet, f: usize, rng: &mut Rng) -> Vec3 {
    let w: [f32; 3] = std::array::from_fn(|_| rng.random_range(0.0..1.0));
    let s: f32 = w.iter().sum();
    let v = FACE_VERTICES[f];
    (0..3).map(|i| t[v[i]] * (w[i] / s)).sum()
}

/// A ray that stabs the tetrahedron through two of its faces; the origin is inside (half the time)
/// or up to one diameter before the entry face.
pub fn stabbing_ray(t: &Tet, rng: &mut Rng) -> Ray {
    let e = rng.random_range(0..4);
    let x = (e + rng.random_range(1..4)) % 4;
    let (a, b) = (face_point(t, e, rng), face_point(t, x, rng));
    let dir = b - a;
    let s = if rng.random_bool(0.5) {
        rng.random_range(0.05..0.95)
    } else {
        -rng.random_range(0.0..1.0)
    };
    Ray {
        org: a + dir * s,
        dir,
    }
}

/// What a tie-aiming ray aims at.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    Edge,
    Vertex,
}

/// A tetrahedron of `shape` with integer coordinates (scaled by a power of two so its flat dimension
/// still spans a few dozen units), and a ray from a lattice point inside it passing exactly through the
/// midpoint of an edge or through a vertex; all of it exact in f32, so the line truly meets the edge or
/// vertex. `None` if 100 draws found none (only for flatness far below 1e-4).
pub fn through(
    shape: TetShape,
    flatness: f32,
    target: Target,
    rng: &mut Rng,
) -> Option<(Tet, Ray)> {
    let scale = (64.0 / flatness.clamp(1e-5, 1.0)).log2().ceil().exp2();
    for _ in 0..100 {
        let t = tet(shape, flatness, rng).map(|v| (v * scale).round());
        if orientation(&t) <= 0 {
            continue;
        }
        let p = interior_point(&t, rng).round();
        let inside = FACE_VERTICES
            .iter()
            .all(|v| orientation(&[t[v[0]], t[v[1]], t[v[2]], p]) > 0);
        if !inside {
            continue;
        }
        let aim = match target {
            Target::Vertex => t[rng.random_range(0..4)],
            Target::Edge => {
                let [a, b] = EDGES[rng.random_range(0..6)];
                (t[a] + t[b]) * 0.5
            }
        };
        let dir = aim - p;
        if dir == Vec3::ZERO {
            continue;
        }
        // Start behind the interior point half the time, still exactly on the line.
        let org = if rng.random_bool(0.5) { p } else { p - dir };
        return Some((t, Ray { org, dir }));
    }
    None
}

/// `x` moved by `k` ulps (towards +∞ for positive `k`).
pub(crate) fn ulps(x: f32, k: i32) -> f32 {
    let mut y = x;
    for _ in 0..k.unsigned_abs() {
        y = if k > 0 { y.next_up() } else { y.next_down() };
    }
    y
}

/// The ulp of the case's scale: of the largest magnitude `scale` among its coordinates (2^-149 below
/// the normal range).
fn ulp_of(scale: f32) -> f64 {
    let e = (scale.abs() as f64).log2().floor().max(-126.0);
    (e - 23.0).exp2()
}

/// `org` moved along a random axis by 1 to `k` ulps of the case's scale (the largest magnitude among
/// the case's coordinates, `scale`), either way: "near" measured at the case's scale, so a zero
/// coordinate moves as far as the others, not by a subnormal. The generators' coordinates are
/// integers or dyadic, so the step is exact (a multiple of each coordinate's ulp); where moving away
/// from zero would leave the binade and round, it moves towards zero instead.
pub(crate) fn nudge(org: Vec3, scale: f32, k: i32, rng: &mut Rng) -> Vec3 {
    let axis = rng.random_range(0..3);
    let by = rng.random_range(1..=k.max(1)) * if rng.random_bool(0.5) { 1 } else { -1 };
    let step = by as f64 * ulp_of(scale);
    let x = org[axis] as f64;
    let exact = |y: f64| (y as f32) as f64 == y;
    let moved = if exact(x + step) { x + step } else { x - step };
    let mut out = org;
    out[axis] = moved as f32;
    out
}

/// The largest magnitude among points' coordinates.
pub(crate) fn scale_of<'a>(points: impl IntoIterator<Item = &'a Vec3>) -> f32 {
    points
        .into_iter()
        .map(|p| p.abs().max_element())
        .fold(0.0, f32::max)
}

/// [`through`], then the origin moved by 1 to `k` ulps of the case's scale along a random axis
/// ([`nudge`]): a line that misses the edge or vertex by a hair.
pub fn near(
    shape: TetShape,
    flatness: f32,
    target: Target,
    k: i32,
    rng: &mut Rng,
) -> Option<(Tet, Ray)> {
    let (t, mut ray) = through(shape, flatness, target, rng)?;
    let scale = scale_of(t.iter().chain([&ray.org]));
    ray.org = nudge(ray.org, scale, k, rng);
    Some((t, ray))
}

/// The tetrahedron and ray moved by `offset` (rounded to f32); `None` when rounding flattened it.
pub fn translated(t: &Tet, ray: &Ray, offset: Vec3) -> Option<(Tet, Ray)> {
    let (t, _) = normalize(&t.map(|v| v + offset));
    (orientation(&t) != 0).then_some((
        t,
        Ray {
            org: ray.org + offset,
            dir: ray.dir,
        },
    ))
}
