//! Arbitrary bytes as TetGen files, as a Gmsh, VTK or MEDIT file, and as a JSON case line (a found
//! case too): errors are fine, panics, hangs and unbounded allocations are not.
#![no_main]

use libfuzzer_sys::fuzz_target;
use tetwalk::mesh::formats::{Format, parse};
use tetwalk::mesh::{Faces, TetgenTexts, parse_tetgen};

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    // A case line of whichever family its keys name, a found case too.
    if let Ok(obj) = tetwalk::cases::object(&text) {
        let _ = tetwalk::with_family!(tetwalk::family::owner(&obj), F => {
            tetwalk::engine::found::Found::<F>::from_object(obj).is_ok()
        });
    }
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
    for format in [Format::Gmsh, Format::Vtk, Format::Vtu, Format::Medit] {
        let _ = parse(data, format, Faces::Optional, "fuzz");
    }
});
