//! Tetrahedral meshes: f32 points, tetrahedra, neighbours across each face, constrained faces; checked
//! with exact predicates when they are built, whatever they were built from.

pub mod export;
#[cfg(feature = "formats")]
pub mod formats;
pub mod layout;
pub mod reorder;
pub mod surface;
mod tetgen;
pub mod valid;

pub use tetgen::{Faces, TetgenTexts, load_tetgen, load_tetgen_with, parse_tetgen, tetgen_files};

use crate::tet::{FACE_VERTICES, Tet, orientation};
use glam::Vec3;
use std::collections::HashMap;

/// No neighbour: the face is on the mesh boundary.
pub const HULL: u32 = u32::MAX;

/// A validated tetrahedral mesh; every tetrahedron positively oriented ([`crate::tet::orientation`]).
#[derive(Clone, Debug)]
pub struct Mesh {
    pub points: Vec<Vec3>,
    pub tets: Vec<[u32; 4]>,
    /// Tetrahedron across face `i` (opposite vertex `i`), or [`HULL`].
    pub neighbors: Vec<[u32; 4]>,
    /// Which face of that neighbour is the shared one.
    pub(crate) mirror: Vec<[u8; 4]>,
    /// Bit `i` set: face `i` is constrained (occlusive), a face of the scene.
    pub constrained: Vec<u8>,
    /// How many tetrahedra were swapped to the positive orientation when the mesh was built.
    pub flipped: usize,
    /// What a walk step reads of each tetrahedron, together (Maria et al.'s Tet80 layout, packed into
    /// one 64-byte line), derived from the fields above when the mesh is made: one fetch per step.
    pub(crate) cells: Vec<Cell>,
}

/// A tetrahedron as a walk step reads it, in one 64-byte cache line: its four vertices inline and,
/// across each face, a [`Link`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(64))]
pub struct Cell {
    pub(crate) v: Tet,
    pub(crate) links: [Link; 4],
}

/// What lies across one face of a [`Cell`], in one word: the neighbour (bits 3..32; all ones for
/// [`HULL`]), the face of the neighbour that is shared (bits 1..3) and whether the face is
/// constrained (bit 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Link(u32);

impl Link {
    /// The most tetrahedra a [`Link`] can name (one index is kept for [`HULL`]).
    pub(crate) const MAX_TETS: usize = (1 << 29) - 1;
    const HULL: u32 = HULL >> 3;

    /// `neighbor` below [`Link::MAX_TETS`] or [`HULL`], `mirror` in `0..4`.
    pub(crate) fn new(neighbor: u32, mirror: u8, constrained: bool) -> Link {
        debug_assert!(neighbor == HULL || (neighbor as usize) < Link::MAX_TETS);
        Link(neighbor << 3 | (mirror as u32 & 3) << 1 | constrained as u32)
    }

    #[inline(always)]
    pub(crate) fn constrained(self) -> bool {
        self.0 & 1 != 0
    }

    /// The neighbour's face that is this one.
    #[inline(always)]
    pub(crate) fn mirror(self) -> usize {
        (self.0 >> 1 & 3) as usize
    }

    /// The neighbour; `None` on the mesh boundary.
    #[inline(always)]
    pub(crate) fn neighbor(self) -> Option<u32> {
        let n = self.0 >> 3;
        (n != Link::HULL).then_some(n)
    }
}

/// The cells of a mesh, from its other fields.
pub fn cells(
    points: &[Vec3],
    tets: &[[u32; 4]],
    neighbors: &[[u32; 4]],
    mirror: &[[u8; 4]],
    constrained: &[u8],
) -> Vec<Cell> {
    (0..tets.len())
        .map(|t| Cell {
            v: tets[t].map(|i| points[i as usize]),
            links: std::array::from_fn(|f| {
                Link::new(
                    neighbors[t][f],
                    mirror[t][f],
                    constrained[t] & (1 << f) != 0,
                )
            }),
        })
        .collect()
}

/// A mesh as read or generated, before checking.
#[derive(Clone, Debug, Default)]
pub struct RawMesh {
    pub points: Vec<Vec3>,
    pub tets: Vec<[u32; 4]>,
    /// Neighbours as given (e.g. TetGen's `.neigh`, `-1` for none); derived from shared faces if absent.
    pub neighbors: Option<Vec<[i64; 4]>>,
    /// Constrained faces as vertex triples.
    pub constrained: Vec<[u32; 3]>,
}

