//! The rule a mesh must meet to be counted: it is a tetrahedralization of its region, decided exactly
//! (every sign below is the exact sign of a determinant of f32 coordinates: `robust`'s adaptive
//! predicates, exact for f64 inputs, which f32 values are, and rationals where a point is not an f32).
//!
//! With every tetrahedron positively oriented (checked before, in `Mesh::build_at`):
//!
//! 1. no two vertices of the mesh coincide (a duplicated point opens a crack);
//! 2. every face is shared by at most two tetrahedra, and two that share one see it with opposite
//!    orientations, so they lie on opposite sides of it (else a fold);
//! 3. the boundary (the faces of one tetrahedron only) is closed: each of its edges is run as often
//!    one way as the other;
//! 4. the boundary is embedded: two of its triangles meet only in the vertex or edge they share;
//! 5. where the boundary has several components (surfaces joined across the edges exactly two of
//!    its faces share), the region just inside each is covered once: the boundary's winding number
//!    there is 1.
//!
//! Why that is enough: by 2 the tetrahedra's boundary chain is the boundary `B` (shared faces cancel),
//! so a point on no face lies in as many tetrahedra as `B` winds around it. By 4, `B`'s winding number
//! is constant on each region `B` leaves; a region of the largest winding number lies inside each
//! component that bounds it, so 5 finds it if it is 2 or more; one embedded component winds once
//! around its inside. So no point lies in two tetrahedra: no overlap, fold or crack.

use super::{HULL, Item};
use crate::tet::FACE_VERTICES;
use glam::Vec3;
use rug::Rational;
use std::collections::HashMap;

/// What is wrong, and where: the item and why.
pub(crate) type Invalid = (Item, String);

/// The exact sign of `orient3d(a, b, c, d)`: positive when `d` lies below the plane of `a, b, c`
/// (counter-clockwise seen from above), as `crate::tet::orientation` reads it.
fn o3(a: Vec3, b: Vec3, c: Vec3, d: Vec3) -> i8 {
    let q = |v: Vec3| robust::Coord3D {
        x: v.x as f64,
        y: v.y as f64,
        z: v.z as f64,
    };
    let o = robust::orient3d(q(a), q(b), q(c), q(d));
    (o > 0.0) as i8 - (o < 0.0) as i8
}

/// The exact sign of `orient2d` of three points projected by dropping axis `k`.
fn o2(a: Vec3, b: Vec3, c: Vec3, k: usize) -> i8 {
    let q = |v: Vec3| {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        robust::Coord {
            x: v[i] as f64,
            y: v[j] as f64,
        }
    };
    let o = robust::orient2d(q(a), q(b), q(c));
    (o > 0.0) as i8 - (o < 0.0) as i8
}

/// An axis whose dropping keeps triangle `abc` (not flat) a triangle.
fn projection(a: Vec3, b: Vec3, c: Vec3) -> usize {
    (0..3)
        .find(|&k| o2(a, b, c, k) != 0)
        .expect("a triangle with three non-collinear vertices")
}

/// Whether closed segments `pq` and `rs`, coplanar, meet (in the projection dropping axis `k`, which
/// keeps their plane's triangles triangles).
fn segments_meet_2d(p: Vec3, q: Vec3, r: Vec3, s: Vec3, k: usize) -> bool {
    let (d1, d2) = (o2(p, q, r, k), o2(p, q, s, k));
    let (d3, d4) = (o2(r, s, p, k), o2(r, s, q, k));
    if d1 * d2 < 0 && d3 * d4 < 0 {
        return true;
    }
    // An endpoint on the other segment: collinear with it and within its box.
    let on = |a: Vec3, b: Vec3, x: Vec3| {
        o2(a, b, x, k) == 0 && (0..3).all(|i| x[i] >= a[i].min(b[i]) && x[i] <= a[i].max(b[i]))
    };
    on(p, q, r) || on(p, q, s) || on(r, s, p) || on(r, s, q)
}

/// Whether point `x` lies in the closed triangle `abc` of its plane (projection dropping `k`).
fn in_triangle_2d(x: Vec3, [a, b, c]: [Vec3; 3], k: usize) -> bool {
    let s = [o2(a, b, x, k), o2(b, c, x, k), o2(c, a, x, k)];
    !(s.contains(&1) && s.contains(&-1))
}

