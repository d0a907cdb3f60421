//! Embeds the built-in scenes (`src/scenes/built_in.rs` lists them): each TetGen file of
//! `corpora/scenes/` compressed with zlib into `OUT_DIR`, and a table of them that
//! `src/scenes/mod.rs` includes. The binary then reads no file of the source tree.

use std::fmt::Write as _;
use std::path::Path;

include!("src/scenes/built_in.rs");

fn main() {
    let out = std::env::var("OUT_DIR").expect("cargo sets OUT_DIR");
    println!("cargo::rerun-if-changed=src/scenes/built_in.rs");
    let mut table = String::from(
        "/// Each built-in scene's TetGen files, zlib-compressed, in `BUILT_IN_FILES` order.\n\
         pub(crate) static EMBEDDED: [(&str, [&[u8]; BUILT_IN_FILES.len()]); BUILT_IN.len()] = [\n",
    );
    for name in BUILT_IN {
        let _ = write!(table, "    ({name:?}, [");
        for ext in BUILT_IN_FILES {
            let from = format!("corpora/scenes/{name}.{ext}");
            println!("cargo::rerun-if-changed={from}");
            let text = std::fs::read(&from).unwrap_or_else(|e| panic!("{from}: {e}"));
            let packed = miniz_oxide::deflate::compress_to_vec_zlib(&text, 6);
            let to = Path::new(&out).join(format!("{name}.{ext}.z"));
            std::fs::write(&to, packed).unwrap_or_else(|e| panic!("{}: {e}", to.display()));
            let _ = write!(table, "include_bytes!({:?}), ", to.display().to_string());
        }
        table += "]),\n";
    }
    table += "];\n";
    let to = Path::new(&out).join("built_in_scenes.rs");
    std::fs::write(&to, table).unwrap_or_else(|e| panic!("{}: {e}", to.display()));
}
