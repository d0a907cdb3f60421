//! The conformance kit's entry point for this family (a file of the kit layer in the family's
//! folder; `crate::kit` re-exports it from the families' list).

use super::Triangle;
use crate::kit::run::check;
use crate::kit::{Failed, Passed, Settings, short_name};
use crate::methods::triangle::HitMethod;
use crate::registry::TriangleMethod;

/// Judge ray–triangle method `M` exactly on closed meshes: every stress row (shapes × aims × places),
/// then a property campaign through the `triangle_hit` fuzz target's generator. A failure is a wrong
/// first hit, or with [`crate::kit::Accept::claim_only`] a leak.
pub fn triangles<M: HitMethod>(s: &Settings) -> Result<Passed, Box<Failed>> {
    check::<Triangle>(&TriangleMethod::outside::<M>(short_name::<M>()), s)
}
