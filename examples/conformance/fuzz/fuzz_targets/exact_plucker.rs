//! The user's exact Plücker test fuzzed on tetrahedron cases decoded as tetwalk's `exit_face` target
//! decodes its own (near-degenerate by construction); a wrong exit face panics with the kit's report.
#![no_main]

use libfuzzer_sys::fuzz_target;
use tetwalk::kit::prelude::Case;

fuzz_target!(|case: Case| tetwalk_conformance_example::fuzz_exact_plucker(case));
