//! Exact ray–triangle intersection with rationals, and the brute-force first hit over a mesh's
//! constrained faces: the reference that walks are checked against.

use super::ExactError;
use super::rational::{det, neg, q3, sub};
use crate::mesh::Mesh;
use crate::tet::{Ray, Tri, orientation};
use glam::Vec3;
use rug::Rational;

/// Where the line `o + t·d` crosses a closed triangle.
#[derive(Clone, Debug, PartialEq)]
pub struct Crossing {
    /// The line parameter of the crossing, exactly.
    pub t: Rational,
    /// The point lies on the triangle's boundary (an edge or a vertex).
    pub on_boundary: bool,
}

/// Cramer's rule on `o + t d = a + u ab + v ac` for a triangle `abc` and a ray: the columns `ab`,
/// `ac`, `-d`, the right side `o - a` and the determinant, not 0 (`None` where the line lies parallel
/// to the triangle's plane).
struct Cramer {
    ab: [Rational; 3],
    ac: [Rational; 3],
    nd: [Rational; 3],
    rhs: [Rational; 3],
    den: Rational,
}

impl Cramer {
    fn of(tri: [Vec3; 3], ray: &Ray) -> Option<Cramer> {
        let [a, b, c] = tri.map(q3);
        let (ab, ac, nd) = (sub(&b, &a), sub(&c, &a), neg(&q3(ray.dir)));
        let den = det(&ab, &ac, &nd);
        let rhs = sub(&q3(ray.org), &a);
        (!den.cmp0().is_eq()).then_some(Cramer {
            ab,
            ac,
            nd,
            rhs,
            den,
        })
    }

    /// The line's parameter `t` where it meets the plane.
    fn t(&self) -> Rational {
        det(&self.ab, &self.ac, &self.rhs) / &self.den
    }
}

/// Where the line `o + t·d` crosses the closed triangle `abc`, if it crosses it (a line in the
/// triangle's plane does not cross it).
pub fn line_triangle(tri: [Vec3; 3], ray: &Ray) -> Option<Crossing> {
    let c = Cramer::of(tri, ray)?;
    let u = det(&c.rhs, &c.ac, &c.nd) / &c.den;
    let v = det(&c.ab, &c.rhs, &c.nd) / &c.den;
    let w = Rational::from(1) - Rational::from(&u + &v);
    let inside = u.cmp0().is_ge() && v.cmp0().is_ge() && w.cmp0().is_ge();
    let on_boundary = u.cmp0().is_eq() || v.cmp0().is_eq() || w.cmp0().is_eq();
    inside.then(|| Crossing {
        t: c.t(),
        on_boundary,
    })
}

/// The exact answer for a ray and one triangle (seed 004's question): a hit is a crossing of the
/// closed triangle at `t > 0` (an origin on the triangle is a miss; a ray parallel to the plane misses
/// it, even in it), on its boundary when the point lies on an edge or vertex.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RayHit {
    /// The ray hits the closed triangle at `t > 0`.
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
    // The perturbed line crosses the triangle's interior, so the line meets the closed triangle: only
    // `t` is needed.
    let t = Cramer::of(tri, ray)?.t();
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

/// The first crossing of the ray ([`perturbed_crossing`]) with any of `tris` (each with a label), by
/// trying every one: the smallest `t` and the label of every triangle crossed there.
pub fn first_crossing<K>(
    tris: impl IntoIterator<Item = (K, Tri)>,
    ray: &Ray,
) -> Option<(Rational, Vec<K>)> {
    let mut best: Option<(Rational, Vec<K>)> = None;
    for (k, tri) in tris {
        let Some(x) = perturbed_crossing(tri, ray) else {
            continue;
        };
        match &mut best {
            Some((bt, at)) if *bt == x => at.push(k),
            Some((bt, _)) if *bt < x => {}
            _ => best = Some((x, vec![k])),
        }
    }
    best
}

