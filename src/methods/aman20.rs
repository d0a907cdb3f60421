//! `aman20` and `aman20-scaled`: Aman, Demirci, Güdükbay (seed 003) §4: the tetrahedron projected onto
//! a 2-D frame around the ray, Algorithm 1 exit selection from the one newly fetched vertex.

use super::lanes::{self, F4, Lane, V4};
use super::{Arith, ExitMethod, each, leaves};
use crate::tet::{FACE_VERTICES, Ray, Tet};
use glam::{Vec2, Vec3};

/// `det(a, b) = a.x·b.y - a.y·b.x` (Algorithm 1).
#[inline(always)]
fn det<A: Arith>(a: Vec2, b: Vec2) -> f32 {
    A::mad(a.x, b.y, -(a.y * b.x))
}

/// A 2-D frame around the ray onto which vertices are projected, with the ray at the origin.
pub trait Frame: Copy + Send + Sync {
    /// The projection of the point with coordinates `p` (one point, or four in lanes).
    fn project_lanes<A: Arith, L: Lane>(&self, p: [L; 3]) -> [L; 2];

    /// The projection of `p`.
    #[inline(always)]
    fn project<A: Arith>(&self, p: Vec3) -> Vec2 {
        Vec2::from(self.project_lanes::<A, f32>(p.to_array()))
    }

    /// The projections of a tetrahedron's four vertices, computed in four lanes.
    #[inline(always)]
    fn project_tet<A: Arith>(&self, tet: &Tet) -> [Vec2; 4] {
        let v = V4::of(tet);
        let [x, y] = self
            .project_lanes::<A, F4>([v.x, v.y, v.z])
            .map(F4::to_array);
        [0, 1, 2, 3].map(|i| Vec2::new(x[i], y[i]))
    }
}

/// Algorithm 1, GETEXITFACE: `p0 p1 p2` the entry face, `p3` the new vertex; returns `k`, the exit face
/// being the one across `p_k`. Two determinants, four multiplications, the second chosen by the first
/// (the layout walks', `crate::walk::layouts`, which follow one walk at a time).
#[inline(always)]
pub fn get_exit_face<A: Arith>(p: &[Vec2; 4]) -> usize {
    let mut exit = 0;
    if det::<A>(p[3], p[0]) < 0.0 {
        if det::<A>(p[3], p[2]) >= 0.0 {
            exit = 1;
        }
    } else if det::<A>(p[3], p[1]) < 0.0 {
        exit = 2;
    }
    exit
}

/// [`get_exit_face`] with all three determinants taken and the branch chosen without a jump: the same
/// face (a determinant's value does not depend on whether it is taken; a unit test holds the two
/// together), so that a thread's walks interleave ([`ExitMethod::LANES`]: the default count's aman20
/// walks 18 % faster; a single walk, which the processor runs ahead on its predicted branches, slows).
#[inline(always)]
fn get_exit_face_unbranched<A: Arith>(p: &[Vec2; 4]) -> usize {
    let a = det::<A>(p[3], p[0]) < 0.0;
    let b = det::<A>(p[3], p[2]) >= 0.0;
    let c = det::<A>(p[3], p[1]) < 0.0;
    (a & b) as usize | ((!a & c) as usize) << 1
}

/// The shared method over a projection: with an entry face, its vertices in the order Algorithm 1
/// expects (counterclockwise seen along the ray: the outward cycle reversed) and the opposite vertex
/// as `p3`. Projecting per call gives the same f32 values as the paper's walk, which keeps the three
/// shared projections and projects only the new vertex. Without an entry face, §4's "at most four
/// point-in-triangle tests": the first face whose projected outward cycle has the origin on the left of
/// (or on) all three edges, not all on them.
#[inline(always)]
fn exit_2d<A: Arith>(tet: &Tet, frame: &impl Frame, entry: Option<usize>) -> Option<usize> {
    let p = frame.project_tet::<A>(tet);
    match entry {
        Some(e) => {
            let [a0, a1, a2] = FACE_VERTICES[e];
            let idx = [a0, a2, a1, e];
            Some(idx[get_exit_face_unbranched::<A>(&each(idx, |i| p[i]))])
        }
        None => start_exit_face::<A>(&p),
    }
}

/// §4's exit from the starting tetrahedron, from its four projected vertices.
#[inline(always)]
pub fn start_exit_face<A: Arith>(p: &[Vec2; 4]) -> Option<usize> {
    (0..4).find(|&f| {
        let v = FACE_VERTICES[f];
        let d = each([0, 1, 2], |k| det::<A>(p[v[k]], p[v[(k + 1) % 3]]));
        leaves(&d)
    })
}

/// The ray origin and the orthonormal 2-D basis of Duff et al. 2017 around the unit ray direction.
#[derive(Clone, Copy, Debug)]
pub struct DuffFrame {
    org: Vec3,
    u: Vec3,
    v: Vec3,
}

/// §4 with the Duff et al. 2017 basis of the normalised direction; each vertex is projected as
/// `(u · (v - o), v · (v - o))` (Algorithm 2: 3 sub, 6 mul, 4 add), then Algorithm 1 (4 mul, 2 sub,
/// 2 comparisons).
pub struct Aman20;

impl ExitMethod for Aman20 {
    type RayData = DuffFrame;
    const LANES: usize = 4;

