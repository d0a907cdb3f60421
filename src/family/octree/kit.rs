//! The conformance kit's entry point for this family (a file of the kit layer in the family's
//! folder; `crate::kit` re-exports it from the families' list).

use super::OctreeCells;
use crate::kit::run::check;
use crate::kit::{Failed, Passed, Settings, short_name};
use crate::methods::CellMethod;
use crate::registry::OctreeMethod;

/// Judge octree cell method `M` exactly: every stress row of octree cells (aims × places), then a
/// property campaign through the `octree_cell` fuzz target's generator. A failure is an exit face the
/// line does not leave through, or a quarter (neighbour) the exit point is not in.
pub fn cells<M: CellMethod>(s: &Settings) -> Result<Passed, Box<Failed>> {
    check::<OctreeCells>(&OctreeMethod::outside::<M>(short_name::<M>()), s)
}
