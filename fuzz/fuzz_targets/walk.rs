//! A small generated mesh (edge fan, Kuhn grid, jittered grid, near or far) and a ray decoded from the
//! input; fails when a required method's walk cycles, runs out of steps, or ends anywhere but the exact
//! first hit.
#![no_main]

use libfuzzer_sys::fuzz_target;
use tetwalk::found::{Finding, check_walk, required_methods};
use tetwalk::scenes::from_bytes::walk_case;

fuzz_target!(|data: &[u8]| {
    let methods = required_methods().expect("TETWALK_FUZZ_METHOD");
    let mut u = arbitrary::Unstructured::new(data);
    let Ok(case) = walk_case(&mut u) else { return };
    if let Some(f) = check_walk(&case, &methods) {
        panic!(
            "{}",
            serde_json::to_string(&Finding::walk(&case, f)).unwrap()
        );
    }
});
