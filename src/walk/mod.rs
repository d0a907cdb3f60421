//! The walk: locate the tetrahedron holding the ray origin, then step from tetrahedron to tetrahedron
//! with a method until a constrained face or the mesh boundary. Always bounded; always a typed outcome.

pub mod layouts;
mod locate;

pub use locate::{LocateError, locate};

use crate::exact::{self, FaceSet};
use crate::mesh::{HULL, Mesh};
use crate::methods::{Arith, ExitMethod};
use crate::tet::Ray;

/// How a walk ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Outcome {
    /// Stopped on constrained face `face` of `tet`.
    Hit { tet: u32, face: u8 },
    /// Left through boundary face `face` of `tet`.
    LeftMesh { tet: u32, face: u8 },
    /// The method found no exit face in `tet`.
    NoExitFace { tet: u32 },
    /// The walk came back to a state it had been in (same tetrahedron, same entry face): it would loop
    /// forever; `period` tetrahedra per turn.
    Cycle { tet: u32, period: u32 },
    /// `max_steps` tetrahedra traversed without ending.
    StepLimit { tet: u32 },
}

impl Outcome {
    /// Position of the kind in table order: hit, left mesh, no exit face, cycle, step limit.
    pub fn index(&self) -> usize {
        match self {
            Outcome::Hit { .. } => 0,
            Outcome::LeftMesh { .. } => 1,
            Outcome::NoExitFace { .. } => 2,
            Outcome::Cycle { .. } => 3,
            Outcome::StepLimit { .. } => 4,
        }
    }

    pub fn kind(&self) -> &'static str {
        match self {
            Outcome::Hit { .. } => "hit",
            Outcome::LeftMesh { .. } => "left_mesh",
            Outcome::NoExitFace { .. } => "no_exit_face",
            Outcome::Cycle { .. } => "cycle",
            Outcome::StepLimit { .. } => "step_limit",
        }
    }
}

/// A walk's outcome and the number of tetrahedra it traversed (exit faces asked for).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Walk {
    pub outcome: Outcome,
    pub steps: u32,
}

/// The first step of a checked walk at which the method's face was not an exact exit face.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Divergence {
    /// 1-based step.
    pub step: u32,
    pub tet: u32,
    /// What the method answered.
    pub face: Option<u8>,
    /// The exact exit faces there (empty when the line misses that tetrahedron).
    pub exact_exit: [bool; 4],
}

/// A walk specialised to one method and arithmetic: `(mesh, ray, start tetrahedron, max_steps)`.
pub type WalkFn = fn(&Mesh, &Ray, u32, u32) -> Walk;
/// The same, checking every step against the oracle.
pub type CheckedWalkFn = fn(&Mesh, &Ray, u32, u32) -> (Walk, Option<Divergence>);

/// A generous step cap for `mesh`: a walk has at most `4 × tetrahedra` distinct states, so any walk
/// longer than that has cycled, and cycle detection stops it within twice that.
pub fn default_max_steps(mesh: &Mesh) -> u32 {
    (mesh.tets.len() as u32)
        .saturating_mul(8)
        .saturating_add(64)
}

/// [`walk`], also listing the tetrahedra visited, in order.
pub fn walk_traced<M: ExitMethod, A: Arith>(
    mesh: &Mesh,
    ray: &Ray,
    start: u32,
    max_steps: u32,
) -> (Walk, Vec<u32>) {
    let mut visited = Vec::new();
    let w = walk_observed::<M, A>(mesh, ray, start, max_steps, |t, _, _| visited.push(t));
    (w, visited)
}

/// Walk with method `M` from `start` (which must contain the ray origin).
pub fn walk<M: ExitMethod, A: Arith>(mesh: &Mesh, ray: &Ray, start: u32, max_steps: u32) -> Walk {
    walk_observed::<M, A>(mesh, ray, start, max_steps, |_, _, _| {})
}

/// [`walk`], judging every step with the exact oracle and reporting the first wrong one.
pub fn walk_checked<M: ExitMethod, A: Arith>(
    mesh: &Mesh,
    ray: &Ray,
    start: u32,
    max_steps: u32,
) -> (Walk, Option<Divergence>) {
    let mut first = None;
    let mut step = 0;
    let w = walk_observed::<M, A>(mesh, ray, start, max_steps, |tet, _entry, face| {
        step += 1;
        if first.is_some() {
            return;
        }
        let exit = exact::classify(&mesh.tet(tet), ray).map_or(FaceSet::default(), |c| c.exit);
        if !face.is_some_and(|f| exit.contains(f)) {
            first = Some(Divergence {
                step,
                tet,
                face: face.map(|f| f as u8),
                exact_exit: std::array::from_fn(|f| exit.contains(f)),
            });
        }
    });
    (w, first)
}

