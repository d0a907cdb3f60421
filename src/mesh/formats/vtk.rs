//! VTK unstructured grids (VTK file formats: the legacy `.vtk` and the XML `.vtu`): legacy ASCII
//! files (versions up to 5.1) read here, every error naming its line; binary legacy and XML files
//! through `vtkio`: every inline piece's points and cells, tetrahedra (type 10, 24) and triangles
//! (type 5, 22, 34).

use super::{MeshError, Read, Shape};
use vtkio::model::{DataSet, Piece, VertexNumbers};

/// What a VTK cell type (its number, `vtkCellType.h`) is to tetwalk.
fn shape(t: u8) -> Shape {
    match t {
        10 | 24 => Shape::Tet,
        5 | 22 | 34 => Shape::Triangle,
        1 | 2 | 3 | 4 | 21 | 35 => Shape::Ignored,
        11 | 12 => Shape::Refused("hexahedron"),
        13 => Shape::Refused("wedge"),
        14 => Shape::Refused("pyramid"),
        8 | 9 => Shape::Refused("quadrilateral"),
        6 => Shape::Refused("triangle strip"),
        7 => Shape::Refused("polygon"),
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
    } else if let Some(text) = legacy_ascii(bytes) {
        return read_ascii(text, file);
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
            read.take(shape(t as u8), &nodes, id, &at)?;
        }
        cells_before += cells.len() as u64;
    }
    Ok(read)
}

/// The text of a legacy ASCII file (its third line `ASCII`), or `None` for another (binary, XML).
fn legacy_ascii(bytes: &[u8]) -> Option<&str> {
    let text = std::str::from_utf8(bytes).ok()?;
    (text.lines().nth(2)?.trim() == "ASCII").then_some(text)
}

/// The words of a text with their line numbers (from 1).
struct Words<'a> {
    lines: std::iter::Peekable<std::iter::Enumerate<std::str::Lines<'a>>>,
    line: std::vec::IntoIter<&'a str>,
    /// The line of the last word taken.
    at: usize,
    file: &'a str,
}

impl<'a> Words<'a> {
    fn error(&self, what: String) -> MeshError {
        MeshError {
            place: format!("{} line {}", self.file, self.at),
            what,
        }
    }

    /// The next word, or an error saying the file ends where `what` was expected.
    fn next(&mut self, what: &str) -> Result<&'a str, MeshError> {
        loop {
            if let Some(w) = self.line.next() {
                return Ok(w);
            }
            let Some((n, l)) = self.lines.next() else {
                return Err(self.error(format!("the file ends where {what} was expected")));
            };
            self.at = n + 1;
            self.line = l.split_ascii_whitespace().collect::<Vec<_>>().into_iter();
        }
    }

    /// The next word as a count or index (0 or more), or an error naming it.
    fn count(&mut self, what: &str) -> Result<u64, MeshError> {
        let w = self.next(what)?;
        w.parse::<u64>().map_err(|_| {
            self.error(format!(
                "'{}' is not {what} (an integer, 0 or more)",
                w.chars().take(40).collect::<String>()
            ))
        })
    }

    /// The next word as a number (`nan` and `inf` too: the mesh refuses them, naming the point).
    fn number(&mut self, what: &str) -> Result<f64, MeshError> {
        let w = self.next(what)?;
        w.parse::<f64>().map_err(|_| {
            self.error(format!(
                "'{}' is not {what} (a number)",
                w.chars().take(40).collect::<String>()
            ))
        })
    }

    /// Every word left on the current line.
    fn rest_of_line(&mut self) -> Vec<&'a str> {
        self.line.by_ref().collect()
    }
}

/// Most entries a count may announce: one per two bytes of the file (an entry and a separator).
fn bounded(w: &Words, n: u64, what: &str, text: &str) -> Result<usize, MeshError> {
    if n > text.len() as u64 / 2 {
        return Err(w.error(format!(
            "announces {n} {what}, more than the file ({} bytes) could hold",
            text.len()
        )));
    }
    Ok(n as usize)
}

