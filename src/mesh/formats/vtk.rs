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
    if xml {
        compressed_sizes(bytes).map_err(fail)?;
    }
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

/// Most bytes the compressed arrays of a `.vtu` file may claim to hold once decompressed, together
/// (tetwalk's memory budget): `vtkio` allocates what a block header claims before it decompresses.
const MAX_DECOMPRESSED: u128 = 8 << 30;

/// The value of attribute `name` in the tag `tag` (the text from `<` to `>`).
fn attribute<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let at = tag.find(&format!(" {name}=\""))? + name.len() + 3;
    tag[at..].split('"').next()
}

/// Standard base64, as far as it decodes (padding and whitespace end it).
fn base64(text: &[u8]) -> Vec<u8> {
    let value = |c: u8| match c {
        b'A'..=b'Z' => Some(c - b'A'),
        b'a'..=b'z' => Some(c - b'a' + 26),
        b'0'..=b'9' => Some(c - b'0' + 52),
        b'+' => Some(62),
        b'/' => Some(63),
        _ => None,
    };
    let (mut out, mut acc, mut bits) = (Vec::new(), 0u32, 0);
    for v in text.iter().map_while(|&c| value(c)) {
        acc = acc << 6 | v as u32;
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
        }
    }
    out
}

/// Refuse a `.vtu` file whose compressed arrays claim more than [`MAX_DECOMPRESSED`] bytes, or more
/// blocks than the file could hold, before `vtkio` allocates what they claim.
fn compressed_sizes(bytes: &[u8]) -> Result<(), String> {
    let text = String::from_utf8_lossy(bytes);
    let Some(start) = text.find("<VTKFile") else {
        return Ok(());
    };
    let head = &text[start..start + text[start..].find('>').unwrap_or(0)];
    if attribute(head, "compressor").is_none_or(str::is_empty) {
        return Ok(());
    }
    let word = match attribute(head, "header_type") {
        Some("UInt64") => 8,
        _ => 4,
    };
    let big = attribute(head, "byte_order") == Some("BigEndian");
    let number = |b: &[u8]| -> u128 {
        let mut w = [0u8; 8];
        w[..b.len()].copy_from_slice(b);
        if big {
            w[..b.len()].reverse();
        }
        u64::from_le_bytes(w) as u128
    };
    // The appended data, after its `_`, raw or in base64.
    let appended = text.find("<AppendedData").map(|a| {
        let tag = &text[a..a + text[a..].find('>').unwrap_or(0)];
        let raw = attribute(tag, "encoding") != Some("base64");
        let from = a + text[a..].find('_').map_or(0, |u| u + 1);
        (from, raw)
    });
    let mut claimed = 0u128;
    let mut at = 0;
    while let Some(i) = text[at..].find("<DataArray") {
        let open = at + i;
        let close = open + text[open..].find('>').unwrap_or(0);
        let tag = &text[open..close];
        at = close.max(open + 1);
        let header = match attribute(tag, "format") {
            Some("binary") => {
                let body = text[close + 1..].trim_start();
                base64(&body.as_bytes()[..body.len().min(4 * 3 * word)])
            }
            Some("appended") => match (
                appended,
                attribute(tag, "offset").and_then(|o| o.parse::<usize>().ok()),
            ) {
                (Some((from, raw)), Some(offset)) => {
                    let data = bytes.get(from + offset..).unwrap_or(&[]);
                    match raw {
                        true => data[..data.len().min(3 * word)].to_vec(),
                        false => base64(&data[..data.len().min(4 * 3 * word)]),
                    }
                }
                _ => continue,
            },
            _ => continue,
        };
        if header.len() < 3 * word {
            continue;
        }
        let [blocks, size, last] = [0, 1, 2].map(|k| number(&header[k * word..(k + 1) * word]));
        if blocks * word as u128 > bytes.len() as u128 {
            return Err(format!(
                "a DataArray's compression header claims {blocks} blocks, more than the file could hold ({} bytes)",
                bytes.len()
            ));
        }
        claimed += size * blocks.saturating_sub(1) + last;
        if claimed > MAX_DECOMPRESSED {
            return Err(format!(
                "its compressed arrays claim {claimed} bytes once decompressed, more than the {MAX_DECOMPRESSED} tetwalk reads (a corrupt compression header?)"
            ));
        }
    }
    Ok(())
}
