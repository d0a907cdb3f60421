//! Tetrahedra and rays in f32, and the one orientation convention that all of tetwalk shares.
#![warn(missing_docs)]

use glam::Vec3;

/// The line `org + t·dir`, in f32 as the methods see it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// The origin.
    pub org: Vec3,
    /// The direction (any length but zero).
    pub dir: Vec3,
}

/// A triangle's three vertices `P0, P1, P2` (seed 004 Figure 2).
pub type Tri = [Vec3; 3];

/// Four vertices; face `i` is the face opposite vertex `i` (TetGen's convention).
pub type Tet = [Vec3; 4];

/// One exit-face case: a tetrahedron (either orientation), a ray, and the face the ray entered through
/// (`None` in a starting tetrahedron). Its text form is in the `cases` module.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Case {
    /// The tetrahedron, in either orientation.
    pub tet: Tet,
    /// The ray's origin.
    pub org: Vec3,
    /// The ray's direction (any length but zero).
    pub dir: Vec3,
    /// The face the ray entered through, or `None` in a starting tetrahedron.
    pub entry: Option<u8>,
}

impl Case {
    /// The same case with the tetrahedron's vertices relabelled by `p` (new vertex `i` is old vertex
    /// `p[i]`, so new face `f` is old face `p[f]`); the entry face follows.
    pub fn relabelled(&self, p: [usize; 4]) -> Case {
        Case {
            tet: p.map(|i| self.tet[i]),
            entry: self
                .entry
                .and_then(|e| p.iter().position(|&i| i == e as usize).map(|j| j as u8)),
            ..*self
        }
    }

    /// The case's ray.
    pub fn ray(&self) -> Ray {
        Ray {
            org: self.org,
            dir: self.dir,
        }
    }
}

/// Vertices of face `i`, counterclockwise seen from outside a positively oriented tetrahedron,
/// so that `orient3d(face..., v_i) > 0`.
pub const FACE_VERTICES: [[usize; 3]; 4] = [[1, 3, 2], [0, 2, 3], [0, 3, 1], [0, 1, 2]];

/// The six edges `(i, j)`, `i < j`.
pub const EDGES: [[usize; 2]; 6] = [[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]];

/// [`edge_index`] for every pair of distinct vertices, computed once from [`EDGES`].
pub(crate) const EDGE_OF: [[(usize, bool); 4]; 4] = {
    let mut t = [[(usize::MAX, false); 4]; 4];
    let mut e = 0;
    while e < 6 {
        let [a, b] = EDGES[e];
        t[a][b] = (e, false);
        t[b][a] = (e, true);
        e += 1;
    }
    t
};

/// Index into [`EDGES`] of the edge joining `i` and `j`, with `true` when it runs `j → i`.
#[inline(always)]
pub fn edge_index(i: usize, j: usize) -> (usize, bool) {
    let r = EDGE_OF[i][j];
    assert!(
        r.0 < 6,
        "{i} and {j} are distinct vertices of a tetrahedron"
    );
    r
}

/// Face permutation applied by [`normalize`] when it swaps vertices 0 and 1.
pub const SWAP01: [usize; 4] = [1, 0, 2, 3];

/// The 12 orientation-preserving relabellings of a tetrahedron's vertices (the even permutations; new
/// vertex `i` is old vertex `p[i]`), the identity first.
pub const EVEN_PERMUTATIONS: [[usize; 4]; 12] = [
    [0, 1, 2, 3],
    [1, 2, 0, 3],
    [2, 0, 1, 3],
    [1, 3, 2, 0],
    [3, 0, 2, 1],
    [2, 1, 3, 0],
    [3, 1, 0, 2],
    [0, 2, 3, 1],
    [0, 3, 1, 2],
    [1, 0, 3, 2],
    [2, 3, 0, 1],
    [3, 2, 1, 0],
];

/// `x` times 2^`e` where that is an f32 exactly (not rounded into the subnormals, to zero or to
/// infinity), else `None`: a case or mesh scaled by a power of two stays the same geometry.
pub fn times_two_to(x: f32, e: i32) -> Option<f32> {
    let exact = x as f64 * 2f64.powi(e);
    let y = exact as f32;
    (y.is_finite() && y as f64 == exact).then_some(y)
}

/// **The orientation convention**, stated once: a tetrahedron `[v0, v1, v2, v3]` is positively oriented
/// (+1) when `robust::orient3d(v0, v1, v2, v3) > 0`, i.e. `v3` lies below the plane of `v0, v1, v2` seen
/// counterclockwise from above; the labelling Maria et al. 2017 Table 2 assumes. Exact; 0 when flat.
/// Meshes and cases are normalised to +1 where they are read ([`normalize`]); TetGen writes -1.
pub fn orientation(tet: &Tet) -> i8 {
    let c = |v: Vec3| robust::Coord3D {
        x: v.x as f64,
        y: v.y as f64,
        z: v.z as f64,
    };
    let o = robust::orient3d(c(tet[0]), c(tet[1]), c(tet[2]), c(tet[3]));
    (o > 0.0) as i8 - (o < 0.0) as i8
}

/// Bring a tetrahedron to the positive orientation by swapping vertices 0 and 1 when it is negative.
/// Returns the tetrahedron and whether it was swapped (faces 0 and 1 then trade places, see [`SWAP01`]).
/// A flat tetrahedron is returned as it is; callers reject it.
pub fn normalize(tet: &Tet) -> (Tet, bool) {
    if orientation(tet) < 0 {
        ([tet[1], tet[0], tet[2], tet[3]], true)
    } else {
        (*tet, false)
    }
}

/// Whether every coordinate of the points is finite.
pub fn all_finite(points: &[Vec3]) -> bool {
    points.iter().all(|p| p.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn faces_are_outward_on_positive_tets() {
        let tet = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
        ];
        assert_eq!(orientation(&tet), 1);
        for (i, f) in FACE_VERTICES.iter().enumerate() {
            assert!(!f.contains(&i));
            let t = [tet[f[0]], tet[f[1]], tet[f[2]], tet[i]];
            assert_eq!(orientation(&t), 1, "face {i}");
        }
        let (n, swapped) = normalize(&[tet[1], tet[0], tet[2], tet[3]]);
        assert!(swapped);
        assert_eq!(n, tet);
    }

    #[test]
    fn edge_index_finds_both_directions() {
        assert_eq!(edge_index(2, 3), (5, false));
        assert_eq!(edge_index(3, 0), (2, true));
    }
}
