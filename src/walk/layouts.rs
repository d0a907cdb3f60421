//! Aman et al.'s walk over the compact layouts (seed 003 §4, Algorithms 2, 4 and 6): one new vertex
//! fetched and projected per tetrahedron, decoded from the xor-sum; the next tetrahedron decoded by
//! GETNEXTTET32/20/16.

use super::{Brent, OutcomeKind};
use crate::mesh::layout::{BOUNDARY, Layout, STOP, next_tet16, next_tet20, next_tet32, rank};
use crate::mesh::{HULL, Mesh};
use crate::methods::aman20::{Frame, get_exit_face, start_exit_face};
use crate::methods::{Arith, ExitMethod};
use crate::tet::{FACE_VERTICES, Ray};
use glam::Vec3;

/// Which layout to walk.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum LayoutKind {
    Tet32,
    Tet20,
    Tet16,
}

crate::choice!(LayoutKind { Tet32 => "tet32", Tet20 => "tet20", Tet16 => "tet16" });

/// The source tetrahedron of §3: the walk's start, with complete vertex and neighbour information.
#[derive(Clone, Copy, Debug)]
pub struct Source {
    pub(crate) tet: u32,
    pub(crate) vertices: [u32; 4],
    /// Neighbour fields as the layouts encode them ([`STOP`] set for constrained and boundary faces).
    pub(crate) neighbors: [u32; 4],
}

impl Source {
    /// Tetrahedron `t` as a source: its vertices and encoded neighbours, from Tet32.
    pub fn new(layout: &Layout, t: u32) -> Source {
        let r = &layout.tet32[t as usize];
        let fourth = r.v[0] ^ r.v[1] ^ r.v[2] ^ r.vx;
        Source {
            tet: t,
            vertices: [r.v[0], r.v[1], r.v[2], fourth],
            neighbors: r.n,
        }
    }
}

/// How a layout walk ended. Tet20 and Tet16 keep no vertex order, so a face is named by the vertex it is
/// across (`x` for hit and left mesh), not by its index; `x` is the period of a cycle, else 0.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct LayoutOutcome {
    pub(crate) kind: OutcomeKind,
    pub(crate) tet: u32,
    pub(crate) x: u32,
}

impl LayoutOutcome {
    /// The outcome with faces named by index in the plain mesh's tetrahedra, as [`super::walk`] gives it.
    pub fn to_outcome(self, mesh: &Mesh) -> super::Outcome {
        let x = match self.kind {
            OutcomeKind::Hit | OutcomeKind::LeftMesh => mesh.tets[self.tet as usize]
                .iter()
                .position(|&v| v == self.x)
                .unwrap_or(4) as u32,
            _ => self.x,
        };
        super::Outcome::from_parts(self.kind, self.tet, x)
    }
}

/// One step as decoded from the layout: the tetrahedron entered, the vertex index recovered from the
/// xor-sum, and the next neighbour field.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Decoded {
    pub tet: u32,
    pub fourth: u32,
    /// The vertex across the exit face Algorithm 1 chose.
    pub across: u32,
    pub next: u32,
}

/// Walk with method `M` (`aman20` or `aman20-scaled`) over `kind` from `source`; `observe` sees every
/// decoded step. Steps count tetrahedra whose exit face was sought, as in [`super::walk`].
pub fn walk_layout<M, A>(
    kind: LayoutKind,
    layout: &Layout,
    points: &[Vec3],
    ray: &Ray,
    source: &Source,
    max_steps: u32,
    mut observe: impl FnMut(Decoded),
) -> (LayoutOutcome, u32)
where
    M: ExitMethod,
    M::RayData: Frame,
    A: Arith,
{
    let end = |kind, tet, x| LayoutOutcome { kind, tet, x };
    let frame = M::prepare::<A>(ray);
    let project = |i: u32| frame.project::<A>(points[i as usize]);
    let p4 = source.vertices.map(project);
    let Some(f) = start_exit_face::<A>(&p4) else {
        return (end(OutcomeKind::NoExitFace, source.tet, 0), 1);
    };
    // The exit face's outward cycle is the order Algorithm 1 expects for the entry face of the next one.
    let mut idx = FACE_VERTICES[f].map(|k| source.vertices[k]);
    let mut p = FACE_VERTICES[f].map(|k| p4[k]);
    let (mut tet, mut next, mut across) = (source.tet, source.neighbors[f], source.vertices[f]);
    // States are (tetrahedron, vertex across its exit face), which match the plain walk's (next
    // tetrahedron, entry face) one to one; the start's sentinel matches its (start, no entry face).
    let mut brent = Brent::new((tet, u32::MAX));
    let mut steps = 1;
    loop {
        if next & STOP != 0 {
            let kind = if next == STOP | BOUNDARY {
                OutcomeKind::LeftMesh
            } else {
                OutcomeKind::Hit
            };
            return (end(kind, tet, across), steps);
        }
        if let Some(period) = brent.step((tet, across)) {
            return (end(OutcomeKind::Cycle, next, period), steps);
        }
        if steps >= max_steps {
            return (end(OutcomeKind::StepLimit, next, 0), steps);
        }
        let prev = tet;
        tet = next;
        steps += 1;
        let t = tet as usize;
        let vx = match kind {
            LayoutKind::Tet32 => layout.tet32[t].vx,
            LayoutKind::Tet20 => layout.tet20[t].vx,
            LayoutKind::Tet16 => layout.tet16[t].vx,
        };
        let fourth = idx[0] ^ idx[1] ^ idx[2] ^ vx;
        let p3 = project(fourth);
        let k = get_exit_face::<A>(&[p[0], p[1], p[2], p3]);
        across = idx[k];
        let all = [idx[0], idx[1], idx[2], fourth];
        next = match kind {
            LayoutKind::Tet32 => next_tet32(&layout.tet32[t], across),
            LayoutKind::Tet20 => next_tet20(&layout.tet20[t], rank(&all, across)),
            LayoutKind::Tet16 => next_tet16(
                &layout.tet16[t],
                prev,
                rank(&all, fourth),
                rank(&all, across),
            ),
        };
        observe(Decoded {
            tet,
            fourth,
            across,
            next,
        });
        idx[k] = fourth;
        p[k] = p3;
    }
}

/// A layout walk specialised to one method and arithmetic, for callers that pick methods at run time.
pub(crate) type LayoutWalkFn =
    fn(LayoutKind, &Layout, &[Vec3], &Ray, &Source, u32) -> (LayoutOutcome, u32);

/// [`walk_layout`] with nothing observing it.
pub(crate) fn walk_layout_unobserved<M, A>(
    kind: LayoutKind,
    layout: &Layout,
    points: &[Vec3],
    ray: &Ray,
    source: &Source,
    max_steps: u32,
) -> (LayoutOutcome, u32)
where
    M: ExitMethod,
    M::RayData: Frame,
    A: Arith,
{
    A::run(
        (layout, points, ray, source),
        #[inline(always)]
        |(layout, points, ray, source)| {
            walk_layout::<M, A>(kind, layout, points, ray, source, max_steps, |_| {})
        },
    )
}

/// The plain mesh's neighbour across face `f` of `t` as the layouts encode it (for checking decodes).
pub fn encoded_neighbor(mesh: &Mesh, layout: &Layout, t: u32, f: usize) -> u32 {
    let nb = mesh.neighbors[t as usize][f];
    if mesh.is_constrained(t, f) || nb == HULL {
        layout.tet32[t as usize].n[f]
    } else {
        nb
    }
}
