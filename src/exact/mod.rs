//! The exact oracle: through which faces a line enters and leaves a tetrahedron, decided exactly from
//! the signs of Plücker side products and face normals (filtered f64, then exact integers).
#![warn(missing_docs)]

pub mod boxes;
pub mod clip;
pub mod hit;
pub(crate) mod rational;
pub mod sign;

pub use sign::{SignCounts, counts};

use crate::tet::{EDGES, FACE_VERTICES, Ray, Tet, all_finite, edge_index, orientation};
use glam::Vec3;

/// A set of faces of one tetrahedron (bit `i` = face `i`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct FaceSet(pub u8);

impl FaceSet {
    /// Whether face `face` is in the set.
    pub fn contains(self, face: usize) -> bool {
        face < 4 && self.0 & (1 << face) != 0
    }
    /// Whether the set holds no face.
    pub fn is_empty(self) -> bool {
        self.0 == 0
    }
    /// Add face `face`.
    pub fn insert(&mut self, face: usize) {
        self.0 |= 1 << face;
    }
    /// The faces, lowest first.
    pub fn iter(self) -> impl Iterator<Item = usize> {
        (0..4).filter(move |&f| self.contains(f))
    }
    /// The lowest face, if any.
    pub fn first(self) -> Option<usize> {
        self.iter().next()
    }
    /// The faces, lowest first.
    pub fn to_vec(self) -> Vec<usize> {
        self.iter().collect()
    }
}

/// What the oracle decides for one tetrahedron and one line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Classification {
    /// Faces through which the line leaves towards +dir (empty iff the line misses the closed tetrahedron).
    pub exit: FaceSet,
    /// Faces through which it enters, i.e. leaves towards -dir.
    pub entry: FaceSet,
}

impl Classification {
    /// Whether the line meets the closed tetrahedron.
    pub fn meets(&self) -> bool {
        !self.exit.is_empty()
    }
}

/// Why the oracle cannot answer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ExactError {
    /// A coordinate is NaN or infinite.
    #[error("a coordinate is NaN or infinite")]
    NonFinite,
    /// The tetrahedron has zero volume.
    #[error("the tetrahedron is flat (zero volume)")]
    FlatTet,
    /// The ray's direction is zero.
    #[error("the ray direction is zero")]
    ZeroDirection,
    /// The triangle's vertices are collinear.
    #[error("the triangle is degenerate (its vertices are collinear)")]
    FlatTriangle,
    /// The box is empty or flat.
    #[error("the box is empty or flat (every lower corner coordinate must be below the upper one)")]
    FlatBox,
}

/// Signs the oracle derives everything from, computed once per tetrahedron and line.
struct Signs {
    /// Sign of the side product of the line with each edge of [`EDGES`], `det[a - o, b - o, d]`.
    side: [i8; 6],
    /// Sign of `n_f · d` for each face, `n_f` its outward normal.
    normal: [i8; 4],
    /// The tetrahedron's orientation.
    orient: i8,
}

/// Whether the oracle can take `points` and `ray`: every coordinate finite, a nonzero direction.
pub fn check_ray(points: &[Vec3], ray: &Ray) -> Result<(), ExactError> {
    if !all_finite(points) || !all_finite(&[ray.org, ray.dir]) {
        return Err(ExactError::NonFinite);
    }
    if ray.dir == Vec3::ZERO {
        return Err(ExactError::ZeroDirection);
    }
    Ok(())
}

fn check(tet: &Tet, ray: &Ray) -> Result<i8, ExactError> {
    check_ray(tet, ray)?;
    match orientation(tet) {
        0 => Err(ExactError::FlatTet),
        s => Ok(s),
    }
}

fn signs(tet: &Tet, ray: &Ray) -> Result<Signs, ExactError> {
    let s = check(tet, ray)?;
    let side = EDGES.map(|[a, b]| side(tet[a], tet[b], ray));
    // Faces of a negatively oriented tetrahedron wind inwards: flip so that `normal` is outward.
    let normal =
        FACE_VERTICES.map(|[a, b, c]| s * sign::sign_det(tet[b], tet[a], tet[c], tet[a], ray.dir));
    Ok(Signs {
        side,
        normal,
        orient: s,
    })
}

