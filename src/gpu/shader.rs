//! The WGSL module, generated from the Rust definitions and template files: the buffer structs shared
//! with the host and the bindings (each from one table, the Rust side too), the outcome codes, the face
//! tables, each method's hand-written WGSL (`src/methods/NAME.wgsl`), and the entry points filled in
//! from `src/gpu/templates/` — an exit and a walk entry point per exit-face method (and its layout
//! walks), a pair and a nearest-hit entry point per ray–triangle method, and the octree's cell exit and
//! walk once, its methods chosen by override constants. The result is committed as
//! `src/gpu/tetwalk.wgsl` for reading; `cargo run --example codegen` rewrites it, and `--check` and a test
//! (`tests/gpu_shader.rs`) fail when it is stale.

use crate::choice::Choice;
use crate::mesh::HULL;
use crate::mesh::layout::{BOUNDARY, STOP, Tet16, Tet20, Tet32};
use crate::methods::Model;
use crate::registry::{
    GpuVersion, METHODS, Method, Named, OCTREE_METHODS, TRIANGLE_METHODS, TriangleMethod,
};
use crate::tet::{EDGES, FACE_VERTICES, edge_index};
use crate::walk::OutcomeKind;
use crate::walk::layouts::LayoutKind;
use std::fmt::Write;

/// Threads per workgroup.
pub(crate) const GROUP: u32 = 64;

/// What a method's WGSL answers when its f32 stage cannot settle a case (`certified`): the CPU then
/// answers it.
pub(crate) const UNSETTLED: i32 = -2;

/// The walk code of a ray a method flagged ([`UNSETTLED`] at some step); the CPU walks it.
pub(crate) const FLAGGED: u32 = 255;