/// The first crossing of the ray ([`perturbed_crossing`]) with any constrained face of the mesh, by
/// trying every one: the smallest `t` and every `(tetrahedron, face)` crossed there.
pub fn first_hit(mesh: &Mesh, ray: &Ray) -> Option<(Rational, Vec<(u32, u8)>)> {
    let faces = (0..mesh.tets.len() as u32)
        .flat_map(|t| (0..4).map(move |f| (t, f)))
        .filter(|&(t, f)| mesh.is_constrained(t, f))
        .map(|(t, f)| {
            let tri = mesh.face(t, f).map(|i| mesh.points[i as usize]);
            ((t, f as u8), tri)
        });
    first_crossing(faces, ray)
}

/// One point where a ray meets a triangle case's surface, exactly.
#[derive(Clone, Debug, PartialEq)]
pub struct HitPoint {
    /// The ray parameter of the point, exactly.
    pub t: rug::Rational,
    /// The triangles holding the point.
    pub holding: Vec<u32>,
    /// Whether the ray crosses the surface there: every triangle holding the point faces the same way
    /// along the ray (`n·d` of one sign) and none whose plane holds the ray shares the point. Otherwise
    /// it only touches it (an edge or vertex on the silhouette, or runs along a triangle) — or crosses
    /// a saddle, which this test does not tell apart.
    pub crosses: bool,
    /// The triangles around the point that face the way the ray crosses there: those sharing a vertex
    /// with a triangle holding it, with `n·d` of the same sign. A ray that crosses the surface and hits none of them passes through: a leak, unless a silhouette is near ([`HitPoint::silhouette`]).
    pub around: Vec<u32>,
    /// Whether the point lies so near a silhouette that a miss may be rounding carrying the ray off it
    /// rather than through a crack: a triangle around it is seen within 2^-10 radians of edge-on, or,
    /// for a point inside one triangle, the triangle across its nearest edge faces the other way (or
    /// is parallel to the ray), or the point is within 1/1000 of that edge's length from a vertex around
    /// which a triangle does. Measured in f64: it sorts misses into leaks and misses beside the
    /// object, and decides no answer.
    pub silhouette: bool,
}

/// How a method misses where a ray crosses a closed surface ([`HitTruth::missed`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Missed {
    /// Through the surface: a crack at a shared edge or vertex, or between triangles.
    Leak,
    /// Beside the object as the method rounds the ray: near a silhouette, or no hit on it at all.
    Beside,
}

/// The exact answer to a triangle case.
#[derive(Clone, Debug, PartialEq)]
pub struct HitTruth {
    /// Per triangle, whether the ray hits it and on its boundary ([`ray_triangle`]).
    pub each: Vec<RayHit>,
    /// Where the ray meets the surface, nearest first.
    pub points: Vec<HitPoint>,
    /// The case is a closed mesh (`tris`), not one triangle.
    pub closed: bool,
    /// Per triangle, the sign of its normal `(b - a) × (c - a)` dotted with the ray's direction:
    /// negative where the ray sees it counter-clockwise (its front, as `mt` tests it).
    pub facing: Vec<i8>,
}

impl HitTruth {
    /// The first point the ray meets.
    pub fn first(&self) -> Option<&HitPoint> {
        self.points.first()
    }

    /// Whether the ray meets the back of every triangle at its first point (they face its way): a
    /// method that culls back faces (`mt`, as published) misses it by design, not by rounding.
    pub fn back_face(&self) -> bool {
        self.first()
            .is_some_and(|p| p.holding.iter().all(|&i| self.facing[i as usize] > 0))
    }

    /// The first point where the ray crosses the surface.
    pub fn first_crossing(&self) -> Option<&HitPoint> {
        self.points.iter().find(|p| p.crosses)
    }

