//! Users' own meshes: Gmsh `.msh` (4.1 through `mshio`; 2.2, which no crate reads, here), VTK
//! unstructured grids (`.vtk` and `.vtu`, through `vtkio`) and MEDIT `.mesh`: their tetrahedra, and
//! their triangles (boundary triangles, or the surfaces of physical groups) as the constrained faces.
//! Every one is checked as TetGen's files are ([`Mesh::build_at`]), errors naming the file and the
//! element.

mod gmsh;
mod medit;
mod vtk;

use super::{Faces, Item, Mesh, MeshError, RawMesh};
use glam::Vec3;
use std::path::Path;

/// A mesh file format tetwalk reads besides TetGen's, by its extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Gmsh,
    /// A legacy `.vtk` file.
    Vtk,
    /// An XML `.vtu` file.
    Vtu,
    Medit,
}

impl Format {
    /// The format of `path`, by its extension (`.msh`, `.vtk`, `.vtu`, `.mesh`).
    pub(crate) fn of(path: &Path) -> Option<Format> {
        match path.extension()?.to_str()? {
            "msh" => Some(Format::Gmsh),
            "vtk" => Some(Format::Vtk),
            "vtu" => Some(Format::Vtu),
            "mesh" => Some(Format::Medit),
            _ => None,
        }
    }
}

/// What an element of a file is to tetwalk.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Shape {
    /// A tetrahedron (its first four nodes, the corners, for a second-order one).
    Tet,
    /// A triangle: a constrained face (its first three nodes).
    Triangle,
    /// Points and lines: nothing to walk.
    Ignored,
    /// Anything else: a mesh tetwalk cannot walk (hexahedra, prisms, pyramids, quadrilaterals).
    Refused(&'static str),
}

/// A file as read: its points (as written, rounded to f32 when the mesh is built), its tetrahedra and
/// triangles as point indices, and each one's name in the file (its tag or number) for errors.
#[derive(Default)]
struct Read {
    points: Vec<[f64; 3]>,
    point_ids: Vec<u64>,
    tets: Vec<[u32; 4]>,
    tet_ids: Vec<u64>,
    triangles: Vec<[u32; 3]>,
    triangle_ids: Vec<u64>,
    /// What the file calls a point, a tetrahedron and a triangle: `["node", "element", "element"]`, …
    names: [&'static str; 3],
}

impl Read {
    /// Take an element of `shape` with `nodes` (point indices), named `id`; `at` names it in an error.
    fn take(
        &mut self,
        shape: Shape,
        nodes: &[u32],
        id: u64,
        at: &dyn Fn() -> String,
    ) -> Result<(), MeshError> {
        let need = match shape {
            Shape::Tet => 4,
            Shape::Triangle => 3,
            Shape::Ignored => return Ok(()),
            Shape::Refused(what) => {
                return Err(MeshError {
                    place: at(),
                    what: format!(
                        "a {what}: tetwalk walks tetrahedral meshes (tetrahedra, and triangles as their constrained faces)"
                    ),
                });
            }
        };
        if nodes.len() < need {
            return Err(MeshError {
                place: at(),
                what: format!(
                    "{} nodes, fewer than the {need} corners of its shape",
                    nodes.len()
                ),
            });
        }
        match shape {
            Shape::Tet => {
                self.tets.push([nodes[0], nodes[1], nodes[2], nodes[3]]);
                self.tet_ids.push(id);
            }
            _ => {
                self.triangles.push([nodes[0], nodes[1], nodes[2]]);
                self.triangle_ids.push(id);
            }
        }
        Ok(())
    }
}

/// `read` (a third-party reader on a user's file), its panic turned into an error: `vtkio` panics on
/// some malformed `.vtu` files (a DataArray longer than its data; `tests/formats.rs` keeps one), and
/// a bad file gets an error naming it, never a panic. The panic's own message is kept from standard
/// error while the reader runs.
fn guarded<T>(reader: &str, file: &str, read: impl FnOnce() -> T) -> Result<T, MeshError> {
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let got = std::panic::catch_unwind(std::panic::AssertUnwindSafe(read));
    std::panic::set_hook(hook);
    got.map_err(|p| MeshError {
        place: file.to_string(),
        what: format!(
            "{reader} failed on it ({}): the file is malformed",
            p.downcast_ref::<String>()
                .map(String::as_str)
                .or_else(|| p.downcast_ref::<&str>().copied())
                .unwrap_or("a panic")
        ),
    })
}

/// Load a mesh of `format` from `path` ([`parse`]).
pub(crate) fn load(path: &Path, format: Format, faces: Faces) -> Result<Mesh, MeshError> {
    let file = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| MeshError {
        place: file.clone(),
        what: format!("cannot read: {e}"),
    })?;
    parse(&bytes, format, faces, &file)
}

/// A mesh of `format` from a file's bytes (`file` names it in errors): its tetrahedra, and its
/// triangles as constrained faces (which must be there unless `faces` is [`Faces::Optional`]).
/// Coordinates are rounded to the nearest f32.
pub fn parse(bytes: &[u8], format: Format, faces: Faces, file: &str) -> Result<Mesh, MeshError> {
    let fail = |what: String| MeshError {
        place: file.to_string(),
        what,
    };
    let read = match format {
        Format::Gmsh => gmsh::read(bytes, file)?,
        Format::Vtk | Format::Vtu => vtk::read(bytes, format == Format::Vtu, file)?,
        Format::Medit => {
            let text =
                std::str::from_utf8(bytes).map_err(|e| fail(format!("not a text file: {e}")))?;
            medit::read(text, file)?
        }
    };
    if read.tets.is_empty() {
        return Err(fail("holds no tetrahedra".into()));
    }
    if read.triangles.is_empty() && faces == Faces::Required {
        return Err(fail(
            "holds no triangles: a scene's constrained faces (its surfaces) come from its boundary triangles or the surfaces of its physical groups; to walk a mesh without surfaces, ask for it (--no-faces)".into(),
        ));
    }
    let Read {
        points,
        point_ids,
        tets,
        tet_ids,
        triangles,
        triangle_ids,
        names: [point, tet, triangle],
    } = read;
    let raw = RawMesh {
        points: points
            .iter()
            .map(|p| Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32))
            .collect(),
        tets,
        neighbors: None,
        constrained: triangles,
    };
    Mesh::build_at(raw, &|item| match item {
        Item::Point(i) => format!("{file}, {point} {}", point_ids[i]),
        Item::Tet(i) | Item::Neighbors(i) => format!("{file}, {tet} {}", tet_ids[i]),
        Item::Constrained(i) => format!("{file}, {triangle} {}", triangle_ids[i]),
    })
}
