//! One wrong ray of a count, written out so a person can look at it and replay it: where the method
//! stopped and where the `exact` walk stopped (tetrahedron, face, its three vertex ids), the first step
//! at which the method left the exact exit set, how far the exact hit point lies from the nearest edge
//! of the method's triangle (in f32 ulps), and whether the wrong face is adjacent to the right one.

use crate::backend::BackendKind;
use crate::exact::hit::line_triangle;
use crate::mesh::Mesh;
use crate::registry::Method;
use crate::tet::Ray;
use crate::walk::{Divergence, Outcome, OutcomeKind, Walk};
use glam::DVec3;
use rug::Rational;

/// Where a walk stopped.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Stop {
    pub outcome: Outcome,
    /// The three vertex ids of the face it stopped on (hit, left mesh).
    pub vertices: Option<[u32; 3]>,
}

impl Stop {
    pub fn of(mesh: &Mesh, w: &Walk) -> Stop {
        let vertices = match w.outcome {
            Outcome::Hit { tet, face } | Outcome::LeftMesh { tet, face } => {
                Some(mesh.face(tet, face as usize))
            }
            _ => None,
        };
        Stop {
            outcome: w.outcome,
            vertices,
        }
    }
}

/// Where a wrong face lies: touching a triangle that holds the exact hit point, or elsewhere.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Class {
    /// The method's triangle shares an edge or a vertex with a triangle holding the exact hit point.
    Adjacent,
    /// It does not (or there is no exact hit point: the `exact` walk left the mesh).
    Elsewhere,
}

/// The constrained faces' triangles (as sorted vertex ids) holding the point where the ray crosses
/// `(tet, face)`, the `exact` walk's hit: that one, and where the point lies on its boundary, every
/// other constrained triangle through it.
fn triangles_at(mesh: &Mesh, ray: &Ray, tet: u32, face: u8) -> (Option<Rational>, Vec<[u32; 3]>) {
    let tri = |t: u32, f: usize| mesh.face(t, f).map(|i| mesh.points[i as usize]);
    let Some(c) = line_triangle(tri(tet, face as usize), ray) else {
        return (None, vec![mesh.face(tet, face as usize)]);
    };
    let mut out = vec![mesh.face(tet, face as usize)];
    if c.on_boundary {
        for t in 0..mesh.tets.len() as u32 {
            for f in 0..4 {
                if mesh.is_constrained(t, f)
                    && line_triangle(tri(t, f), ray).is_some_and(|x| x.t == c.t)
                {
                    out.push(mesh.face(t, f));
                }
            }
        }
    }
    (Some(c.t), out)
}

/// Whether a wrong face (`w` a hit) is adjacent to the exact hit or elsewhere.
pub fn class(mesh: &Mesh, ray: &Ray, w: &Walk, reference: &Walk) -> Option<Class> {
    let Outcome::Hit { tet, face } = w.outcome else {
        return None;
    };
    let mine = mesh.face(tet, face as usize);
    let Outcome::Hit { tet: rt, face: rf } = reference.outcome else {
        return Some(Class::Elsewhere);
    };
    let (_, holding) = triangles_at(mesh, ray, rt, rf);
    let touches = holding.iter().any(|t| t.iter().any(|v| mine.contains(v)));
    Some(if touches {
        Class::Adjacent
    } else {
        Class::Elsewhere
    })
}

/// Distance of the exact hit point (the `exact` walk's crossing) from the nearest edge of the method's
/// triangle, in f32 ulps at the point's magnitude; `None` unless both walks hit.
pub fn ulps_from_edge(mesh: &Mesh, ray: &Ray, w: &Walk, reference: &Walk) -> Option<f64> {
    let (Outcome::Hit { tet, face }, Outcome::Hit { tet: rt, face: rf }) =
        (w.outcome, reference.outcome)
    else {
        return None;
    };
    let (t, _) = triangles_at(mesh, ray, rt, rf);
    let t = t?.to_f64();
    let p = ray.org.as_dvec3() + ray.dir.as_dvec3() * t;
    let v = mesh
        .face(tet, face as usize)
        .map(|i| mesh.points[i as usize].as_dvec3());
    let seg = |a: DVec3, b: DVec3| {
        let ab = b - a;
        let s = ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
        (a + ab * s - p).length()
    };
    let d = seg(v[0], v[1]).min(seg(v[1], v[2])).min(seg(v[2], v[0]));
    let scale = p.abs().max_element().max(f32::MIN_POSITIVE as f64);
    let ulp = 2f64.powi(scale.log2().floor() as i32 - 23);
    Some(d / ulp)
}

/// One wrong ray, as `count --dump` writes it (one JSON line) and `tetwalk replay` reads it.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WrongRay {
    pub scene: String,
    pub view: usize,
    /// Column and row.
    pub pixel: [u32; 2],
    /// The ray as the method saw it; each number's decimal reads back as exactly that f32.
    pub org: [f32; 3],
    pub dir: [f32; 3],
    pub method: String,
    pub backend: BackendKind,
    /// The kind of wrong ending ([`OutcomeKind::wrong_key`]).
    pub kind: String,
    /// For a wrong face: adjacent to the exact hit, or elsewhere.
    pub class: Option<Class>,
    /// Where the method's walk stopped, and after how many tetrahedra.
    pub stopped: Stop,
    pub steps: u32,
    /// Where the `exact` walk stopped.
    pub exact: Stop,
    /// The first step at which the method's face was not an exact exit face (the CPU walk of the same
    /// arithmetic; none for a GPU run, whose steps are not observed).
    pub divergence: Option<Divergence>,
    /// Distance of the exact hit point from the nearest edge of the method's triangle, in f32 ulps.
    pub ulps_from_edge: Option<f64>,
}

/// Where in a count a ray was, and how it was walked.
#[derive(Clone, Copy)]
pub struct Seen<'a> {
    pub scene: &'a str,
    pub view: usize,
    pub pixel: [u32; 2],
    pub method: &'a Method,
    pub backend: BackendKind,
}

impl WrongRay {
    /// Describe a wrong walk `w` of `ray` beside the `exact` walk `reference`, from `start`.
    pub fn of(
        mesh: &Mesh,
        seen: &Seen,
        ray: &Ray,
        w: &Walk,
        reference: &Walk,
        start: u32,
        max_steps: u32,
    ) -> WrongRay {
        let divergence = match seen.backend {
            BackendKind::Gpu => None,
            b => {
                let fma = b == BackendKind::CpuFma;
                seen.method.walk_checked(fma)(mesh, ray, start, max_steps).1
            }
        };
        WrongRay {
            scene: seen.scene.to_string(),
            view: seen.view,
            pixel: seen.pixel,
            org: ray.org.to_array(),
            dir: ray.dir.to_array(),
            method: seen.method.name.to_string(),
            backend: seen.backend,
            kind: w.outcome.kind().wrong_key().to_string(),
            class: class(mesh, ray, w, reference),
            stopped: Stop::of(mesh, w),
            steps: w.steps,
            exact: Stop::of(mesh, reference),
            divergence,
            ulps_from_edge: ulps_from_edge(mesh, ray, w, reference),
        }
    }

    /// The ray.
    pub fn ray(&self) -> Ray {
        Ray {
            org: self.org.into(),
            dir: self.dir.into(),
        }
    }

    /// The kind of wrong ending.
    pub fn kind(&self) -> Option<OutcomeKind> {
        OutcomeKind::from_wrong_key(&self.kind)
    }
}
