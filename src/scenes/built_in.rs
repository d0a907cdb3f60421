// The one list of built-in scenes: `src/scenes/mod.rs` exports it, and `build.rs` includes this file
// to embed each scene's TetGen files (compressed) in the library, so that the binary needs no source
// tree. Plain items only: `build.rs` reads it with `include!`.

/// The scenes shipped in `corpora/scenes/` and embedded in the binary, by name.
pub const BUILT_IN: [&str; 4] = [
    "bunny-quality",
    "bunny-cdt",
    "bunny-far",
    "bunny-quality-far",
];

/// The TetGen files of a built-in scene, by extension, in the order they are embedded.
pub const BUILT_IN_FILES: [&str; 4] = ["node", "ele", "neigh", "face"];
