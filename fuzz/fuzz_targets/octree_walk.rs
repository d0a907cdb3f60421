//! A closed triangle mesh and a ray decoded from the input (through or near a shared edge or vertex,
//! near or far from the origin) walked through seed 001's octree over the mesh; fails on the first cell
//! whose exit face or quarter a held octree method (`tetwalk::engine::fuzz::held`) chooses wrongly
//! (printed as that cell's box case, a found case), or on a walk that never ends.
#![no_main]

use libfuzzer_sys::fuzz_target;
use tetwalk::engine::found::FoundError;
use tetwalk::engine::fuzz::held;
use tetwalk::family::OctreeCells;
use tetwalk::family::octree::engine::octree_walk;

fuzz_target!(|data: &[u8]| {
    if let Err(e) = held::<OctreeCells>() {
        panic!("{e}");
    }
    match octree_walk(data) {
        Ok(Some(found)) => panic!("{}", found.to_json()),
        Err(e @ FoundError::EndlessWalk(_)) => panic!("{e}"),
        _ => {}
    }
});
