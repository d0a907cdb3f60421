//! One tetrahedron and a ray decoded from the input, near-degenerate by construction; fails when a
//! required method (`tetwalk::found::required_methods`) answers a face that is not an exact exit face.
#![no_main]

use libfuzzer_sys::fuzz_target;
use tetwalk::found::{Finding, check_exit, required_methods};
use tetwalk::scenes::from_bytes::exit_case;

fuzz_target!(|data: &[u8]| {
    let methods = required_methods().expect("TETWALK_FUZZ_METHOD");
    let mut u = arbitrary::Unstructured::new(data);
    let Ok(Some(case)) = exit_case(&mut u) else {
        return;
    };
    if let Some(f) = check_exit(&case, &methods) {
        panic!(
            "{}",
            serde_json::to_string(&Finding::exit(&case, f)).unwrap()
        );
    }
});
