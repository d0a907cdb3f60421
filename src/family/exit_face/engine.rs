//! The exit-face family's runs beyond its `Family` (a file of the engine's layer in the family's
//! folder): a predicate map's grid of exit faces (`render predicate`).

use crate::backend::{Backend, BackendError};
use crate::cases::Case;
use crate::registry::Method;
use crate::scenes::tets::ulps;

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
