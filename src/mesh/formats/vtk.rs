//! VTK unstructured grids (VTK file formats: the legacy `.vtk` and the XML `.vtu`) through `vtkio`:
//! every inline piece's points and cells, tetrahedra (type 10, 24) and triangles (type 5, 22).

use super::{MeshError, Read, Shape};
use vtkio::model::{CellType, DataSet, Piece, VertexNumbers};

/// What a VTK cell type is to tetwalk.
fn shape(t: CellType) -> Shape {
    match t {
        CellType::Tetra | CellType::QuadraticTetra => Shape::Tet,
        CellType::Triangle | CellType::QuadraticTriangle | CellType::BiquadraticTriangle => {
            Shape::Triangle
        }
        CellType::Vertex
        | CellType::PolyVertex
        | CellType::Line
        | CellType::PolyLine
        | CellType::QuadraticEdge
        | CellType::CubicLine => Shape::Ignored,
        CellType::Hexahedron | CellType::Voxel => Shape::Refused("hexahedron"),
        CellType::Wedge => Shape::Refused("wedge"),
        CellType::Pyramid => Shape::Refused("pyramid"),
        CellType::Quad | CellType::Pixel => Shape::Refused("quadrilateral"),
        CellType::TriangleStrip => Shape::Refused("triangle strip"),
        CellType::Polygon => Shape::Refused("polygon"),
        _ => Shape::Refused("cell of a type tetwalk does not walk"),
    }
}

/// A legacy file (`xml` false) or an XML one.
pub(super) fn read(bytes: &[u8], xml: bool, file: &str) -> Result<Read, MeshError> {
    let fail = |what: String| MeshError {
        place: file.to_string(),
        what,
    };
    let vtk = super::guarded("the VTK reader (vtkio)", file, || match xml {
        false => vtkio::Vtk::parse_legacy_be(bytes),
        true => vtkio::Vtk::parse_xml(bytes),
    })?
    .map_err(|e| fail(format!("not a readable VTK file: {e}")))?;
    let DataSet::UnstructuredGrid { pieces, .. } = vtk.data else {
        return Err(fail("not an unstructured grid (DATASET UNSTRUCTURED_GRID, or a .vtu file): tetwalk walks tetrahedral meshes".into()));
    };
    let mut read = Read {
        names: ["point", "cell", "cell"],
        ..Read::default()
    };
    let mut cells_before = 0u64;
    for (k, piece) in pieces.into_iter().enumerate() {
        let Piece::Inline(p) = piece else {
            return Err(fail(format!(
                "piece {k} lives in another file (a parallel .pvtu): give tetwalk that piece's own file"
            )));
        };
        let first = read.points.len() as u64;
        let coords: Vec<f64> = p
            .points
            .cast_into::<f64>()
            .ok_or_else(|| fail(format!("piece {k}: its points are not numbers")))?;
        if !coords.len().is_multiple_of(3) {
            return Err(fail(format!(
                "piece {k}: {} point coordinates, not a multiple of 3",
                coords.len()
            )));
        }
        for (i, c) in coords.chunks_exact(3).enumerate() {
            read.points.push([c[0], c[1], c[2]]);
            read.point_ids.push(first + i as u64);
        }
        let count = read.points.len() as u64;
        // Each cell's points: a legacy list (`n i_1 … i_n` per cell) or XML connectivity and offsets.
        let mut cells: Vec<Vec<u64>> = Vec::with_capacity(p.cells.types.len());
        match p.cells.cell_verts {
            VertexNumbers::Legacy { vertices, .. } => {
                let mut rest = &vertices[..];
                while let Some((&n, tail)) = rest.split_first() {
                    let (cell, tail) = tail.split_at_checked(n as usize).ok_or_else(|| {
                        fail(format!(
                            "piece {k}: cell {} names {n} points, past the end of the list",
                            cells.len()
                        ))
                    })?;
                    cells.push(cell.iter().map(|&i| i as u64).collect());
                    rest = tail;
                }
            }
            VertexNumbers::XML {
                connectivity,
                offsets,
            } => {
                let mut start = 0usize;
                for &end in &offsets {
                    let cell = connectivity.get(start..end as usize).ok_or_else(|| {
                        fail(format!(
                            "piece {k}: cell {} ends at offset {end}, outside its connectivity",
                            cells.len()
                        ))
                    })?;
                    cells.push(cell.to_vec());
                    start = end as usize;
                }
            }
        }
        if cells.len() != p.cells.types.len() {
            return Err(fail(format!(
                "piece {k}: {} cells but {} cell types",
                cells.len(),
                p.cells.types.len()
            )));
        }
        for (i, (cell, &t)) in cells.iter().zip(&p.cells.types).enumerate() {
            let id = cells_before + i as u64;
            let at = || format!("{file}, cell {id}");
            let nodes: Vec<u32> = cell
                .iter()
                .map(|&v| {
                    (v < count - first)
                        .then_some((first + v) as u32)
                        .ok_or_else(|| MeshError {
                            place: at(),
                            what: format!(
                                "point {v} out of range (the piece has {} points)",
                                count - first
                            ),
                        })
                })
                .collect::<Result<_, _>>()?;
            read.take(shape(t), &nodes, id, &at)?;
        }
        cells_before += cells.len() as u64;
    }
    Ok(read)
}
