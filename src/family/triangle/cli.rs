//! The `stress` flags that choose this family's rows (a file of the command line's layer in the
//! family's folder; `stress` flattens every family's).

use super::{TriRows, Triangle};
use crate::cli::choice;
use crate::cli::stress::{Rows, Shape, or_all};
use crate::scenes::closed::{MeshShape, TriAim, TriPlace};

/// Triangle rows.
#[derive(clap::Args)]
pub struct StressFlags {
    /// Triangle rows: closed mesh shapes (comma-separated) [default: all].
    #[arg(long, value_parser = choice::<MeshShape>(), value_delimiter = ',')]
    shapes: Vec<MeshShape>,
    /// Triangle rows: where rays are aimed (comma-separated) [default: all].
    #[arg(long, value_parser = choice::<TriAim>(), value_delimiter = ',')]
    aims: Vec<TriAim>,
    /// Triangle rows: where meshes are placed (comma-separated) [default: all].
    #[arg(long, value_parser = choice::<TriPlace>(), value_delimiter = ',')]
    places: Vec<TriPlace>,
}

impl Rows for Triangle {
    type Flags = StressFlags;
    fn own(all: &crate::cli::stress::RowFlags) -> &StressFlags {
        &all.triangle
    }
    fn given(f: &StressFlags) -> Vec<&'static str> {
        [
            ("--shapes", !f.shapes.is_empty()),
            ("--aims", !f.aims.is_empty()),
            ("--places", !f.places.is_empty()),
        ]
        .into_iter()
        .filter_map(|(flag, given)| given.then_some(flag))
        .collect()
    }
    fn chosen(f: &StressFlags, s: Shape) -> TriRows {
        TriRows {
            shapes: or_all(&f.shapes),
            aims: or_all(&f.aims),
            places: or_all(&f.places),
            flatness: s.flatness,
            ulps: s.ulps,
        }
    }
}
