//! A small generated mesh (edge fan, Kuhn grid, jittered grid, near or far) and a ray decoded from the
//! input; fails when a held method's walk cycles, runs out of steps, or ends anywhere but the exact
//! first hit.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| tetwalk::engine::fuzz::target::<tetwalk::family::Walks>(data));
