//! Gmsh's MSH files (Gmsh reference manual, "MSH file format"): version 4.1 (ASCII or binary) through
//! `mshio`, version 2.2 (ASCII) read here. Node tags may be sparse; elements name nodes by tag.

use super::{MeshError, Read, Shape};
use std::collections::HashMap;

/// What a Gmsh element type (`GmshDefines.h`) is to tetwalk.
fn shape(kind: i64) -> Shape {
    match kind {
        4 | 11 | 29 | 30 | 31 => Shape::Tet,
        2 | 9 | 20 | 21 | 22 | 23 | 24 | 25 => Shape::Triangle,
        1 | 8 | 15 | 26 | 27 | 28 => Shape::Ignored,
        3 | 10 | 16 => Shape::Refused("quadrilateral"),
        5 | 12 | 17 => Shape::Refused("hexahedron"),
        6 | 13 | 18 => Shape::Refused("prism"),
        7 | 14 | 19 => Shape::Refused("pyramid"),
        _ => Shape::Refused("element of a type tetwalk does not know"),
    }
}

/// The file's version and whether it is binary, from `$MeshFormat`.
fn header(bytes: &[u8], file: &str) -> Result<(String, bool), MeshError> {
    let fail = |what: &str| MeshError {
        place: file.to_string(),
        what: what.to_string(),
    };
    let text = String::from_utf8_lossy(&bytes[..bytes.len().min(256)]);
    let mut lines = text.lines().map(str::trim);
    if lines.next() != Some("$MeshFormat") {
        return Err(fail(
            "not a Gmsh MSH file: it does not start with $MeshFormat",
        ));
    }
    let line = lines.next().unwrap_or("");
    let mut words = line.split_whitespace();
    let version = words.next().unwrap_or("").to_string();
    let binary = words.next() == Some("1");
    Ok((version, binary))
}

pub(super) fn read(bytes: &[u8], file: &str) -> Result<Read, MeshError> {
    let (version, binary) = header(bytes, file)?;
    match version.as_str() {
        "4.1" => read_41(bytes, file),
        "2.2" | "2.1" | "2" | "2.0" if !binary => read_22(&String::from_utf8_lossy(bytes), file),
        v => Err(MeshError {
            place: file.to_string(),
            what: format!(
                "MSH version {v}{}: tetwalk reads MSH 4.1 (ASCII or binary) and 2.2 (ASCII); save it as one of those (gmsh -save -format msh41)",
                if binary { " binary" } else { "" }
            ),
        }),
    }
}

/// MSH 4.1 through `mshio`: node blocks in order, each node's tag its block's own (sparse tags) or the
/// next of the section's consecutive ones; element blocks in order.
fn read_41(bytes: &[u8], file: &str) -> Result<Read, MeshError> {
    let msh = super::guarded("the MSH reader (mshio)", file, || {
        mshio::parse_msh_bytes(bytes).map_err(|e| e.to_string())
    })?
    .map_err(|e| MeshError {
        place: file.to_string(),
        what: format!("not a readable MSH 4.1 file: {e}"),
    })?;
    let mut read = Read {
        names: ["node", "element", "element"],
        ..Read::default()
    };
    let mut index: HashMap<u64, u32> = HashMap::new();
    if let Some(nodes) = &msh.data.nodes {
        let mut next = nodes.min_node_tag;
        for block in &nodes.node_blocks {
            let tags: Vec<u64> = match &block.node_tags {
                Some(map) => {
                    let mut t = vec![0; block.nodes.len()];
                    map.iter().for_each(|(&tag, &i)| t[i] = tag);
                    t
                }
                None => (0..block.nodes.len() as u64).map(|i| next + i).collect(),
            };
            next += block.nodes.len() as u64;
            for (n, tag) in block.nodes.iter().zip(tags) {
                index.insert(tag, read.points.len() as u32);
                read.points.push([n.x, n.y, n.z]);
                read.point_ids.push(tag);
            }
        }
    }
    if let Some(elements) = &msh.data.elements {
        for block in &elements.element_blocks {
            let kind = shape(block.element_type as i64);
            for e in &block.elements {
                let at = || format!("{file}, element {}", e.element_tag);
                let nodes = node_indices(&e.nodes, &index, &at)?;
                read.take(kind, &nodes, e.element_tag, &at)?;
            }
        }
    }
    Ok(read)
}

/// Each node tag's point index; an error names a tag no node has.
fn node_indices(
    tags: &[u64],
    index: &HashMap<u64, u32>,
    at: &dyn Fn() -> String,
) -> Result<Vec<u32>, MeshError> {
    tags.iter()
        .map(|t| {
            index.get(t).copied().ok_or_else(|| MeshError {
                place: at(),
                what: format!("node {t}, which the file does not define"),
            })
        })
        .collect()
}

/// MSH 2.2 ASCII: `$Nodes` (count, then `tag x y z`) and `$Elements` (count, then `tag type ntags
/// tags… nodes…`); other sections skipped.
fn read_22(text: &str, file: &str) -> Result<Read, MeshError> {
    let mut read = Read {
        names: ["node", "element", "element"],
        ..Read::default()
    };
    let mut index: HashMap<u64, u32> = HashMap::new();
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l.trim()));
    let err = |n: usize, what: String| MeshError {
        place: format!("{file} line {n}"),
        what,
    };
    let int = |n: usize, w: &str| {
        w.parse::<u64>()
            .map_err(|_| err(n, format!("'{w}' is not a non-negative integer")))
    };
    while let Some((n, line)) = lines.next() {
        let section = match line {
            "$Nodes" => "$EndNodes",
            "$Elements" => "$EndElements",
            _ => continue,
        };
        let (cn, count) = lines
            .next()
            .ok_or_else(|| err(n, format!("{line} ends the file")))?;
        let count = int(cn, count)?;
        for _ in 0..count {
            let (k, row) = lines.next().ok_or_else(|| {
                err(
                    cn,
                    format!("{line} announces {count} rows; the file ends first"),
                )
            })?;
            let words: Vec<&str> = row.split_whitespace().collect();
            if section == "$EndNodes" {
                if words.len() != 4 {
                    return Err(err(k, format!("a node is 'tag x y z', not '{row}'")));
                }
                let tag = int(k, words[0])?;
                let mut p = [0.0; 3];
                for c in 0..3 {
                    p[c] = words[c + 1]
                        .parse::<f64>()
                        .map_err(|_| err(k, format!("'{}' is not a number", words[c + 1])))?;
                }
                if index.insert(tag, read.points.len() as u32).is_some() {
                    return Err(err(k, format!("node {tag} defined twice")));
                }
                read.points.push(p);
                read.point_ids.push(tag);
            } else {
                let nums: Vec<u64> = words.iter().map(|w| int(k, w)).collect::<Result<_, _>>()?;
                let (Some(&tag), Some(&kind), Some(&ntags)) =
                    (nums.first(), nums.get(1), nums.get(2))
                else {
                    return Err(err(
                        k,
                        format!("an element is 'tag type ntags tags… nodes…', not '{row}'"),
                    ));
                };
                let nodes = nums.get(3 + ntags as usize..).unwrap_or(&[]);
                let at = || format!("{file} line {k}, element {tag}");
                let nodes = node_indices(nodes, &index, &at)?;
                read.take(shape(kind as i64), &nodes, tag, &at)?;
            }
        }
        match lines.next() {
            Some((_, end)) if end == section => {}
            Some((k, other)) => {
                return Err(err(k, format!("'{other}' where {section} was expected")));
            }
            None => return Err(err(n, format!("{line} is not closed by {section}"))),
        }
    }
    Ok(read)
}