    /// How a method whose hits (any `t`) are `hits` misses where the ray crosses the surface: `None`
    /// when it hits a triangle around the first crossing that faces the ray's way. A leak where the
    /// crossing is at a shared edge or vertex, or where the method sees the surface elsewhere along the
    /// ray (it passed through); [`Missed::Beside`] where rounding may have carried the ray off the
    /// object: a silhouette near ([`HitPoint::silhouette`]), a chord inside the object shorter than
    /// 2^-10 of the way to it (the ray only clips a corner), or, inside a triangle, no hit at all.
    pub fn missed(&self, hits: &[u32]) -> Option<Missed> {
        let k = self.points.iter().position(|p| p.crosses)?;
        let p = &self.points[k];
        if p.around.is_empty() || hits.iter().any(|i| p.around.contains(i)) {
            return None;
        }
        let at_edge =
            p.holding.len() > 1 || p.holding.iter().any(|&h| self.each[h as usize].on_boundary);
        let thin = self
            .points
            .get(k + 1)
            .is_some_and(|q| rug::Rational::from(&q.t - &p.t) * rug::Rational::from(1024) < p.t);
        Some(if !p.silhouette && !thin && (at_edge || !hits.is_empty()) {
            Missed::Leak
        } else {
            Missed::Beside
        })
    }

    /// What a wrong nearest hit (`answer`, of hits `hits`) on a closed mesh is, by the stress rows'
    /// rules: `"leak"` or `"miss_beside"` ([`HitTruth::missed`]), `"neighbour"` (a triangle around the
    /// first crossing that does not hold it: the ray passed beside the pair onto a neighbour), or
    /// `"wrong_first_hit"` (any other); `None` when the answer's triangle is right.
    pub fn wrong_kind(&self, hits: &[u32], answer: Option<u32>) -> Option<&'static str> {
        if self.right(answer) {
            return None;
        }
        Some(match self.missed(hits) {
            Some(Missed::Leak) => "leak",
            Some(Missed::Beside) => "miss_beside",
            None if answer
                .is_some_and(|a| self.first_crossing().is_some_and(|p| p.around.contains(&a))) =>
            {
                "neighbour"
            }
            None => "wrong_first_hit",
        })
    }

    /// Whether the method leaks ([`HitTruth::missed`]).
    pub fn leaks(&self, hits: &[u32]) -> bool {
        self.missed(hits) == Some(Missed::Leak)
    }

    /// Whether a method's nearest hit (a triangle, or none) is right. One triangle: a hit on its
    /// boundary may be answered either way, otherwise hit or miss must match. A closed mesh: a
    /// triangle holding the first point the ray crosses the surface at, or one holding a point before
    /// it where the ray only touches the surface; a miss when the ray never crosses it.
    pub fn right(&self, answer: Option<u32>) -> bool {
        if !self.closed {
            return self.each[0].on_boundary || answer.is_some() == self.each[0].hit;
        }
        let upto = self
            .points
            .iter()
            .position(|p| p.crosses)
            .map_or(self.points.len(), |k| k + 1);
        match answer {
            None => self.first_crossing().is_none(),
            Some(i) => self.points[..upto].iter().any(|p| p.holding.contains(&i)),
        }
    }
}

/// How far an f32 `t` lies from the exact `t`, in ulps of the f32 nearest the exact one (2^-149 below
/// the normal range; the largest f32's ulp beyond it).
pub fn ulps_from(t: f32, exact: &rug::Rational) -> f64 {
    let near = exact.to_f32().abs().min(f32::MAX);
    let ulp = if near < f32::MIN_POSITIVE {
        2f64.powi(-149)
    } else {
        2f64.powi(near.log2().floor() as i32 - 23)
    };
    let off = rug::Rational::from_f32(t).map(|q| (q - exact).abs());
    off.map_or(f64::INFINITY, |d| {
        (d / rug::Rational::from_f64(ulp).expect("a power of two")).to_f64()
    })
}

/// How far, in ulps of the exact `t`, a hit's `t` may lie from it and still be right, unless a
/// command is given another bound (`--t-ulps`): 2^12, a relative error of 2^-11 (about 0.05%). On the
/// stress rows' slivers and needles the seeds' methods go beyond it, up to 180,002 ulps where `t` is
/// ill-conditioned (`corpora/results/hit-t.md`).
pub const T_ULPS: f64 = 4096.0;

/// An answer to a ray–triangle case judged ([`HitTruth::judge`]): its triangle, its `t`, and both.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HitJudged {
    /// The nearest hit is on a right triangle, or the miss is right ([`HitTruth::right`]).
    pub triangle: bool,
    /// A hit's `t` judged; `None` for a miss.
    pub t: Option<TJudged>,
    /// Right: the triangle, and a hit's `t` too.
    pub right: bool,
}

