//! `portalez16`: Portalez & Duguet 2016 (seed 001), the exit face of an octree cell and the neighbour
//! across it from Plücker orientations against axis-parallel lines and two lookup tables, "sans
//! division ni branchement". Faces, vertices and quarters are numbered as [`crate::octree::cell`]
//! states.
//!
//! Two readings of eq. 1: the ray as the points `P = o`, `Q = o + d` (`Q` rounded to f32, then eq. 1
//! as printed: [`Points`]), or with `Q - P = d` substituted (`π2 = d_x`, …, [`Direction`]).

use super::{Arith, CellMethod};
use crate::octree::cell::{FACE_AXIS, FACE_HIGH};
use crate::tet::Ray;
use glam::Vec3;

/// Seed 001 eq. 8, `outFacesLookup[exit vertex][Π^P(R)]`: the exit face; 7 where no ray can be.
pub const OUT_FACES_LOOKUP: [[u8; 8]; 8] = [
    [7, 2, 5, 2, 3, 3, 5, 7],
    [5, 7, 1, 1, 5, 2, 7, 2],
    [3, 3, 7, 5, 0, 7, 0, 5],
    [0, 5, 0, 7, 7, 5, 1, 1],
    [2, 4, 2, 7, 7, 4, 3, 3],
    [1, 1, 7, 4, 2, 7, 2, 4],
    [4, 7, 3, 3, 4, 0, 7, 0],
    [7, 0, 4, 0, 1, 1, 4, 7],
];

/// Seed 001 eq. 9, `faceToNeighborIndex[exit face][Π^P(R)]` with `P` the exit face's centre: which of
/// four neighbours across the face the ray enters.
pub const FACE_TO_NEIGHBOR_INDEX: [[u8; 8]; 6] = [
    [1, 3, 1, 3, 0, 2, 0, 2],
    [2, 2, 0, 0, 3, 3, 1, 1],
    [2, 0, 2, 0, 3, 1, 3, 1],
    [1, 1, 3, 3, 0, 0, 2, 2],
    [2, 0, 3, 1, 2, 0, 3, 1],
    [1, 3, 0, 2, 1, 3, 0, 2],
];

/// What eq. 8 answers where no ray can be.
pub const NO_FACE: u8 = 7;

/// The ray's Plücker coordinates `π0 … π5` (seed 001 eq. 1).
pub type Pi = [f32; 6];

/// How eq. 1 is read.
pub trait Reading {
    /// The ray's `π0 … π5`, in arithmetic model `A`.
    fn pi<A: Arith>(ray: &Ray) -> Pi;
}

/// Eq. 1 as printed, from two points of the ray: `P = o`, `Q = o + d` (rounded to f32).
pub struct Points;

impl Reading for Points {
    fn pi<A: Arith>(ray: &Ray) -> Pi {
        let (p, q) = (ray.org, ray.org + ray.dir);
        [
            A::mad(q.x, p.y, -(p.x * q.y)),
            A::mad(q.x, p.z, -(p.x * q.z)),
            q.x - p.x,
            A::mad(q.y, p.z, -(p.y * q.z)),
            q.z - p.z,
            p.y - q.y,
        ]
    }
}

/// Eq. 1 with `Q - P = d` substituted: `π0 = d_x o_y - o_x d_y`, `π1 = d_x o_z - o_x d_z`, `π2 = d_x`,
/// `π3 = d_y o_z - o_y d_z`, `π4 = d_z`, `π5 = -d_y`.
pub struct Direction;

impl Reading for Direction {
    fn pi<A: Arith>(ray: &Ray) -> Pi {
        let (o, d) = (ray.org, ray.dir);
        [
            A::mad(d.x, o.y, -(o.x * d.y)),
            A::mad(d.x, o.z, -(o.x * d.z)),
            d.x,
            A::mad(d.y, o.z, -(o.y * d.z)),
            d.z,
            -d.y,
        ]
    }
}

