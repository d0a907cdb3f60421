//! Portalez & Duguet's octree (seed 001 §2.2, §3): leaves over a scene's triangles, at most `depth`
//! levels deep and split while they hold more than `capacity` triangles, under the regularity
//! constraint (face neighbours differ by at most one level, so a face has 0, 1 or 4 neighbours);
//! serialised as eq. 3 (`tCount | tOffset | i | nCount | N…`, six neighbour counts in 24 bits), with
//! the box array and the cube map of boundary cells (§4.1). Every neighbour link is checked when the
//! octree is built.
//!
//! The root is a cube around the triangles, placed on a power-of-two grid so that every cell's corners
//! are exact in f32 (the paper does not say how it is placed).

pub mod cell;

use crate::tet::Tri;
use cell::{FACE_AXIS, FACE_HIGH, face_axes};
use glam::{DVec3, Vec3};
use std::collections::{HashMap, HashSet};

/// How an octree is built.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Settings {
    /// Deepest level (the root is level 0); the paper: 8 for the bunny.
    pub depth: u32,
    /// A node is split while it holds more triangles than this (and is above `depth`).
    pub capacity: usize,
}

impl Settings {
    /// Whether an octree can be built with these settings (checked before any work).
    pub(crate) fn check(&self) -> Result<(), OctreeError> {
        match (self.depth, self.capacity) {
            (0, _) => Err(OctreeError::NoDepth),
            (d, _) if d > MAX_DEPTH => Err(OctreeError::TooDeep(d)),
            (_, 0) => Err(OctreeError::NoCapacity),
            _ => Ok(()),
        }
    }

    /// Seed 001's bunny: depth 8, about 6 triangles per leaf.
    pub const PAPER: Settings = Settings {
        depth: 8,
        capacity: 6,
    };
}

/// Deepest level an octree may have (the cube map holds `6 · 4^depth` cells).
pub(crate) const MAX_DEPTH: u32 = 10;

/// A node: its level and integer coordinates at that level.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Key {
    pub level: u32,
    pub(crate) at: [u32; 3],
}

impl Key {
    fn child(self, k: usize) -> Key {
        Key {
            level: self.level + 1,
            at: std::array::from_fn(|a| 2 * self.at[a] + (k >> a & 1) as u32),
        }
    }

    fn parent(self) -> Key {
        Key {
            level: self.level - 1,
            at: self.at.map(|c| c / 2),
        }
    }

    /// The node of the same level across face `f`, if inside the root.
    fn across(self, f: usize) -> Option<Key> {
        let a = FACE_AXIS[f];
        let n = 1u32 << self.level;
        let mut at = self.at;
        if FACE_HIGH[f] {
            at[a] = at[a].checked_add(1).filter(|&c| c < n)?;
        } else {
            at[a] = at[a].checked_sub(1)?;
        }
        Some(Key {
            level: self.level,
            at,
        })
    }
}

/// An octree that failed to build or check, naming the cell.
#[derive(Debug, thiserror::Error)]
pub enum OctreeError {
    #[error("an octree needs at least one triangle")]
    Empty,
    #[error("a triangle coordinate is not finite")]
    NonFinite,
    #[error("depth {0} is more than {MAX_DEPTH}")]
    TooDeep(u32),
    #[error(
        "depth 0: the root alone would be a cell on its own grid (the rule that keeps every corner exact in f32), which cannot hold triangles on both sides of a multiple of its side; an octree is 1 to {MAX_DEPTH} levels deep"
    )]
    NoDepth,
    #[error("no power-of-two cube on the grid of its deepest cells holds the triangles in f32")]
    NoRoot,
    #[error("leaf capacity 0: every node would split to the deepest level")]
    NoCapacity,
    #[error("cell {cell} (level {level}, at {at:?}), face {face}: {why}")]
    Link {
        cell: u32,
        level: u32,
        at: [u32; 3],
        face: &'static str,
        why: String,
    },
}