/// A hit's `t` judged: the rule of docs/triangles.md (a hit has `0 < t < ∞`) and its distance from the exact
/// `t` of the point the answer names, within `bound` ulps ([`ulps_from`]).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct TJudged {
    /// `None` when the answer names no exact hit point (a wrong triangle, or a hit where there is
    /// none).
    pub ulps: Option<f64>,
    /// The `t` is right: `0 < t < ∞` and within the bound.
    pub right: bool,
}

impl HitTruth {
    /// The exact `t` of the hit on triangle `tri` this answer may name: the one-triangle case's hit,
    /// or the closed mesh's point holding `tri` at which [`HitTruth::right`] accepts it.
    pub fn exact_t(&self, tri: u32) -> Option<&rug::Rational> {
        if !self.closed {
            return match self.each[0].hit {
                true => self.points.first().map(|p| &p.t),
                false => None,
            };
        }
        let upto = self
            .points
            .iter()
            .position(|p| p.crosses)
            .map_or(self.points.len(), |k| k + 1);
        self.points[..upto]
            .iter()
            .find(|p| p.holding.contains(&tri))
            .map(|p| &p.t)
    }

    /// The one rule every command, the kit and found cases judge a ray–triangle answer by: its
    /// nearest hit (a triangle and its `t`, or none) is right when its triangle is and, for a hit,
    /// its `t` lies within `bound` ulps of the exact one ([`T_ULPS`] unless a command is told
    /// otherwise).
    pub fn judge(&self, answer: Option<(u32, f32)>, bound: f64) -> HitJudged {
        let triangle = self.right(answer.map(|(i, _)| i));
        let t = answer.map(|(i, t)| self.judge_t(i, t, bound));
        HitJudged {
            triangle,
            t,
            right: triangle && t.is_none_or(|t| t.right),
        }
    }

    /// A hit on `tri` at `t` judged for its `t` ([`TJudged`]).
    pub fn judge_t(&self, tri: u32, t: f32, bound: f64) -> TJudged {
        let ulps = self.exact_t(tri).map(|e| ulps_from(t, e));
        let rule = t > 0.0 && t.is_finite();
        TJudged {
            ulps,
            right: rule && ulps.is_some_and(|u| u <= bound),
        }
    }
}

/// The oracle's answer to a ray and triangles: one triangle, or a closed mesh (`closed`).
pub fn judge_hit(tris: &[Tri], closed: bool, ray: &Ray) -> Result<HitTruth, ExactError> {
    let ray = *ray;
    let mut each = Vec::with_capacity(tris.len());
    let mut points: Vec<HitPoint> = Vec::new();
    for (i, tri) in tris.iter().enumerate() {
        let h = ray_triangle(*tri, &ray)?;
        each.push(h);
        let Some(t) = ray_triangle_t(*tri, &ray)? else {
            continue;
        };
        match points.iter_mut().find(|p| p.t == t) {
            Some(p) => p.holding.push(i as u32),
            None => points.push(HitPoint {
                t,
                holding: vec![i as u32],
                crosses: true,
                around: Vec::new(),
                silhouette: false,
            }),
        }
    }
    points.sort_by(|a, b| a.t.cmp(&b.t));
    let facing: Vec<i8> = tris
        .iter()
        .map(|[a, b, c]| super::normal_dot(*a, *b, *c, ray.dir))
        .collect();
    for p in &mut points {
        let way = facing[p.holding[0] as usize];
        p.crosses = p.holding.iter().all(|&i| facing[i as usize] == way)
            && !lies_in_at(tris, &facing, &p.holding, &ray);
        let touches = |j: usize| {
            p.holding
                .iter()
                .any(|&i| tris[i as usize].iter().any(|v| tris[j].contains(v)))
        };
        p.around = (0..tris.len())
            .filter(|&j| facing[j] == way && touches(j))
            .map(|j| j as u32)
            .collect();
        // A triangle around the point seen within 2^-10 radians of edge-on: rounding may turn it.
        let edge_on = (0..tris.len()).any(|j| touches(j) && edge_on(&tris[j], ray.dir));
        p.silhouette = edge_on
            || matches!(p.holding[..], [h] if near_silhouette(tris, &facing, h as usize, way, &ray, &p.t));
    }
    Ok(HitTruth {
        each,
        points,
        closed,
        facing,
    })
}

