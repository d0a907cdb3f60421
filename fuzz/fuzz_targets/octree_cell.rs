//! An octree cell and a ray decoded from the input (through or near a cell edge, corner or face centre
//! line, parallel to axes, near or far from the origin); fails when a required octree method
//! (`tetwalk::found::required_octree_methods`) answers a wrong exit face or quarter (a wrong neighbour).
#![no_main]

use libfuzzer_sys::fuzz_target;
use tetwalk::cases::{BoxCase, Subject};
use tetwalk::found::fuzz_check;
use tetwalk::scenes::from_bytes::cell_case;

fuzz_target!(|data: &[u8]| {
    let mut u = arbitrary::Unstructured::new(data);
    let Ok((lo, hi, ray)) = cell_case(&mut u) else {
        return;
    };
    let case = BoxCase {
        lo,
        hi,
        org: ray.org,
        dir: ray.dir,
    };
    if let Some(found) = fuzz_check(Subject::Box(case)) {
        panic!("{}", found.to_json());
    }
});
