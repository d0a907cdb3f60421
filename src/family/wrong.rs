//! One wrong ray of a count, written out so a person can look at it and replay it: where the method
//! stopped and where the `exact` walk stopped (tetrahedron, face, its three vertex ids), the first step
//! at which the method left the exact exit set, how far the exact hit point lies from the nearest edge
//! of the method's triangle (in f32 ulps), and whether the wrong face is adjacent to the right one.

use crate::backend::BackendKind;
use crate::exact::hit::line_triangle;
use crate::mesh::Mesh;
use crate::registry::Method;
use crate::scenes::camera::Views;
use crate::tet::Case;
use crate::tet::Ray;
use crate::walk::{Divergence, Fault, Outcome, OutcomeKind, Walk};
use glam::{DVec3, Vec3};
use rug::Rational;

/// Where a walk stopped.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Stop {
    pub(crate) outcome: Outcome,
    /// The three vertex ids of the face it stopped on (hit, left mesh).
    pub vertices: Option<[u32; 3]>,
}

impl Stop {
    pub(crate) fn of(mesh: &Mesh, w: &Walk) -> Stop {
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

/// Where the ray crosses the face the `exact` walk stopped on: the parameter `t` (none when the line
/// does not cross it, as where only the perturbed ray does), and the constrained triangles holding that
/// point (as vertex ids): that face, and where the point lies on its boundary, every other one through
/// it, found by trying them all.
struct ExactHit {
    t: Option<Rational>,
    holding: Vec<[u32; 3]>,
}

impl ExactHit {
    fn of(mesh: &Mesh, ray: &Ray, tet: u32, face: u8) -> ExactHit {
        let tri = |t: u32, f: usize| mesh.face(t, f).map(|i| mesh.points[i as usize]);
        let mut holding = vec![mesh.face(tet, face as usize)];
        let Some(c) = line_triangle(tri(tet, face as usize), ray) else {
            return ExactHit { t: None, holding };
        };
        if c.on_boundary {
            for t in 0..mesh.tets.len() as u32 {
                for f in 0..4 {
                    if mesh.is_constrained(t, f)
                        && line_triangle(tri(t, f), ray).is_some_and(|x| x.t == c.t)
                    {
                        holding.push(mesh.face(t, f));
                    }
                }
            }
        }
        ExactHit {
            t: Some(c.t),
            holding,
        }
    }

    /// Whether a wrong face `mine` is adjacent to the exact hit or elsewhere.
    fn class(&self, mine: [u32; 3]) -> Class {
        let touches = self
            .holding
            .iter()
            .any(|t| t.iter().any(|v| mine.contains(v)));
        if touches {
            Class::Adjacent
        } else {
            Class::Elsewhere
        }
    }

    /// Distance of the exact hit point from the nearest edge of the triangle `v`, in f32 ulps at the
    /// point's magnitude.
    fn ulps_from_edge(&self, ray: &Ray, v: [Vec3; 3]) -> Option<f64> {
        let t = self.t.as_ref()?.to_f64();
        let p = ray.org.as_dvec3() + ray.dir.as_dvec3() * t;
        let v = v.map(|x| x.as_dvec3());
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
}

/// One wrong ray, as `count --dump` writes it (one JSON line) and `tetwalk replay` reads it.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WrongRay {
    pub(crate) scene: String,
    pub(crate) view: usize,
    /// Column and row.
    pub pixel: [u32; 2],
    /// The ray as the method saw it; each number's decimal reads back as exactly that f32.
    pub(crate) org: [f32; 3],
    pub(crate) dir: [f32; 3],
    pub(crate) method: String,
    /// Where the method answered; none for walks given from outside (`tetwalk judge`).
    pub(crate) backend: Option<BackendKind>,
    /// The kind of wrong ending ([`OutcomeKind::wrong_key`]).
    pub(crate) kind: String,
    /// For a wrong face: adjacent to the exact hit, or elsewhere.
    pub class: Option<Class>,
    /// Where the method's walk stopped, and after how many tetrahedra.
    pub(crate) stopped: Stop,
    pub(crate) steps: u32,
    /// Where the `exact` walk stopped.
    pub exact: Stop,
    /// The first step at which the method's face was not an exact exit face (the CPU walk of the same
    /// arithmetic; none for a GPU run or given walks, whose steps are not observed).
    pub(crate) divergence: Option<Divergence>,
    /// Distance of the exact hit point from the nearest edge of the method's triangle, in f32 ulps.
    pub(crate) ulps_from_edge: Option<f64>,
    /// The one-tetrahedron case of the step where the walk diverged (the case format `exit` reads:
    /// that tetrahedron, the ray, the face it was entered through), which the method fails as it
    /// failed there; `tetwalk shrink` shrinks it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) case: Option<serde_json::Map<String, serde_json::Value>>,
    /// The count that found it (its family, views and the family's settings), for `tetwalk replay`
    /// to answer the ray's view again as the count did; none in dumps written before tetwalk kept it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) count: Option<Counting>,
}

/// What a dump's line records of its count: the family counted, the views (each view's camera and
/// rays), and the family's own settings ([`super::count::Counted::CountSettings`], as JSON).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Counting {
    /// The family's name ([`super::Family::NAME`]), as a count report's `family`.
    pub(crate) family: String,
    pub(crate) views: Views,
    pub(crate) settings: serde_json::Value,
}

/// Where in a count a ray was, and who answered it: a method on a backend, or walks given from outside
/// (`tetwalk judge`, no backend), named.
#[derive(Clone, Copy)]
pub struct Seen<'a> {
    pub scene: &'a str,
    pub view: usize,
    pub pixel: [u32; 2],
    pub name: &'a str,
    pub backend: Option<BackendKind>,
    /// The exit-face method behind the answer, whose CPU walk finds the diverging step.
    pub walker: Option<&'a Method>,
}

