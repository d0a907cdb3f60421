//! The conformance kit's entry point for this family (a file of the kit layer in the family's
//! folder; `crate::kit` re-exports it from the families' list).

use super::ExitFace;
use crate::family::Walks;
use crate::kit::run::check;
use crate::kit::{Failed, Passed, Settings, short_name};
use crate::methods::ExitMethod;
use crate::registry::Method;

/// Judge exit-face method `M` exactly: every stress row of tetrahedron cases, a property campaign
/// through the `exit_face` fuzz target's generator, then walks through the lattice-tie scenes (a cycle
/// or step limit is an endless walk) and a property campaign through the `walk` target's.
pub fn exit_faces<M: ExitMethod>(s: &Settings) -> Result<Passed, Box<Failed>> {
    let m = Method::outside::<M>(short_name::<M>());
    let mut passed = check::<ExitFace>(&m, s)?;
    passed.groups.extend(check::<Walks>(&m, s)?.groups);
    Ok(passed)
}
