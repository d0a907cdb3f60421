//! The `stress` flags that choose this family's rows (a file of the command line's layer in the
//! family's folder; `stress` flattens every family's).

use super::{CellRows, OctreeCells};
use crate::cli::choice;
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
