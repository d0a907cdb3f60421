//! The compact tetrahedron layouts of Aman, Demirci, Güdükbay (seed 003 §3): Tet32, Tet20 and Tet16,
//! built on the xor-sum of vertex indices and, for Tet16, xor-compressed neighbours.

use super::{HULL, Mesh};

/// Neighbour fields with this bit set name no tetrahedron: the face is constrained or on the boundary,
/// and the walk stops there (§3's bitmask). The other 31 bits are [`BOUNDARY`] or the index of the face in
/// [`Layout::constrained`].
pub const STOP: u32 = 1 << 31;
/// Payload of a boundary face.
pub const BOUNDARY: u32 = STOP - 1;

/// Tet32 (Figure 2): three vertex indices, their xor-sum with the fourth, four neighbours.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(C)]
pub struct Tet32 {
    pub v: [u32; 3],
    pub vx: u32,
    /// Across vertex `j` (`j = 3`: the vertex recovered from `vx`).
    pub n: [u32; 4],
}

/// Tet20 (Figure 3): the xor-sum and the neighbours, sorted by the index of the vertex they are across.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(C)]
pub struct Tet20 {
    pub vx: u32,
    pub n: [u32; 4],
}

/// Tet16 (Figure 4): the xor-sum and `NX_j = N_j ⊕ N_3` over Tet20's sorted neighbours.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(C)]
pub struct Tet16 {
    pub vx: u32,
    pub(crate) nx: [u32; 3],
}

/// All three layouts of one mesh, and the constrained faces their neighbour fields point to.
#[derive(Clone, Debug)]
pub struct Layout {
    pub tet32: Vec<Tet32>,
    pub tet20: Vec<Tet20>,
    pub tet16: Vec<Tet16>,
    /// Each constrained face: the tetrahedra on its two sides ([`HULL`] for none).
    pub constrained: Vec<[u32; 2]>,
}

/// `VX = V0 ⊕ V1 ⊕ V2 ⊕ V3`.
pub fn xor_sum(v: &[u32; 4]) -> u32 {
    v[0] ^ v[1] ^ v[2] ^ v[3]
}

/// Rank of vertex index `x` among a tetrahedron's four (0 for the smallest): where Tet20 and Tet16 keep
/// the neighbour across it.
#[inline(always)]
pub fn rank(v: &[u32; 4], x: u32) -> usize {
    v.iter().filter(|&&y| y < x).count()
}

impl Layout {
    pub fn build(mesh: &Mesh) -> Layout {
        let mut constrained = Vec::new();
        let mut face_id = std::collections::HashMap::new();
        let mut field = |t: u32, f: usize| -> u32 {
            let nb = mesh.neighbors[t as usize][f];
            if mesh.is_constrained(t, f) {
                let key = if nb == HULL || t < nb {
                    (t, f as u8)
                } else {
                    (nb, mesh.mirror[t as usize][f])
                };
                let id = *face_id.entry(key).or_insert_with(|| {
                    constrained.push([t.min(nb), if nb == HULL { HULL } else { t.max(nb) }]);
                    constrained.len() as u32 - 1
                });
                STOP | id
            } else if nb == HULL {
                STOP | BOUNDARY
            } else {
                nb
            }
        };
        let n = mesh.tets.len();
        let (mut tet32, mut tet20, mut tet16) = (
            Vec::with_capacity(n),
            Vec::with_capacity(n),
            Vec::with_capacity(n),
        );
        for (t, v) in mesh.tets.iter().enumerate() {
            let nb: [u32; 4] = std::array::from_fn(|f| field(t as u32, f));
            tet32.push(Tet32 {
                v: [v[0], v[1], v[2]],
                vx: xor_sum(v),
                n: nb,
            });
            let mut sorted = [0u32; 4];
            for f in 0..4 {
                sorted[rank(v, v[f])] = nb[f];
            }
            tet20.push(Tet20 {
                vx: xor_sum(v),
                n: sorted,
            });
            tet16.push(Tet16 {
                vx: xor_sum(v),
                nx: std::array::from_fn(|j| sorted[j] ^ sorted[3]),
            });
        }
        Layout {
            tet32,
            tet20,
            tet16,
            constrained,
        }
    }

    /// Bytes per tetrahedron of each layout, and Maria et al.'s Tet80 (seed 000 §3.2) for comparison.
    pub(crate) const BYTES: [(&'static str, usize); 4] =
        [("Tet80", 80), ("Tet32", 32), ("Tet20", 20), ("Tet16", 16)];
}

/// Algorithm 3 (GETNEXTTET32): the neighbour across vertex `exit` of tetrahedron `t`.
#[inline(always)]
pub(crate) fn next_tet32(tet: &Tet32, exit: u32) -> u32 {
    let mut next = tet.n[3];
    for i in 0..3 {
        if exit == tet.v[i] {
            next = tet.n[i];
        }
    }
    next
}

/// Algorithm 5 (GETNEXTTET20): the neighbour at the exit vertex's rank.
#[inline(always)]
pub(crate) fn next_tet20(tet: &Tet20, order: usize) -> u32 {
    tet.n[order]
}

/// Algorithm 7 (GETNEXTTET16): from the previous tetrahedron (at rank `order_a`, across the newly
/// fetched vertex) to the one at the exit vertex's rank `order_b`.
#[inline(always)]
pub fn next_tet16(tet: &Tet16, prev: u32, order_a: usize, order_b: usize) -> u32 {
    let mut next = prev;
    if order_a != 3 {
        next ^= tet.nx[order_a];
    }
    if order_b != 3 {
        next ^= tet.nx[order_b];
    }
    next
}