/// The octree of seed 001 over a list of triangles.
#[derive(Clone, Debug)]
pub struct Octree {
    pub(crate) settings: Settings,
    /// The root cube's lower corner and side.
    pub(crate) lo: Vec3,
    pub(crate) size: f32,
    /// Leaf `i`'s node.
    pub leaves: Vec<Key>,
    /// Leaf `i`'s Morton code at the deepest level and its level, ascending: what
    /// [`Octree::leaf_holding`] searches (one code per level tried, none per comparison).
    pub(crate) leaf_keys: Vec<(u64, u32)>,
    /// Leaf `i`'s box (eq. 3's `i` indexes it).
    pub(crate) boxes: Vec<[Vec3; 2]>,
    /// Eq. 3, every leaf in turn.
    pub words: Vec<u32>,
    /// Leaf `i`'s address in `words`.
    pub address: Vec<u32>,
    /// The triangle array: triangle ids (into the scene's list), each leaf's run at its `tOffset`.
    pub(crate) triangles: Vec<u32>,
    /// §4.1's cube map: per root face, `2^depth × 2^depth` addresses of the boundary leaves, indexed
    /// `u + v · 2^depth` along the face's axes ([`face_axes`]).
    pub(crate) cube_map: [Vec<u32>; 6],
    /// Leaves before the regularity constraint (seed 001 Table 1's "non contraint").
    pub unconstrained_leaves: usize,
}

/// Words of eq. 3 before a leaf's neighbour addresses.
pub(crate) const HEADER_WORDS: usize = 4;

/// Whether the triangle meets the closed box (Akenine-Möller's separating-axis test in f64, the box
/// grown by 2^-20 of its side so that rounding can only add triangles, never drop one).
fn overlaps(t: &Tri, lo: DVec3, hi: DVec3) -> bool {
    let grow = (hi - lo) * (1.0 / (1 << 20) as f64);
    let (c, h) = ((lo + hi) * 0.5, (hi - lo) * 0.5 + grow);
    let v = t.map(|p| p.as_dvec3() - c);
    for a in 0..3 {
        let (mn, mx) = (
            v[0][a].min(v[1][a]).min(v[2][a]),
            v[0][a].max(v[1][a]).max(v[2][a]),
        );
        if mn > h[a] || mx < -h[a] {
            return false;
        }
    }
    let e = [v[1] - v[0], v[2] - v[1], v[0] - v[2]];
    let n = e[0].cross(e[1]);
    let separated = |axis: DVec3| {
        let p = v.map(|x| x.dot(axis));
        let r = h.x * axis.x.abs() + h.y * axis.y.abs() + h.z * axis.z.abs();
        p.iter().cloned().fold(f64::INFINITY, f64::min) > r
            || p.iter().cloned().fold(f64::NEG_INFINITY, f64::max) < -r
    };
    if separated(n) {
        return false;
    }
    for ei in e {
        for a in 0..3 {
            let mut u = DVec3::ZERO;
            u[a] = 1.0;
            let axis = ei.cross(u);
            if axis != DVec3::ZERO && separated(axis) {
                return false;
            }
        }
    }
    true
}

/// Morton code of a node's lower corner at level `depth` (leaves in this order are near in memory
/// when near in space).
fn morton(k: Key, depth: u32) -> u64 {
    let at = k.at.map(|c| (c as u64) << (depth - k.level));
    let mut m = 0u64;
    for b in 0..depth {
        for (a, c) in at.iter().enumerate() {
            m |= (c >> b & 1) << (3 * b + a as u32);
        }
    }
    m
}