/// Whether the closed segment `pq` meets the closed triangle `t`.
fn segment_meets_triangle(p: Vec3, q: Vec3, t: [Vec3; 3]) -> bool {
    let [a, b, c] = t;
    let (sp, sq) = (o3(a, b, c, p), o3(a, b, c, q));
    if sp * sq > 0 {
        return false;
    }
    if sp == 0 && sq == 0 {
        let k = projection(a, b, c);
        return in_triangle_2d(p, t, k)
            || in_triangle_2d(q, t, k)
            || (0..3).any(|e| segments_meet_2d(p, q, t[e], t[(e + 1) % 3], k));
    }
    // The line crosses the plane (or touches it at an endpoint) at a point of the closed triangle.
    let s = [o3(p, q, a, b), o3(p, q, b, c), o3(p, q, c, a)];
    !(s.contains(&1) && s.contains(&-1))
}

/// Whether two boundary triangles (vertex ids and points) meet in more than the vertices and edge
/// they share.
fn meet_improperly(ia: [u32; 3], ta: [Vec3; 3], ib: [u32; 3], tb: [Vec3; 3]) -> bool {
    let shared: Vec<(usize, usize)> = (0..3)
        .flat_map(|i| (0..3).map(move |j| (i, j)))
        .filter(|&(i, j)| ia[i] == ib[j])
        .collect();
    let edges = |t: [Vec3; 3]| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])];
    match shared.as_slice() {
        [] => {
            edges(ta)
                .iter()
                .any(|&(p, q)| segment_meets_triangle(p, q, tb))
                || edges(tb)
                    .iter()
                    .any(|&(p, q)| segment_meets_triangle(p, q, ta))
        }
        // Sharing one vertex: they meet elsewhere exactly where the edge opposite it in one meets
        // the other triangle.
        [(i, j)] => {
            let opposite = |t: [Vec3; 3], v: usize| (t[(v + 1) % 3], t[(v + 2) % 3]);
            let (p, q) = opposite(ta, *i);
            let (r, s) = opposite(tb, *j);
            segment_meets_triangle(p, q, tb) || segment_meets_triangle(r, s, ta)
        }
        // Sharing an edge: only in one plane, on the same side of it, do they overlap.
        [(i0, _), (i1, _)] => {
            let (u, v) = (ta[*i0], ta[*i1]);
            let c = ta[3 - i0 - i1];
            let f = tb[(0..3)
                .find(|&j| ib[j] != ia[*i0] && ib[j] != ia[*i1])
                .expect("a triangle's third vertex")];
            if o3(ta[0], ta[1], ta[2], f) != 0 {
                return false;
            }
            let k = projection(ta[0], ta[1], ta[2]);
            o2(u, v, c, k) == o2(u, v, f, k)
        }
        _ => true,
    }
}

/// A boundary face: its tetrahedron, face index, vertex ids (counter-clockwise seen from outside)
/// and points.
#[derive(Clone, Copy)]
struct Face {
    tet: u32,
    face: u8,
    ids: [u32; 3],
    at: [Vec3; 3],
}

/// Rule 4: every pair of boundary triangles whose boxes meet, tested exactly (a sweep along x).
fn embedded(faces: &[Face]) -> Result<(), Invalid> {
    let boxes: Vec<(Vec3, Vec3)> = faces
        .iter()
        .map(|f| {
            (
                f.at[0].min(f.at[1]).min(f.at[2]),
                f.at[0].max(f.at[1]).max(f.at[2]),
            )
        })
        .collect();
    let mut order: Vec<usize> = (0..faces.len()).collect();
    order.sort_by(|&a, &b| boxes[a].0.x.total_cmp(&boxes[b].0.x));
    let mut active: Vec<usize> = Vec::new();
    for &i in &order {
        let lo = boxes[i].0.x;
        active.retain(|&j| boxes[j].1.x >= lo);
        for &j in &active {
            let (a, b) = (boxes[i], boxes[j]);
            let overlap = (0..3).all(|k| a.0[k] <= b.1[k] && b.0[k] <= a.1[k]);
            if overlap && meet_improperly(faces[i].ids, faces[i].at, faces[j].ids, faces[j].at) {
                let (f, g) = (faces[i], faces[j]);
                return Err((
                    Item::Tet(f.tet as usize),
                    format!(
                        "its face {} {:?} on the mesh's boundary meets the boundary face {} {:?} of tetrahedron {} in more than their shared vertices: the boundary crosses itself (an overlap, a fold or a crack)",
                        f.face, f.ids, g.face, g.ids, g.tet
                    ),
                ));
            }
        }
        active.push(i);
    }
    Ok(())
}

