//! The conformance kit's entry points for this family (a file of the kit layer in the family's
//! folder; `crate::kit` re-exports its public items from the families' list).

use super::Triangle;
use crate::cases::HitCase;
use crate::kit::run::{check, check_case, kit_case};
use crate::kit::{Failed, Passed, Settings, short_name};
use crate::methods::triangle::HitMethod;
use crate::registry::TriangleMethod;

kit_case!(HitCase, Triangle);

/// Judge ray–triangle method `M` exactly on closed meshes: every stress row (shapes × aims × places),
/// then a property campaign through the `triangle_hit` fuzz target's generator. A failure is a wrong
/// first hit, or with [`crate::kit::Accept::claim_only`] a leak.
pub fn triangles<M: HitMethod>(s: &Settings) -> Result<Passed, Box<Failed>> {
    check::<Triangle>(&TriangleMethod::outside::<M>(short_name::<M>()), s)
}

/// Judge ray–triangle method `M` on one case: `Ok` where its first hit is right (with
/// [`crate::kit::Accept::claim_only`]: where it does not leak), else the failure, shrunk.
pub fn judge_triangle<M: HitMethod>(case: &HitCase, s: &Settings) -> Result<(), Box<Failed>> {
    check_case::<Triangle>(&TriangleMethod::outside::<M>(short_name::<M>()), case, s)
}