/// A mesh that failed to read or check, with the place it failed at.
#[derive(Debug, thiserror::Error)]
#[error("{place}: {what}")]
pub struct MeshError {
    /// File and line, or tetrahedron and face.
    pub(crate) place: String,
    pub(crate) what: String,
}

/// Where an item of the mesh came from, for error messages.
pub(crate) enum Item {
    Point(usize),
    Tet(usize),
    Neighbors(usize),
    Constrained(usize),
}

impl Mesh {
    /// The same mesh with every tetrahedron's vertices relabelled by `p` (new vertex `i` is old vertex
    /// `p[i]`, so the neighbour across new face `i` is the old one across face `p[i]`; an even
    /// permutation keeps the orientation), checked again.
    pub fn relabelled(&self, p: [usize; 4]) -> Result<Mesh, MeshError> {
        let mut raw = self.to_raw();
        raw.tets = raw.tets.iter().map(|v| p.map(|i| v[i])).collect();
        raw.neighbors = raw
            .neighbors
            .map(|n| n.iter().map(|r| p.map(|i| r[i])).collect());
        Mesh::build(raw)
    }

    /// Check `raw` and build the mesh, naming places with plain indices.
    pub fn build(raw: RawMesh) -> Result<Mesh, MeshError> {
        Self::build_at(raw, &|item| match item {
            Item::Point(i) => format!("point {i}"),
            Item::Tet(t) | Item::Neighbors(t) => format!("tetrahedron {t}"),
            Item::Constrained(i) => format!("constrained face {i}"),
        })
    }