/// A `#[repr(C)]` struct shared with the shader: the Rust type and its WGSL declaration from one list.
macro_rules! shared_struct {
    ($(#[$meta:meta])* $name:ident { $($(#[$fm:meta])* $field:ident: $rust:ty => $wgsl:literal),* $(,)? }) => {
        $(#[$meta])*
        #[repr(C)]
        #[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
        pub struct $name { $($(#[$fm])* pub $field: $rust),* }

        impl $name {
            /// The WGSL declaration of this struct.
            pub const WGSL: &'static str = concat!(
                "struct ", stringify!($name), " {\n",
                $("    ", stringify!($field), ": ", $wgsl, ",\n",)*
                "}\n"
            );
        }
    };
}

shared_struct! {
    /// The uniform parameters of a dispatch (items are numbered across a 2-D grid of workgroups, so one
    /// dispatch covers any count): `limit` is a walk's step bound, or the triangles a nearest-hit
    /// search tries.
    Params {
        count: u32 => "u32",
        limit: u32 => "u32",
        /// The index of the dispatch's first item among a batch's (`compare_endings` reads the
        /// reference walk's ending of item `first + i`).
        first: u32 => "u32",
        /// The index of the dispatch's first item among the items bound: its `first` where a
        /// compared walk reads the reference walk's rays kept on the GPU, else 0.
        item_first: u32 => "u32",
    }
}

shared_struct! {
    /// One ray to walk and the tetrahedron holding its origin.
    WalkRay {
        org: [f32; 3] => "vec3f",
        start: u32 => "u32",
        dir: [f32; 3] => "vec3f",
        pad: u32 => "u32",
    }
}

shared_struct! {
    /// One ray to walk over a compact layout, with its source tetrahedron (seed 003 §4.2): its vertices
    /// and its neighbour fields as the layouts encode them.
    LayoutRay {
        org: [f32; 3] => "vec3f",
        start: u32 => "u32",
        dir: [f32; 3] => "vec3f",
        pad: u32 => "u32",
        vertices: [u32; 4] => "vec4u",
        neighbors: [u32; 4] => "vec4u",
    }
}

shared_struct! {
    /// A tetrahedron as a walk step reads it (the CPU's `mesh::Cell`): each vertex with the neighbour
    /// across the face opposite it, 64 bytes, one load per step besides [`faceinfo`](BINDINGS).
    Cell {
        v0: [f32; 3] => "vec3f",
        n0: u32 => "u32",
        v1: [f32; 3] => "vec3f",
        n1: u32 => "u32",
        v2: [f32; 3] => "vec3f",
        n2: u32 => "u32",
        v3: [f32; 3] => "vec3f",
        n3: u32 => "u32",
    }
}

shared_struct! {
    /// One exit-face case as the shader reads it (a positively oriented tetrahedron; `entry` -1 for
    /// none).
    Case {
        v0: [f32; 4] => "vec4f",
        v1: [f32; 4] => "vec4f",
        v2: [f32; 4] => "vec4f",
        v3: [f32; 4] => "vec4f",
        org: [f32; 4] => "vec4f",
        dir: [f32; 4] => "vec4f",
        entry: i32 => "i32",
        pad0: i32 => "i32",
        pad1: i32 => "i32",
        pad2: i32 => "i32",
    }
}

shared_struct! {
    /// One walk's ending as the shader writes it: [`OutcomeKind::code`], tetrahedron, face or period
    /// ([`crate::walk::Outcome::parts`]), steps.
    Ending {
        kind: u32 => "u32",
        tet: u32 => "u32",
        x: u32 => "u32",
        steps: u32 => "u32",
    }
}

shared_struct! {
    /// A walk the GPU sent back because it could not settle that it ends where the reference walk
    /// ends (`compare_endings`, `compare_hits`), or a reference walk's ending it flagged
    /// (`hold_endings`): the ray's index in its batch, its [`Ending`], and the reference walk's
    /// ending without its steps (`r_kind`, `r_tet`, `r_x`; the ending itself for `hold_endings`).
    Sent {
        index: u32 => "u32",
        kind: u32 => "u32",
        tet: u32 => "u32",
        x: u32 => "u32",
        steps: u32 => "u32",
        r_kind: u32 => "u32",
        r_tet: u32 => "u32",
        r_x: u32 => "u32",
    }
}

/// The module's bindings: each binding's index, its WGSL declaration and what it holds. The WGSL
/// lines ([`BINDINGS`]) and the indices the host binds ([`binding`]) come from this one table.
macro_rules! bindings {
    ($($(#[doc = $doc:literal])* $name:ident = $at:literal: $decl:literal;)*) => {
        /// Binding indices, from the table of [`BINDINGS`].
        pub mod binding {
            $($(#[doc = $doc])* pub const $name: u32 = $at;)*
        }

        /// The WGSL declarations of every binding.
        pub const BINDINGS: &str = concat!(
            $($("//", $doc, "\n",)* "@group(0) @binding(", stringify!($at), ") ", $decl, ";\n",)*
        );
    };
}

bindings! {
    /// The dispatch's parameters.
    PARAMS = 0: "var<uniform> params: Params";
    /// One-tetrahedron and octree cell cases, and their answers.
    CASES = 1: "var<storage, read> cases: array<Case>";
    FACES = 2: "var<storage, read_write> faces: array<i32>";
    /// The walk: rays with their starting tetrahedra, the mesh's cells, mirror faces and constrained
    /// bits (bits 0-7: the mirror face of each face, 2 bits each; bits 8-11: constrained faces), and
    /// each walk's ending.
    RAYS = 3: "var<storage, read> rays: array<WalkRay>";
    CELLS = 4: "var<storage, read> cells: array<Cell>";
    FACEINFO = 5: "var<storage, read> faceinfo: array<u32>";
    ENDINGS = 6: "var<storage, read_write> endings: array<Ending>";
    /// The layout walks: one layout's words, the mesh points (three a triangle, for ray–triangle
    /// tests), the rays with their source tetrahedra.
    LAYOUT_WORDS = 7: "var<storage, read> layout_words: array<u32>";
    POINTS = 8: "var<storage, read> points: array<vec4f>";
    LAYOUT_RAYS = 9: "var<storage, read> layout_rays: array<LayoutRay>";
    /// Seed 001's octree: eq. 3's words, each leaf's box (two points), the triangle array (ids into
    /// `points`, three points a triangle).
    OCTREE = 10: "var<storage, read> octree: array<u32>";
    OCTREE_BOXES = 11: "var<storage, read> octree_boxes: array<vec4f>";
    OCTREE_TRIS = 12: "var<storage, read> octree_tris: array<u32>";
    /// A count's comparison on the GPU: the reference walk's endings kept there, the walks sent
    /// back, and the counters (walks sent back, steps summed: low and high words).
    REFERENCE = 13: "var<storage, read> reference: array<Ending>";
    SENT = 14: "var<storage, read_write> sent: array<Sent>";
    COUNTERS = 15: "var<storage, read_write> counters: array<atomic<u32>, 4>";
    /// Where each triangle of a nearest-hit search came from: its constrained face (tetrahedron and
    /// face, from both sides), which `compare_hits` settles a hit on.
    HIT_FACES = 16: "var<storage, read> hit_faces: array<vec4u>";
}

/// A template (`src/gpu/templates/`) with each `{{key}}` replaced by its value.
fn fill(template: &str, values: &[(&str, &str)]) -> String {
    values.iter().fold(template.to_string(), |s, (k, v)| {
        s.replace(&format!("{{{{{k}}}}}"), v)
    })
}

const EXIT_WALK: &str = include_str!("templates/exit_walk.wgsl");
const LAYOUT: &str = include_str!("templates/layout.wgsl");
const TRIANGLE: &str = include_str!("templates/triangle.wgsl");
const OCTREE: &str = include_str!("templates/octree.wgsl");

/// The entry points of an exit-face method: `exit_IDENT` over cases, `walk_IDENT` over rays through a
/// mesh.
pub fn entry_points(m: &Method) -> [String; 2] {
    let id = m.ident();
    [format!("exit_{id}"), format!("walk_{id}")]
}

/// The layout entry point of `m` over `kind`: `layout_IDENT_KIND`.
pub(crate) fn layout_entry_point(m: &Method, kind: LayoutKind) -> String {
    format!("layout_{}_{}", m.ident(), kind.name())
}

/// The entry points of a ray–triangle method: `hit_IDENT` over (ray, triangle) pairs, `nearest_IDENT`
/// over rays and a list of triangles.
pub fn triangle_entry_points(m: &TriangleMethod) -> [String; 2] {
    let id = m.ident();
    [format!("hit_{id}"), format!("nearest_{id}")]
}

/// The octree's entry points: the exit of each cell case, and the walk.
pub(crate) const CELL_EXIT: &str = "cell_exit";
pub(crate) const OCTREE_WALK: &str = "octree_walk";

/// The override constant choosing the octree method of [`CELL_EXIT`] and [`OCTREE_WALK`].
pub(crate) const OCTREE_METHOD: &str = "OCTREE_METHOD";

/// The override constant choosing the ray–triangle test of [`OCTREE_WALK`].
pub(crate) const TRIANGLE_METHOD: &str = "TRIANGLE_METHOD";

/// The value of the override constant that chooses `m` among `all`: its place in the registry, or
/// `None` for a method the registry does not hold.
pub(crate) fn place<T: Named>(m: &T, all: &[T]) -> Option<f64> {
    all.iter()
        .position(|x| x.name() == m.name())
        .map(|i| i as f64)
}

/// Override constant `constant` and a `switch` on it choosing among the methods with WGSL, by their
/// place in the registry ([`place`]): `fn NAME(ARGS) -> TY` returning `call(IDENT)` for each,
/// `fallback` otherwise.
fn dispatch<T: Named>(
    (name, args, ty): (&str, &str, &str),
    constant: &str,
    methods: &[T],
    call: impl Fn(&str) -> String,
    fallback: &str,
) -> String {
    let mut s = format!(
        "override {constant}: u32 = 0u;\n\nfn {name}({args}) -> {ty} {{\n    switch {constant} {{\n"
    );
    for (i, m) in methods.iter().enumerate() {
        if let GpuVersion::Wgsl(_) = m.info().gpu {
            let _ = writeln!(s, "        case {i}u: {{ return {}; }}", call(&m.ident()));
        }
    }
    let _ = writeln!(s, "        default: {{ return {fallback}; }}");
    s + "    }\n}\n"
}

/// A `switch` function returning `ty` values from a table.
fn table<const N: usize>(name: &str, ty: &str, rows: &[[usize; N]]) -> String {
    let mut s = format!("fn {name}(i: u32) -> {ty} {{\n    switch i {{\n");
    for (i, r) in rows.iter().enumerate() {
        let vals: Vec<String> = r.iter().map(|v| format!("{v}u")).collect();
        let case = if i + 1 == rows.len() {
            "default".to_string()
        } else {
            format!("case {i}u")
        };
        let _ = writeln!(s, "        {case}: {{ return {ty}({}); }}", vals.join(", "));
    }
    s + "    }\n}\n"
}

/// A power of two as an exact WGSL hexadecimal float literal.
fn power_of_two(v: f32) -> String {
    assert!(
        v > 0.0 && v.is_normal() && v.to_bits() & 0x7f_ffff == 0,
        "{v} is not a normal power of two"
    );
    format!("0x1p{}f", (v.to_bits() >> 23) as i32 - 127)
}

/// What every entry point builds on: constants, the shared structs and bindings, the face tables and
/// the shared helpers (`common.wgsl`).
fn prelude() -> String {
    let mut s = String::new();
    let _ = writeln!(s, "const GROUP: u32 = {GROUP}u;");
    let _ = writeln!(s, "const NONE: i32 = {};", super::NONE);
    let _ = writeln!(s, "const UNSETTLED: i32 = {UNSETTLED};");
    let _ = writeln!(s, "const FLAGGED: u32 = {FLAGGED}u;");
    s += &certified_constants();
    let _ = writeln!(s, "const HULL: u32 = {HULL:#x}u;");
    s += "// What a ray-triangle method's WGSL answers for no hit (a t no ray accepts).\nconst NO_HIT: f32 = -1.0;\n";
    let _ = writeln!(s, "const MAX_F32: f32 = {:e}f;", f32::MAX);
    s += "\n// Outcome kinds (tetwalk::walk::OutcomeKind).\n";
    for k in OutcomeKind::ALL {
        let _ = writeln!(s, "const {}: u32 = {}u;", k.wgsl_name(), k.code());
    }
    s += "\n";
    s += Params::WGSL;
    s += "\n";
    s += WalkRay::WGSL;
    s += "\n";
    s += Cell::WGSL;
    s += "\n";
    s += LayoutRay::WGSL;
    s += "\n";
    s += Case::WGSL;
    s += "\n";
    s += Ending::WGSL;
    s += "\n";
    s += Sent::WGSL;
    s += "\n";
    s += BINDINGS;
    s += &face_tables();
    s += "\n// Seed 001 eqs. 8 and 9 (tetwalk::methods::portalez16), an entry per nibble and per two bits,\n// and the cell's face axes and sides (tetwalk::octree::cell).\n";
    let packed = |rows: &[[u8; 8]], bits: usize| -> String {
        rows.iter()
            .map(|r| {
                let w = r
                    .iter()
                    .enumerate()
                    .fold(0u32, |w, (i, &v)| w | (v as u32) << (bits * i));
                format!("{w:#x}u")
            })
            .collect::<Vec<_>>()
            .join(", ")
    };
    use crate::methods::portalez16::{FACE_TO_NEIGHBOR_INDEX, OUT_FACES_LOOKUP};
    let _ = writeln!(
        s,
        "const PORTALEZ16_OUT_FACES = array<u32, 8>({});",
        packed(&OUT_FACES_LOOKUP, 4)
    );
    let _ = writeln!(
        s,
        "const PORTALEZ16_NEIGHBOR = array<u32, 6>({});",
        packed(&FACE_TO_NEIGHBOR_INDEX, 2)
    );
    let _ = writeln!(
        s,
        "const PORTALEZ16_FACE_AXIS = array<u32, 6>({});",
        crate::octree::cell::FACE_AXIS
            .map(|a| format!("{a}u"))
            .join(", ")
    );
    let _ = writeln!(
        s,
        "const PORTALEZ16_FACE_HIGH = array<u32, 6>({});",
        crate::octree::cell::FACE_HIGH
            .map(|h| format!("{}u", h as u32))
            .join(", ")
    );
    s += "\n";
    s += include_str!("faces.wgsl");
    s += "\n";
    s += include_str!("common.wgsl");
    s
}

/// certified's bound constants (`tetwalk::methods::certified::{GPU, TINY}`), exactly.
fn certified_constants() -> String {
    use crate::methods::certified::{GPU, TINY};
    let mut s = String::from("// tetwalk::methods::certified::{GPU, TINY}, exactly.\n");
    for (name, v) in [
        ("CERTIFIED_A", GPU.a),
        ("CERTIFIED_MU", GPU.mu),
        ("CERTIFIED_C", GPU.c),
        ("CERTIFIED_TINY", TINY),
    ] {
        let _ = writeln!(s, "const {name}: f32 = {};", power_of_two(v));
    }
    s
}

/// The face and edge tables of a tetrahedron and Maria et al.'s, from the Rust definitions.
fn face_tables() -> String {
    let mut s = String::new();
    s += "\n// Face i's vertices, counterclockwise seen from outside (tetwalk::tet::FACE_VERTICES).\n";
    s += &table("face_vertices", "vec3u", &FACE_VERTICES);
    s += "\n// The six edges (tetwalk::tet::EDGES).\n";
    s += &table("edge_points", "vec2u", &EDGES);
    s += "\n// Index in EDGES of the edge lo -> hi (tetwalk::tet::edge_index).\n";
    s += "fn edge_index(lo: u32, hi: u32) -> i32 {\n    switch lo * 4u + hi {\n";
    for [a, b] in EDGES {
        let _ = writeln!(
            s,
            "        case {}u: {{ return {}; }}",
            a * 4 + b,
            edge_index(a, b).0
        );
    }
    s += "        default: { return -1; }\n    }\n}\n";
    s += "\n// Maria et al. 2017 Table 2 (tetwalk::methods::maria17::FACE_VERTICES).\n";
    s += &table(
        "maria17_face_vertices",
        "vec3u",
        &crate::methods::maria17::FACE_VERTICES,
    );
    s += "\n// Maria et al. 2017 Table 1 (tetwalk::methods::maria17::GET_FACE).\n";
    s += &table(
        "maria17_get_face",
        "vec3u",
        &crate::methods::maria17::GET_FACE,
    );
    s
}

/// `certified` as one self-contained WGSL module (`tetwalk export-kernel`): its constants, the
/// tables and helpers it calls, its f32 stage, and `tetwalk_certified_exit_face`, with a compute
/// entry point over a buffer of cases that shows it called.
pub(crate) fn certified_kernel() -> String {
    let mut s = String::new();
    let _ = writeln!(s, "const UNSETTLED: i32 = {UNSETTLED};");
    let _ = writeln!(s, "const MAX_F32: f32 = {:e}f;", f32::MAX);
    s += &certified_constants();
    s += &face_tables();
    s += "\n";
    s += include_str!("faces.wgsl");
    s += "\n";
    s += include_str!("../methods/certified.wgsl");
    s += "\n";
    s += include_str!("export.wgsl");
    s
}

/// The whole WGSL module.
pub fn generate() -> String {
    let mut s = String::from(
        "// GENERATED by tetwalk::gpu::shader::generate() from the Rust definitions and template files\n\
         // (src/gpu/shader.rs, src/registry.rs, src/gpu/common.wgsl, src/gpu/templates/*.wgsl,\n\
         // src/methods/*.wgsl). Do not edit: `cargo run --example codegen` rewrites it.\n\n",
    );
    s += &prelude();
    let mut included: Vec<&str> = Vec::new();
    let gpus = METHODS
        .iter()
        .map(|m| m.info().gpu)
        .chain(TRIANGLE_METHODS.iter().map(|m| m.info().gpu))
        .chain(OCTREE_METHODS.iter().map(|m| m.info().gpu));
    for g in gpus {
        if let GpuVersion::Wgsl(sources) = g {
            for src in sources {
                if !included.contains(src) {
                    included.push(src);
                    s += "\n";
                    s += src;
                }
            }
        }
    }
    s += "\n// Seed 003's layouts (tetwalk::mesh::layout).\n";
    let words = |bytes: usize| bytes / std::mem::size_of::<u32>();
    let _ = writeln!(
        s,
        "const TET32_WORDS: u32 = {}u;",
        words(size_of::<Tet32>())
    );
    let _ = writeln!(
        s,
        "const TET20_WORDS: u32 = {}u;",
        words(size_of::<Tet20>())
    );
    let _ = writeln!(
        s,
        "const TET16_WORDS: u32 = {}u;",
        words(size_of::<Tet16>())
    );
    let _ = writeln!(s, "const STOP: u32 = {STOP:#x}u;");
    let _ = writeln!(s, "const BOUNDARY: u32 = {BOUNDARY:#x}u;");
    s += include_str!("../walk/layouts.wgsl");
    for m in METHODS {
        if let GpuVersion::Wgsl(_) = m.info().gpu {
            let _ = write!(s, "\n// ---- {} ----\n\n", m.name());
            s += &fill(EXIT_WALK, &[("ident", &m.ident())]);
            if m.layout_walk(Model::Plain).is_some() {
                for kind in LayoutKind::ALL {
                    s += "\n";
                    s += &fill(LAYOUT, &[("ident", &m.ident()), ("kind", kind.name())]);
                }
            }
        }
    }
    for m in TRIANGLE_METHODS {
        if let GpuVersion::Wgsl(_) = m.info().gpu {
            let _ = write!(s, "\n// ---- {} ----\n\n", m.name());
            s += &fill(TRIANGLE, &[("ident", &m.ident())]);
        }
    }
    s += "\n// ---- the octree ----\n\n";
    let mut choosers = String::from(
        "// The octree method OCTREE_METHOD's eq. 1 (by its place in tetwalk::registry::OCTREE_METHODS).\n",
    );
    choosers += &dispatch(
        ("octree_pi", "o: vec3f, d: vec3f", "array<f32, 6>"),
        OCTREE_METHOD,
        OCTREE_METHODS,
        |id| format!("{id}_pi(o, d)"),
        "array<f32, 6>()",
    );
    choosers += "\n// The ray-triangle test TRIANGLE_METHOD (by its place in tetwalk::registry::TRIANGLE_METHODS).\n";
    choosers += &dispatch(
        (
            "triangle_hit",
            "p0: vec3f, p1: vec3f, p2: vec3f, o: vec3f, d: vec3f",
            "f32",
        ),
        TRIANGLE_METHOD,
        TRIANGLE_METHODS,
        |id| format!("{id}_hit(p0, p1, p2, o, d)"),
        "NO_HIT",
    );
    s += &fill(OCTREE, &[("choosers", &choosers)]);
    s
}

/// What a user's WGSL file (`--wgsl FILE`) must define, with `R` any type it chooses: the ray prepared
/// once (`o`, `d` as the case gives them), then for each tetrahedron (its four vertices, positively
/// oriented, face `i` opposite vertex `i`) and the face the walk entered through (`-1` in the starting
/// tetrahedron) the exit face `0..3`, or `-1` for none. It may call tetwalk's WGSL helpers under their
/// names prefixed with [`USER_PREFIX`] (`tw_face_vertices`, `tw_edge_of`, `tw_leaves`, …); no other
/// name of the module is tetwalk's.
pub(crate) const USER_SIGNATURE: &str = "fn user_prepare(o: vec3f, d: vec3f) -> R\n\
     fn user_exit(t: ptr<function, array<vec3f, 4>>, r: R, entry: i32) -> i32";

/// Prefix of every module-scope name of tetwalk's in the module built around a user's WGSL, so that
/// none can clash with theirs.
pub(crate) const USER_PREFIX: &str = "tw_";

/// The module with a user's exit-face functions spliced in as method `user`: their source first, so
/// that the compiler's line numbers are theirs, then tetwalk's module and the entry points of
/// [`crate::registry::USER_WGSL`], with every module-scope name of tetwalk's but the entry points
/// prefixed with [`USER_PREFIX`] (the names naga finds in tetwalk's module).
pub(crate) fn with_user(source: &str) -> String {
    let ours = format!(
        "{COMMITTED}\n// ---- user ----\n\n{}",
        fill(EXIT_WALK, &[("ident", "user")])
    );
    format!(
        "{source}\n// ---- tetwalk ----\n{}",
        rename_words(&ours, &module_names())
    )
}

/// Every module-scope name of tetwalk's module but the entry points: its functions, named types,
/// constants, override constants and bindings, as naga parses them.
fn module_names() -> Vec<String> {
    let Ok(m) = wgpu::naga::front::wgsl::parse_str(COMMITTED) else {
        return Vec::new();
    };
    let mut names: Vec<String> = m
        .functions
        .iter()
        .filter_map(|(_, f)| f.name.clone())
        .collect();
    names.extend(m.types.iter().filter_map(|(_, t)| t.name.clone()));
    names.extend(m.constants.iter().filter_map(|(_, c)| c.name.clone()));
    names.extend(m.overrides.iter().filter_map(|(_, o)| o.name.clone()));
    names.extend(
        m.global_variables
            .iter()
            .filter_map(|(_, g)| g.name.clone()),
    );
    names.sort();
    names.dedup();
    names
}

/// `text` with each whole word in `names` prefixed with [`USER_PREFIX`].
fn rename_words(text: &str, names: &[String]) -> String {
    let mut out = String::with_capacity(text.len() * 2);
    let mut word = String::new();
    let flush = |word: &mut String, out: &mut String| {
        if names.iter().any(|n| n == word) {
            out.push_str(USER_PREFIX);
        }
        out.push_str(word);
        word.clear();
    };
    for c in text.chars() {
        if c.is_alphanumeric() || c == '_' {
            word.push(c);
        } else {
            flush(&mut word, &mut out);
            out.push(c);
        }
    }
    flush(&mut word, &mut out);
    out
}

/// The committed module, which [`generate`] must reproduce.
pub const COMMITTED: &str = include_str!("tetwalk.wgsl");
