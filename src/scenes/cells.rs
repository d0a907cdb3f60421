//! Octree cells and rays for seed 001's questions: dyadic cells (corners on a power-of-two grid, as an
//! octree's are), rays exactly through a cell edge, a corner or a face's centre line (where four
//! smaller neighbours meet), within a few ulps of one, or parallel to one or two axes; near the origin,
//! at 2^16 or at 2^24.

use super::Rng;
use super::tets::{nudge, scale_of};
use crate::octree::cell::face_axes;
use crate::tet::Ray;
use glam::Vec3;
use rand::RngExt;

/// Where the ray leaves the cell.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum CellAim {
    /// Exactly through a point of an edge.
    Edge,
    /// Exactly through a corner.
    Corner,
    /// Exactly through a face's centre line.
    CentreLine,
    /// Exactly through a face's centre (both centre lines).
    Centre,
    /// Within a few ulps of an edge.
    NearEdge,
    /// Within a few ulps of a corner.
    NearCorner,
    /// Within a few ulps of a centre line.
    NearCentreLine,
    /// Parallel to one or two axes, through a centre line or an edge's plane.
    AxisParallel,
    /// Through a random point of a face.
    Face,
}

crate::choice!(CellAim {
    Edge => "edge",
    Corner => "corner",
    CentreLine => "centre-line",
    Centre => "centre",
    NearEdge => "near-edge",
    NearCorner => "near-corner",
    NearCentreLine => "near-centre-line",
    AxisParallel => "axis-parallel",
    Face => "face",
});

/// How far from the origin the cell lies.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum CellPlace {
    Origin,
    /// Around 2^16 on every axis.
    Far,
    /// Around 2^24 on every axis (f32's ulp is 2 there).
    Farthest,
}

crate::choice!(CellPlace { Origin => "origin", Far => "far", Farthest => "farthest" });

impl CellPlace {
    /// The offset, and the smallest cell side whose quarter points are exact there.
    fn at(self) -> (f32, i32) {
        match self {
            CellPlace::Origin => (0.0, -4),
            CellPlace::Far => (65536.0, -2),
            CellPlace::Farthest => (16_777_216.0, 5),
        }
    }
}

/// A cell `[lo, hi]` and a ray aimed as `aim` says, placed as `place` says; `k` the largest ulp
/// offset.
pub fn case(aim: CellAim, place: CellPlace, k: i32, r: &mut Rng) -> (Vec3, Vec3, Ray) {
    let (offset, least) = place.at();
    let side = 2f32.powi(r.random_range(least..least + 6));
    let lo = Vec3::from_array([0; 3].map(|_| offset + side * r.random_range(-8..8) as f32));
    let hi = lo + Vec3::splat(side);
    let q = side / 8.0;
    // A dyadic interior point (eighths of the side), then the exit point on the boundary.
    let interior =
        |r: &mut Rng| lo + Vec3::from_array([0; 3].map(|_| q * r.random_range(1..8) as f32));
    let axis = r.random_range(0..3usize);
    let high = r.random_bool(0.5);
    let [u, v] = face_axes(axis);
    let centre = (lo + hi) * 0.5;
    let mut x = interior(r);
    x[axis] = if high { hi[axis] } else { lo[axis] };
    let side_of = |r: &mut Rng, a: usize| if r.random_bool(0.5) { hi[a] } else { lo[a] };
    match aim {
        CellAim::Edge | CellAim::NearEdge => x[u] = side_of(r, u),
        CellAim::Corner | CellAim::NearCorner => {
            x[u] = side_of(r, u);
            x[v] = side_of(r, v);
        }
        CellAim::CentreLine | CellAim::NearCentreLine => {
            let a = if r.random_bool(0.5) { u } else { v };
            x[a] = centre[a];
        }
        CellAim::Centre => {
            x[u] = centre[u];
            x[v] = centre[v];
        }
        CellAim::AxisParallel | CellAim::Face => {}
    }
    let (org, dir) = if aim == CellAim::AxisParallel {
        // Along the face normal (and maybe one more axis), from inside, through a centre line or an
        // edge's plane.
        let mut d = Vec3::ZERO;
        d[axis] = if high { 1.0 } else { -1.0 };
        if r.random_bool(0.5) {
            x[u] = if r.random_bool(0.5) {
                centre[u]
            } else {
                side_of(r, u)
            };
        } else {
            let other = if r.random_bool(0.5) { u } else { v };
            d[other] = q * if r.random_bool(0.5) { 1.0 } else { -1.0 };
            d[axis] *= q;
        }
        (x - d * 4.0, d)
    } else {
        let o = interior(r);
        (o, x - o)
    };
    let (org, dir) = match aim {
        CellAim::NearEdge | CellAim::NearCorner | CellAim::NearCentreLine => {
            (nudge(org, scale_of([&lo, &hi, &org]), k, r), dir)
        }
        _ => (org, dir),
    };
    (lo, hi, Ray { org, dir })
}
