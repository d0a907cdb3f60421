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

/// Most characters of a reader's message kept in an error (`mshio` quotes the file's bytes).
const MESSAGE: usize = 300;

/// MSH 4.1 through `mshio` for the coordinates and elements, each node's tag read here as the file
/// lists it ([`node_tags_41`]: `mshio` numbers a block's nodes from the section's smallest tag
/// whenever the tags span a dense range, whatever their order); element blocks in order.
fn read_41(bytes: &[u8], file: &str) -> Result<Read, MeshError> {
    let fail = |what: String| MeshError {
        place: file.to_string(),
        what,
    };
    // The tags first: they bound every count the section announces by the file's size.
    let tags = node_tags_41(bytes).map_err(|e| fail(format!("$Nodes: {e}")))?;
    let msh = super::guarded("the MSH reader (mshio)", file, || {
        mshio::parse_msh_bytes(bytes).map_err(|e| e.to_string())
    })?
    .map_err(|e| {
        let e: String = e
            .lines()
            .next()
            .unwrap_or("")
            .chars()
            .take(MESSAGE)
            .collect();
        fail(format!("not a readable MSH 4.1 file: {e}"))
    })?;
    let mut read = Read {
        names: ["node", "element", "element"],
        ..Read::default()
    };
    let mut index: HashMap<u64, u32> = HashMap::new();
    if let Some(nodes) = &msh.data.nodes {
        if nodes.node_blocks.len() != tags.len() {
            return Err(fail(format!(
                "$Nodes: {} node blocks read, {} listed",
                nodes.node_blocks.len(),
                tags.len()
            )));
        }
        for (k, (block, tags)) in nodes.node_blocks.iter().zip(&tags).enumerate() {
            if block.nodes.len() != tags.len() {
                return Err(fail(format!(
                    "$Nodes block {}: {} coordinates read, {} tags listed",
                    k + 1,
                    block.nodes.len(),
                    tags.len()
                )));
            }
            for (n, &tag) in block.nodes.iter().zip(tags) {
                if index.insert(tag, read.points.len() as u32).is_some() {
                    return Err(fail(format!(
                        "$Nodes block {}: node {tag} defined twice",
                        k + 1
                    )));
                }
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

/// The node tags of an MSH 4.1 file's `$Nodes` section, block by block, in the order the file lists
/// them (ASCII or binary, either byte order; MSH 4.1: `numEntityBlocks numNodes minNodeTag
/// maxNodeTag`, then per block `entityDim entityTag parametric numNodesInBlock`, its tags, its
/// coordinates). Every count is bounded by the bytes left before it is used; an error says which.
/// No `$Nodes` section: no blocks.
fn node_tags_41(bytes: &[u8]) -> Result<Vec<Vec<u64>>, String> {
    let (_, binary) = header(bytes, "").map_err(|e| e.what)?;
    let find = |pat: &[u8], from: usize| {
        bytes
            .get(from..)
            .and_then(|b| b.windows(pat.len()).position(|w| w == pat))
            .map(|i| from + i)
    };
    let Some(at) = find(b"\n$Nodes", 0) else {
        return Ok(Vec::new());
    };
    let start = at + b"\n$Nodes".len();
    let body = start
        + bytes[start..]
            .iter()
            .position(|&b| b == b'\n')
            .map_or(0, |i| i + 1);
    let mut r = if binary {
        // The version line (`4.1 1 8`: the data size last), then the binary int 1 in the file's
        // byte order.
        let version = find(b"\n", 0).map_or(0, |i| i + 1);
        let one = find(b"\n", version).map_or(0, |i| i + 1);
        let line = String::from_utf8_lossy(&bytes[version..one]).to_string();
        let size = match line.split_whitespace().nth(2) {
            Some("8") => 8,
            Some("4") => 4,
            other => return Err(format!("a data size of {other:?}, not 4 or 8")),
        };
        let big = bytes
            .get(one..one + 4)
            .is_some_and(|b| u32::from_be_bytes([b[0], b[1], b[2], b[3]]) == 1);
        Fields::Binary {
            at: body,
            size,
            big,
        }
    } else {
        let end = find(b"$EndNodes", body).ok_or("not closed by $EndNodes")?;
        let text = std::str::from_utf8(&bytes[body..end]).map_err(|_| "not text")?;
        Fields::Ascii(text.split_ascii_whitespace(), text.len())
    };
    let blocks = r.size_t(bytes, "number of blocks")?;
    let nodes = r.size_t(bytes, "number of nodes")?;
    for what in ["smallest tag", "largest tag"] {
        r.size_t(bytes, what)?;
    }
    if nodes > r.left(bytes) as u64 / 8 || blocks > r.left(bytes) as u64 / 8 {
        return Err(format!(
            "announces {nodes} nodes in {blocks} blocks, more than the {} bytes left could hold",
            r.left(bytes)
        ));
    }
    let mut out = Vec::new();
    for k in 1..=blocks {
        let of = |what: &str| format!("block {k}'s {what}");
        r.int(bytes, &of("dimension"))?;
        r.int(bytes, &of("entity"))?;
        let parametric = r.int(bytes, &of("parametric flag"))?;
        let n = r.size_t(bytes, &of("number of nodes"))?;
        // A node is at least its tag and three coordinates: 8 characters, or its binary size.
        let coordinates = 3 + parametric.min(3) as usize;
        let least = match &r {
            Fields::Ascii(..) => 8,
            Fields::Binary { size, .. } => size + 8 * coordinates,
        };
        if n > (r.left(bytes) / least) as u64 {
            return Err(format!(
                "block {k} announces {n} nodes, more than the {} bytes left could hold",
                r.left(bytes)
            ));
        }
        let tags = (0..n)
            .map(|_| r.size_t(bytes, &of("node tag")))
            .collect::<Result<Vec<_>, _>>()?;
        for _ in 0..n as usize * coordinates {
            r.double(bytes, &of("coordinates"))?;
        }
        out.push(tags);
    }
    Ok(out)
}

/// The fields of an MSH section read in order: words of ASCII text, or binary values.
enum Fields<'a> {
    /// The section's words, and its length (a bound on what is left).
    Ascii(std::str::SplitAsciiWhitespace<'a>, usize),
    Binary {
        /// Where the next value starts in the file's bytes.
        at: usize,
        /// Bytes of a `size_t`.
        size: usize,
        /// Big-endian.
        big: bool,
    },
}

impl Fields<'_> {
    /// The next `n` bytes as an unsigned integer, or an error naming `what` ended the file.
    fn bytes(&mut self, bytes: &[u8], n: usize, what: &str) -> Result<u64, String> {
        let Fields::Binary { at, big, .. } = self else {
            unreachable!("binary fields only");
        };
        let b = bytes
            .get(*at..*at + n)
            .ok_or_else(|| format!("ends before its {what}"))?;
        *at += n;
        let mut w = [0u8; 8];
        w[..n].copy_from_slice(b);
        if *big {
            w[..n].reverse();
        }
        Ok(u64::from_le_bytes(w))
    }

    /// The next word, or an error naming `what`.
    fn word<'w>(
        words: &mut std::str::SplitAsciiWhitespace<'w>,
        what: &str,
    ) -> Result<&'w str, String> {
        words
            .next()
            .ok_or_else(|| format!("ends before its {what}"))
    }

    /// A `size_t` (a count or a tag).
    fn size_t(&mut self, bytes: &[u8], what: &str) -> Result<u64, String> {
        match self {
            Fields::Ascii(words, _) => {
                let w = Self::word(words, what)?;
                w.parse::<u64>().map_err(|_| {
                    format!(
                        "'{}' is not a {what}",
                        w.chars().take(40).collect::<String>()
                    )
                })
            }
            Fields::Binary { size, .. } => {
                let n = *size;
                self.bytes(bytes, n, what)
            }
        }
    }

    /// An `int`.
    fn int(&mut self, bytes: &[u8], what: &str) -> Result<u64, String> {
        match self {
            Fields::Ascii(words, _) => {
                let w = Self::word(words, what)?;
                w.parse::<i64>().map(|v| v.max(0) as u64).map_err(|_| {
                    format!(
                        "'{}' is not a {what}",
                        w.chars().take(40).collect::<String>()
                    )
                })
            }
            Fields::Binary { .. } => self.bytes(bytes, 4, what),
        }
    }

    /// A `double`, skipped (the coordinates are `mshio`'s to read).
    fn double(&mut self, bytes: &[u8], what: &str) -> Result<(), String> {
        match self {
            Fields::Ascii(words, _) => Self::word(words, what).map(drop),
            Fields::Binary { .. } => self.bytes(bytes, 8, what).map(drop),
        }
    }

    /// Bytes left to read (for text, the section's length: a bound).
    fn left(&self, bytes: &[u8]) -> usize {
        match self {
            Fields::Ascii(_, len) => *len,
            Fields::Binary { at, .. } => bytes.len().saturating_sub(*at),
        }
    }
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
