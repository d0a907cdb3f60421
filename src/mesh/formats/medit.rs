//! MEDIT's ASCII `.mesh` files (Frey, "MEDIT: an interactive mesh visualization software", INRIA
//! RT-0253, and libMeshb's keywords): `Dimension 3`, `Vertices` (`x y z ref`), `Tetrahedra`
//! (`v1 v2 v3 v4 ref`) and `Triangles` (`v1 v2 v3 ref`), 1-based; other keywords skipped by their
//! known sizes.

use super::{MeshError, Read, Shape};

/// Numbers per entry of the keywords tetwalk skips (in 3D).
fn skipped(keyword: &str) -> Option<usize> {
    Some(match keyword {
        "Edges" => 3,
        "Corners"
        | "RequiredVertices"
        | "Ridges"
        | "RequiredEdges"
        | "RequiredTriangles"
        | "RequiredQuadrilaterals"
        | "RequiredTetrahedra" => 1,
        "Normals" | "Tangents" => 3,
        "NormalAtVertices" | "TangentAtVertices" => 2,
        "NormalAtTriangleVertices" => 3,
        "NormalAtQuadrilateralVertices" => 3,
        "TangentAtEdgeVertices" => 3,
        _ => return None,
    })
}

pub(super) fn read(text: &str, file: &str) -> Result<Read, MeshError> {
    // Words with their line numbers; `#` starts a comment to the end of its line.
    let mut words = text
        .lines()
        .enumerate()
        .flat_map(|(i, l)| {
            l.split('#')
                .next()
                .unwrap_or("")
                .split_whitespace()
                .map(move |w| (i + 1, w))
        })
        .peekable();
    let err = |n: usize, what: String| MeshError {
        place: format!("{file} line {n}"),
        what,
    };
    let mut read = Read {
        names: ["vertex", "tetrahedron", "triangle"],
        ..Read::default()
    };
    let next_number = |words: &mut dyn Iterator<Item = (usize, &str)>, after: &str, at: usize| {
        let (n, w) = words
            .next()
            .ok_or_else(|| err(at, format!("the file ends inside {after}")))?;
        w.parse::<f64>()
            .map(|x| (n, x))
            .map_err(|_| err(n, format!("'{w}' is not a number ({after})")))
    };
    let mut dimension = None;
    let mut last = 1;
    while let Some((n, keyword)) = words.next() {
        last = n;
        if keyword == "End" {
            break;
        }
        if keyword == "MeshVersionFormatted" {
            next_number(&mut words, keyword, n)?;
            continue;
        }
        if keyword == "Dimension" {
            let (k, d) = next_number(&mut words, keyword, n)?;
            if d != 3.0 {
                return Err(err(k, format!("dimension {d}: tetwalk walks 3D meshes")));
            }
            dimension = Some(3);
            continue;
        }
        if matches!(
            keyword,
            "Hexahedra" | "Hexaedra" | "Prisms" | "Pyramids" | "Quadrilaterals"
        ) {
            return Err(err(
                n,
                format!(
                    "{keyword}: tetwalk walks tetrahedral meshes (tetrahedra, and triangles as their constrained faces)"
                ),
            ));
        }
        let per = match keyword {
            "Vertices" => 4,
            "Tetrahedra" => 5,
            "Triangles" => 4,
            k => skipped(k).ok_or_else(|| err(n, format!("unknown keyword '{k}'")))?,
        };
        if dimension.is_none() {
            return Err(err(n, format!("{keyword} before Dimension 3")));
        }
        let (k, count) = next_number(&mut words, keyword, n)?;
        if count < 0.0 || count.fract() != 0.0 {
            return Err(err(k, format!("{count} entries of {keyword}")));
        }
        for e in 0..count as u64 {
            if let Some(&(n, w)) = words
                .peek()
                .filter(|(_, w)| w.starts_with(char::is_alphabetic))
            {
                return Err(err(
                    n,
                    format!(
                        "{keyword} announces {count} entries, but '{w}' comes after {e} (the count is wrong: TetGen's -g writes such files)"
                    ),
                ));
            }
            let mut row = [0.0; 5];
            let mut at = k;
            for x in row.iter_mut().take(per) {
                (at, *x) = next_number(&mut words, keyword, at)?;
            }
            let vertex = |x: f64| {
                (x.fract() == 0.0 && x >= 1.0 && x <= read.points.len() as f64)
                    .then_some(x as u32 - 1)
                    .ok_or_else(|| {
                        err(
                            at,
                            format!("vertex {x} out of range (1..={})", read.points.len()),
                        )
                    })
            };
            match keyword {
                "Vertices" => {
                    read.points.push([row[0], row[1], row[2]]);
                    read.point_ids.push(e + 1);
                }
                "Tetrahedra" | "Triangles" => {
                    let corners = per - 1;
                    let nodes: Vec<u32> = row[..corners]
                        .iter()
                        .map(|&x| vertex(x))
                        .collect::<Result<_, _>>()?;
                    let shape = if corners == 4 {
                        Shape::Tet
                    } else {
                        Shape::Triangle
                    };
                    let place = format!("{file} line {at}, {keyword} {}", e + 1);
                    read.take(shape, &nodes, e + 1, &|| place.clone())?;
                }
                _ => {}
            }
        }
    }
    if dimension.is_none() {
        return Err(err(last, "no Dimension 3: not a MEDIT mesh".into()));
    }
    Ok(read)
}
