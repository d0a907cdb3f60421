//! Reordering for cache locality (seed 003 §5): tetrahedra grouped by region (connected through faces
//! that are not constrained), then sorted along a 3-D Hilbert curve by centroid; points by position.

use super::{HULL, Mesh, bounds};
use glam::Vec3;

/// Hilbert keys of points quantised to 16 bits per axis over `lo..hi`.
fn hilbert_key(p: Vec3, lo: Vec3, hi: Vec3) -> u64 {
    let q = ((p - lo) / (hi - lo).max(Vec3::splat(f32::MIN_POSITIVE)) * 65535.0)
        .clamp(Vec3::ZERO, Vec3::splat(65535.0));
    lindel::hilbert_encode([q.x as u16, q.y as u16, q.z as u16])
}

/// Region of each tetrahedron: connected components across faces that are neither constrained nor on
/// the boundary.
pub fn regions(mesh: &Mesh) -> Vec<u32> {
    let mut region = vec![u32::MAX; mesh.tets.len()];
    let mut next = 0;
    let mut stack = Vec::new();
    for s in 0..mesh.tets.len() {
        if region[s] != u32::MAX {
            continue;
        }
        region[s] = next;
        stack.push(s as u32);
        while let Some(t) = stack.pop() {
            for f in 0..4 {
                let nb = mesh.neighbors[t as usize][f];
                if nb != HULL && !mesh.is_constrained(t, f) && region[nb as usize] == u32::MAX {
                    region[nb as usize] = next;
                    stack.push(nb);
                }
            }
        }
        next += 1;
    }
    region
}

/// The same mesh reordered as §5 does: points in Hilbert order; tetrahedra by region (regions in the
/// Hilbert order of their first tetrahedron), then by the Hilbert order of their centroids. Vertex
/// order inside each tetrahedron, and so its orientation and face numbering, is kept.
pub fn hilbert_sorted(mesh: &Mesh) -> Mesh {
    let (lo, hi) = bounds(&mesh.points);
    let mut point_order: Vec<u32> = (0..mesh.points.len() as u32).collect();
    point_order.sort_by_key(|&i| (hilbert_key(mesh.points[i as usize], lo, hi), i));
    let mut new_point = vec![0u32; mesh.points.len()];
    for (n, &o) in point_order.iter().enumerate() {
        new_point[o as usize] = n as u32;
    }
    let keys: Vec<u64> = (0..mesh.tets.len() as u32)
        .map(|t| hilbert_key(mesh.tet(t).iter().sum::<Vec3>() / 4.0, lo, hi))
        .collect();
    let region = regions(mesh);
    let mut region_key = vec![u64::MAX; region.iter().max().map_or(0, |&r| r as usize + 1)];
    for (t, &r) in region.iter().enumerate() {
        region_key[r as usize] = region_key[r as usize].min(keys[t]);
    }
    let mut tet_order: Vec<u32> = (0..mesh.tets.len() as u32).collect();
    tet_order.sort_by_key(|&t| {
        (
            region_key[region[t as usize] as usize],
            region[t as usize],
            keys[t as usize],
            t,
        )
    });
    let mut new_tet = vec![0u32; mesh.tets.len()];
    for (n, &o) in tet_order.iter().enumerate() {
        new_tet[o as usize] = n as u32;
    }
    let remap_tet = |x: u32| if x == HULL { HULL } else { new_tet[x as usize] };
    let mut out = Mesh {
        points: point_order
            .iter()
            .map(|&o| mesh.points[o as usize])
            .collect(),
        tets: tet_order
            .iter()
            .map(|&o| mesh.tets[o as usize].map(|v| new_point[v as usize]))
            .collect(),
        neighbors: tet_order
            .iter()
            .map(|&o| mesh.neighbors[o as usize].map(remap_tet))
            .collect(),
        mirror: tet_order.iter().map(|&o| mesh.mirror[o as usize]).collect(),
        constrained: tet_order
            .iter()
            .map(|&o| mesh.constrained[o as usize])
            .collect(),
        flipped: mesh.flipped,
        cells: Vec::new(),
    };
    out.cells = crate::mesh::cells(
        &out.points,
        &out.tets,
        &out.neighbors,
        &out.mirror,
        &out.constrained,
    );
    out
}
