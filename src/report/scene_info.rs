//! `tetwalk scene info`'s tables: seed 000 Table 3 and seed 003 Table 4 of a scene, its flatness, and
//! seed 001's octree over its constrained faces.

use crate::engine::info::{OctreeInfo, SceneCheck, SceneInfo, Validity};

impl SceneCheck {
    /// `scene check`'s line: a tetrahedralization and its counts, or what is wrong.
    pub(crate) fn line(&self) -> String {
        let scene = &self.scene;
        match &self.checked {
            Validity::Valid {
                points,
                tetrahedra,
                summary: s,
                constrained,
            } => format!(
                "{scene}: a tetrahedralization: {points} points, {tetrahedra} tetrahedra, {} interior and {} boundary faces ({} boundary {}), {constrained} constrained faces",
                s.interior_faces,
                s.boundary_faces,
                s.boundary_components,
                if s.boundary_components == 1 {
                    "component"
                } else {
                    "components"
                },
            ),
            Validity::Invalid { error } => format!("{scene}: not a tetrahedralization: {error}"),
        }
    }
}

impl OctreeInfo {
    pub(crate) fn markdown(&self) -> String {
        let mb = |b: usize| b as f64 / 1e6;
        let total: usize = self.bytes.iter().map(|(_, b)| b).sum();
        let mut s = format!(
            "seed 001's octree over the {} constrained faces, depth {}, leaf capacity {}\n\n\
             | | leaves, unconstrained | constrained | ratio | neighbours per cell | bytes per cell |\n|---|---|---|---|---|---|\n\
             | this scene | {} | {} | {:.0}% | {:.1} | {:.1} |\n\
             | seed 001's bunny (69k triangles, depth 8) | 69k | 83k | 120% | about 7 | about 44 |\n\n| MB | ",
            self.triangles,
            self.settings.depth,
            self.settings.capacity,
            self.leaves_unconstrained,
            self.leaves,
            100.0 * self.leaves as f64 / self.leaves_unconstrained.max(1) as f64,
            self.mean_neighbors,
            self.bytes_per_cell
        );
        for (n, _) in &self.bytes {
            s += &format!("{n} | ");
        }
        s += "total |\n|---|---|---|---|---|---|\n| this scene | ";
        for (_, b) in &self.bytes {
            s += &format!("{:.2} | ", mb(*b));
        }
        s += &format!(
            "{:.2} |\n| seed 001's bunny (Table 3) | 1.5 | 3.6 | 12.2 | 1.3 | 18.6 |\n",
            mb(total)
        );
        s
    }
}

/// Seed 000 Table 3, the BUNNY column: tetrahedra, occlusive faces, non-occlusive faces, memory (MB).
pub(crate) const SEED000_TABLE3_BUNNY: (usize, usize, usize, f64) =
    (682_733, 222_775, 1_142_650, 62.0);

impl SceneInfo {
    pub(crate) fn markdown(&self) -> String {
        let (t, occl, other, mb) = SEED000_TABLE3_BUNNY;
        let tet80 = self
            .layout_bytes
            .iter()
            .find(|(n, _)| n == "Tet80")
            .map_or("-".into(), |(_, b)| format!("{:.1}", *b as f64 / 1e6));
        let mut s = format!(
            "| | points | tetrahedra | constrained faces | other faces | Tet80 MB |\n|---|---|---|---|---|---|\n| this scene | {} | {} | {} | {} | {tet80} |\n| seed 000's BUNNY (Table 3) | - | {t} | {occl} | {other} | {mb} |\n\n",
            self.points, self.tetrahedra, self.constrained_faces, self.other_faces
        );
        s += "| layout | MB |\n|---|---|\n";
        for (n, b) in &self.layout_bytes {
            s += &format!("| {n} | {:.2} |\n", *b as f64 / 1e6);
        }
        s += "\n| min dihedral | tetrahedra |\n|---|---|\n";
        for (k, n) in self
            .min_dihedral_deg_5
            .iter()
            .enumerate()
            .filter(|(_, n)| **n > 0)
        {
            s += &format!("| {}–{}° | {n} |\n", 5 * k, 5 * k + 5);
        }
        s += "\n| volume / longest edge³ | tetrahedra |\n|---|---|\n";
        for (k, n) in self
            .volume_ratio_decades
            .iter()
            .enumerate()
            .filter(|(_, n)| **n > 0)
        {
            s += &format!("| 1e-{}–1e-{} | {n} |\n", k + 1, k);
        }
        if let Some(o) = &self.octree {
            s += "\n";
            s += &o.markdown();
        }
        s
    }
}