    /// Check `raw` and build the mesh; `place` names an item in errors (file and line for loaders).
    ///
    /// Checks: coordinates finite; vertex indices in range and distinct; every tetrahedron non-flat, all
    /// of one orientation (negative ones, as TetGen writes, are swapped to positive here, the one place
    /// this happens); no face shared by more than two tetrahedra; given neighbours the ones the
    /// tetrahedra's shared faces make; every constrained face a face of the mesh; and the mesh a
    /// tetrahedralization of its region, decided exactly ([`valid`]: no overlap, fold or crack).
    pub(crate) fn build_at(
        raw: RawMesh,
        place: &dyn Fn(Item) -> String,
    ) -> Result<Mesh, MeshError> {
        let err = |item, what: String| MeshError {
            place: place(item),
            what,
        };
        for (i, p) in raw.points.iter().enumerate() {
            if !p.is_finite() {
                return Err(err(
                    Item::Point(i),
                    format!("coordinate not finite in f32: {p}"),
                ));
            }
        }
        let n = raw.points.len();
        let mut tets = raw.tets;
        if tets.is_empty() {
            return Err(err(Item::Tet(0), "the mesh has no tetrahedra".into()));
        }
        if tets.len() > Link::MAX_TETS {
            let what = format!(
                "the mesh has {} tetrahedra; a walk addresses at most {}",
                tets.len(),
                Link::MAX_TETS
            );
            return Err(err(Item::Tet(Link::MAX_TETS), what));
        }
        let mut signs = Vec::with_capacity(tets.len());
        for (t, v) in tets.iter().enumerate() {
            if let Some(&i) = v.iter().find(|&&i| i as usize >= n) {
                let what = format!("vertex index {i} out of range (the mesh has {n} points)");
                return Err(err(Item::Tet(t), what));
            }
            if (0..4).any(|a| (a + 1..4).any(|b| v[a] == v[b])) {
                return Err(err(Item::Tet(t), format!("repeated vertex in {v:?}")));
            }
            let s = orientation(&v.map(|i| raw.points[i as usize]));
            if s == 0 {
                return Err(err(
                    Item::Tet(t),
                    format!("flat tetrahedron (zero volume), vertices {v:?}"),
                ));
            }
            signs.push(s);
        }
        // The mesh's orientation is its majority's (the first tetrahedron's on a tie); the first
        // tetrahedron against it is inverted.
        let negative = signs.iter().filter(|&&s| s < 0).count();
        let sign0 = match (2 * negative).cmp(&signs.len()) {
            std::cmp::Ordering::Greater => -1,
            std::cmp::Ordering::Less => 1,
            std::cmp::Ordering::Equal => signs[0],
        };
        if let Some(t) = signs.iter().position(|&s| s != sign0) {
            let what = format!(
                "inverted: orientation {:+}, against {:+} for {} of {} tetrahedra",
                signs[t],
                sign0,
                if sign0 < 0 {
                    negative
                } else {
                    signs.len() - negative
                },
                signs.len()
            );
            return Err(err(Item::Tet(t), what));
        }
        let flip = sign0 < 0;
        if flip {
            for v in &mut tets {
                v.swap(0, 1);
            }
        }
        let derived = derive_neighbors(&tets).map_err(|(t, what)| err(Item::Tet(t), what))?;
        let neighbors = match raw.neighbors {
            Some(mut given) => {
                if given.len() != tets.len() {
                    let what = format!(
                        "{} neighbour rows for {} tetrahedra",
                        given.len(),
                        tets.len()
                    );
                    return Err(err(Item::Neighbors(given.len().min(tets.len())), what));
                }
                let mut out = Vec::with_capacity(given.len());
                for (t, row) in given.iter_mut().enumerate() {
                    if flip {
                        row.swap(0, 1);
                    }
                    let mut r = [HULL; 4];
                    for f in 0..4 {
                        r[f] = match row[f] {
                            -1 => HULL,
                            x if x >= 0 && (x as usize) < tets.len() => x as u32,
                            x => {
                                return Err(err(
                                    Item::Neighbors(t),
                                    format!("neighbour {x} out of range"),
                                ));
                            }
                        };
                    }
                    out.push(r);
                }
                // Given neighbours must be the tetrahedra's own: the faces they share.
                for (t, (mine, theirs)) in out.iter().zip(&derived).enumerate() {
                    if let Some(f) = (0..4).find(|&f| mine[f] != theirs[f]) {
                        let name = |n: u32| match n {
                            HULL => "none (the boundary)".to_string(),
                            n => format!("tetrahedron {n}"),
                        };
                        let ids = sorted(FACE_VERTICES[f].map(|i| tets[t][i]));
                        return Err(err(
                            Item::Neighbors(t),
                            format!(
                                "across face {f} {ids:?} the neighbours name {}, the tetrahedra {}",
                                name(mine[f]),
                                name(theirs[f])
                            ),
                        ));
                    }
                }
                out
            }
            None => derived,
        };
        let mirror =
            mirrors(&tets, &neighbors).map_err(|(t, what)| err(Item::Neighbors(t), what))?;
        valid::check(&raw.points, &tets, &neighbors).map_err(|(item, what)| err(item, what))?;
        let mut constrained = vec![0u8; tets.len()];
        let faces = face_index(&tets);
        for (i, tri) in raw.constrained.iter().enumerate() {
            let Some(&(t, f)) = faces.get(&sorted(*tri)) else {
                return Err(err(
                    Item::Constrained(i),
                    format!("{tri:?} is not a face of any tetrahedron"),
                ));
            };
            constrained[t as usize] |= 1 << f;
            let nb = neighbors[t as usize][f as usize];
            if nb != HULL {
                constrained[nb as usize] |= 1 << mirror[t as usize][f as usize];
            }
        }
        Ok(Mesh {
            cells: cells(&raw.points, &tets, &neighbors, &mirror, &constrained),
            points: raw.points,
            flipped: if flip { tets.len() } else { 0 },
            tets,
            neighbors,
            mirror,
            constrained,
        })
    }

    /// The four points of tetrahedron `t`.
    #[inline(always)]
    pub fn tet(&self, t: u32) -> Tet {
        self.cells[t as usize].v
    }

    /// Whether face `f` of tetrahedron `t` is constrained.
    #[inline(always)]
    pub fn is_constrained(&self, t: u32, f: usize) -> bool {
        self.constrained[t as usize] & (1 << f) != 0
    }

