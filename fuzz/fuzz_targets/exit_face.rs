//! One tetrahedron and a ray decoded from the input, near-degenerate by construction; fails when a
//! required method (`tetwalk::found::required_methods`) answers a face that is not an exact exit face.
#![no_main]

use libfuzzer_sys::fuzz_target;
use tetwalk::cases::Subject;
use tetwalk::found::fuzz_check;
use tetwalk::scenes::from_bytes::exit_case;

fuzz_target!(|data: &[u8]| {
    let mut u = arbitrary::Unstructured::new(data);
    let Ok(Some(case)) = exit_case(&mut u) else {
        return;
    };
    if let Some(found) = fuzz_check(Subject::Exit(case)) {
        panic!("{}", found.to_json());
    }
});