impl Signs {
    fn classification(&self) -> Classification {
        let mut c = Classification {
            exit: FaceSet::default(),
            entry: FaceSet::default(),
        };
        for f in 0..4 {
            let cyc = cycle(&self.side, f, self.orient);
            if self.normal[f] > 0 && cyc.iter().all(|&x| x >= 0) {
                c.exit.insert(f);
            }
            if self.normal[f] < 0 && cyc.iter().all(|&x| x <= 0) {
                c.entry.insert(f);
            }
        }
        c
    }
}

/// Signs of the side products along face `f`'s outward counterclockwise cycle, given per-edge signs.
fn cycle(side: &[i8; 6], f: usize, orient: i8) -> [i8; 3] {
    let v = FACE_VERTICES[f];
    std::array::from_fn(|k| {
        let (e, rev) = edge_index(v[k], v[(k + 1) % 3]);
        orient * if rev { -side[e] } else { side[e] }
    })
}

/// The smallest over the six edges of `|side| / (|d| · |b - a| · R)`, `R` the largest coordinate
/// magnitude among the origin and the vertices: how far, relative to the f32 rounding a side product
/// suffers, the line passes from every edge. Side products are computed with rationals, then rounded.
pub fn edge_margin(tet: &Tet, ray: &Ray) -> f64 {
    let r = tet
        .iter()
        .chain([&ray.org])
        .map(|v| v.abs().max_element())
        .fold(0.0f32, f32::max) as f64;
    EDGES
        .iter()
        .map(|&[a, b]| {
            let side = sign::exact_det(tet[a], ray.org, tet[b], ray.org, ray.dir).abs();
            side / (ray.dir.as_dvec3().length() * (tet[b] - tet[a]).as_dvec3().length() * r)
        })
        .fold(f64::INFINITY, f64::min)
}

/// Exit and entry faces of the line through the closed tetrahedron (any orientation, not flat).
/// Face `f` is an exit face iff `n_f · d > 0` and the three side products along its outward cycle
/// are all `≥ 0` (the line crosses the closed triangle); entry faces likewise with `< 0` and `≤ 0`.
pub fn classify(tet: &Tet, ray: &Ray) -> Result<Classification, ExactError> {
    Ok(signs(tet, ray)?.classification())
}

/// The exit face under symbolic perturbation (Simulation of Simplicity) of the ray origin to
/// `o + ε·x + ε²·y + ε³·z`: the perturbed line meets no edge that is not parallel to `d`, so at most one
/// face is an exit face, and tetrahedra sharing a face agree on it, which makes walks with it
/// consistent. The perturbed side sign of edge `a → b` is the first nonzero of
/// `(side, -m_x, -m_y, -m_z)`, `m = (b - a) × d`. `None` when the perturbed line misses the tetrahedron.
pub fn perturbed_exit(tet: &Tet, ray: &Ray) -> Result<(Option<usize>, Classification), ExactError> {
    let mut s = signs(tet, ray)?;
    let c = s.classification();
    if c.exit.is_empty() {
        return Ok((None, c));
    }
    for (e, &[a, b]) in EDGES.iter().enumerate() {
        if s.side[e] == 0 {
            s.side[e] = perturbed_side_of_zero(tet[a], tet[b], ray);
        }
    }
    let face =
        (0..4).find(|&f| s.normal[f] > 0 && cycle(&s.side, f, s.orient).iter().all(|&x| x > 0));
    Ok((face, c))
}

/// Sign that the perturbation `o + ε·x + ε²·y + ε³·z` gives to a quantity that is zero at `o` and
/// whose gradient with respect to `o` is `-(p - q) × r`.
fn perturbed_zero(p: Vec3, q: Vec3, r: Vec3) -> i8 {
    (0..3)
        .map(|axis| -sign::sign_cross(p, q, r, axis))
        .find(|&x| x != 0)
        .unwrap_or(0)
}

