//! A closed triangle mesh and a ray decoded from the input (through or near a shared edge or vertex,
//! near or far from the origin); fails when a held ray–triangle method (`tetwalk::engine::fuzz::held`)
//! leaks (misses every triangle where the ray crosses), or, held to every answer, is wrong.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| tetwalk::engine::fuzz::target::<tetwalk::family::Triangle>(data));
