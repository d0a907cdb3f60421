//! Seed 001 §4: the octree walk, from face neighbour to face neighbour. The entry cell from the cube
//! map (§4.1), then the loop of §4.2.3: test the leaf's triangles (any hit ends the walk), find the
//! exit face (eq. 8) and, across a face with four neighbours, the neighbour (eq. 10); no neighbour is
//! a miss. Bounded, with Brent's cycle detection on the cell, and ending in the outcome vocabulary.
//! [`walk_exact`] is the same walk decided exactly: the reference.

use super::{Brent, Outcome, OutcomeKind};
use crate::exact::boxes::box_exit;
use crate::exact::hit::perturbed_crossing;
use crate::methods::Arith;
use crate::methods::CellMethod;
use crate::methods::triangle::nearest_of;
use crate::octree::Octree;
use crate::octree::cell::{FACE_AXIS, face_axes, quarter_of};
use crate::tet::{Ray, Tri};
use glam::Vec3;
use rug::Rational;

/// How an octree walk ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum End {
    /// A triangle of the cell was hit (the nearest of its triangles), at `t`.
    Hit { tri: u32, t: f32 },
    /// The ray missed the root, or left it.
    Miss,
    /// Eq. 8 gave no exit face in `cell` (a leaf index).
    NoExitFace { cell: u32 },
    /// The walk came back to `cell`: it would loop forever.
    Cycle { cell: u32, period: u32 },
    /// `max_steps` cells without ending.
    StepLimit { cell: u32 },
}

impl End {
    pub fn kind(&self) -> OutcomeKind {
        match self {
            End::Hit { .. } => OutcomeKind::Hit,
            End::Miss => OutcomeKind::LeftMesh,
            End::NoExitFace { .. } => OutcomeKind::NoExitFace,
            End::Cycle { .. } => OutcomeKind::Cycle,
            End::StepLimit { .. } => OutcomeKind::StepLimit,
        }
    }

    /// As a tetrahedral walk's outcome, with the `(tetrahedron, face)` each triangle came from.
    pub(crate) fn outcome(&self, from: &[(u32, u8)]) -> Outcome {
        match *self {
            End::Hit { tri, .. } => {
                let (tet, face) = from[tri as usize];
                Outcome::Hit { tet, face }
            }
            End::Miss => Outcome::LeftMesh { tet: 0, face: 0 },
            End::NoExitFace { cell } => Outcome::NoExitFace { tet: cell },
            End::Cycle { cell, period } => Outcome::Cycle { tet: cell, period },
            End::StepLimit { cell } => Outcome::StepLimit { tet: cell },
        }
    }
}

/// A walk's end and the cells it visited (Φ).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OctreeWalk {
    pub end: End,
    pub cells: u32,
}

/// A generous step cap: a walk that does not cycle visits each leaf at most once.
pub fn default_max_steps(o: &Octree) -> u32 {
    (o.leaves.len() as u32).saturating_mul(2).saturating_add(64)
}

/// §4.1: the address of the first cell the ray enters, from the cube map: the ray against the root
/// box (slabs, in f32), the entry point's texel on the entry face; a ray starting inside the root
/// starts in the leaf holding its origin (the paper's primary rays start outside). `None`: a miss.
pub(crate) fn entry(o: &Octree, ray: &Ray) -> Option<u32> {
    let (lo, hi) = (o.lo, o.lo + Vec3::splat(o.size));
    if (0..3).all(|a| ray.org[a] >= lo[a] && ray.org[a] <= hi[a]) {
        return o.leaf_holding(ray.org);
    }
    let mut t_in = f32::NEG_INFINITY;
    let mut t_out = f32::INFINITY;
    let mut face = 0;
    for a in 0..3 {
        if ray.dir[a] == 0.0 {
            if ray.org[a] < lo[a] || ray.org[a] > hi[a] {
                return None;
            }
            continue;
        }
        let (t0, t1) = (
            (lo[a] - ray.org[a]) / ray.dir[a],
            (hi[a] - ray.org[a]) / ray.dir[a],
        );
        let (near, far) = if t0 < t1 { (t0, t1) } else { (t1, t0) };
        if near > t_in {
            t_in = near;
            face = crate::octree::cell::face_of(a, ray.dir[a] < 0.0);
        }
        t_out = t_out.min(far);
    }
    if t_in > t_out || t_out < 0.0 {
        return None;
    }
    let p = ray.org + ray.dir * t_in;
    let n = 1u32 << o.settings.depth;
    let [u, v] = face_axes(FACE_AXIS[face]);
    let texel = |b: usize| (((p[b] - lo[b]) / o.size * n as f32).max(0.0) as u32).min(n - 1);
    Some(o.cube_map[face][(texel(u) + texel(v) * n) as usize])
}

/// The cell after the one at `address` across face `f`, into quarter `q` (eq. 3: with one neighbour
/// the offset `(count / 4) · q` is 0); `None` at the root's boundary.
#[inline(always)]
fn next(o: &Octree, address: u32, f: usize, q: usize) -> Option<u32> {
    let list = o.neighbors(address, f);
    let count = list.len();
    (count > 0).then(|| list[(count / 4) * q])
}

/// Seed 001 §4.2.3 with cell method `M` in arithmetic `A`, and `hit` for each leaf's triangles.
pub(crate) fn walk<M: CellMethod, A: Arith>(
    o: &Octree,
    tris: &[Tri],
    hit: fn(&Tri, &Ray) -> Option<f32>,
    ray: &Ray,
    max_steps: u32,
) -> OctreeWalk {
    A::run(
        (o, tris, ray),
        #[inline(always)]
        |(o, tris, ray)| walk_observed::<M, A>(o, tris, hit, ray, max_steps, |_, _| {}),
    )
}

