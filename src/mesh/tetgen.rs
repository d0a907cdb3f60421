//! Reading TetGen's `.node`, `.ele`, `.neigh` and `.face` files (Si 2015, TetGen manual §5.2).

use super::{Item, Mesh, MeshError, RawMesh};
use glam::Vec3;
use std::path::{Path, PathBuf};

/// Numeric rows with their line numbers.
type Rows = [(usize, Vec<f64>)];

/// One file's numeric lines, with their line numbers (comments and blank lines dropped).
struct Table {
    path: PathBuf,
    rows: Vec<(usize, Vec<f64>)>,
}

impl Table {
    fn read(path: &Path) -> Result<String, MeshError> {
        std::fs::read_to_string(path).map_err(|e| MeshError {
            place: path.display().to_string(),
            what: format!("cannot read: {e}"),
        })
    }

    fn parse(path: &Path, text: &str) -> Result<Table, MeshError> {
        let mut rows = Vec::new();
        for (i, line) in text.lines().enumerate() {
            let body = line.split('#').next().unwrap_or("");
            if body.trim().is_empty() {
                continue;
            }
            let nums: Result<Vec<f64>, _> =
                body.split_whitespace().map(str::parse::<f64>).collect();
            match nums {
                Ok(v) => rows.push((i + 1, v)),
                Err(_) => {
                    return Err(Self::err_at(
                        path,
                        i + 1,
                        format!("not a number in '{}'", line.trim()),
                    ));
                }
            }
        }
        Ok(Table {
            path: path.to_path_buf(),
            rows,
        })
    }

    fn err_at(path: &Path, line: usize, what: String) -> MeshError {
        MeshError {
            place: format!("{} line {line}", path.display()),
            what,
        }
    }

    fn err(&self, row: usize, what: String) -> MeshError {
        let line = self.rows.get(row).map_or(0, |r| r.0);
        Self::err_at(&self.path, line, what)
    }

    /// The header's count, then `count` rows each with at least `min_cols` numbers.
    fn body(&self, min_cols: usize) -> Result<(&[f64], &Rows), MeshError> {
        let Some((_, header)) = self.rows.first() else {
            return Err(Self::err_at(&self.path, 1, "empty file".into()));
        };
        let count = header.first().copied().unwrap_or(-1.0);
        if count < 0.0 || count.fract() != 0.0 || count as usize > self.rows.len() - 1 {
            let what = format!(
                "header announces {count} rows, the file has {}",
                self.rows.len() - 1
            );
            return Err(self.err(0, what));
        }
        if (count as usize) < self.rows.len() - 1 {
            let what = format!(
                "a row beyond the {count} the header announces (the file has {}): counts as announced, or the mesh would be read short",
                self.rows.len() - 1
            );
            return Err(self.err(count as usize + 1, what));
        }
        let body = &self.rows[1..=count as usize];
        if let Some(k) = body.iter().position(|(_, r)| r.len() < min_cols) {
            let what = format!(
                "expected at least {min_cols} numbers, found {}",
                body[k].1.len()
            );
            return Err(self.err(k + 1, what));
        }
        Ok((header, body))
    }

    /// Column `c` of a body row as an index, shifted by `base` and checked against `limit`.
    fn index(
        &self,
        row: usize,
        v: f64,
        base: i64,
        limit: usize,
        what: &str,
    ) -> Result<u32, MeshError> {
        if v.fract() != 0.0 {
            return Err(self.err(row, format!("{what} {v} is not an integer")));
        }
        let i = v as i64 - base;
        if i < 0 || i as usize >= limit {
            let what = format!(
                "{what} {v} out of range ({base}..{})",
                base + limit as i64 - 1
            );
            return Err(self.err(row, what));
        }
        Ok(i as u32)
    }
}

/// Whether a mesh must have constrained faces (a scene's surfaces, from `.face`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Faces {
    /// A missing or empty `.face` is an error: a scene without surfaces is a mistake unless asked for.
    Required,
    /// Asked for explicitly: a missing `.face` means no constrained faces.
    Optional,
}

