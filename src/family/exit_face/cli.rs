//! The family's flags (a file of the command line's layer in the family's folder): those of `stress`
//! that choose its rows; the commands flatten every family's.

use super::{ExitFace, ExitRows, TetRow};
use crate::cli::choice;
use crate::cli::stress::{Rows, Shape, or_all};

/// Exit-face rows.
#[derive(clap::Args)]
pub struct StressFlags {
    /// Exit-face rows (comma-separated) [default: all].
    #[arg(long, alias = "families", value_parser = choice::<TetRow>(), value_delimiter = ',')]
    rows: Vec<TetRow>,
    /// Exit-face rows: every case moved this far from the origin along (1, 1, 1) (rounded to f32;
    /// each case judged as it then is).
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.0, value_parser = finite)]
    offset: f32,
}

/// A finite f32.
fn finite(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(x) if x.is_finite() => Ok(x),
        Ok(x) => Err(format!("{x} is not finite")),
        Err(e) => Err(e.to_string()),
    }
}

impl Rows for ExitFace {
    type Flags = StressFlags;
    fn own(all: &crate::cli::stress::RowFlags) -> &StressFlags {
        &all.exit_face
    }
    fn given(f: &StressFlags) -> Vec<&'static str> {
        [
            ("--rows", !f.rows.is_empty()),
            ("--offset", f.offset != 0.0),
        ]
        .into_iter()
        .filter_map(|(flag, given)| given.then_some(flag))
        .collect()
    }
    fn chosen(f: &StressFlags, s: Shape) -> ExitRows {
        ExitRows {
            rows: or_all(&f.rows),
            flatness: s.flatness,
            ulps: s.ulps,
            offset: f.offset,
            ..ExitRows::default()
        }
    }
}