/// The perturbed sign of a side product `det[a - o, b - o, d]` that is exactly zero: its gradient with
/// respect to `o` is `-(b - a) × d`. Zero only when the edge is parallel to `d`.
fn perturbed_side_of_zero(a: Vec3, b: Vec3, ray: &Ray) -> i8 {
    perturbed_zero(b, a, ray.dir)
}

/// Sign of the side product of the ray with edge `a → b`, `det[a - o, b - o, d]`, exactly (0 when the
/// line meets the edge's line or is parallel to it). Inputs must be finite.
pub fn side(a: Vec3, b: Vec3, ray: &Ray) -> i8 {
    sign::sign_det(a, ray.org, b, ray.org, ray.dir)
}

/// Sign of the side product of the ray with edge `a → b`, `det[a - o, b - o, d]`, under the perturbation
/// of [`perturbed_exit`]. Inputs must be finite.
pub fn perturbed_side(a: Vec3, b: Vec3, ray: &Ray) -> i8 {
    match side(a, b, ray) {
        0 => perturbed_side_of_zero(a, b, ray),
        s => s,
    }
}

/// Sign of `n · d` for the triangle `a, b, c` with `n = (b - a) × (c - a)`, exactly.
pub fn normal_dot(a: Vec3, b: Vec3, c: Vec3, d: Vec3) -> i8 {
    sign::sign_det(b, a, c, a, d)
}

/// Sign of `orient3d(a, b, c, o)` under the same perturbation of `o` as [`perturbed_exit`]:
/// never 0 unless `a, b, c` are collinear. Used to locate the ray origin.
pub fn perturbed_orient(a: Vec3, b: Vec3, c: Vec3, o: Vec3) -> i8 {
    let s = orientation(&[a, b, c, o]);
    if s != 0 {
        return s;
    }
    // orient3d(a, b, c, x) = -(x - a) · ((b - a) × (c - a)): its gradient is -(b - a) × (c - a).
    (0..3)
        .map(|axis| -normal_dot(a, b, c, unit(axis)))
        .find(|&x| x != 0)
        .unwrap_or(0)
}

pub(crate) fn unit(axis: usize) -> Vec3 {
    let mut v = Vec3::ZERO;
    v[axis] = 1.0;
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_tet() -> Tet {
        [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
        ]
    }

    #[test]
    fn vertical_ray_enters_bottom_leaves_slanted_face() {
        let ray = Ray {
            org: Vec3::new(0.2, 0.2, -1.0),
            dir: Vec3::Z,
        };
        let c = classify(&unit_tet(), &ray).unwrap();
        assert_eq!(c.entry.to_vec(), vec![3]);
        assert_eq!(c.exit.to_vec(), vec![0]);
        assert_eq!(perturbed_exit(&unit_tet(), &ray).unwrap().0, Some(0));
    }

    #[test]
    fn ray_through_edge_has_two_exit_faces_and_one_perturbed() {
        // From the centroid through the midpoint of edge v1 v3 = (0,1,0)-(0,0,1).
        let ray = Ray {
            org: Vec3::splat(0.25),
            dir: Vec3::new(-0.25, 0.25, 0.25),
        };
        let c = classify(&unit_tet(), &ray).unwrap();
        assert_eq!(c.exit.to_vec(), vec![0, 2]);
        let (f, _) = perturbed_exit(&unit_tet(), &ray).unwrap();
        assert!(f.is_some_and(|f| c.exit.contains(f)));
    }

    #[test]
    fn errors_are_typed() {
        let flat = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::X + Vec3::Y];
        let ray = Ray {
            org: Vec3::ZERO,
            dir: Vec3::Z,
        };
        assert_eq!(classify(&flat, &ray), Err(ExactError::FlatTet));
        let zero = Ray {
            org: Vec3::ZERO,
            dir: Vec3::ZERO,
        };
        assert_eq!(classify(&unit_tet(), &zero), Err(ExactError::ZeroDirection));
        let nan = Ray {
            org: Vec3::NAN,
            dir: Vec3::Z,
        };
        assert_eq!(classify(&unit_tet(), &nan), Err(ExactError::NonFinite));
    }
}
