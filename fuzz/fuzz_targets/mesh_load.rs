//! Arbitrary bytes as TetGen files and as a JSON case line (a found case too): errors are fine, panics, hangs and
//! unbounded allocations are not.
#![no_main]

use libfuzzer_sys::fuzz_target;
use tetwalk::mesh::{TetgenTexts, parse_tetgen};

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let _ = tetwalk::found::Record::parse(&text);
    // Four files separated by form feeds.
    let mut parts = text.split('\x0c');
    let (node, ele) = (parts.next().unwrap_or(""), parts.next().unwrap_or(""));
    let (neigh, face) = (parts.next(), parts.next());
    let _ = parse_tetgen(
        std::path::Path::new("fuzz"),
        &TetgenTexts {
            node,
            ele,
            neigh,
            face,
        },
    );
});