/// A legacy ASCII unstructured grid (VTK file formats, "Simple Legacy Formats"): `POINTS n type` and
/// 3n numbers; `CELLS n size` and the cells (`k i_1 … i_k` each, or version 5.1's `OFFSETS` and
/// `CONNECTIVITY` arrays); `CELL_TYPES n` and n types; what follows them (attribute data) is not read.
fn read_ascii(text: &str, file: &str) -> Result<Read, MeshError> {
    let mut w = Words {
        lines: text.lines().enumerate().peekable(),
        line: Vec::new().into_iter(),
        at: 0,
        file,
    };
    // The version line, the title and ASCII: three lines, whatever they hold.
    for _ in 0..3 {
        if let Some((n, _)) = w.lines.next() {
            w.at = n + 1;
        }
    }
    let dataset = (w.next("DATASET")?, w.next("the dataset's kind")?);
    if dataset != ("DATASET", "UNSTRUCTURED_GRID") {
        return Err(w.error(format!(
            "'{} {}': not an unstructured grid (DATASET UNSTRUCTURED_GRID): tetwalk walks tetrahedral meshes",
            dataset.0, dataset.1
        )));
    }
    let mut read = Read {
        names: ["point", "cell", "cell"],
        ..Read::default()
    };
    let mut cells: Option<Vec<Vec<u64>>> = None;
    let mut types: Option<Vec<u8>> = None;
    while read.points.is_empty() || cells.is_none() || types.is_none() {
        let Ok(key) = w.next("POINTS, CELLS or CELL_TYPES") else {
            let missing = [
                ("POINTS", read.points.is_empty()),
                ("CELLS", cells.is_none()),
                ("CELL_TYPES", types.is_none()),
            ];
            let missing: Vec<&str> = missing.iter().filter(|m| m.1).map(|m| m.0).collect();
            return Err(w.error(format!("the file ends without {}", missing.join(", "))));
        };
        match key {
            "POINTS" => {
                let n = w.count("the number of points")?;
                let n = bounded(&w, n, "points", text)?;
                w.rest_of_line();
                for i in 0..n {
                    let what = format!("point {i}'s coordinates (POINTS announces {n})");
                    let p = [w.number(&what)?, w.number(&what)?, w.number(&what)?];
                    read.points.push(p);
                    read.point_ids.push(i as u64);
                }
            }
            "CELLS" => {
                let n = w.count("the number of cells")?;
                let n = bounded(&w, n, "cells", text)?;
                let size = w.count("the size of the cell list")?;
                let size = bounded(&w, size, "entries", text)?;
                w.rest_of_line();
                let mut list = Vec::with_capacity(n);
                if w.lines
                    .peek()
                    .is_some_and(|(_, l)| l.trim_start().starts_with("OFFSETS"))
                {
                    // Version 5.1: `n` is the number of offsets (cells + 1), `size` the connectivity's.
                    w.next("OFFSETS")?;
                    w.rest_of_line();
                    let offsets = (0..n)
                        .map(|k| w.count(&format!("offset {k} (CELLS announces {n})")))
                        .collect::<Result<Vec<_>, _>>()?;
                    if w.next("CONNECTIVITY")? != "CONNECTIVITY" {
                        return Err(w.error("CONNECTIVITY was expected after the offsets".into()));
                    }
                    w.rest_of_line();
                    let points = (0..size)
                        .map(|k| {
                            w.count(&format!("connectivity entry {k} (CELLS announces {size})"))
                        })
                        .collect::<Result<Vec<_>, _>>()?;
                    for (k, pair) in offsets.windows(2).enumerate() {
                        let cell = points.get(pair[0] as usize..pair[1] as usize).ok_or_else(|| {
                            w.error(format!(
                                "cell {k}'s offsets {}..{} lie outside the {size} connectivity entries",
                                pair[0], pair[1]
                            ))
                        })?;
                        list.push(cell.to_vec());
                    }
                } else {
                    let mut taken = 0usize;
                    for k in 0..n {
                        let what = format!("cell {k} (CELLS announces {n} cells, {size} entries)");
                        let m = w.count(&what)? as usize;
                        taken = taken.saturating_add(1).saturating_add(m);
                        if taken > size {
                            return Err(w.error(format!(
                                "cell {k} names {m} points, past the {size} entries CELLS announces"
                            )));
                        }
                        list.push((0..m).map(|_| w.count(&what)).collect::<Result<_, _>>()?);
                    }
                }
                cells = Some(list);
            }
            "CELL_TYPES" => {
                let n = w.count("the number of cell types")?;
                let n = bounded(&w, n, "cell types", text)?;
                let t = (0..n)
                    .map(|k| {
                        let v = w.count(&format!("cell {k}'s type (CELL_TYPES announces {n})"))?;
                        u8::try_from(v).map_err(|_| w.error(format!("{v} is not a cell type")))
                    })
                    .collect::<Result<Vec<_>, _>>()?;
                types = Some(t);
            }
            "POINT_DATA" | "CELL_DATA" | "FIELD" | "METADATA" => {
                return Err(w.error(format!(
                    "{key} before POINTS, CELLS and CELL_TYPES were all read"
                )));
            }
            other => {
                return Err(w.error(format!(
                    "'{}' where POINTS, CELLS or CELL_TYPES was expected",
                    other.chars().take(40).collect::<String>()
                )));
            }
        }
    }
    let (cells, types) = (cells.unwrap_or_default(), types.unwrap_or_default());
    if cells.len() != types.len() {
        return Err(MeshError {
            place: file.to_string(),
            what: format!("{} cells but {} cell types", cells.len(), types.len()),
        });
    }
    let count = read.points.len() as u64;
    for (i, (cell, &t)) in cells.iter().zip(&types).enumerate() {
        let at = || format!("{file}, cell {i}");
        let nodes: Vec<u32> = cell
            .iter()
            .map(|&v| {
                (v < count).then_some(v as u32).ok_or_else(|| MeshError {
                    place: at(),
                    what: format!("point {v} out of range (the file has {count} points)"),
                })
            })
            .collect::<Result<_, _>>()?;
        read.take(shape(t), &nodes, i as u64, &at)?;
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

/// Refuse a `.vtu` file whose compressed arrays claim more than [`MAX_DECOMPRESSED`] bytes, more
/// blocks than the file could hold, a block larger than that budget, or no block but a size (`vtkio`
/// computes `size · (blocks - 1) + last`, which wraps for zero blocks), before `vtkio` allocates what
/// they claim.
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
        if blocks == 0 && (size != 0 || last != 0) {
            return Err(format!(
                "a DataArray's compression header claims no block but blocks of {size} bytes (the last {last}): a corrupt compression header"
            ));
        }
        if size > MAX_DECOMPRESSED || last > size {
            return Err(format!(
                "a DataArray's compression header claims blocks of {size} bytes (the last {last}), more than the {MAX_DECOMPRESSED} tetwalk reads or a last block larger than the others: a corrupt compression header"
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