impl Octree {
    /// Build the octree of `tris` (seed 001 §2.2): split, then split more until the regularity
    /// constraint holds; serialise; check every link.
    pub fn build(tris: &[Tri], s: Settings) -> Result<Octree, OctreeError> {
        if tris.is_empty() {
            return Err(OctreeError::Empty);
        }
        s.check()?;
        if !tris.iter().flatten().all(|p| p.is_finite()) {
            return Err(OctreeError::NonFinite);
        }
        let (lo, size) = root(tris, s.depth)?;
        let cell = |k: Key| -> (DVec3, DVec3) {
            let side = size as f64 / (1u64 << k.level) as f64;
            let l = lo.as_dvec3() + DVec3::from(k.at.map(|c| c as f64)) * side;
            (l, l + DVec3::splat(side))
        };
        let keep = |k: Key, ids: &[u32]| -> Vec<u32> {
            let (l, h) = cell(k);
            ids.iter()
                .copied()
                .filter(|&i| overlaps(&tris[i as usize], l, h))
                .collect()
        };
        let mut internal: HashSet<Key> = HashSet::new();
        let mut leaves: HashMap<Key, Vec<u32>> = HashMap::new();
        let mut stack = vec![(
            Key {
                level: 0,
                at: [0; 3],
            },
            (0..tris.len() as u32).collect::<Vec<u32>>(),
        )];
        while let Some((k, ids)) = stack.pop() {
            if k.level < s.depth && ids.len() > s.capacity {
                internal.insert(k);
                for c in 0..8 {
                    let child = k.child(c);
                    stack.push((child, keep(child, &ids)));
                }
            } else {
                leaves.insert(k, ids);
            }
        }
        let unconstrained_leaves = leaves.len();
        // The regularity constraint: split a leaf while a face neighbour's region holds a node two
        // levels deeper (an internal child of its same-level neighbour touching the shared face).
        let mut work: Vec<Key> = leaves.keys().copied().collect();
        while let Some(k) = work.pop() {
            if !leaves.contains_key(&k) {
                continue;
            }
            let too_coarse = (0..6).any(|f| {
                k.across(f).is_some_and(|n| {
                    internal.contains(&n)
                        && touching_children(n, f).iter().any(|c| internal.contains(c))
                })
            });
            if !too_coarse {
                continue;
            }
            let ids = leaves.remove(&k).expect("checked above");
            internal.insert(k);
            for c in 0..8 {
                let child = k.child(c);
                leaves.insert(child, keep(child, &ids));
                work.push(child);
            }
            // Its coarser neighbours may now be too coarse in turn.
            for f in 0..6 {
                if let Some(n) = k.across(f) {
                    let mut up = n;
                    while !leaves.contains_key(&up) && up.level > 0 {
                        up = up.parent();
                    }
                    work.push(up);
                }
            }
        }
        let mut order: Vec<Key> = leaves.keys().copied().collect();
        order.sort_by_key(|&k| (morton(k, s.depth), k.level));
        let index: HashMap<Key, u32> = order
            .iter()
            .enumerate()
            .map(|(i, k)| (*k, i as u32))
            .collect();
        // Neighbours of each leaf across each face, in eq. 3's order (face 0..5, quarter 0..3).
        let mut neighbors: Vec<[Vec<u32>; 6]> = Vec::with_capacity(order.len());
        for (i, &k) in order.iter().enumerate() {
            let mut per: [Vec<u32>; 6] = Default::default();
            for (f, list) in per.iter_mut().enumerate() {
                let Some(n) = k.across(f) else { continue };
                let link = |why: String| OctreeError::Link {
                    cell: i as u32,
                    level: k.level,
                    at: k.at,
                    face: cell::FACE_NAMES[f],
                    why,
                };
                if let Some(&j) = index.get(&n) {
                    list.push(j);
                } else if internal.contains(&n) {
                    for c in touching_children(n, f) {
                        let j = index.get(&c).ok_or_else(|| {
                            link(format!("neighbour {c:?} is not a leaf: two levels apart"))
                        })?;
                        list.push(*j);
                    }
                } else {
                    let p = n.parent();
                    let j = index
                        .get(&p)
                        .ok_or_else(|| link(format!("no leaf holds the region {n:?} across it")))?;
                    list.push(*j);
                }
            }
            neighbors.push(per);
        }
        let mut address = Vec::with_capacity(order.len());
        let mut at = 0u32;
        for per in &neighbors {
            address.push(at);
            at += (HEADER_WORDS + per.iter().map(Vec::len).sum::<usize>()) as u32;
        }
        let mut words = Vec::with_capacity(at as usize);
        let mut triangles = Vec::new();
        for (i, k) in order.iter().enumerate() {
            let ids = &leaves[k];
            words.push(ids.len() as u32);
            words.push(triangles.len() as u32);
            words.push(i as u32);
            let counts = neighbors[i]
                .iter()
                .enumerate()
                .fold(0u32, |c, (f, l)| c | (l.len() as u32) << (4 * f));
            words.push(counts);
            for list in &neighbors[i] {
                words.extend(list.iter().map(|&j| address[j as usize]));
            }
            triangles.extend_from_slice(ids);
        }
        let boxes = order
            .iter()
            .map(|&k| {
                let (l, h) = cell(k);
                [l.as_vec3(), h.as_vec3()]
            })
            .collect();
        let n = 1u32 << s.depth;
        let leaf_at = |at: [u32; 3]| -> u32 {
            let mut k = Key { level: s.depth, at };
            loop {
                if let Some(&i) = index.get(&k) {
                    return address[i as usize];
                }
                k = k.parent();
            }
        };
        let cube_map = std::array::from_fn(|f| {
            let [u, v] = face_axes(FACE_AXIS[f]);
            let mut map = Vec::with_capacity((n * n) as usize);
            for j in 0..n {
                for i in 0..n {
                    let mut at = [0u32; 3];
                    at[FACE_AXIS[f]] = if FACE_HIGH[f] { n - 1 } else { 0 };
                    at[u] = i;
                    at[v] = j;
                    map.push(leaf_at(at));
                }
            }
            map
        });
        let leaf_keys = order
            .iter()
            .map(|&l| (morton(l, s.depth), l.level))
            .collect();
        let o = Octree {
            settings: s,
            lo,
            size,
            leaves: order,
            leaf_keys,
            boxes,
            words,
            address,
            triangles,
            cube_map,
            unconstrained_leaves,
        };
        o.check()?;
        Ok(o)
    }

