//! `exact`: the oracle as a method, ties broken by symbolic perturbation so walks always progress.

use super::{Arith, ExitMethod};
use crate::exact::perturbed_exit;
use crate::tet::{Ray, Tet};

/// The exact exit face ([`crate::exact::perturbed_exit`]); where only the unperturbed line touches the
/// tetrahedron (a graze along an edge or vertex), the lowest exact exit face.
pub struct Exact;

impl ExitMethod for Exact {
    type RayData = Ray;

    fn prepare<A: Arith>(ray: &Ray) -> Ray {
        *ray
    }

    fn exit_face<A: Arith>(tet: &Tet, ray: &Ray, _entry: Option<usize>) -> Option<usize> {
        let (face, c) = perturbed_exit(tet, ray).ok()?;
        face.or(c.exit.first())
    }
}
