//! Closed triangle models read from OFF, OBJ or ASCII PLY, every coordinate rounded to f32.

use super::SceneError;
use glam::Vec3;
use std::collections::HashMap;
use std::path::Path;

/// A closed model's triangle surface, as read from OFF, OBJ or ASCII PLY (named apart from the
/// arithmetic models, `crate::methods::Model`).
#[derive(Clone, Debug, Default)]
pub struct Surface {
    pub(crate) points: Vec<Vec3>,
    pub triangles: Vec<[u32; 3]>,
}

fn err(path: &Path, line: usize, what: impl std::fmt::Display) -> SceneError {
    SceneError::Model {
        place: format!("{} line {line}", path.display()),
        why: what.to_string(),
    }
}

fn whole(path: &Path, what: impl std::fmt::Display) -> SceneError {
    SceneError::Model {
        place: path.display().to_string(),
        why: what.to_string(),
    }
}

impl Surface {
    /// Read a model by its extension (`.off`, `.obj`, `.ply`); polygons are fanned into triangles.
    pub fn read(path: &Path) -> Result<Surface, SceneError> {
        let text =
            std::fs::read_to_string(path).map_err(|e| whole(path, format!("cannot read: {e}")))?;
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .unwrap_or("")
            .to_ascii_lowercase();
        let m = match ext.as_str() {
            "off" => read_off(path, &text)?,
            "obj" => read_obj(path, &text)?,
            "ply" => read_ply(path, &text)?,
            _ => {
                return Err(whole(path, "unknown model format (off, obj or ply)"));
            }
        };
        if m.triangles.is_empty() {
            return Err(whole(path, "no triangles"));
        }
        Ok(m)
    }

    /// Every edge must be used by exactly two triangles, once in each direction.
    pub fn check_closed(&self) -> Result<(), SceneError> {
        let mut uses: HashMap<(u32, u32), i32> = HashMap::new();
        for t in &self.triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                *uses.entry((a.min(b), a.max(b))).or_default() += if a < b { 1 } else { 1000 };
            }
        }
        if let Some(((a, b), n)) = uses.iter().find(|&(_, &n)| n != 1001) {
            let what = if n % 1000 + n / 1000 < 2 {
                "is used by one triangle only (a hole)"
            } else {
                "is not shared by exactly two consistently oriented triangles"
            };
            return Err(SceneError::NotClosed { a: *a, b: *b, what });
        }
        Ok(())
    }
}

fn push_polygon(
    m: &mut Surface,
    poly: &[u32],
    n: usize,
    path: &Path,
    line: usize,
) -> Result<(), SceneError> {
    if poly.len() < 3 {
        return Err(err(path, line, "a face needs three vertices"));
    }
    if let Some(&i) = poly.iter().find(|&&i| i as usize >= n) {
        return Err(err(path, line, format!("vertex {i} out of range (0..{n})")));
    }
    for k in 1..poly.len() - 1 {
        m.triangles.push([poly[0], poly[k], poly[k + 1]]);
    }
    Ok(())
}

fn point(path: &Path, line: usize, xs: &[&str]) -> Result<Vec3, SceneError> {
    let p: Result<Vec<f32>, _> = xs.iter().take(3).map(|x| x.parse::<f32>()).collect();
    match p {
        Ok(v) if v.len() == 3 && v.iter().all(|x| x.is_finite()) => Ok(Vec3::new(v[0], v[1], v[2])),
        _ => Err(err(path, line, "expected three finite coordinates")),
    }
}

/// Lines without comments or blanks, numbered from 1.
fn lines(text: &str) -> impl Iterator<Item = (usize, Vec<&str>)> {
    text.lines()
        .enumerate()
        .map(|(i, l)| {
            (
                i + 1,
                l.split('#')
                    .next()
                    .unwrap_or("")
                    .split_whitespace()
                    .collect::<Vec<_>>(),
            )
        })
        .filter(|(_, w)| !w.is_empty())
}