    /// Every face of the mesh once: `(t, f)` with `t` the lower-numbered of the tetrahedra that share it.
    pub(crate) fn faces_once(&self) -> impl Iterator<Item = (u32, usize)> + '_ {
        (0..self.tets.len() as u32).flat_map(move |t| {
            (0..4).filter_map(move |f| {
                let nb = self.neighbors[t as usize][f];
                (nb == HULL || nb > t).then_some((t, f))
            })
        })
    }

    /// How many faces are constrained (each counted once).
    pub(crate) fn constrained_faces(&self) -> usize {
        self.faces_once()
            .filter(|&(t, f)| self.is_constrained(t, f))
            .count()
    }

    /// Vertex indices of face `f` of tetrahedron `t`, counterclockwise seen from outside.
    pub fn face(&self, t: u32, f: usize) -> [u32; 3] {
        FACE_VERTICES[f].map(|i| self.tets[t as usize][i])
    }

    /// The same mesh with every point moved by `offset` (rounded to f32), checked again.
    pub(crate) fn translated(&self, offset: Vec3) -> Result<Mesh, MeshError> {
        let mut raw = self.to_raw();
        raw.points.iter_mut().for_each(|p| *p += offset);
        Mesh::build(raw)
    }

    /// The mesh with every point times 2^`e`, exactly: an error names the first point that would
    /// round (underflow to a subnormal or zero, or overflow).
    pub(crate) fn scaled(&self, e: i32) -> Result<Mesh, MeshError> {
        let mut raw = self.to_raw();
        for (i, p) in raw.points.iter_mut().enumerate() {
            let q = p.to_array().map(|x| crate::tet::times_two_to(x, e));
            let [Some(x), Some(y), Some(z)] = q else {
                return Err(MeshError {
                    place: format!("point {i}"),
                    what: format!("{p} times 2^{e} is not an f32 (it underflows or overflows)"),
                });
            };
            *p = Vec3::new(x, y, z);
        }
        Mesh::build(raw)
    }

    /// Back to unchecked form (neighbours kept).
    pub(crate) fn to_raw(&self) -> RawMesh {
        let neighbors = self
            .neighbors
            .iter()
            .map(|r| r.map(|n| if n == HULL { -1 } else { n as i64 }));
        let mut constrained = Vec::new();
        for t in 0..self.tets.len() as u32 {
            for f in 0..4 {
                let nb = self.neighbors[t as usize][f];
                if self.is_constrained(t, f) && (nb == HULL || nb > t) {
                    constrained.push(self.face(t, f));
                }
            }
        }
        RawMesh {
            points: self.points.clone(),
            tets: self.tets.clone(),
            neighbors: Some(neighbors.collect()),
            constrained,
        }
    }
}

/// The axis-aligned bounding box of points: `(lower corner, upper corner)`.
pub fn bounds(points: &[Vec3]) -> (Vec3, Vec3) {
    points
        .iter()
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(a, b), &p| {
            (a.min(p), b.max(p))
        })
}

fn sorted(mut f: [u32; 3]) -> [u32; 3] {
    f.sort_unstable();
    f
}

/// Each face (sorted vertex triple) with one tetrahedron and face index that has it.
fn face_index(tets: &[[u32; 4]]) -> HashMap<[u32; 3], (u32, u8)> {
    let mut map = HashMap::with_capacity(tets.len() * 2);
    for (t, v) in tets.iter().enumerate() {
        for (f, fv) in FACE_VERTICES.iter().enumerate() {
            map.entry(sorted(fv.map(|i| v[i])))
                .or_insert((t as u32, f as u8));
        }
    }
    map
}

/// Neighbours from shared faces; a face shared by three or more tetrahedra is an error.
fn derive_neighbors(tets: &[[u32; 4]]) -> Result<Vec<[u32; 4]>, (usize, String)> {
    let mut first: HashMap<[u32; 3], (u32, u8)> = HashMap::with_capacity(tets.len() * 2);
    let mut out = vec![[HULL; 4]; tets.len()];
    for (t, v) in tets.iter().enumerate() {
        for (f, fv) in FACE_VERTICES.iter().enumerate() {
            let key = sorted(fv.map(|i| v[i]));
            match first.get(&key) {
                None => {
                    first.insert(key, (t as u32, f as u8));
                }
                Some(&(u, g)) => {
                    if out[u as usize][g as usize] != HULL {
                        return Err((
                            t,
                            format!("face {f} {key:?} is shared by three or more tetrahedra"),
                        ));
                    }
                    out[u as usize][g as usize] = t as u32;
                    out[t][f] = u;
                }
            }
        }
    }
    Ok(out)
}