impl WrongRay {
    /// Describe a wrong walk `w` of `ray` beside the `exact` walk `reference`, walked as `judging`
    /// says; `fault`: its first wrong step and the case sent there, where its steps were judged when
    /// asked (under a contract).
    pub(crate) fn of(
        mesh: &Mesh,
        seen: &Seen,
        ray: &Ray,
        (w, reference): (&Walk, &Walk),
        judging: &crate::walk::Judging,
        fault: Option<&Fault>,
    ) -> WrongRay {
        let (start, max_steps) = (judging.start, judging.max_steps);
        let divergence = match fault {
            Some(f) => Some(f.divergence.clone()),
            None => seen
                .walker
                .zip(seen.backend)
                .and_then(|(m, b)| Some(m.walk_checked(b.model()?)(mesh, ray, start, max_steps).1))
                .flatten(),
        };
        // For a wrong face: adjacent or elsewhere, and how far from its edge the exact hit lies (the
        // exact hit found once, since on a boundary that means trying every constrained face).
        let (class, ulps_from_edge) = match (fault, w.outcome, reference.outcome) {
            // A wrong exit face of one tetrahedron shares an edge with each of its exact ones.
            (Some(f), ..) => (
                (f.kind == OutcomeKind::Hit).then_some(Class::Adjacent),
                None,
            ),
            (None, Outcome::Hit { tet, face }, Outcome::Hit { tet: rt, face: rf }) => {
                let hit = ExactHit::of(mesh, ray, rt, rf);
                let mine = mesh.face(tet, face as usize);
                (
                    Some(hit.class(mine)),
                    hit.ulps_from_edge(ray, mine.map(|i| mesh.points[i as usize])),
                )
            }
            // No exact hit point: the `exact` walk left the mesh.
            (None, Outcome::Hit { .. }, _) => (Some(Class::Elsewhere), None),
            _ => (None, None),
        };
        WrongRay {
            scene: seen.scene.to_string(),
            view: seen.view,
            pixel: seen.pixel,
            org: ray.org.to_array(),
            dir: ray.dir.to_array(),
            method: seen.name.to_string(),
            backend: seen.backend,
            kind: fault
                .map_or(w.outcome.kind(), |f| f.kind)
                .wrong_key()
                .to_string(),
            class,
            stopped: Stop::of(mesh, w),
            steps: w.steps,
            exact: Stop::of(mesh, reference),
            case: match fault {
                Some(f) => Some(crate::cases::tet_case_json(&f.sent)),
                None => divergence.as_ref().map(|d| {
                    crate::cases::tet_case_json(&Case {
                        tet: mesh.tet(d.tet),
                        org: ray.org,
                        dir: ray.dir,
                        entry: d.entry,
                    })
                }),
            },
            divergence,
            ulps_from_edge,
            count: None,
        }
    }

    /// The ray.
    pub(crate) fn ray(&self) -> Ray {
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
