//! Small generated meshes: a Kuhn-subdivided cube grid (many exactly coplanar faces), a jittered one, and
//! a fan of thin tetrahedra around one edge (the classic trap for walks that cycle).

use super::Rng;
use crate::mesh::RawMesh;
use glam::Vec3;
use rand::RngExt;

/// The six tetrahedra of Kuhn's subdivision of the unit cube, as corner bit masks (x = 1, y = 2, z = 4),
/// all sharing the diagonal from corner 0 to corner 7.
const KUHN: [[usize; 4]; 6] = [
    [0, 1, 3, 7],
    [0, 1, 5, 7],
    [0, 2, 3, 7],
    [0, 2, 6, 7],
    [0, 4, 5, 7],
    [0, 4, 6, 7],
];

/// An `n³` grid of unit cubes with integer corners, each split into Kuhn's six tetrahedra. The faces on
/// the boundary of the inner box `[1, n-1]³` are constrained (an object to hit); `n ≥ 3`
/// ([`super::generated_mesh`] refuses less).
pub fn kuhn_grid(n: u32) -> RawMesh {
    let id = |x: u32, y: u32, z: u32| x + (n + 1) * (y + (n + 1) * z);
    let mut points = Vec::new();
    for z in 0..=n {
        for y in 0..=n {
            for x in 0..=n {
                points.push(Vec3::new(x as f32, y as f32, z as f32));
            }
        }
    }
    let mut tets = Vec::new();
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                let corner = |c: usize| {
                    id(
                        x + (c & 1) as u32,
                        y + (c >> 1 & 1) as u32,
                        z + (c >> 2 & 1) as u32,
                    )
                };
                for k in KUHN {
                    let mut t = k.map(corner);
                    // Half of Kuhn's tetrahedra are mirror images: give all one orientation.
                    if crate::tet::orientation(&t.map(|i| points[i as usize])) < 0 {
                        t.swap(0, 1);
                    }
                    tets.push(t);
                }
            }
        }
    }
    let inner = |p: Vec3| p.cmpge(Vec3::ONE).all() && p.cmple(Vec3::splat((n - 1) as f32)).all();
    let mut constrained = Vec::new();
    for t in &tets {
        for f in crate::tet::FACE_VERTICES {
            let tri = f.map(|i| t[i]);
            let ps = tri.map(|i| points[i as usize]);
            let on_box = (0..3).any(|a| {
                let k = ps[0][a];
                (k == 1.0 || k == (n - 1) as f32) && ps.iter().all(|p| p[a] == k)
            });
            if on_box && ps.iter().all(|&p| inner(p)) {
                constrained.push(tri);
            }
        }
    }
    constrained.sort_unstable_by_key(|f| {
        let mut s = *f;
        s.sort_unstable();
        s
    });
    constrained.dedup_by_key(|f| {
        let mut s = *f;
        s.sort_unstable();
        s
    });
    RawMesh {
        points,
        tets,
        neighbors: None,
        constrained,
    }
}

/// [`kuhn_grid`] with every point off the outer boundary moved by up to `amount` (≤ 0.15) per axis, in
/// steps of 1/16 so that translating it by up to 2^20 stays exact.
pub(crate) fn jittered_grid(n: u32, amount: f32, rng: &mut Rng) -> RawMesh {
    let mut m = kuhn_grid(n);
    let top = n as f32;
    let k = (amount.clamp(0.0, 0.15) * 16.0).floor() as i32;
    for p in &mut m.points {
        let on_hull = (0..3).any(|a| p[a] == 0.0 || p[a] == top);
        if !on_hull && k > 0 {
            for a in 0..3 {
                p[a] += rng.random_range(-k..=k) as f32 / 16.0;
            }
        }
    }
    m
}

/// `k` thin tetrahedra around the edge from `(0, 0, -1)` to `(0, 0, 1)`, their outer vertices on a circle
/// of `radius` in the plane `z = 0`, rounded to multiples of 1/1024. The lower hull faces are
/// constrained; rays through the axis edge meet every tetrahedron at once.
pub(crate) fn edge_fan(k: u32, radius: f32) -> RawMesh {
    let k = k.max(3);
    let mut points = vec![Vec3::new(0.0, 0.0, -1.0), Vec3::new(0.0, 0.0, 1.0)];
    for i in 0..k {
        let a = std::f32::consts::TAU * i as f32 / k as f32;
        let q = |x: f32| (x * 1024.0).round() / 1024.0;
        points.push(Vec3::new(q(radius * a.cos()), q(radius * a.sin()), 0.0));
    }
    let ring = |i: u32| 2 + i % k;
    let tets = (0..k).map(|i| [0, 1, ring(i), ring(i + 1)]).collect();
    let constrained = (0..k).map(|i| [0, ring(i), ring(i + 1)]).collect();
    RawMesh {
        points,
        tets,
        neighbors: None,
        constrained,
    }
}