/// For each face with a neighbour, the neighbour's face index; checks symmetry and shared vertices.
fn mirrors(tets: &[[u32; 4]], neighbors: &[[u32; 4]]) -> Result<Vec<[u8; 4]>, (usize, String)> {
    let mut out = vec![[u8::MAX; 4]; tets.len()];
    for (t, row) in neighbors.iter().enumerate() {
        for f in 0..4 {
            let nb = row[f];
            if nb == HULL {
                continue;
            }
            if nb as usize == t {
                return Err((t, format!("face {f}: the tetrahedron is its own neighbour")));
            }
            let Some(g) = neighbors[nb as usize].iter().position(|&x| x as usize == t) else {
                return Err((t, format!("face {f}: neighbour {nb} does not name it back")));
            };
            let mine = sorted(FACE_VERTICES[f].map(|i| tets[t][i]));
            let theirs = sorted(FACE_VERTICES[g].map(|i| tets[nb as usize][i]));
            if mine != theirs {
                let what = format!("face {f} {mine:?}: neighbour {nb} shares {theirs:?} instead");
                return Err((t, what));
            }
            out[t][f] = g as u8;
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cell is one 64-byte line, and a link gives back what it was made of, at the ends of its ranges.
    #[test]
    fn cell_is_a_line_and_links_round_trip() {
        assert_eq!(std::mem::size_of::<Cell>(), 64);
        assert_eq!(std::mem::align_of::<Cell>(), 64);
        for n in [0, 1, 12345, Link::MAX_TETS as u32 - 1, HULL] {
            for m in 0..4u8 {
                for c in [false, true] {
                    let l = Link::new(n, m, c);
                    let want = (n != HULL).then_some(n);
                    assert_eq!(
                        (l.neighbor(), l.mirror(), l.constrained()),
                        (want, m as usize, c)
                    );
                }
            }
        }
    }

    fn two_tets() -> RawMesh {
        RawMesh {
            points: vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
                Vec3::new(0.0, 0.0, 1.0),
                Vec3::new(0.0, 0.0, -1.0),
            ],
            // Both negative, as TetGen writes them.
            tets: vec![[0, 1, 2, 3], [1, 0, 2, 4]],
            neighbors: None,
            constrained: vec![[2, 1, 0]],
        }
    }

    #[test]
    fn negative_meshes_are_flipped_and_linked() {
        let m = Mesh::build(two_tets()).unwrap();
        assert_eq!(m.flipped, 2);
        for t in 0..2 {
            assert_eq!(orientation(&m.tet(t)), 1);
        }
        let f = m.neighbors[0].iter().position(|&n| n == 1).unwrap();
        assert_eq!(m.neighbors[1][m.mirror[0][f] as usize], 0);
        assert!(m.is_constrained(0, f) && m.is_constrained(1, m.mirror[0][f] as usize));
    }

    #[test]
    fn bad_meshes_name_the_place() {
        let mut r = two_tets();
        r.tets[1] = [1, 0, 2, 3];
        let e = Mesh::build(r).unwrap_err();
        assert!(e.place == "tetrahedron 1", "{e}");
        let mut r = two_tets();
        r.tets[1] = [0, 1, 2, 4];
        assert!(Mesh::build(r).unwrap_err().to_string().contains("inverted"));
        let mut r = two_tets();
        r.neighbors = Some(vec![[-1, -1, -1, 1], [-1, -1, -1, -1]]);
        assert!(
            Mesh::build(r)
                .unwrap_err()
                .to_string()
                .contains("the neighbours name none (the boundary), the tetrahedra tetrahedron 0")
        );
        let mut r = two_tets();
        r.constrained = vec![[0, 3, 4]];
        assert!(
            Mesh::build(r)
                .unwrap_err()
                .to_string()
                .contains("constrained face 0")
        );
        let mut r = two_tets();
        r.points[4].z = f32::NAN;
        assert!(Mesh::build(r).unwrap_err().to_string().contains("point 4"));
    }
}