/// The walk loop; `observe(tet, entry, face)` sees every step (a no-op closure compiles away).
/// Cycle detection is Brent's: one state comparison per step, no allocation.
#[inline(always)]
fn walk_observed<M: ExitMethod, A: Arith>(
    mesh: &Mesh,
    ray: &Ray,
    start: u32,
    max_steps: u32,
    mut observe: impl FnMut(u32, Option<usize>, Option<usize>),
) -> Walk {
    let data = M::prepare::<A>(ray);
    let (mut tet, mut entry) = (start, None);
    let mut brent = Brent::new((tet, entry));
    for steps in 1..=max_steps {
        let face = M::exit_face::<A>(&mesh.tet(tet), &data, entry);
        observe(tet, entry, face);
        let end = |outcome| Walk { outcome, steps };
        let Some(f) = face else {
            return end(Outcome::NoExitFace { tet });
        };
        if mesh.is_constrained(tet, f) {
            return end(Outcome::Hit { tet, face: f as u8 });
        }
        let next = mesh.neighbors[tet as usize][f];
        if next == HULL {
            return end(Outcome::LeftMesh { tet, face: f as u8 });
        }
        entry = Some(mesh.mirror[tet as usize][f] as usize);
        tet = next;
        if let Some(period) = brent.step((tet, entry)) {
            return end(Outcome::Cycle { tet, period });
        }
    }
    Walk {
        outcome: Outcome::StepLimit { tet },
        steps: max_steps,
    }
}

/// Whether walk `w` ends rightly, `reference` being the `exact` walk of the same ray: both leave the
/// mesh, or `w` stops on a constrained face that contains the exact point where the ray first meets the
/// constrained faces — the reference's hit point (a point on a shared edge or vertex may be claimed by
/// any face holding it), or, where the reference left the mesh, a point where the ray grazes the
/// boundary of a constrained face (the reference's perturbation passes beside it; the true ray touches it).
pub fn same_result(mesh: &Mesh, ray: &Ray, w: &Walk, reference: &Walk) -> bool {
    let tri = |t: u32, f: u8| {
        let mut v = mesh.face(t, f as usize);
        v.sort_unstable();
        v
    };
    let crossing = |t: u32, f: u8| {
        let p = mesh.face(t, f as usize).map(|i| mesh.points[i as usize]);
        exact::hit::line_triangle(p, ray).filter(|c| c.t.cmp0().is_ge())
    };
    match (w.outcome, reference.outcome) {
        (Outcome::LeftMesh { .. }, Outcome::LeftMesh { .. }) => true,
        (Outcome::Hit { tet, face }, Outcome::Hit { tet: rt, face: rf }) => {
            tri(tet, face) == tri(rt, rf)
                || matches!((crossing(tet, face), crossing(rt, rf)), (Some(x), Some(y)) if x.t == y.t)
        }
        (Outcome::Hit { tet, face }, Outcome::LeftMesh { .. }) => {
            crossing(tet, face).is_some_and(|c| c.on_boundary)
        }
        _ => false,
    }
}

/// Brent's cycle detection over a walk's states (tetrahedron and entry face).
struct Brent<S> {
    saved: S,
    power: u32,
    lam: u32,
}

impl<S: PartialEq> Brent<S> {
    fn new(s: S) -> Self {
        Brent {
            saved: s,
            power: 1,
            lam: 0,
        }
    }

    /// Feed the next state; the cycle length once a state repeats.
    #[inline(always)]
    fn step(&mut self, s: S) -> Option<u32> {
        self.lam += 1;
        if s == self.saved {
            return Some(self.lam);
        }
        if self.lam == self.power {
            self.saved = s;
            self.power = self.power.saturating_mul(2);
            self.lam = 0;
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn brent_finds_the_period() {
        let seq = [1u32, 2, 3, 4, 5, 6, 4, 5, 6, 4, 5, 6, 4, 5, 6, 4, 5, 6];
        let mut b = Brent::new((0u32, None::<usize>));
        let found = seq.iter().find_map(|&x| b.step((x, None)));
        assert_eq!(found, Some(3));
    }
}