fn read_off(path: &Path, text: &str) -> Result<Surface, SceneError> {
    let mut it = lines(text);
    let (l, head) = it.next().ok_or_else(|| err(path, 1, "empty file"))?;
    let mut counts = if head[0] == "OFF" {
        head[1..].to_vec()
    } else {
        return Err(err(path, l, "not an OFF file"));
    };
    let mut line = l;
    if counts.is_empty() {
        let (l2, c) = it.next().ok_or_else(|| err(path, l, "missing counts"))?;
        counts = c;
        line = l2;
    }
    let parse = |s: &str| {
        s.parse::<usize>()
            .map_err(|_| err(path, line, "bad counts"))
    };
    let (nv, nf) = (
        parse(counts[0])?,
        parse(counts.get(1).copied().unwrap_or("x"))?,
    );
    let mut m = Surface::default();
    for _ in 0..nv {
        let (l, w) = it
            .next()
            .ok_or_else(|| err(path, line, "fewer vertices than announced"))?;
        m.points.push(point(path, l, &w)?);
    }
    for _ in 0..nf {
        let (l, w) = it
            .next()
            .ok_or_else(|| err(path, line, "fewer faces than announced"))?;
        let k: usize = w[0].parse().map_err(|_| err(path, l, "bad face"))?;
        let idx: Result<Vec<u32>, _> = w.iter().skip(1).take(k).map(|x| x.parse::<u32>()).collect();
        let idx = idx.map_err(|_| err(path, l, "bad vertex index"))?;
        if idx.len() != k {
            return Err(err(path, l, "face shorter than its count"));
        }
        push_polygon(&mut m, &idx, nv, path, l)?;
    }
    Ok(m)
}

fn read_obj(path: &Path, text: &str) -> Result<Surface, SceneError> {
    let mut m = Surface::default();
    let mut faces = Vec::new();
    for (l, w) in lines(text) {
        match w[0] {
            "v" => m.points.push(point(path, l, &w[1..])?),
            "f" => {
                let idx: Result<Vec<i64>, _> = w[1..]
                    .iter()
                    .map(|x| x.split('/').next().unwrap_or("").parse::<i64>())
                    .collect();
                faces.push((l, idx.map_err(|_| err(path, l, "bad vertex index"))?));
            }
            _ => {}
        }
    }
    let n = m.points.len();
    for (l, idx) in faces {
        let idx: Vec<u32> = idx
            .iter()
            .map(|&i| {
                if i < 0 {
                    (n as i64 + i) as u32
                } else {
                    (i - 1) as u32
                }
            })
            .collect();
        push_polygon(&mut m, &idx, n, path, l)?;
    }
    Ok(m)
}

fn read_ply(path: &Path, text: &str) -> Result<Surface, SceneError> {
    let mut it = lines(text);
    let (mut nv, mut nf) = (0usize, 0usize);
    let mut header_end = 0;
    for (l, w) in it.by_ref() {
        match w.as_slice() {
            ["format", f, ..] if *f != "ascii" => {
                return Err(err(path, l, "only ASCII PLY is read"));
            }
            ["element", "vertex", n] => nv = n.parse().map_err(|_| err(path, l, "bad count"))?,
            ["element", "face", n] => nf = n.parse().map_err(|_| err(path, l, "bad count"))?,
            ["end_header"] => {
                header_end = l;
                break;
            }
            _ => {}
        }
    }
    let mut m = Surface::default();
    for _ in 0..nv {
        let (l, w) = it
            .next()
            .ok_or_else(|| err(path, header_end, "fewer vertices than announced"))?;
        m.points.push(point(path, l, &w)?);
    }
    for _ in 0..nf {
        let (l, w) = it
            .next()
            .ok_or_else(|| err(path, header_end, "fewer faces than announced"))?;
        let idx: Result<Vec<u32>, _> = w.iter().skip(1).map(|x| x.parse::<u32>()).collect();
        push_polygon(
            &mut m,
            &idx.map_err(|_| err(path, l, "bad vertex index"))?,
            nv,
            path,
            l,
        )?;
    }
    Ok(m)
}
