//! One tetrahedron and a ray decoded from the input, near-degenerate by construction; fails when a
//! held method (`tetwalk::engine::fuzz::held`) answers a face that is not an exact exit face.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| tetwalk::engine::fuzz::target::<tetwalk::family::ExitFace>(data));