/// A point's coordinates exactly.
fn q(v: Vec3) -> [Rational; 3] {
    [v.x, v.y, v.z].map(|x| Rational::try_from(x).expect("finite"))
}

/// The sign of a rational.
fn sign(x: &Rational) -> i8 {
    x.cmp0() as i8
}

/// Rule 5 for one component: the boundary's winding number just inside face `f`, from rays along an
/// axis leaving `f` outwards from points inside it; `None` when every ray tried passes through an edge
/// or a vertex.
fn winding_inside(f: &Face, faces: &[Face]) -> Option<i64> {
    const WEIGHTS: [[u32; 3]; 6] = [
        [1, 1, 1],
        [1, 2, 4],
        [2, 3, 5],
        [4, 1, 2],
        [3, 5, 7],
        [6, 1, 3],
    ];
    let [a, b, c] = f.at;
    for w in WEIGHTS {
        let total = w[0] + w[1] + w[2];
        let (qa, qb, qc) = (q(a), q(b), q(c));
        let o: [Rational; 3] = std::array::from_fn(|k| {
            (Rational::from(&qa[k] * w[0])
                + Rational::from(&qb[k] * w[1])
                + Rational::from(&qc[k] * w[2]))
                / total
        });
        // An interval of f64 around each coordinate of the origin, for the boxes' quick rejection.
        let near: [(f64, f64); 3] = std::array::from_fn(|k| enclosing(&o[k]));
        'axis: for k in 0..3 {
            // The axis direction that leaves f outwards: the exact sign of the normal's k-th component
            // is the sign of the projection dropping k.
            let out = o2(a, b, c, k);
            if out == 0 {
                continue;
            }
            let dir = out;
            let (i, j) = ((k + 1) % 3, (k + 2) % 3);
            let mut sum = 0i64;
            for g in faces {
                if g.tet == f.tet && g.face == f.face {
                    continue;
                }
                let lo = g.at[0].min(g.at[1]).min(g.at[2]);
                let hi = g.at[0].max(g.at[1]).max(g.at[2]);
                let column = [i, j]
                    .iter()
                    .all(|&m| (lo[m] as f64) <= near[m].1 && near[m].0 <= hi[m] as f64);
                let ahead = if dir > 0 {
                    hi[k] as f64 >= near[k].0
                } else {
                    lo[k] as f64 <= near[k].1
                };
                if !column || !ahead {
                    continue;
                }
                match crossing(&o, k, &g.at) {
                    Crossing::Degenerate => continue 'axis,
                    Crossing::Miss => {}
                    Crossing::Through { facing, t_sign } => {
                        if t_sign == dir {
                            sum += (facing * dir) as i64;
                        } else if t_sign == 0 {
                            continue 'axis;
                        }
                    }
                }
            }
            return Some(1 + sum);
        }
    }
    None
}

/// The f64 interval `[lo, hi]` holding a rational: its value rounded towards zero and the next f64
/// on its far side (the same twice where it is an f64).
fn enclosing(x: &Rational) -> (f64, f64) {
    let r = x.to_f64();
    match Rational::from_f64(r).map(|back| back.cmp(x)) {
        Some(std::cmp::Ordering::Equal) => (r, r),
        Some(std::cmp::Ordering::Less) => (r, r.next_up()),
        _ => (r.next_down(), r),
    }
}

/// How the line through `o` along axis `k` meets a triangle.
enum Crossing {
    /// It misses the closed triangle.
    Miss,
    /// It meets an edge or a vertex, or lies in the triangle's plane: the ray cannot decide.
    Degenerate,
    /// It crosses the interior: the sign of the normal's `k` component (`facing`), and on which side
    /// of `o` along the axis (`t_sign`: 1 ahead, -1 behind, 0 at `o`).
    Through { facing: i8, t_sign: i8 },
}

