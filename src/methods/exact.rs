//! `exact`: the oracle as a method, ties broken by symbolic perturbation so walks always progress.

use super::certified::decision_tree;
use super::maria17::FACE_VERTICES;
use super::{Arith, ExitMethod};
use crate::exact::{perturbed_exit, side};
use crate::tet::{Ray, Tet};

/// The exact exit face ([`crate::exact::perturbed_exit`]); where only the unperturbed line touches the
/// tetrahedron (a graze along an edge or vertex), the lowest exact exit face. Knowing the entry face,
/// it decides only the two signs Maria et al.'s decision tree needs, each exactly (f64 filter, then
/// exact arithmetic), and all ten only at a tie or in the starting tetrahedron: the same face, since
/// away from ties the exit face of a line entering through `e` is what the tree says.
pub struct Exact;

impl ExitMethod for Exact {
    type RayData = Ray;

    fn prepare<A: Arith>(ray: &Ray) -> Ray {
        *ray
    }

    fn exit_face<A: Arith>(tet: &Tet, ray: &Ray, entry: Option<usize>) -> Option<usize> {
        // The oracle reads subnormals as themselves, whatever the caller's model.
        crate::fpenv::standard((tet, ray), |(tet, ray)| exit_face(tet, ray, entry))
    }
}

fn exit_face(tet: &Tet, ray: &Ray, entry: Option<usize>) -> Option<usize> {
    let finite = ray.org.is_finite() && ray.dir.is_finite();
    entry
        .filter(|_| finite)
        .and_then(|e| decision_tree(e, |k| side(tet[FACE_VERTICES[e][k]], tet[e], ray)))
        .or_else(|| {
            let (face, c) = perturbed_exit(tet, ray).ok()?;
            face.or(c.exit.first())
        })
}
