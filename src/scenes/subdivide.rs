//! Loop subdivision of a closed model (Loop 1987, with Warren's vertex weights), every new point
//! computed in f64 from f32 points and rounded once to f32: the same model gives the same points, bit
//! for bit, on every machine. It makes the paper-scale bunny (seed 000's BUNNY has about 69k triangles).

use super::SceneError;
use super::model::Surface;
use glam::Vec3;
use std::collections::HashMap;

/// Warren's weight β of a vertex with `n` neighbours: 3/16 for 3, else 3/(8n).
fn beta(n: usize) -> f64 {
    if n == 3 {
        3.0 / 16.0
    } else {
        3.0 / (8.0 * n as f64)
    }
}

fn f64s(p: Vec3) -> [f64; 3] {
    p.to_array().map(f64::from)
}

fn rounded(p: [f64; 3]) -> Vec3 {
    Vec3::from_array(p.map(|x| x as f32))
}

impl Surface {
    /// One level of Loop subdivision of a closed model: every triangle split into four, each old point
    /// moved to `(1 - nβ) p + β Σ neighbours` and each edge point `3/8 (a + b) + 1/8 (c + d)` (`c`, `d`
    /// the far corners of the edge's two triangles). Refuses a model that is not closed.
    pub(crate) fn loop_subdivided(&self) -> Result<Surface, SceneError> {
        self.check_closed()?;
        // Each directed edge a → b names the third corner of its triangle; each point its neighbours,
        // in the order the triangles list them.
        let mut far: HashMap<(u32, u32), u32> = HashMap::new();
        let mut around: Vec<Vec<u32>> = vec![Vec::new(); self.points.len()];
        for t in &self.triangles {
            for k in 0..3 {
                let (a, b, c) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
                far.insert((a, b), c);
                if !around[a as usize].contains(&b) {
                    around[a as usize].push(b);
                }
            }
        }
        let p = |i: u32| f64s(self.points[i as usize]);
        let mut points: Vec<Vec3> = self
            .points
            .iter()
            .zip(&around)
            .map(|(&q, nb)| {
                let w = beta(nb.len());
                let mut s = f64s(q).map(|x| (1.0 - nb.len() as f64 * w) * x);
                for &j in nb {
                    for (sk, pk) in s.iter_mut().zip(p(j)) {
                        *sk += w * pk;
                    }
                }
                rounded(s)
            })
            .collect();
        let mut edge_point: HashMap<(u32, u32), u32> = HashMap::new();
        let mut mid = |a: u32, b: u32, points: &mut Vec<Vec3>| -> u32 {
            *edge_point.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (c, d) = (far[&(a, b)], far[&(b, a)]);
                let (pa, pb, pc, pd) = (p(a), p(b), p(c), p(d));
                let q = std::array::from_fn(|k| 0.375 * (pa[k] + pb[k]) + 0.125 * (pc[k] + pd[k]));
                points.push(rounded(q));
                points.len() as u32 - 1
            })
        };
        let mut triangles = Vec::with_capacity(self.triangles.len() * 4);
        for &[a, b, c] in &self.triangles {
            let (ab, bc, ca) = (
                mid(a, b, &mut points),
                mid(b, c, &mut points),
                mid(c, a, &mut points),
            );
            triangles.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
        }
        Ok(Surface { points, triangles })
    }

    /// The model as OFF text, each coordinate the shortest decimal that reads back as its f32.
    pub(crate) fn off_text(&self) -> String {
        use std::fmt::Write;
        let mut s = format!("OFF\n{} {} 0\n", self.points.len(), self.triangles.len());
        for q in &self.points {
            let _ = writeln!(s, "{} {} {}", q.x, q.y, q.z);
        }
        for t in &self.triangles {
            let _ = writeln!(s, "3 {} {} {}", t[0], t[1], t[2]);
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tetrahedron() -> Surface {
        Surface {
            points: vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z],
            triangles: vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
        }
    }

    /// One level quadruples the triangles, adds a point per edge, keeps the model closed, and moves
    /// a tetrahedron's corner (3 neighbours) by Warren's 3/16.
    #[test]
    fn one_level_of_a_tetrahedron() {
        let m = tetrahedron().loop_subdivided().unwrap();
        assert_eq!(m.triangles.len(), 16);
        assert_eq!(m.points.len(), 4 + 6);
        m.check_closed().unwrap();
        // Corner 0 = (1 - 9/16)·0 + 3/16·(X + Y + Z).
        assert_eq!(m.points[0], Vec3::splat(3.0 / 16.0));
        let again = m.loop_subdivided().unwrap();
        assert_eq!(again.triangles.len(), 64);
        again.check_closed().unwrap();
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("again.off");
        std::fs::write(&path, again.off_text()).unwrap();
        let back = Surface::read(&path).unwrap();
        assert_eq!(back.points, again.points, "OFF text reads back bit for bit");
        assert_eq!(back.triangles, again.triangles);
    }

    #[test]
    fn an_open_model_is_refused() {
        let mut m = tetrahedron();
        m.triangles.pop();
        assert!(matches!(
            m.loop_subdivided(),
            Err(SceneError::NotClosed { .. })
        ));
    }
}
