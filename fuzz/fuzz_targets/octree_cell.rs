//! An octree cell and a ray decoded from the input (through or near a cell edge, corner or face centre
//! line, parallel to axes, near or far from the origin); fails when a held octree method
//! (`tetwalk::engine::fuzz::held`) answers a wrong exit face or quarter (a wrong neighbour).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| tetwalk::engine::fuzz::target::<tetwalk::family::OctreeCells>(data));
