//! The exit-face family's runs beyond its `Family` (a file of the engine's layer in the family's
//! folder): a predicate map's grid of exit faces (`render predicate`), and free cases for `tetwalk
//! exit` (`gen-cases` without `--row`).

use super::ExitFace;
use crate::backend::{Backend, BackendError};
use crate::cases::Case;
use crate::family::Scale;
use crate::family::contract::Contract;
use crate::registry::Method;
use crate::scenes::tets::{Target, TetShape, ulps};
use crate::tet::{Ray, Tet};

/// Free (tetrahedron, ray) cases, as `gen-cases` writes them without `--row`: each of `tries` made
/// by `make`, moved by `offset` along (1, 1, 1), and kept where `exit` can judge it (finite, a
/// direction, a tetrahedron not flat in f32); with `with_entry` given its exact entry face (the
/// lowest); at `scale`, kept where it still reads back and the oracle still judges it; made to hold
/// `contract` (keyed by the cases kept before it), kept where it then does.
pub(crate) fn free_cases<'a>(
    tries: usize,
    mut make: impl FnMut() -> Option<(Tet, Ray)> + 'a,
    offset: f32,
    with_entry: bool,
    scale: Scale,
    contract: &'a Contract,
) -> impl Iterator<Item = Case> + 'a {
    let mut kept = 0u64;
    (0..tries).filter_map(move |_| {
        let (t, ray) = make().and_then(|(t, ray)| {
            crate::scenes::tets::translated(&t, &ray, glam::Vec3::splat(offset))
        })?;
        if crate::exact::check_ray(&t, &ray).is_err() || crate::tet::orientation(&t) == 0 {
            return None;
        }
        let entry = if with_entry {
            crate::exact::classify(&t, &ray)
                .ok()
                .and_then(|c| c.entry.first())
                .map(|f| f as u8)
        } else {
            None
        };
        let case = Case {
            tet: t,
            org: ray.org,
            dir: ray.dir,
            entry,
        };
        let case = if scale.is_one() {
            case
        } else {
            crate::family::scaled_judged::<ExitFace>(&case, scale)?.0
        };
        let case = if contract.is_default() {
            case
        } else {
            crate::family::contract::within::<ExitFace>(contract, &case, kept)?.0
        };
        kept += 1;
        Some(case)
    })
}

/// The case a predicate map is drawn around: a tetrahedron of `shape` and a ray exactly through one
/// of its edges (`edge`) or vertices, from `seed`.
pub(crate) fn predicate_case(shape: TetShape, edge: bool, seed: u64) -> Option<Case> {
    let target = if edge { Target::Edge } else { Target::Vertex };
    let (tet, ray) =
        crate::scenes::tets::through(shape, 1.0, target, &mut crate::scenes::rng(seed))?;
    Some(Case {
        tet,
        org: ray.org,
        dir: ray.dir,
        entry: None,
    })
}

/// A predicate map (after Kettner et al.'s classroom examples): the case's origin moved on a
/// `size × size` grid of ulp steps in x and y around itself, each pixel the exit face `method` gives on
/// `backend` (the reference gives the exact one, ties broken as it breaks them).
pub fn predicate_grid(
    case: &Case,
    size: u32,
    method: &Method,
    backend: &Backend,
) -> Result<Vec<Option<usize>>, BackendError> {
    let half = (size / 2) as i32;
    let cases: Vec<Case> = (0..size)
        .flat_map(|y| (0..size).map(move |x| (x, y)))
        .map(|(x, y)| {
            let mut c = *case;
            c.org.x = ulps(c.org.x, x as i32 - half);
            c.org.y = ulps(c.org.y, half - y as i32);
            c
        })
        .collect();
    backend.exit_faces(method, &cases)
}