    /// Every neighbour link of eq. 3 checked against the boxes: a cell has neighbours across a face
    /// unless it lies on the root's boundary there, 1 or 4 of them; each shares the face's plane and
    /// overlaps it, four lie one in each quarter in quarter order, and each links back.
    pub fn check(&self) -> Result<(), OctreeError> {
        let by_address: HashMap<u32, usize> = self
            .address
            .iter()
            .enumerate()
            .map(|(i, &a)| (a, i))
            .collect();
        for (i, k) in self.leaves.iter().enumerate() {
            let at = self.address[i] as usize;
            let fail = |f: usize, why: String| OctreeError::Link {
                cell: i as u32,
                level: k.level,
                at: k.at,
                face: cell::FACE_NAMES[f],
                why,
            };
            if self.words[at + 2] != i as u32 {
                return Err(fail(0, format!("its index word is {}", self.words[at + 2])));
            }
            let [lo, hi] = self.boxes[i];
            for f in 0..6 {
                let list = self.neighbors(self.address[i], f);
                let a = FACE_AXIS[f];
                let plane = if FACE_HIGH[f] { hi[a] } else { lo[a] };
                let on_root = plane
                    == if FACE_HIGH[f] {
                        self.lo[a] + self.size
                    } else {
                        self.lo[a]
                    };
                if list.is_empty() != on_root || !matches!(list.len(), 0 | 1 | 4) {
                    return Err(fail(
                        f,
                        format!(
                            "{} neighbours (on the root's boundary: {on_root})",
                            list.len()
                        ),
                    ));
                }
                for (q, &addr) in list.iter().enumerate() {
                    let j = *by_address
                        .get(&addr)
                        .ok_or_else(|| fail(f, format!("address {addr} is no cell's")))?;
                    let [nlo, nhi] = self.boxes[j];
                    let their = if FACE_HIGH[f] { nlo[a] } else { nhi[a] };
                    let [u, v] = face_axes(a);
                    let overlap = [u, v].iter().all(|&b| nlo[b] < hi[b] && nhi[b] > lo[b]);
                    if their != plane || !overlap {
                        return Err(fail(f, format!("neighbour {j} does not share the face")));
                    }
                    if list.len() == 4 {
                        let centre = (lo + hi) * 0.5;
                        let signs = cell::quarter_signs(q);
                        let inside = [u, v].iter().zip(signs).all(|(&b, s)| {
                            if s < 0 {
                                nhi[b] == centre[b]
                            } else {
                                nlo[b] == centre[b]
                            }
                        });
                        if !inside {
                            return Err(fail(f, format!("neighbour {j} is not in quarter {q}")));
                        }
                    }
                    let back = f ^ if f < 4 { 2 } else { 1 };
                    if !self
                        .neighbors(self.address[j], back)
                        .contains(&self.address[i])
                    {
                        return Err(fail(f, format!("neighbour {j} does not link back")));
                    }
                }
            }
        }
        Ok(())
    }

