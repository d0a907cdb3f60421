//! What seed 000 Table 3 and seed 003 Table 4 report of a scene, how flat its tetrahedra are, and
//! seed 001's octree over its constrained faces (Tables 1 and 3), measured (`tetwalk scene info`).

use crate::mesh::Mesh;
use crate::mesh::layout::Layout;
use crate::tet::{EDGES, FACE_VERTICES};

/// Whether a scene loads as a tetrahedralization (`tetwalk scene check`): its counts and what it is
/// made of, or what is wrong, and where.
#[derive(Clone, Debug, serde::Serialize)]
pub(crate) struct SceneCheck {
    pub(crate) scene: String,
    pub(crate) valid: bool,
    #[serde(flatten)]
    pub(crate) checked: Validity,
}

/// A scene checked: a tetrahedralization, or not.
#[derive(Clone, Debug, serde::Serialize)]
#[serde(untagged)]
pub(crate) enum Validity {
    Valid {
        points: usize,
        tetrahedra: usize,
        summary: crate::mesh::valid::Summary,
        /// Its constrained faces.
        #[serde(skip)]
        constrained: usize,
    },
    /// What is wrong, and where (the loader's error).
    Invalid { error: String },
}

impl SceneCheck {
    /// The scene `scene` as it loaded (`loaded`), checked; an error where a loaded mesh fails the
    /// rules (loading checks them).
    pub(crate) fn of(
        scene: &str,
        loaded: Result<crate::scenes::Loaded, crate::mesh::MeshError>,
    ) -> Result<SceneCheck, String> {
        let checked = match loaded.map(|s| s.mesh) {
            Ok(m) => Validity::Valid {
                points: m.points.len(),
                tetrahedra: m.tets.len(),
                summary: crate::mesh::valid::check(&m.points, &m.tets, &m.neighbors)
                    .map_err(|(_, what)| what)?,
                constrained: m.constrained_faces(),
            },
            Err(e) => Validity::Invalid {
                error: e.to_string(),
            },
        };
        Ok(SceneCheck {
            scene: scene.to_string(),
            valid: matches!(checked, Validity::Valid { .. }),
            checked,
        })
    }
}

/// Counts of a scene.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct SceneInfo {
    pub points: usize,
    pub tetrahedra: usize,
    /// Distinct faces that are constrained (occlusive): model and box triangles.
    pub constrained_faces: usize,
    /// Distinct faces that are not.
    pub other_faces: usize,
    /// Bytes of the tetrahedra in each layout (Tet80 is Maria et al.'s), points not included.
    pub layout_bytes: Vec<(String, usize)>,
    /// Tetrahedra per minimum dihedral angle, in 5° bins from 0°.
    pub min_dihedral_deg_5: Vec<usize>,
    /// Tetrahedra per decade of volume / (longest edge)³: bin k holds [10^-(k+1), 10^-k).
    pub volume_ratio_decades: Vec<usize>,
    /// Seed 001's octree over the constrained faces (Tables 1 and 3, §5.1), if it could be built.
    pub(crate) octree: Option<OctreeInfo>,
}

/// What seed 001 reports of its octrees: leaves with and without the regularity constraint (Table
/// 1), neighbours and bytes per cell (§5.1), and the four arrays' sizes (Table 3).
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct OctreeInfo {
    pub(crate) settings: crate::octree::Settings,
    pub(crate) triangles: usize,
    pub(crate) leaves_unconstrained: usize,
    pub(crate) leaves: usize,
    /// Mean neighbour links per leaf.
    pub(crate) mean_neighbors: f64,
    /// Mean bytes of a leaf in eq. 3: four words and its neighbour addresses.
    pub(crate) bytes_per_cell: f64,
    /// Bytes of the cube map, the octree (eq. 3), the triangles (three f32 points per reference) and
    /// the boxes.
    pub(crate) bytes: [(String, usize); 4],
}

impl OctreeInfo {
    pub(crate) fn of(mesh: &Mesh, settings: crate::octree::Settings) -> Option<OctreeInfo> {
        let (tris, _) = crate::mesh::surface::scene_triangles(mesh, &vec![false; mesh.tets.len()]);
        let o = crate::octree::Octree::build(&tris, settings).ok()?;
        let [octree, triangles, boxes, cube_map] = o.bytes();
        Some(OctreeInfo {
            settings,
            triangles: tris.len(),
            leaves_unconstrained: o.unconstrained_leaves,
            leaves: o.leaves.len(),
            mean_neighbors: o.mean_neighbors(),
            bytes_per_cell: octree as f64 / o.leaves.len() as f64,
            bytes: [
                ("cube map".into(), cube_map),
                ("octree".into(), octree),
                ("triangles".into(), triangles),
                ("boxes".into(), boxes),
            ],
        })
    }
}

/// The smallest dihedral angle of a tetrahedron, in degrees (f64).
pub(crate) fn min_dihedral(t: &crate::tet::Tet) -> f64 {
    let p = t.map(|v| v.as_dvec3());
    let normal = |f: usize| {
        let [a, b, c] = FACE_VERTICES[f].map(|i| p[i]);
        (b - a).cross(c - a).normalize()
    };
    // The dihedral angle at the edge (i, j) is between the two faces containing it, opposite k and l.
    EDGES
        .iter()
        .map(|&[i, j]| {
            let others: Vec<usize> = (0..4).filter(|&x| x != i && x != j).collect();
            let cos = -normal(others[0]).dot(normal(others[1]));
            cos.clamp(-1.0, 1.0).acos().to_degrees()
        })
        .fold(f64::INFINITY, f64::min)
}

impl SceneInfo {
    /// The scene's counts, with seed 001's octree over its constrained faces built as `octree` says.
    pub fn of(mesh: &Mesh, octree: crate::octree::Settings) -> SceneInfo {
        let constrained = mesh.constrained_faces();
        let other = mesh.faces_once().count() - constrained;
        let mut dihedral = vec![0; 19];
        let mut decades = vec![0; 12];
        for t in 0..mesh.tets.len() as u32 {
            let tet = mesh.tet(t);
            dihedral[((min_dihedral(&tet) / 5.0) as usize).min(18)] += 1;
            let p = tet.map(|v| v.as_dvec3());
            let vol = (p[1] - p[0]).dot((p[2] - p[0]).cross(p[3] - p[0])).abs() / 6.0;
            let longest = EDGES
                .iter()
                .map(|&[i, j]| (p[j] - p[i]).length())
                .fold(0.0, f64::max);
            let ratio = vol / longest.powi(3);
            decades[((-ratio.log10()).floor().max(0.0) as usize).min(11)] += 1;
        }
        SceneInfo {
            points: mesh.points.len(),
            tetrahedra: mesh.tets.len(),
            constrained_faces: constrained,
            other_faces: other,
            layout_bytes: Layout::BYTES
                .iter()
                .map(|(n, b)| (n.to_string(), b * mesh.tets.len()))
                .collect(),
            min_dihedral_deg_5: dihedral,
            volume_ratio_decades: decades,
            octree: OctreeInfo::of(mesh, octree),
        }
    }
}
