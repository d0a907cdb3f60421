//! The conformance kit's entry point for one walk case (a file of the kit layer in the family's
//! folder; `crate::kit` re-exports its public items from the families' list). Whole runs of walks
//! are part of [`crate::kit::exit_faces`].

use super::Walks;
use crate::cases::WalkCase;
use crate::kit::run::{check_case, kit_case};
use crate::kit::{Failed, Settings, short_name};
use crate::methods::ExitMethod;
use crate::registry::Method;

kit_case!(WalkCase, Walks);

/// Judge exit-face method `M` walking one walk case's generated mesh: `Ok` where the walk ends as
/// the exact walk does, else the failure (a wrong ending, a cycle or the step limit), shrunk.
pub fn judge_walk<M: ExitMethod>(case: &WalkCase, s: &Settings) -> Result<(), Box<Failed>> {
    check_case::<Walks>(&Method::outside::<M>(short_name::<M>()), case, s)
}