fn crossing(o: &[Rational; 3], k: usize, t: &[Vec3; 3]) -> Crossing {
    let (i, j) = ((k + 1) % 3, (k + 2) % 3);
    let p = t.map(q);
    // 2-D orientations in the projection dropping k: (p_b - p_a) × (o - p_a).
    let side = |a: &[Rational; 3], b: &[Rational; 3]| {
        let (ui, uj) = (Rational::from(&b[i] - &a[i]), Rational::from(&b[j] - &a[j]));
        let (vi, vj) = (Rational::from(&o[i] - &a[i]), Rational::from(&o[j] - &a[j]));
        sign(&(Rational::from(&ui * &vj) - Rational::from(&uj * &vi)))
    };
    let s = [side(&p[0], &p[1]), side(&p[1], &p[2]), side(&p[2], &p[0])];
    let facing = o2(t[0], t[1], t[2], k);
    if facing == 0 {
        // The triangle is parallel to the axis: the line meets it only in its plane.
        // Its projection is a segment: the line lies in the plane only where the origin's projection
        // is on that segment's line (every side product zero).
        return match s == [0, 0, 0] {
            true => Crossing::Degenerate,
            false => Crossing::Miss,
        };
    }
    if s.contains(&1) && s.contains(&-1) {
        return Crossing::Miss;
    }
    if s.contains(&0) {
        return Crossing::Degenerate;
    }
    // Where along the axis: the sign of det[p_a - o, p_b - o, p_c - o] against the facing.
    let r: Vec<[Rational; 3]> = p
        .iter()
        .map(|x| std::array::from_fn(|m| Rational::from(&x[m] - &o[m])))
        .collect();
    let cross: [Rational; 3] = std::array::from_fn(|m| {
        let (n1, n2) = ((m + 1) % 3, (m + 2) % 3);
        Rational::from(&r[1][n1] * &r[2][n2]) - Rational::from(&r[1][n2] * &r[2][n1])
    });
    let det = (0..3).fold(Rational::new(), |acc, m| {
        acc + Rational::from(&r[0][m] * &cross[m])
    });
    Crossing::Through {
        facing,
        t_sign: sign(&det) * facing,
    }
}

/// Most triangle tests rule 5 may make (components × boundary faces): about a second.
const MAX_WINDING_WORK: u64 = 1 << 30;

/// What a mesh that meets the rule is made of.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub(crate) struct Summary {
    /// Faces shared by two tetrahedra.
    pub(crate) interior_faces: usize,
    /// Faces of one tetrahedron: the region's boundary.
    pub(crate) boundary_faces: usize,
    /// Connected components of the boundary (an outer surface, cavities, separate parts).
    pub(crate) boundary_components: usize,
}