    /// The neighbour addresses of the leaf at `address` across face `f` (eq. 3).
    pub fn neighbors(&self, address: u32, f: usize) -> &[u32] {
        let at = address as usize;
        let counts = self.words[at + 3];
        let before: u32 = (0..f).map(|g| counts >> (4 * g) & 15).sum();
        let n = (counts >> (4 * f) & 15) as usize;
        let start = at + HEADER_WORDS + before as usize;
        &self.words[start..start + n]
    }

    /// The leaf holding point `p` (its lowest corner's cell where `p` lies on a boundary), if `p` is
    /// in the root cube: by descending levels from the deepest.
    pub(crate) fn leaf_holding(&self, p: Vec3) -> Option<u32> {
        let n = 1u32 << self.settings.depth;
        let rel = (p - self.lo) / self.size * n as f32;
        if !(0..3).all(|a| rel[a] >= 0.0 && rel[a] <= n as f32) {
            return None;
        }
        let at = [0, 1, 2].map(|a| (rel[a] as u32).min(n - 1));
        let mut k = Key {
            level: self.settings.depth,
            at,
        };
        loop {
            if let Ok(i) = self
                .leaf_keys
                .binary_search(&(morton(k, self.settings.depth), k.level))
            {
                return Some(self.address[i]);
            }
            if k.level == 0 {
                return None;
            }
            k = k.parent();
        }
    }

    /// Bytes of the four arrays (seed 001 Table 3): octree words, triangles (as three f32 points each,
    /// per reference), boxes, cube map.
    pub(crate) fn bytes(&self) -> [usize; 4] {
        [
            self.words.len() * 4,
            self.triangles.len() * 36,
            self.boxes.len() * 24,
            self.cube_map.iter().map(Vec::len).sum::<usize>() * 4,
        ]
    }

    /// Mean neighbours per leaf (seed 001 §5.1: about 7).
    pub(crate) fn mean_neighbors(&self) -> f64 {
        let links = self.words.len() - HEADER_WORDS * self.leaves.len();
        links as f64 / self.leaves.len().max(1) as f64
    }
}

/// The four children of `n` that touch its face opposite `f` (the face it shares with the node it is
/// across `f` from), in quarter order ([`cell::quarter_signs`]).
fn touching_children(n: Key, f: usize) -> [Key; 4] {
    let a = FACE_AXIS[f];
    let [u, v] = face_axes(a);
    std::array::from_fn(|q| {
        let s = cell::quarter_signs(q);
        let mut k = 0usize;
        // Across the high face, the neighbour's touching children are its low ones, and so on.
        if !FACE_HIGH[f] {
            k |= 1 << a;
        }
        if s[0] > 0 {
            k |= 1 << u;
        }
        if s[1] > 0 {
            k |= 1 << v;
        }
        n.child(k)
    })
}

/// The root cube: a power-of-two side `2^e ≥` the triangles' extent, its lower corner on the grid of
/// the deepest cells, so that every cell corner is exact in f32.
fn root(tris: &[Tri], depth: u32) -> Result<(Vec3, f32), OctreeError> {
    let (lo, hi) = tris
        .iter()
        .flatten()
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(a, b), &p| {
            (a.min(p), b.max(p))
        });
    let extent = (hi - lo).max_element().max(f32::MIN_POSITIVE);
    let mut size = 2f32.powi(extent.log2().ceil() as i32);
    while size.is_finite() {
        let cell = size / (1u32 << depth) as f32;
        let l = (lo / cell).floor() * cell;
        // In f64, exactly: l and size are multiples of the cell (an f32 difference could round down).
        if (0..3).all(|a| hi[a] as f64 <= l[a] as f64 + size as f64) {
            return Ok((l, size));
        }
        size *= 2.0;
    }
    Err(OctreeError::NoRoot)
}