/// One step of a walk: the leaf and the exit face and quarter the method chose there (none: no face).
pub(crate) type Step = (u32, Option<(usize, usize)>);

/// [`walk`], also listing each cell's exit as the method chose it.
pub(crate) fn walk_traced<M: CellMethod, A: Arith>(
    o: &Octree,
    tris: &[Tri],
    hit: fn(&Tri, &Ray) -> Option<f32>,
    ray: &Ray,
    max_steps: u32,
) -> (OctreeWalk, Vec<Step>) {
    A::run(
        (o, tris, ray),
        #[inline(always)]
        |(o, tris, ray)| {
            let mut steps = Vec::new();
            let w = walk_observed::<M, A>(o, tris, hit, ray, max_steps, |c, x| steps.push((c, x)));
            (w, steps)
        },
    )
}

fn walk_observed<M: CellMethod, A: Arith>(
    o: &Octree,
    tris: &[Tri],
    hit: fn(&Tri, &Ray) -> Option<f32>,
    ray: &Ray,
    max_steps: u32,
    mut observe: impl FnMut(u32, Option<(usize, usize)>),
) -> OctreeWalk {
    let Some(mut address) = entry(o, ray) else {
        return OctreeWalk {
            end: End::Miss,
            cells: 0,
        };
    };
    let r = M::prepare::<A>(ray);
    let mut brent = Brent::new(address);
    for cells in 1..=max_steps {
        let at = address as usize;
        let (count, offset, cell) = (o.words[at], o.words[at + 1], o.words[at + 2]);
        let ids = &o.triangles[offset as usize..(offset + count) as usize];
        let hits: Vec<(u32, f32)> = ids
            .iter()
            .filter_map(|&i| hit(&tris[i as usize], ray).map(|t| (i, t)))
            .collect();
        if let Some((tri, t)) = nearest_of(&hits) {
            return OctreeWalk {
                end: End::Hit { tri, t },
                cells,
            };
        }
        let [lo, hi] = o.boxes[cell as usize];
        let exit = M::exit::<A>(lo, hi, &r);
        observe(cell, exit);
        let Some((f, q)) = exit else {
            return OctreeWalk {
                end: End::NoExitFace { cell },
                cells,
            };
        };
        let Some(n) = next(o, address, f, q) else {
            return OctreeWalk {
                end: End::Miss,
                cells,
            };
        };
        address = n;
        if let Some(period) = brent.step(address) {
            return OctreeWalk {
                end: End::Cycle {
                    cell: o.words[address as usize + 2],
                    period,
                },
                cells,
            };
        }
    }
    OctreeWalk {
        end: End::StepLimit {
            cell: o.words[address as usize + 2],
        },
        cells: max_steps,
    }
}

/// The walk decided exactly (the reference): entry at the exact point where the ray enters the root
/// (or its origin), each leaf's triangles hit as the `exact` tetrahedral walk sees them (the ray's
/// origin symbolically perturbed, [`perturbed_crossing`]) and only up to where the ray leaves the
/// leaf, the exit face and quarter exactly ([`box_exit`], the first of several at a tie). The hit's
/// `t` is rounded to f32.
pub(crate) fn walk_exact(o: &Octree, tris: &[Tri], ray: &Ray, max_steps: u32) -> OctreeWalk {
    let miss = OctreeWalk {
        end: End::Miss,
        cells: 0,
    };
    let Some((t_in, t_out)) = box_exit(o.lo, o.lo + Vec3::splat(o.size), ray)
        .ok()
        .and_then(|x| x.interval)
    else {
        return miss;
    };
    if t_out.cmp0().is_lt() {
        return miss;
    }
    let t = if t_in.cmp0().is_gt() {
        t_in
    } else {
        Rational::new()
    };
    // The entry point (or the origin, inside the root), exactly.
    let q = |v: Vec3| v.to_array().map(|x| Rational::from_f32(x).expect("finite"));
    let (org, dir) = (q(ray.org), q(ray.dir));
    let p: [Rational; 3] = std::array::from_fn(|a| Rational::from(&dir[a] * &t) + &org[a]);
    let Some(mut address) = o
        .boxes
        .iter()
        .position(|[lo, hi]| (0..3).all(|a| p[a] >= lo[a] && p[a] <= hi[a]))
        .map(|i| o.address[i])
    else {
        return miss;
    };
    for cells in 1..=max_steps {
        let a = address as usize;
        let (count, offset, cell) = (o.words[a], o.words[a + 1], o.words[a + 2]);
        let [lo, hi] = o.boxes[cell as usize];
        let x = box_exit(lo, hi, ray).ok();
        let leave = x.as_ref().and_then(|x| x.interval.as_ref()).map(|(_, t)| t);
        let ids = &o.triangles[offset as usize..(offset + count) as usize];
        let best = ids
            .iter()
            .filter_map(|&i| perturbed_crossing(tris[i as usize], ray).map(|t| (i, t)))
            .filter(|(_, t)| leave.is_none_or(|l| t <= l))
            .min_by(|a, b| a.1.cmp(&b.1));
        if let Some((tri, t)) = best {
            return OctreeWalk {
                end: End::Hit { tri, t: t.to_f32() },
                cells,
            };
        }
        let Some(x) = x.filter(|x| !x.faces.is_empty()) else {
            return OctreeWalk {
                end: End::NoExitFace { cell },
                cells,
            };
        };
        let (f, quarter) = (x.faces[0], quarter_of(x.quarters[0][0]));
        let Some(n) = next(o, address, f, quarter) else {
            return OctreeWalk {
                end: End::Miss,
                cells,
            };
        };
        address = n;
    }
    OctreeWalk {
        end: End::StepLimit {
            cell: o.words[address as usize + 2],
        },
        cells: max_steps,
    }
}