/// Seed 001 eqs. 4–5: the orientations `Π_x^P`, `Π_y^P`, `Π_z^P` of the ray against the lines through
/// `P` parallel to the axes, each positively oriented.
#[inline(always)]
pub fn orientations<A: Arith>(pi: &Pi, p: Vec3) -> [f32; 3] {
    [
        A::mad(pi[5], p.z, pi[4] * p.y) + pi[3],
        A::mad(pi[2], p.z, -pi[1]) - pi[4] * p.x,
        A::mad(-pi[2], p.y, pi[0]) - pi[5] * p.x,
    ]
}

/// Seed 001 eq. 6, `Π^P(R) = Π_x | Π_y | Π_z`: bit `k` of the table index is set where the `k`-th
/// orientation is negative. (With "1 = positive" and this bit order, no numbering of Figure 4 makes
/// eq. 8 right; it works only in a left-handed frame. `tests/octree.rs` checks this reading.) An exact
/// zero reads as 0.
#[inline(always)]
pub fn index(o: [f32; 3]) -> usize {
    (o[0] < 0.0) as usize | ((o[1] < 0.0) as usize) << 1 | ((o[2] < 0.0) as usize) << 2
}

/// The exit vertex (eq. 8's row): bit `k` set where `d_k > 0`.
#[inline(always)]
pub fn exit_vertex(d: Vec3) -> usize {
    (d.x > 0.0) as usize | ((d.y > 0.0) as usize) << 1 | ((d.z > 0.0) as usize) << 2
}

/// §4.2.1: the exit face of the box `[lo, hi]` (0..6), or [`NO_FACE`]: eq. 8 at the exit vertex.
#[inline(always)]
pub fn out_direction<A: Arith>(lo: Vec3, hi: Vec3, pi: &Pi, d: Vec3) -> u8 {
    let v = exit_vertex(d);
    let p = Vec3::select(glam::BVec3::new(v & 1 == 1, v & 2 == 2, v & 4 == 4), hi, lo);
    OUT_FACES_LOOKUP[v][index(orientations::<A>(pi, p))]
}

/// The centre of face `f` of the box `[lo, hi]`, in f32: `(lo + hi) / 2` on the face's axes.
#[inline(always)]
pub fn face_centre(lo: Vec3, hi: Vec3, f: usize) -> Vec3 {
    let mut c = (lo + hi) * 0.5;
    let a = FACE_AXIS[f];
    c[a] = if FACE_HIGH[f] { hi[a] } else { lo[a] };
    c
}

/// §4.2.2, eq. 10: which of four neighbours across exit face `f` the ray enters.
#[inline(always)]
pub fn neighbor_index<A: Arith>(lo: Vec3, hi: Vec3, f: usize, pi: &Pi) -> usize {
    FACE_TO_NEIGHBOR_INDEX[f][index(orientations::<A>(pi, face_centre(lo, hi, f)))] as usize
}

/// Seed 001's cell test with eq. 1 read as `R` says: a [`CellMethod`].
pub struct Portalez16<R>(std::marker::PhantomData<R>);

/// A ray prepared once (eq. 1).
#[derive(Clone, Copy, Debug)]
pub struct Prepared {
    /// Eq. 1's Plücker coordinates.
    pub pi: Pi,
    /// The ray's direction.
    pub dir: Vec3,
}

impl<R: Reading> CellMethod for Portalez16<R> {
    type RayData = Prepared;

    fn prepare<A: Arith>(ray: &Ray) -> Prepared {
        Prepared {
            pi: R::pi::<A>(ray),
            dir: ray.dir,
        }
    }

    #[inline(always)]
    fn exit<A: Arith>(lo: Vec3, hi: Vec3, r: &Prepared) -> Option<(usize, usize)> {
        let f = out_direction::<A>(lo, hi, &r.pi, r.dir);
        (f != NO_FACE).then(|| {
            let f = f as usize;
            (f, neighbor_index::<A>(lo, hi, f, &r.pi))
        })
    }
}