/// Load a TetGen mesh from `stem.node`, `stem.ele` and `stem.face` (its constrained faces, which must
/// be there and not empty), with `stem.neigh` when present.
pub fn load_tetgen(path: &Path) -> Result<Mesh, MeshError> {
    load_tetgen_with(path, Faces::Required)
}

/// Load a TetGen mesh from `stem.node` and `stem.ele`, with `stem.neigh` and `stem.face` when present
/// (neighbours are derived from shared faces without `.neigh`; every `.face` entry is constrained).
/// `path` may be the stem or any of the four files. Coordinates are rounded to the nearest f32.
pub fn load_tetgen_with(path: &Path, faces: Faces) -> Result<Mesh, MeshError> {
    let stem = tetgen_stem(path);
    let file = |ext: &str| {
        let mut p = stem.clone().into_os_string();
        p.push(".");
        p.push(ext);
        PathBuf::from(p)
    };
    let optional = |ext: &str| {
        file(ext)
            .exists()
            .then(|| Table::read(&file(ext)))
            .transpose()
    };
    let (node, ele) = (Table::read(&file("node"))?, Table::read(&file("ele"))?);
    let (neigh, face) = (optional("neigh")?, optional("face")?);
    if faces == Faces::Required {
        // The header, the first line that is not a comment, starts with the number of faces.
        let count = |t: &str| {
            t.lines()
                .map(|l| l.split('#').next().unwrap_or("").trim())
                .find(|l| !l.is_empty())
                .and_then(|l| l.split_whitespace().next()?.parse::<u64>().ok())
        };
        let why = match &face {
            None => Some("missing"),
            Some(t) if count(t).is_none_or(|n| n == 0) => Some("holds no faces"),
            _ => None,
        };
        if let Some(why) = why {
            return Err(MeshError {
                place: file("face").display().to_string(),
                what: format!(
                    "{why}: a scene's constrained faces (its surfaces) come from it; to walk a mesh without surfaces, ask for it (--no-faces)"
                ),
            });
        }
    }
    parse_tetgen(
        &stem,
        &TetgenTexts {
            node: &node,
            ele: &ele,
            neigh: neigh.as_deref(),
            face: face.as_deref(),
        },
    )
}

/// The stem of a TetGen mesh named by its stem or any of its four files.
fn tetgen_stem(path: &Path) -> PathBuf {
    match path.extension().and_then(|e| e.to_str()) {
        Some("node" | "ele" | "neigh" | "face") => path.with_extension(""),
        _ => path.to_path_buf(),
    }
}

/// The four files of a TetGen mesh named by its stem or any of them: `.node`, `.ele`, `.neigh`,
/// `.face`.
pub fn tetgen_files(path: &Path) -> [PathBuf; 4] {
    let stem = tetgen_stem(path);
    ["node", "ele", "neigh", "face"].map(|ext| {
        let mut p = stem.clone().into_os_string();
        p.push(".");
        p.push(ext);
        PathBuf::from(p)
    })
}

/// The texts of a TetGen mesh's files.
pub struct TetgenTexts<'a> {
    pub node: &'a str,
    pub ele: &'a str,
    pub neigh: Option<&'a str>,
    pub face: Option<&'a str>,
}