    fn prepare<A: Arith>(ray: &Ray) -> DuffFrame {
        let n = ray.dir / A::dot(ray.dir, ray.dir).sqrt();
        let sign = 1.0f32.copysign(n.z);
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        DuffFrame {
            org: ray.org,
            u: Vec3::new(A::mad(sign * n.x, n.x * a, 1.0), sign * b, -sign * n.x),
            v: Vec3::new(b, A::mad(n.y, n.y * a, sign), -n.y),
        }
    }

    #[inline(always)]
    fn exit_face<A: Arith>(tet: &Tet, r: &DuffFrame, entry: Option<usize>) -> Option<usize> {
        exit_2d::<A>(tet, r, entry)
    }
}

/// The specialised scaled basis of §4.1: `u` (eq. 1) and `v` (eq. 2) scaled so their largest
/// components are exactly ±1, with the component indices of eq. 3.
#[derive(Clone, Copy, Debug)]
pub struct ScaledFrame {
    org: Vec3,
    u: Vec3,
    v: Vec3,
    max: usize,
    min: usize,
    other: usize,
}

/// §4.1: eq. 1 `u_min = 0, u_(min+1) = n_(min-1)/n_max, u_(min-1) = -n_(min+1)/n_max`; eq. 2 `v = n × u`
/// scaled so its largest component, at `min`, is ±1 (the text's "only the absolute largest components
/// become one (or minus one)"; its printed divisor `t_(3-max-min)` would make that component large, so we
/// divide by `|t_min|`, which keeps `(u, v)` right-handed around `n`); eq. 3 `p_x = u_max·q_max + u_other·q_other`,
/// `p_y = v_max·q_max + v_other·q_other ± q_min` with `q = p - o`: 3 sub, 3 mul, 3 add (products by ±1 are
/// exact). Then Algorithm 1.
pub struct Aman20Scaled;

impl ExitMethod for Aman20Scaled {
    type RayData = ScaledFrame;
    const LANES: usize = 4;

    fn prepare<A: Arith>(ray: &Ray) -> ScaledFrame {
        let n = ray.dir;
        let m = n.abs();
        let max = if m.x >= m.y && m.x >= m.z {
            0
        } else if m.y >= m.z {
            1
        } else {
            2
        };
        let min = (0..3)
            .filter(|&i| i != max)
            .fold(3, |b, i| if b == 3 || m[i] < m[b] { i } else { b });
        let other = 3 - max - min;
        let (p, q) = ((min + 1) % 3, (min + 2) % 3);
        let mut u = Vec3::ZERO;
        u[p] = n[q] / n[max];
        u[q] = -n[p] / n[max];
        let t = A::cross(n, u);
        let v = t / t[min].abs();
        ScaledFrame {
            org: ray.org,
            u,
            v,
            max,
            min,
            other,
        }
    }

    #[inline(always)]
    fn exit_face<A: Arith>(tet: &Tet, r: &ScaledFrame, entry: Option<usize>) -> Option<usize> {
        exit_2d::<A>(tet, r, entry)
    }
}

impl Frame for DuffFrame {
    #[inline(always)]
    fn project_lanes<A: Arith, L: Lane>(&self, p: [L; 3]) -> [L; 2] {
        let q = [0, 1, 2].map(|k| p[k] - L::splat(self.org[k]));
        let along = |a: Vec3| lanes::dot::<A, L>(a.to_array().map(L::splat), q);
        [along(self.u), along(self.v)]
    }
}

impl Frame for ScaledFrame {
    #[inline(always)]
    fn project_lanes<A: Arith, L: Lane>(&self, p: [L; 3]) -> [L; 2] {
        let q = [0, 1, 2].map(|k| p[k] - L::splat(self.org[k]));
        let (u, v) = (
            self.u.to_array().map(L::splat),
            self.v.to_array().map(L::splat),
        );
        let (max, other, min) = (self.max, self.other, self.min);
        let x = L::mad::<A>(u[max], q[max], u[other] * q[other]);
        let y = L::mad::<A>(v[other], q[other], v[max] * q[max]) + v[min] * q[min];
        [x, y]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::methods::Plain;

    /// The unbranched GETEXITFACE answers as the published tree on 4,000 vertex sets that give every
    /// outcome of the tree's three tests, with zero, subnormal, infinite and NaN coordinates among them.
    #[test]
    fn unbranched_get_exit_face_is_the_published_tree() {
        let xs = [
            -2.0,
            -1.0,
            -f32::MIN_POSITIVE / 4.0,
            0.0,
            -0.0,
            1e-45,
            0.5,
            3.0,
            f32::INFINITY,
            f32::NAN,
        ];
        let mut n = 0;
        // The tree's three tests, `d30 < 0`, `d32 >= 0`, `d31 < 0`, as they fall.
        let mut patterns = std::collections::BTreeSet::new();
        for &a in &xs {
            for &b in &xs {
                for &c in &xs {
                    for &d in &[-1.0, 0.0, 2.0, f32::NAN] {
                        let p = [
                            Vec2::new(a, 1.0),
                            Vec2::new(b, c),
                            Vec2::new(c, a),
                            Vec2::new(d, b),
                        ];
                        assert_eq!(
                            get_exit_face_unbranched::<Plain>(&p),
                            get_exit_face::<Plain>(&p),
                            "{p:?}"
                        );
                        patterns.insert([
                            det::<Plain>(p[3], p[0]) < 0.0,
                            det::<Plain>(p[3], p[2]) >= 0.0,
                            det::<Plain>(p[3], p[1]) < 0.0,
                        ]);
                        n += 1;
                    }
                }
            }
        }
        assert_eq!(n, 4000);
        assert_eq!(patterns.len(), 8, "every outcome of the three tests");
    }
}
