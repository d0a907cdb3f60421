//! `maria17`: Maria, Horna, Aveneau 2017, "Efficient Ray Traversal of Constrained Delaunay
//! Tetrahedralization" — two side products from the entry face, three in the starting tetrahedron.

use super::{Arith, ExitMethod};
use crate::tet::{Ray, Tet};
use glam::Vec3;

/// Table 2: vertices of face `F_i` counterclockwise from inside; `Λ_j` runs from vertex `j` to `V_i`.
pub const FACE_VERTICES: [[usize; 3]; 4] = [[3, 1, 2], [2, 0, 3], [3, 0, 1], [1, 0, 2]];

/// Table 1: exit face from the entry face (column) and the local identifier in {0, 1, 2}.
pub const GET_FACE: [[usize; 3]; 4] = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];

/// The ray as Plücker line `{u : v}`: direction `u = d` and moment `v = o × d`, computed once.
#[derive(Clone, Copy, Debug)]
pub struct Plucker {
    u: Vec3,
    v: Vec3,
}

/// Maria et al.'s method, in one of the two readings of §3.4 ([`MomentFirst`], [`OriginFirst`]).
pub struct Maria17<R>(std::marker::PhantomData<R>);

/// How §3.4's translated moment `v'` of the ray in the frame of the complement vertex `V_f` is
/// computed: the paper gives a formula and an order of operations that do not round alike.
pub trait Reading {
    /// What is computed once per ray.
    type RayData: Copy + Send + Sync;
    /// What is computed once per ray, in arithmetic model `A`.
    fn prepare<A: Arith>(ray: &Ray) -> Self::RayData;
    /// `v'` for the complement vertex `vf`.
    fn moment<A: Arith>(ray: &Self::RayData, vf: Vec3) -> Vec3;
}

/// §3.4's formula: `v' = v - V_f × u`, the moment `v = o × d` computed once per ray (`maria17`).
pub struct MomentFirst;

/// §3.4's stated order of operations, "3 subtractions, 6 multiplications and 3 subtractions":
/// `v' = (o - V_f) × u`, the origin translated first (`maria17-translated`).
pub struct OriginFirst;

impl Reading for MomentFirst {
    type RayData = Plucker;
    fn prepare<A: Arith>(ray: &Ray) -> Plucker {
        Plucker {
            u: ray.dir,
            v: A::cross(ray.org, ray.dir),
        }
    }
    #[inline(always)]
    fn moment<A: Arith>(ray: &Plucker, vf: Vec3) -> Vec3 {
        ray.v - A::cross(vf, ray.u)
    }
}

impl Reading for OriginFirst {
    type RayData = Ray;
    fn prepare<A: Arith>(ray: &Ray) -> Ray {
        *ray
    }
    #[inline(always)]
    fn moment<A: Arith>(ray: &Ray, vf: Vec3) -> Vec3 {
        A::cross(ray.org - vf, ray.dir)
    }
}

/// §3.4: side product of the ray with `Λ = V_k V_f`, in the frame translated to the complement vertex
/// `V_f`, where `Λ` has nil moment: `v' · (V_f - V_k)`.
#[inline(always)]
fn side<A: Arith>(moment: Vec3, vf: Vec3, vk: Vec3) -> f32 {
    A::dot(moment, vf - vk)
}

/// Algorithm 1: exit face search from the entry face `F_e`, exactly two side products, no branch;
/// `moment` is `v'` for `V_f = tet[entry]`.
#[inline(always)]
fn exit_tetra<A: Arith>(tet: &Tet, moment: Vec3, entry: usize) -> usize {
    let vf = tet[entry];
    let lambda = FACE_VERTICES[entry];
    let s = side::<A>(moment, vf, tet[lambda[2]]);
    let id = (s >= 0.0) as usize;
    let s = side::<A>(moment, vf, tet[lambda[id]]);
    let id = id + (s < 0.0) as usize;
    GET_FACE[entry][id]
}

impl<R: Reading> ExitMethod for Maria17<R> {
    type RayData = R::RayData;
    const LANES: usize = 4;

    fn prepare<A: Arith>(ray: &Ray) -> R::RayData {
        R::prepare::<A>(ray)
    }

    /// Algorithm 1 with a known entry face; Algorithm 2 in the starting tetrahedron (side product
    /// with `V_2 V_3`, taken in the frame of `V_3`, then Algorithm 1 with `F_0` or `F_1` as fake entry).
    /// Always answers a face: the published method has no "no exit" outcome.
    #[inline(always)]
    fn exit_face<A: Arith>(tet: &Tet, ray: &R::RayData, entry: Option<usize>) -> Option<usize> {
        let entry = entry.unwrap_or_else(|| {
            let s = side::<A>(R::moment::<A>(ray, tet[3]), tet[3], tet[2]);
            (s < 0.0) as usize
        });
        Some(exit_tetra::<A>(tet, R::moment::<A>(ray, tet[entry]), entry))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Table 1 follows from Table 2: local face `id` is bounded by `Λ_id` and `Λ_(id+2)%3`, so it is the
    /// face opposite the vertex of `Λ_(id+1)%3`.
    #[test]
    fn table_1_follows_from_table_2() {
        for e in 0..4 {
            for id in 0..3 {
                assert_eq!(
                    GET_FACE[e][id],
                    FACE_VERTICES[e][(id + 1) % 3],
                    "entry {e} id {id}"
                );
            }
        }
    }
}