/// Whether a closed mesh is inside out: its triangles turn clockwise seen from outside, so the volume
/// it encloses, `Σ a · (b × c) / 6` over its triangles (exact), is negative.
pub fn inside_out(tris: &[Tri]) -> bool {
    tris.iter()
        .map(|[a, b, c]| det(&q3(*a), &q3(*b), &q3(*c)))
        .fold(Rational::new(), |s, v| s + v)
        < 0
}

/// Whether a triangle whose plane holds the ray shares the edge or vertex of the holding triangles the
/// point lies on (an edge of a holder the line meets, `side = 0`; a vertex where two meet): the ray
/// then runs along the surface there instead of crossing it.
fn lies_in_at(tris: &[Tri], facing: &[i8], holding: &[u32], ray: &Ray) -> bool {
    let mut edges: Vec<[Vec3; 2]> = Vec::new();
    let mut vertices: Vec<Vec3> = Vec::new();
    for &h in holding {
        let t = tris[h as usize];
        let zero: Vec<usize> = (0..3)
            .filter(|&k| super::side(t[k], t[(k + 1) % 3], ray) == 0)
            .collect();
        for &k in &zero {
            edges.push([t[k], t[(k + 1) % 3]]);
        }
        if zero.len() >= 2 {
            // Two edges meet at the vertex between them: the point is that vertex.
            let (k0, k1) = (zero[0], zero[1]);
            vertices.push(if (k0 + 1) % 3 == k1 { t[k1] } else { t[k0] });
        }
    }
    tris.iter().zip(facing).any(|(t, &f)| {
        f == 0
            && crate::tet::orientation(&[t[0], t[1], t[2], ray.org]) == 0
            && (vertices.iter().any(|v| t.contains(v))
                || edges.iter().any(|[a, b]| t.contains(a) && t.contains(b)))
    })
}

/// Whether the ray sees the triangle within 2^-10 radians of edge-on (in f64: it only sorts misses).
fn edge_on(t: &Tri, d: Vec3) -> bool {
    let w = |v: Vec3| glam::DVec3::new(v.x as f64, v.y as f64, v.z as f64);
    let n = (w(t[1]) - w(t[0])).cross(w(t[2]) - w(t[0]));
    n.dot(w(d)).abs() <= n.length() * w(d).length() * 2f64.powi(-10)
}

/// [`HitPoint::silhouette`] for a point `o + t·d` inside triangle `h`, which faces `way`.
fn near_silhouette(
    tris: &[Tri],
    facing: &[i8],
    h: usize,
    way: i8,
    ray: &Ray,
    t: &rug::Rational,
) -> bool {
    let w = |v: Vec3| glam::DVec3::new(v.x as f64, v.y as f64, v.z as f64);
    let p = w(ray.org) + w(ray.dir) * t.to_f64();
    let tri = tris[h].map(w);
    // The nearest edge, by distance from p to the edge's segment.
    let dist = |a: glam::DVec3, b: glam::DVec3| {
        let s = ((p - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
        (a + (b - a) * s - p).length()
    };
    let k = (0..3)
        .min_by(|&i, &j| dist(tri[i], tri[(i + 1) % 3]).total_cmp(&dist(tri[j], tri[(j + 1) % 3])))
        .unwrap_or(0);
    let (a, b) = (tris[h][k], tris[h][(k + 1) % 3]);
    let away = |j: usize| facing[j] != way;
    let across = (0..tris.len()).find(|&j| j != h && tris[j].contains(&a) && tris[j].contains(&b));
    if across.is_none_or(away) {
        return true;
    }
    let len = (w(b) - w(a)).length();
    [a, b].iter().any(|&v| {
        (w(v) - p).length() < len * 1e-3 && (0..tris.len()).any(|j| tris[j].contains(&v) && away(j))
    })
}