/// [`load_tetgen`] from the files' texts; `stem` names them in errors.
pub fn parse_tetgen(stem: &Path, texts: &TetgenTexts) -> Result<Mesh, MeshError> {
    let file = |ext: &str| {
        let mut p = stem.as_os_str().to_owned();
        p.push(".");
        p.push(ext);
        PathBuf::from(p)
    };
    // The four tables are parsed at once; each is checked where it was before, so the first error
    // named is the same.
    let table = |ext: &str, text: &str| Table::parse(&file(ext), text);
    let ((node, ele), (neigh, face)) = rayon::join(
        || rayon::join(|| table("node", texts.node), || table("ele", texts.ele)),
        || {
            rayon::join(
                || texts.neigh.map(|t| table("neigh", t)),
                || texts.face.map(|t| table("face", t)),
            )
        },
    );
    let node = node?;
    let (header, rows) = node.body(4)?;
    if header.get(1).is_some_and(|&d| d != 3.0) {
        return Err(node.err(0, format!("dimension {} is not 3", header[1])));
    }
    let base = rows.first().map_or(0, |r| r.1[0] as i64);
    let mut points = Vec::with_capacity(rows.len());
    for (k, (_, r)) in rows.iter().enumerate() {
        if r[0] as i64 != base + k as i64 {
            return Err(node.err(
                k + 1,
                format!(
                    "point index {} where {} was expected",
                    r[0],
                    base + k as i64
                ),
            ));
        }
        let p = Vec3::new(r[1] as f32, r[2] as f32, r[3] as f32);
        if !p.is_finite() {
            return Err(node.err(
                k + 1,
                format!("coordinate not finite in f32: {:?}", &r[1..4]),
            ));
        }
        points.push(p);
    }
    let ele = ele?;
    let (header, rows) = ele.body(5)?;
    if header.get(1).is_some_and(|&n| n != 4.0 && n != 10.0) {
        return Err(ele.err(
            0,
            format!("{} nodes per tetrahedron (4 or 10 expected)", header[1]),
        ));
    }
    let mut tets = Vec::with_capacity(rows.len());
    for (k, (_, r)) in rows.iter().enumerate() {
        let mut v = [0u32; 4];
        for c in 0..4 {
            v[c] = ele.index(k + 1, r[c + 1], base, points.len(), "vertex index")?;
        }
        tets.push(v);
    }
    if tets.is_empty() {
        return Err(ele.err(0, "no tetrahedra".into()));
    }
    let neigh = neigh.transpose()?;
    let neighbors = match &neigh {
        None => None,
        Some(t) => {
            let (_, rows) = t.body(5)?;
            let mut out = Vec::with_capacity(rows.len());
            for (k, (_, r)) in rows.iter().enumerate() {
                let mut row = [-1i64; 4];
                for c in 0..4 {
                    row[c] = if r[c + 1] == -1.0 {
                        -1
                    } else {
                        t.index(k + 1, r[c + 1], base, tets.len(), "neighbour")? as i64
                    };
                }
                out.push(row);
            }
            Some(out)
        }
    };
    let face = face.transpose()?;
    let mut constrained = Vec::new();
    if let Some(t) = &face {
        let (_, rows) = t.body(4)?;
        for (k, (_, r)) in rows.iter().enumerate() {
            let mut v = [0u32; 3];
            for c in 0..3 {
                v[c] = t.index(k + 1, r[c + 1], base, points.len(), "vertex index")?;
            }
            constrained.push(v);
        }
    }
    let raw = RawMesh {
        points,
        tets,
        neighbors,
        constrained,
    };
    let line = |t: &Table, k: usize| {
        format!(
            "{} line {}",
            t.path.display(),
            t.rows.get(k + 1).map_or(0, |r| r.0)
        )
    };
    Mesh::build_at(raw, &|item| match item {
        Item::Point(i) => format!("{}, point {}", line(&node, i), base + i as i64),
        Item::Tet(i) => format!("{}, tetrahedron {}", line(&ele, i), base + i as i64),
        Item::Neighbors(i) => match &neigh {
            Some(n) if i + 1 < n.rows.len() => {
                format!("{}, tetrahedron {}", line(n, i), base + i as i64)
            }
            _ => format!("{}, tetrahedron {}", line(&ele, i), base + i as i64),
        },
        Item::Constrained(i) => match &face {
            Some(f) => format!("{}, face {}", line(f, i), base + i as i64),
            None => format!("constrained face {i}"),
        },
    })
}
