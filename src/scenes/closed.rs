//! Closed triangle meshes for the ray–triangle stress rows (seed 004's robustness question): convex
//! meshes with integer or dyadic coordinates, outward-oriented, and rays from outside them exactly through
//! a shared edge or vertex, within ulps of one, or along an edge; moved far from the origin.

use super::Rng;
use super::tets::{TetShape, nudge, scale_of, tet};
use crate::tet::{FACE_VERTICES, Ray, Tri, orientation};
use glam::Vec3;
use rand::RngExt;

/// A closed mesh shape.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum MeshShape {
    /// Six integer vertices on the axes, axes scaled by random integers.
    Octahedron,
    /// The pyritohedral icosahedron `(0, ±1, ±3/2)` and its cyclic shifts: dyadic coordinates, axes
    /// scaled by random integers.
    Icosahedron,
    /// A well-shaped tetrahedron's four faces (integer coordinates).
    Tetrahedron,
    /// A sliver's four faces: four vertices near one plane (integer coordinates).
    Sliver,
    /// A needle's four faces: three vertices close together (integer coordinates).
    Needle,
}

crate::choice!(MeshShape { Octahedron => "octahedron", Icosahedron => "icosahedron", Tetrahedron => "tetrahedron", Sliver => "sliver", Needle => "needle" });

/// Where a ray is aimed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum TriAim {
    /// Exactly through the midpoint of an edge (shared by two triangles).
    Edge,
    /// Exactly through a vertex.
    Vertex,
    /// As `edge`, the origin then moved by 1 to `ulps` ulps along one axis.
    NearEdge,
    /// As `vertex`, the origin then moved by 1 to `ulps` ulps along one axis.
    NearVertex,
    /// Exactly through the midpoint of an edge, nearly within the plane of one of its triangles.
    Grazing,
}

crate::choice!(TriAim { Edge => "edge", Vertex => "vertex", NearEdge => "near-edge", NearVertex => "near-vertex", Grazing => "grazing" });

/// Where the mesh and ray are moved to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum TriPlace {
    /// Near the origin.
    Origin,
    /// Moved by 2^16 along (1, 1, 1).
    Far,
    /// Moved to (148376, 1234, -223423), where Embree's watertightness test puts its sphere.
    Embree,
}

crate::choice!(TriPlace { Origin => "origin", Far => "far", Embree => "embree" });

impl TriPlace {
    pub(crate) fn offset(self) -> Vec3 {
        match self {
            TriPlace::Origin => Vec3::ZERO,
            TriPlace::Far => Vec3::splat(65536.0),
            TriPlace::Embree => Vec3::new(148376.0, 1234.0, -223423.0),
        }
    }
}

/// The outward-oriented convex hull of a few points in general position (no four coplanar on a face),
/// by trying every triple: a triangle is a face when every other point lies strictly on one side.
fn hull(points: &[Vec3]) -> Vec<Tri> {
    let n = points.len();
    let mut faces = Vec::new();
    for i in 0..n {
        for j in i + 1..n {
            for k in j + 1..n {
                let (a, b, c) = (points[i], points[j], points[k]);
                let sides: Vec<i8> = (0..n)
                    .filter(|&m| m != i && m != j && m != k)
                    .map(|m| orientation(&[a, b, c, points[m]]))
                    .collect();
                // orient3d(a, b, c, p) > 0: p below `a, b, c` seen counterclockwise from above.
                if sides.iter().all(|&s| s > 0) {
                    faces.push([a, b, c]);
                } else if sides.iter().all(|&s| s < 0) {
                    faces.push([a, c, b]);
                }
            }
        }
    }
    faces
}

/// Random positive integer scales of the three axes.
fn axis_scales(rng: &mut Rng) -> Vec3 {
    Vec3::new(
        rng.random_range(1..=8) as f32,
        rng.random_range(1..=8) as f32,
        rng.random_range(1..=8) as f32,
    )
}

