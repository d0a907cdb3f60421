//! A closed triangle mesh and a ray decoded from the input (through or near a shared edge or vertex,
//! near or far from the origin); fails when a required ray–triangle method
//! (`tetwalk::found::required_triangle_methods`) leaks: misses every triangle where the ray crosses.
#![no_main]

use libfuzzer_sys::fuzz_target;
use tetwalk::cases::{HitCase, Subject};
use tetwalk::found::fuzz_check;
use tetwalk::scenes::from_bytes::hit_case;

fuzz_target!(|data: &[u8]| {
    let mut u = arbitrary::Unstructured::new(data);
    let Ok((mesh, ray)) = hit_case(&mut u) else {
        return;
    };
    let Ok(case) = HitCase::closed(&mesh, ray) else {
        return;
    };
    if let Some(found) = fuzz_check(Subject::Hit(case)) {
        panic!("{}", found.to_json());
    }
});
