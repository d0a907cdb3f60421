//! The family's flags (a file of the command line's layer in the family's folder): those of `stress`
//! that choose its rows and those of `count`; the commands flatten every family's.

use super::{TriCountSettings, TriRows, Triangle};
use crate::cli::choice;
use crate::cli::count::{FamilyFlags, Flags};
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

/// `count --family triangle`'s flags.
#[derive(clap::Args)]
pub struct CountFlags {
    /// `--family triangle`: primary rays per packet side (1, 2, 4 or 8: packets of 1, 4, 16 or 64
    /// rays sharing the camera's origin).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=8), default_value_t = 2)]
    packet: u32,
    /// `--family triangle`: test every triangle per ray (brute force), not each tile's candidates (the
    /// counts are the same; the candidates are derived in `src/family/triangle/bins.rs` and audited).
    #[arg(long)]
    brute_force: bool,
}

impl Flags for Triangle {
    type Flags = CountFlags;
    fn own(all: &FamilyFlags) -> &CountFlags {
        &all.triangle
    }
    fn settings(f: &CountFlags) -> TriCountSettings {
        TriCountSettings {
            packet: f.packet,
            brute_force: f.brute_force,
        }
    }
}
