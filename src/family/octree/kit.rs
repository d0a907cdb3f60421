//! The conformance kit's entry points for this family (a file of the kit layer in the family's
//! folder; `crate::kit` re-exports its public items from the families' list).

use super::OctreeCells;
use crate::cases::BoxCase;
use crate::kit::run::{check, check_case, kit_case};
use crate::kit::{Failed, Passed, Settings, short_name};
use crate::methods::CellMethod;
use crate::registry::OctreeMethod;

kit_case!(BoxCase, OctreeCells);

/// Judge octree cell method `M` exactly: every stress row of octree cells (aims × places), then a
/// property campaign through the `octree_cell` fuzz target's generator. A failure is an exit face the
/// line does not leave through, or a quarter (neighbour) the exit point is not in.
pub fn cells<M: CellMethod>(s: &Settings) -> Result<Passed, Box<Failed>> {
    check::<OctreeCells>(&OctreeMethod::outside::<M>(short_name::<M>()), s)
}

/// Judge octree cell method `M` on one cell case: `Ok` where its exit face and quarter are right or
/// the line misses the cell, else the failure, shrunk.
pub fn judge_cell<M: CellMethod>(case: &BoxCase, s: &Settings) -> Result<(), Box<Failed>> {
    check_case::<OctreeCells>(&OctreeMethod::outside::<M>(short_name::<M>()), case, s)
}
