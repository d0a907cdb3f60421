//! A small generated mesh (edge fan, Kuhn grid, jittered grid, near or far) and a ray decoded from the
//! input; fails when a required method's walk cycles, runs out of steps, or ends anywhere but the exact
//! first hit.
#![no_main]

use libfuzzer_sys::fuzz_target;
use tetwalk::cases::Subject;
use tetwalk::found::fuzz_check;
use tetwalk::scenes::from_bytes::walk_case;

fuzz_target!(|data: &[u8]| {
    let mut u = arbitrary::Unstructured::new(data);
    let Ok(case) = walk_case(&mut u) else { return };
    if let Some(found) = fuzz_check(Subject::Walk(case)) {
        panic!("{}", found.to_json());
    }
});