/// A mesh of `shape` near the origin, outward-oriented and closed; `flatness` as for tetrahedra.
pub fn mesh(shape: MeshShape, flatness: f32, rng: &mut Rng) -> Vec<Tri> {
    let points: Vec<Vec3> = match shape {
        MeshShape::Octahedron => {
            let s = axis_scales(rng) * 2.0;
            [
                Vec3::X,
                Vec3::NEG_X,
                Vec3::Y,
                Vec3::NEG_Y,
                Vec3::Z,
                Vec3::NEG_Z,
            ]
            .map(|p| p * s)
            .to_vec()
        }
        MeshShape::Icosahedron => {
            let s = axis_scales(rng) * 2.0;
            let mut p = Vec::new();
            for a in [-1.0f32, 1.0] {
                for b in [-1.5f32, 1.5] {
                    p.push(Vec3::new(0.0, a, b));
                    p.push(Vec3::new(a, b, 0.0));
                    p.push(Vec3::new(b, 0.0, a));
                }
            }
            p.into_iter().map(|q| q * s).collect()
        }
        MeshShape::Tetrahedron | MeshShape::Sliver | MeshShape::Needle => {
            let family = match shape {
                MeshShape::Sliver => TetShape::Sliver,
                MeshShape::Needle => TetShape::Needle,
                _ => TetShape::Well,
            };
            let scale = (64.0 / flatness.clamp(1e-5, 1.0)).log2().ceil().exp2();
            loop {
                let t = tet(family, flatness, rng).map(|v| (v * scale).round());
                if orientation(&t) > 0 {
                    return FACE_VERTICES.iter().map(|f| f.map(|i| t[i])).collect();
                }
            }
        }
    };
    hull(&points)
}

/// The outward unit normal of an outward-oriented triangle (f32; for aiming only).
fn unit_normal(t: &Tri) -> Vec3 {
    (t[1] - t[0]).cross(t[2] - t[0]).normalize_or_zero()
}

/// A random unit vector.
fn random_unit(rng: &mut Rng) -> Vec3 {
    loop {
        let v = Vec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        if v.length_squared() > 0.01 && v.length_squared() <= 1.0 {
            return v.normalize();
        }
    }
}

/// A closed mesh of `shape` at `place` and a ray aimed as `aim` says. The origin is a lattice point
/// outside the mesh and the direction runs exactly to the target, so the line meets the edge or vertex
/// exactly: the edge and vertex rays come from around the line from the mesh's centre through the
/// target (most cross the surface, some only touch it), the grazing ones come in nearly within the plane of one of the two
/// triangles at an edge. The near rows then move the origin by up to `max_ulps` ulps along one axis.
pub fn case(
    shape: MeshShape,
    aim: TriAim,
    place: TriPlace,
    flatness: f32,
    max_ulps: i32,
    rng: &mut Rng,
) -> (Vec<Tri>, Ray) {
    let mesh = mesh(shape, flatness, rng);
    let size = mesh
        .iter()
        .flatten()
        .map(|p| p.abs().max_element())
        .fold(1.0f32, f32::max);
    let tri = mesh[rng.random_range(0..mesh.len())];
    let k = rng.random_range(0..3);
    let (a, b, c) = (tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]);
    // Outward from the mesh's centre through the target, turned by up to half a radian: most such rays
    // cross the surface there, even at a sliver's vertex, whose cone of inward directions is thin.
    let centre = mesh.iter().flatten().sum::<Vec3>() / (3 * mesh.len()) as f32;
    let from_centre = |target: Vec3, rng: &mut Rng| {
        let turn = *[0.0, 0.01, 0.1, 0.5]
            .get(rng.random_range(0..4))
            .unwrap_or(&0.0);
        ((target - centre).normalize_or_zero() + random_unit(rng) * turn) * size * 2.0
    };
    let (target, from) = match aim {
        TriAim::Edge | TriAim::NearEdge => {
            let m = (a + b) * 0.5;
            (m, from_centre(m, rng))
        }
        TriAim::Vertex | TriAim::NearVertex => (a, from_centre(a, rng)),
        TriAim::Grazing => {
            // Nearly along the triangle's plane, away from its third vertex, a little outside.
            let m = (a + b) * 0.5;
            let along = (m - c).normalize_or_zero() * size * 2.0;
            let lift = unit_normal(&tri) * size * 2.0 / rng.random_range(16.0..256.0);
            (m, along + lift)
        }
    };
    let mut org = (target + from).round();
    let mut s = 1.0f32;
    while !outside(&mesh, org) && s < 1e3 {
        s *= 2.0;
        org = (target + from * s).round();
    }
    let dir = target - org;
    let off = place.offset();
    let mut org = org + off;
    let mesh: Vec<Tri> = mesh.iter().map(|t| t.map(|p| p + off)).collect();
    if matches!(aim, TriAim::NearEdge | TriAim::NearVertex) {
        let scale = scale_of(mesh.iter().flatten().chain([&org]));
        org = nudge(org, scale, max_ulps, rng);
    }
    (mesh, Ray { org, dir })
}

/// Whether `p` lies strictly outside the convex, outward-oriented closed mesh.
fn outside(mesh: &[Tri], p: Vec3) -> bool {
    mesh.iter().any(|t| orientation(&[t[0], t[1], t[2], p]) < 0)
}
