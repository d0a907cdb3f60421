//! The `stress` flags that choose this family's rows (a file of the command line's layer in the
//! family's folder; `stress` flattens every family's).

use super::{WalkRows, WalkScene, Walks};
use crate::cli::choice;
use crate::cli::stress::{Rows, Shape, or_all};

/// Walk rows.
#[derive(clap::Args)]
pub struct StressFlags {
    /// Walk rows: the scenes walked (comma-separated) [default: all].
    #[arg(long, value_parser = choice::<WalkScene>(), value_delimiter = ',')]
    scenes: Vec<WalkScene>,
}

impl Rows for Walks {
    type Flags = StressFlags;
    fn own(all: &crate::cli::stress::RowFlags) -> &StressFlags {
        &all.walk
    }
    fn given(f: &StressFlags) -> Vec<&'static str> {
        if f.scenes.is_empty() {
            vec![]
        } else {
            vec!["--scenes"]
        }
    }
    fn chosen(f: &StressFlags, _: Shape) -> WalkRows {
        WalkRows {
            scenes: or_all(&f.scenes),
        }
    }
}