/// Check rules 1 to 5 on positively oriented `tets` over `points` with their `neighbors`.
pub(crate) fn check(
    points: &[Vec3],
    tets: &[[u32; 4]],
    neighbors: &[[u32; 4]],
) -> Result<Summary, Invalid> {
    // 1. Distinct vertices (-0 and 0 are one point).
    let mut used = vec![false; points.len()];
    for v in tets {
        for &i in v {
            used[i as usize] = true;
        }
    }
    let mut at: HashMap<[u32; 3], u32> = HashMap::with_capacity(points.len());
    for (i, p) in points.iter().enumerate() {
        if !used[i] {
            continue;
        }
        let key = (*p + Vec3::ZERO).to_array().map(f32::to_bits);
        if let Some(&j) = at.get(&key) {
            return Err((
                Item::Point(i),
                format!(
                    "the same point as point {j}, {p}: a tetrahedralization's vertices are distinct (a duplicated point opens a crack)"
                ),
            ));
        }
        at.insert(key, i as u32);
    }
    // 2. Shared faces seen with opposite orientations (neighbours were derived or checked against the
    // tetrahedra: at most two share a face).
    let face = |t: usize, f: usize| FACE_VERTICES[f].map(|i| tets[t][i]);
    let mut boundary = Vec::new();
    for (t, row) in neighbors.iter().enumerate() {
        for (f, &nb) in row.iter().enumerate() {
            if nb == HULL {
                let ids = face(t, f);
                boundary.push(Face {
                    tet: t as u32,
                    face: f as u8,
                    ids,
                    at: ids.map(|i| points[i as usize]),
                });
                continue;
            }
            let mine = face(t, f);
            let g = neighbors[nb as usize]
                .iter()
                .position(|&x| x as usize == t)
                .expect("neighbours are symmetric");
            let theirs = face(nb as usize, g);
            let rotations = [
                theirs,
                [theirs[1], theirs[2], theirs[0]],
                [theirs[2], theirs[0], theirs[1]],
            ];
            let reversed = [mine[0], mine[2], mine[1]];
            if !rotations.contains(&reversed) {
                return Err((
                    Item::Tet(t),
                    format!(
                        "face {f} {mine:?} is shared with tetrahedron {nb}, which lies on the same side of it: a fold (the two overlap)"
                    ),
                ));
            }
        }
    }
    // 3. A closed boundary: each edge run as often one way as the other.
    let mut runs: HashMap<(u32, u32), i64> = HashMap::new();
    for f in &boundary {
        for e in 0..3 {
            let (a, b) = (f.ids[e], f.ids[(e + 1) % 3]);
            *runs.entry((a.min(b), a.max(b))).or_default() += if a < b { 1 } else { -1 };
        }
    }
    let open = boundary.iter().find_map(|f| {
        (0..3)
            .map(|e| (f.ids[e], f.ids[(e + 1) % 3]))
            .find(|&(a, b)| runs[&(a.min(b), a.max(b))] != 0)
            .map(|(a, b)| (f, a, b))
    });
    if let Some((f, a, b)) = open {
        return Err((
            Item::Tet(f.tet as usize),
            format!(
                "the mesh's boundary is not closed at edge ({a}, {b}) of its face {} {:?}",
                f.face, f.ids
            ),
        ));
    }
    // 4. An embedded boundary.
    embedded(&boundary)?;
    // 5. Each component's inside covered once, where there are several.
    let components = components(&boundary);
    let summary = Summary {
        interior_faces: (4 * tets.len() - boundary.len()) / 2,
        boundary_faces: boundary.len(),
        boundary_components: components.len(),
    };
    if components.len() > 1 {
        if components.len() as u64 * boundary.len() as u64 > MAX_WINDING_WORK {
            return Err((
                Item::Tet(boundary[components[1]].tet as usize),
                format!(
                    "the boundary has {} components over {} faces: checking that each is covered once would take {} ray tests, more than the {MAX_WINDING_WORK} a load may take",
                    components.len(),
                    boundary.len(),
                    components.len() as u64 * boundary.len() as u64
                ),
            ));
        }
        for first in components {
            let f = &boundary[first];
            match winding_inside(f, &boundary) {
                Some(1) => {}
                Some(w) => {
                    return Err((
                        Item::Tet(f.tet as usize),
                        format!(
                            "inside its boundary face {} {:?}, {w} tetrahedra cover the same points: the mesh overlaps itself",
                            f.face, f.ids
                        ),
                    ));
                }
                None => {
                    return Err((
                        Item::Tet(f.tet as usize),
                        format!(
                            "the boundary's winding inside its face {} {:?} could not be decided (every ray tried met an edge): the mesh is not checked",
                            f.face, f.ids
                        ),
                    ));
                }
            }
        }
    }
    Ok(summary)
}

/// One boundary face of each component of the boundary: faces joined across the edges exactly two of
/// them share (where more meet, as where a tetrahedron touches the boundary along an edge, the
/// surfaces are told apart, so that each is probed).
fn components(faces: &[Face]) -> Vec<usize> {
    let mut parent: Vec<usize> = (0..faces.len()).collect();
    fn root(parent: &mut [usize], mut x: usize) -> usize {
        while parent[x] != x {
            parent[x] = parent[parent[x]];
            x = parent[x];
        }
        x
    }
    let edge = |f: &Face, e: usize| {
        let (a, b) = (f.ids[e], f.ids[(e + 1) % 3]);
        (a.min(b), a.max(b))
    };
    let mut by_edge: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
    for (n, f) in faces.iter().enumerate() {
        for e in 0..3 {
            by_edge.entry(edge(f, e)).or_default().push(n);
        }
    }
    for (n, f) in faces.iter().enumerate() {
        for e in 0..3 {
            if let [a, b] = by_edge[&edge(f, e)][..] {
                let other = if a == n { b } else { a };
                let (x, y) = (root(&mut parent, n), root(&mut parent, other));
                parent[x] = y;
            }
        }
    }
    (0..faces.len())
        .filter(|&n| root(&mut parent, n) == n)
        .collect()
}
