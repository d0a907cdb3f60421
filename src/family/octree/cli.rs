//! The family's flags (a file of the command line's layer in the family's folder): those of `stress`
//! that choose its rows and those of `count`; the commands flatten every family's.

use super::{CellRows, OctreeCells, OctreeCountSettings};
use crate::cli::choice;
use crate::cli::count::{FamilyFlags, Flags};
use crate::cli::stress::{Rows, Shape, or_all};
use crate::scenes::cells::{CellAim, CellPlace};

/// Octree rows.
#[derive(clap::Args)]
pub struct StressFlags {
    /// Octree rows: where rays leave the cell (comma-separated) [default: all].
    #[arg(long, value_parser = choice::<CellAim>(), value_delimiter = ',')]
    cell_aims: Vec<CellAim>,
    /// Octree rows: where cells are placed (comma-separated) [default: all].
    #[arg(long, value_parser = choice::<CellPlace>(), value_delimiter = ',')]
    cell_places: Vec<CellPlace>,
}

impl Rows for OctreeCells {
    type Flags = StressFlags;
    fn own(all: &crate::cli::stress::RowFlags) -> &StressFlags {
        &all.octree
    }
    fn given(f: &StressFlags) -> Vec<&'static str> {
        [
            ("--cell-aims", !f.cell_aims.is_empty()),
            ("--cell-places", !f.cell_places.is_empty()),
        ]
        .into_iter()
        .filter_map(|(flag, given)| given.then_some(flag))
        .collect()
    }
    fn chosen(f: &StressFlags, s: Shape) -> CellRows {
        CellRows {
            aims: or_all(&f.cell_aims),
            places: or_all(&f.cell_places),
            ulps: s.ulps,
        }
    }
}

/// `count --family octree`'s flags.
#[derive(clap::Args)]
pub struct CountFlags {
    /// `--family octree`: the octree's deepest level (seed 001: 8 for the bunny).
    #[arg(long, default_value_t = 8)]
    depth: u32,
    /// `--family octree`: split a node while it holds more triangles than this.
    #[arg(long, default_value_t = 6)]
    capacity: usize,
    /// `--family octree`: the ray–triangle method testing each leaf's triangles.
    #[arg(long, default_value = "mt")]
    triangle_method: String,
}

impl Flags for OctreeCells {
    type Flags = CountFlags;
    fn own(all: &FamilyFlags) -> &CountFlags {
        &all.octree
    }
    fn settings(f: &CountFlags) -> OctreeCountSettings {
        OctreeCountSettings {
            octree: crate::octree::Settings {
                depth: f.depth,
                capacity: f.capacity,
            },
            triangle_method: f.triangle_method.clone(),
        }
    }
}
