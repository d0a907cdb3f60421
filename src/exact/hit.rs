//! Exact ray–triangle intersection with rationals, and the brute-force first hit over a mesh's
//! constrained faces: the reference that walks are checked against.

use super::ExactError;
use super::rational::{det, neg, q3, sub};
use crate::mesh::Mesh;
use crate::tet::{Ray, orientation};
use glam::Vec3;
use rug::Rational;

/// Where the line `o + t·d` crosses a closed triangle.
#[derive(Clone, Debug, PartialEq)]
pub struct Crossing {
    pub t: Rational,
    /// The point lies on the triangle's boundary (an edge or a vertex).
    pub on_boundary: bool,
}

/// Where the line `o + t·d` crosses the closed triangle `abc`, if it crosses it (a line in the
/// triangle's plane does not cross it).
pub fn line_triangle(tri: [Vec3; 3], ray: &Ray) -> Option<Crossing> {
    let [a, b, c] = tri.map(q3);
    let (o, d) = (q3(ray.org), q3(ray.dir));
    let (ab, ac) = (sub(&b, &a), sub(&c, &a));
    // Cramer on o + t d = a + u ab + v ac.
    let nd = neg(&d);
    let den = det(&ab, &ac, &nd);
    if den.cmp0().is_eq() {
        return None;
    }
    let rhs = sub(&o, &a);
    let u = det(&rhs, &ac, &nd) / &den;
    let v = det(&ab, &rhs, &nd) / &den;
    let t = det(&ab, &ac, &rhs) / &den;
    let w = Rational::from(1) - Rational::from(&u + &v);
    let inside = u.cmp0().is_ge() && v.cmp0().is_ge() && w.cmp0().is_ge();
    let on_boundary = u.cmp0().is_eq() || v.cmp0().is_eq() || w.cmp0().is_eq();
    inside.then_some(Crossing { t, on_boundary })
}

/// The exact answer for a ray and one triangle (seed 004's question): a hit is a crossing of the
/// closed triangle at `t > 0` (an origin on the triangle is a miss; a ray parallel to the plane misses
/// it, even in it), on its boundary when the point lies on an edge or vertex.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RayHit {
    pub hit: bool,
    /// The hit point lies on an edge or a vertex (false for a miss).
    pub on_boundary: bool,
}

/// [`RayHit`] from exact signs (filtered): `n·d` with `n = (b - a) × (c - a)` not 0, each edge's side
/// product `det[p - o, q - o, d]` 0 or of the sign of `n·d`, and `orient3d(a, b, c, o)` (the sign of
/// `n·(a - o)`) of that sign too. An error for a non-finite number, a zero direction or a degenerate
/// triangle.
pub fn ray_triangle(tri: [Vec3; 3], ray: &Ray) -> Result<RayHit, ExactError> {
    let [a, b, c] = tri;
    super::check_ray(&tri, ray)?;
    if (0..3).all(|k| super::normal_dot(a, b, c, super::unit(k)) == 0) {
        return Err(ExactError::FlatTriangle);
    }
    let miss = RayHit {
        hit: false,
        on_boundary: false,
    };
    let nd = super::normal_dot(a, b, c, ray.dir);
    if nd == 0 {
        return Ok(miss);
    }
    let mut on_boundary = false;
    for (p, q) in [(a, b), (b, c), (c, a)] {
        match super::side(p, q, ray) {
            0 => on_boundary = true,
            s if s != nd => return Ok(miss),
            _ => {}
        }
    }
    if orientation(&[a, b, c, ray.org]) != nd {
        return Ok(miss);
    }
    Ok(RayHit {
        hit: true,
        on_boundary,
    })
}

/// The exact `t` of a ray's hit on a triangle ([`ray_triangle`]), `None` for a miss.
pub fn ray_triangle_t(tri: [Vec3; 3], ray: &Ray) -> Result<Option<Rational>, ExactError> {
    Ok(if ray_triangle(tri, ray)?.hit {
        line_triangle(tri, ray).map(|c| c.t)
    } else {
        None
    })
}

/// Whether the ray, its origin perturbed as in [`super::perturbed_exit`], crosses the triangle at
/// `t > 0`; `t` is then the unperturbed crossing parameter. A ray that only grazes an edge or vertex, lies
/// in the triangle's plane, or starts on the triangle and moves away, passes beside it, as the `exact`
/// walk sees it.
pub fn perturbed_crossing(tri: [Vec3; 3], ray: &Ray) -> Option<Rational> {
    let [a, b, c] = tri;
    let nd = super::normal_dot(a, b, c, ray.dir);
    let sides = [(a, b), (b, c), (c, a)].map(|(p, q)| super::perturbed_side(p, q, ray));
    if nd == 0 || sides.iter().any(|&s| s != nd) {
        return None;
    }
    let t = line_triangle(tri, ray)?.t;
    let ahead = match t.cmp0() {
        std::cmp::Ordering::Equal => {
            // t(ε) = n · (a - o_ε) / (n · d): ahead iff -n's first nonzero component has the sign of n · d.
            let n0 = (0..3)
                .map(|k| super::normal_dot(a, b, c, super::unit(k)))
                .find(|&x| x != 0)
                .unwrap_or(0);
            -n0 == nd
        }
        o => o.is_gt(),
    };
    ahead.then_some(t)
}

/// The first crossing of the ray ([`perturbed_crossing`]) with any constrained face of the mesh, by
/// trying every one: the smallest `t` and every `(tetrahedron, face)` crossed there.
pub fn first_hit(mesh: &Mesh, ray: &Ray) -> Option<(Rational, Vec<(u32, u8)>)> {
    let mut best: Option<(Rational, Vec<(u32, u8)>)> = None;
    for t in 0..mesh.tets.len() as u32 {
        for f in 0..4 {
            if !mesh.is_constrained(t, f) {
                continue;
            }
            let tri = mesh.face(t, f).map(|i| mesh.points[i as usize]);
            let Some(x) = perturbed_crossing(tri, ray) else {
                continue;
            };
            match &mut best {
                Some((bt, faces)) if *bt == x => faces.push((t, f as u8)),
                Some((bt, _)) if *bt < x => {}
                _ => best = Some((x, vec![(t, f as u8)])),
            }
        }
    }
    best
}
