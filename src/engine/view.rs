//! One view of a scene, pixel by pixel (what `render` pictures): its camera placed as `count` places
//! it, and the walks' data per pixel that the pictures are drawn from.

use crate::backend::BackendError;
use crate::mesh::{Mesh, bounds};
use crate::scenes::camera::{Camera, Views};
use crate::walk::{LocateError, OutcomeKind, Walk, locate};

/// Why a view could not be walked.
#[derive(Debug, thiserror::Error)]
pub enum ViewError {
    #[error(transparent)]
    Backend(#[from] BackendError),
    #[error("view {view}'s camera is not inside the mesh: {why}")]
    Outside { view: usize, why: LocateError },
    #[error("view {view} does not exist: views are numbered 0 to {} ({views} in all)", views - 1)]
    NoSuchView { view: usize, views: usize },
    #[error("octree: {0}")]
    Octree(String),
}

/// What a view of a scene shows, per pixel (row-major): the exact walk and each method's verdict.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    pub width: u32,
    pub height: u32,
    /// The exact walk of every pixel.
    pub exact: Vec<Walk>,
    /// Per method, per pixel: the kind of wrong ending, or none.
    pub wrong: Vec<(String, Vec<Option<OutcomeKind>>)>,
    /// Shading of the exact hit: `|n · d|` in 0..=255, and whether it is a box (hull) face.
    pub shade: Vec<(u8, bool)>,
}

/// View `index`'s camera (placed as `tetwalk count` places it) and the tetrahedron holding it.
pub(crate) fn located_view(
    mesh: &Mesh,
    views: &Views,
    index: usize,
) -> Result<(Camera, u32), ViewError> {
    if index >= views.views {
        return Err(ViewError::NoSuchView {
            view: index,
            views: views.views,
        });
    }
    let (lo, hi) = bounds(&mesh.points);
    let cam = views.camera(lo, hi, index);
    let start = locate(mesh, cam.eye, 0).map_err(|why| ViewError::Outside { view: index, why })?;
    Ok((cam, start))
}
