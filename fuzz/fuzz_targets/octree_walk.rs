//! A closed triangle mesh and a ray decoded from the input (through or near a shared edge or vertex,
//! near or far from the origin) walked through seed 001's octree over the mesh; fails on the first cell
//! whose exit face or quarter a held octree method (`tetwalk::engine::fuzz::held`) chooses wrongly
//! (printed as that cell's box case, a found case), or on a walk that never ends.
#![no_main]

use libfuzzer_sys::fuzz_target;
use tetwalk::engine::found::FoundError;
use tetwalk::engine::fuzz::{held, octree_walk_find};
use tetwalk::family::OctreeCells;
use tetwalk::scenes::from_bytes::hit_case;

fuzz_target!(|data: &[u8]| {
    let mut u = arbitrary::Unstructured::new(data);
    let Ok((mesh, ray)) = hit_case(&mut u) else {
        return;
    };
    if let Err(e) = held::<OctreeCells>() {
        panic!("{e}");
    }
    match octree_walk_find(&mesh, &ray) {
        Ok(Some(found)) => panic!("{}", found.to_json()),
        Err(e @ FoundError::EndlessWalk(_)) => panic!("{e}"),
        _ => {}
    }
});
