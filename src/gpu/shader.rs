//! The WGSL module, generated from the Rust definitions: the buffer structs shared with the host, the
//! outcome codes, the face tables, and one exit entry point and one walk entry point per registered
//! method, around each method's hand-written WGSL (`src/methods/NAME.wgsl`). The result is committed as
//! `src/gpu/tetwalk.wgsl` for reading; a test fails when it is stale (`TETWALK_BLESS=1` rewrites it).

use crate::choice::Choice;
use crate::mesh::HULL;
use crate::mesh::layout::{BOUNDARY, STOP, Tet16, Tet20, Tet32};
use crate::methods::Model;
use crate::registry::{
    Gpu, METHODS, Method, Named, OCTREE_METHODS, OctreeMethod, TRIANGLE_METHODS, TriangleMethod,
};
use crate::tet::{EDGES, FACE_VERTICES, edge_index};
use crate::walk::OutcomeKind;
use crate::walk::layouts::Kind;
use std::fmt::Write;

/// Threads per workgroup.
pub const GROUP: u32 = 64;

/// What a method's WGSL answers when its f32 stage cannot settle a case (`certified`): the CPU then
/// answers it.
pub const UNSETTLED: i32 = -2;

/// The walk code of a ray a method flagged ([`UNSETTLED`] at some step); the CPU walks it.
pub const FLAGGED: u32 = 255;

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
        pad0: u32 => "u32",
        pad1: u32 => "u32",
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

/// The entry points of a method: `exit_IDENT` over cases, `walk_IDENT` over rays through a mesh.
pub fn entry_points(m: &Method) -> [String; 2] {
    let id = m.ident();
    [format!("exit_{id}"), format!("walk_{id}")]
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

const BINDINGS: &str = "\
@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> cases: array<Case>;
@group(0) @binding(2) var<storage, read_write> faces: array<i32>;
// The walk: rays with their starting tetrahedra, the mesh's cells, mirror faces and constrained bits.
@group(0) @binding(3) var<storage, read> rays: array<WalkRay>;
@group(0) @binding(4) var<storage, read> cells: array<Cell>;
// Bits 0-7: mirror face of each face (2 bits each); bits 8-11: constrained faces.
@group(0) @binding(5) var<storage, read> faceinfo: array<u32>;
@group(0) @binding(6) var<storage, read_write> endings: array<Ending>;
// The layout walks: one layout's words, the mesh points, the rays with their source tetrahedra.
@group(0) @binding(7) var<storage, read> layout_words: array<u32>;
@group(0) @binding(8) var<storage, read> points: array<vec4f>;
@group(0) @binding(9) var<storage, read> layout_rays: array<LayoutRay>;
// Seed 001's octree: eq. 3's words, each leaf's box (two points), the triangle array (ids into
// `points`, three points a triangle).
@group(0) @binding(10) var<storage, read> octree: array<u32>;
@group(0) @binding(11) var<storage, read> octree_boxes: array<vec4f>;
@group(0) @binding(12) var<storage, read> octree_tris: array<u32>;

// The item a thread answers, numbered across the 2-D grid of workgroups.
fn item(gid: vec3u, groups: vec3u) -> u32 {
    return gid.x + gid.y * groups.x * GROUP;
}

// The neighbour across face f.
fn neighbor(c: Cell, f: u32) -> u32 {
    return select(select(c.n0, c.n1, f == 1u), select(c.n2, c.n3, f == 3u), f >= 2u);
}
";

/// The entry points of one method (`IDENT` replaced by its identifier): the exit face of each case,
/// and the bounded walk of each ray with Brent's cycle detection on (tetrahedron, entry face), as
/// `crate::walk::walk` does, the ray prepared once.
const ENTRY_POINTS: &str = "\
@compute @workgroup_size(GROUP)
fn exit_IDENT(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let i = item(gid, groups);
    if i >= params.count {
        return;
    }
    let c = cases[i];
    var t = array<vec3f, 4>(c.v0.xyz, c.v1.xyz, c.v2.xyz, c.v3.xyz);
    faces[i] = IDENT_exit(&t, IDENT_prepare(c.org.xyz, c.dir.xyz), c.entry);
}

@compute @workgroup_size(GROUP)
fn walk_IDENT(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let i = item(gid, groups);
    if i >= params.count {
        return;
    }
    let ray = rays[i];
    let r = IDENT_prepare(ray.org, ray.dir);
    var tet = ray.start;
    var entry = NONE;
    var saved_tet = tet;
    var saved_entry = entry;
    var power = 1u;
    var lam = 0u;
    for (var steps = 1u; steps <= params.limit; steps++) {
        let c = cells[tet];
        var t = array<vec3f, 4>(c.v0, c.v1, c.v2, c.v3);
        let f = IDENT_exit(&t, r, entry);
        if f == UNSETTLED {
            endings[i] = Ending(FLAGGED, tet, 0u, steps);
            return;
        }
        if f < 0 {
            endings[i] = Ending(NO_EXIT_FACE, tet, 0u, steps);
            return;
        }
        let fu = u32(f);
        let info = faceinfo[tet];
        if ((info >> (8u + fu)) & 1u) == 1u {
            endings[i] = Ending(HIT, tet, fu, steps);
            return;
        }
        let next = neighbor(c, fu);
        if next == HULL {
            endings[i] = Ending(LEFT_MESH, tet, fu, steps);
            return;
        }
        entry = i32((info >> (2u * fu)) & 3u);
        tet = next;
        lam += 1u;
        if tet == saved_tet && entry == saved_entry {
            endings[i] = Ending(CYCLE, tet, lam, steps);
            return;
        }
        if lam == power {
            saved_tet = tet;
            saved_entry = entry;
            power = power * 2u;
            lam = 0u;
        }
    }
    endings[i] = Ending(STEP_LIMIT, tet, 0u, params.limit);
}
";

/// The layout walk of one method over one layout (`IDENT`, `KIND` replaced), as
/// `crate::walk::layouts::walk_layout` does: the source's four vertices projected, §4's start, then per
/// tetrahedron one vertex fetched (decoded from the xor-sum), projected, Algorithm 1, and the next
/// tetrahedron decoded; Brent's detection on (tetrahedron, vertex across the exit face).
const LAYOUT_ENTRY_POINT: &str = "\
@compute @workgroup_size(GROUP)
fn layout_IDENT_KIND(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let i = item(gid, groups);
    if i >= params.count {
        return;
    }
    let ray = layout_rays[i];
    let r = IDENT_prepare(ray.org, ray.dir);
    var p4: array<vec2f, 4>;
    for (var k = 0u; k < 4u; k++) {
        p4[k] = IDENT_project(r, points[ray.vertices[k]].xyz);
    }
    let f0 = start_exit_face(&p4);
    if f0 < 0 {
        endings[i] = Ending(NO_EXIT_FACE, ray.start, 0u, 1u);
        return;
    }
    let f = u32(f0);
    let fv = face_vertices(f);
    var idx = vec3u(ray.vertices[fv.x], ray.vertices[fv.y], ray.vertices[fv.z]);
    var p = array<vec2f, 3>(p4[fv.x], p4[fv.y], p4[fv.z]);
    var tet = ray.start;
    var next = ray.neighbors[f];
    var across = ray.vertices[f];
    var saved_tet = tet;
    var saved_across = 0xffffffffu;
    var power = 1u;
    var lam = 0u;
    var steps = 1u;
    loop {
        if (next & STOP) != 0u {
            endings[i] = Ending(select(HIT, LEFT_MESH, next == (STOP | BOUNDARY)), tet, across, steps);
            return;
        }
        lam += 1u;
        if tet == saved_tet && across == saved_across {
            endings[i] = Ending(CYCLE, next, lam, steps);
            return;
        }
        if lam == power {
            saved_tet = tet;
            saved_across = across;
            power = power * 2u;
            lam = 0u;
        }
        if steps >= params.limit {
            endings[i] = Ending(STEP_LIMIT, next, 0u, steps);
            return;
        }
        let prev = tet;
        tet = next;
        steps += 1u;
        let fourth = idx.x ^ idx.y ^ idx.z ^ KIND_vx(tet);
        let p3 = IDENT_project(r, points[fourth].xyz);
        var q = array<vec2f, 4>(p[0], p[1], p[2], p3);
        let k = get_exit_face(&q);
        across = idx[k];
        next = KIND_next(tet, prev, vec4u(idx, fourth), across);
        idx[k] = fourth;
        p[k] = p3;
    }
}
";

/// The entry points of one ray–triangle method (`IDENT` replaced): `hit_IDENT` answers one (ray,
/// triangle) pair per item (the ray's `start` names the triangle, three `points` each), `nearest_IDENT`
/// one ray's nearest hit among the first `params.limit` triangles, every one tried, as
/// `crate::methods::triangle::nearest` keeps it (the first with the smallest accepted `t`). The answer
/// is an [`Ending`]: `HIT` with the triangle and the bits of `t`, or `LEFT_MESH` for none.
const TRIANGLE_ENTRY_POINTS: &str = "\
@compute @workgroup_size(GROUP)
fn hit_IDENT(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let i = item(gid, groups);
    if i >= params.count {
        return;
    }
    let ray = rays[i];
    let k = 3u * ray.start;
    let t = IDENT_hit(points[k].xyz, points[k + 1u].xyz, points[k + 2u].xyz, ray.org, ray.dir);
    if accepts(t) {
        endings[i] = Ending(HIT, ray.start, bitcast<u32>(t), 1u);
    } else {
        endings[i] = Ending(LEFT_MESH, ray.start, 0u, 1u);
    }
}

@compute @workgroup_size(GROUP)
fn nearest_IDENT(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let i = item(gid, groups);
    if i >= params.count {
        return;
    }
    let ray = rays[i];
    var best = HULL;
    var best_t = 0.0;
    for (var k = 0u; k < params.limit; k++) {
        let t = IDENT_hit(points[3u * k].xyz, points[3u * k + 1u].xyz, points[3u * k + 2u].xyz, ray.org, ray.dir);
        if accepts(t) && (best == HULL || t < best_t) {
            best = k;
            best_t = t;
        }
    }
    if best == HULL {
        endings[i] = Ending(LEFT_MESH, 0u, 0u, params.limit);
    } else {
        endings[i] = Ending(HIT, best, bitcast<u32>(best_t), params.limit);
    }
}
";

/// The entry points of a ray–triangle method: `hit_IDENT` over (ray, triangle) pairs, `nearest_IDENT`
/// over rays and a list of triangles.
pub fn triangle_entry_points(m: &TriangleMethod) -> [String; 2] {
    let id = m.ident();
    [format!("hit_{id}"), format!("nearest_{id}")]
}

/// The layout entry point of `m` over `kind`: `layout_IDENT_KIND`.
pub fn layout_entry_point(m: &Method, kind: Kind) -> String {
    format!("layout_{}_{}", m.ident(), kind.name())
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
    {
        use crate::methods::certified::{GPU, TINY};
        s += "// tetwalk::methods::certified::{GPU, TINY}, exactly.\n";
        for (name, v) in [
            ("CERTIFIED_A", GPU.a),
            ("CERTIFIED_MU", GPU.mu),
            ("CERTIFIED_C", GPU.c),
            ("CERTIFIED_TINY", TINY),
        ] {
            let _ = writeln!(s, "const {name}: f32 = {};", power_of_two(v));
        }
    }
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
    s += BINDINGS;
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
    s += include_str!("common.wgsl");
    s
}

/// The whole WGSL module.
pub fn generate() -> String {
    let mut s = String::from(
        "// GENERATED by tetwalk::gpu::shader::generate() from the Rust definitions (src/gpu/shader.rs,\n\
         // src/registry.rs, src/gpu/common.wgsl, src/methods/*.wgsl). Do not edit: run\n\
         // `TETWALK_BLESS=1 cargo test --release --test gpu_shader` to rewrite it.\n\n",
    );
    s += &prelude();
    let mut included: Vec<&str> = Vec::new();
    let gpus = METHODS
        .iter()
        .map(|m| m.info().gpu)
        .chain(TRIANGLE_METHODS.iter().map(|m| m.info().gpu))
        .chain(OCTREE_METHODS.iter().map(|m| m.info().gpu));
    for g in gpus {
        if let Gpu::Wgsl(sources) = g {
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
        if let Gpu::Wgsl(_) = m.info().gpu {
            let _ = write!(s, "\n// ---- {} ----\n\n", m.name());
            s += &ENTRY_POINTS.replace("IDENT", &m.ident());
            if m.layout_walk(Model::Plain).is_some() {
                for kind in Kind::ALL {
                    s += "\n";
                    s += &LAYOUT_ENTRY_POINT
                        .replace("IDENT", &m.ident())
                        .replace("KIND", kind.name());
                }
            }
        }
    }
    for m in TRIANGLE_METHODS {
        if let Gpu::Wgsl(_) = m.info().gpu {
            let _ = write!(s, "\n// ---- {} ----\n\n", m.name());
            s += &TRIANGLE_ENTRY_POINTS.replace("IDENT", &m.ident());
        }
    }
    for m in OCTREE_METHODS {
        if let Gpu::Wgsl(_) = m.info().gpu {
            let _ = write!(s, "\n// ---- {} ----\n\n", m.name());
            s += &CELL_ENTRY_POINT.replace("IDENT", &m.ident());
            for t in TRIANGLE_METHODS {
                if let Gpu::Wgsl(_) = t.info().gpu {
                    s += "\n";
                    s += &OCTREE_ENTRY_POINT
                        .replace("IDENT", &m.ident())
                        .replace("TRI", &t.ident());
                }
            }
        }
    }
    s
}

/// The octree walk of an octree method with a ray–triangle method (`IDENT`, `TRI`): seed 001 §4.2.3
/// from each ray's entry cell (`start`, an address in eq. 3's words; `HULL` for a ray that misses the
/// root), as `crate::walk::octree::walk` walks, with Brent's cycle detection on the cell. Endings: a hit
/// (triangle, `t` as bits), a miss, no exit face, a cycle (period) or the step limit, each with the
/// cells visited.
const OCTREE_ENTRY_POINT: &str = "\
@compute @workgroup_size(GROUP)
fn octree_IDENT_TRI(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let i = item(gid, groups);
    if i >= params.count {
        return;
    }
    let ray = rays[i];
    if ray.start == HULL {
        endings[i] = Ending(LEFT_MESH, 0u, 0u, 0u);
        return;
    }
    let pi = IDENT_pi(ray.org, ray.dir);
    var a = ray.start;
    var saved = a;
    var power = 1u;
    var lam = 0u;
    for (var cells = 1u; cells <= params.limit; cells++) {
        let count = octree[a];
        let offset = octree[a + 1u];
        let cell = octree[a + 2u];
        var best = HULL;
        var best_t = 0.0;
        for (var k = 0u; k < count; k++) {
            let tri = octree_tris[offset + k];
            let t = TRI_hit(points[3u * tri].xyz, points[3u * tri + 1u].xyz, points[3u * tri + 2u].xyz, ray.org, ray.dir);
            if accepts(t) && (best == HULL || t < best_t) {
                best = tri;
                best_t = t;
            }
        }
        if best != HULL {
            endings[i] = Ending(HIT, best, bitcast<u32>(best_t), cells);
            return;
        }
        let fq = portalez16_cell(pi, octree_boxes[2u * cell].xyz, octree_boxes[2u * cell + 1u].xyz, ray.dir);
        if fq < 0 {
            endings[i] = Ending(NO_EXIT_FACE, cell, 0u, cells);
            return;
        }
        let f = u32(fq) / 4u;
        let counts = octree[a + 3u];
        var before = 0u;
        for (var g = 0u; g < f; g++) {
            before += (counts >> (4u * g)) & 15u;
        }
        let n = (counts >> (4u * f)) & 15u;
        if n == 0u {
            endings[i] = Ending(LEFT_MESH, cell, 0u, cells);
            return;
        }
        a = octree[a + 4u + before + (n / 4u) * (u32(fq) % 4u)];
        lam += 1u;
        if a == saved {
            endings[i] = Ending(CYCLE, octree[a + 2u], lam, cells);
            return;
        }
        if lam == power {
            saved = a;
            power *= 2u;
            lam = 0u;
        }
    }
    endings[i] = Ending(STEP_LIMIT, octree[a + 2u], 0u, params.limit);
}
";

/// The octree walk entry point of an octree method with a ray–triangle method.
pub fn octree_entry_point(m: &OctreeMethod, t: &TriangleMethod) -> String {
    format!("octree_{}_{}", m.ident(), t.ident())
}

/// The entry point of an octree method (`IDENT` replaced by its identifier): the exit face and quarter
/// of each cell case (`v0` the lower corner, `v1` the upper), as `4 f + q`, or `NONE`.
const CELL_ENTRY_POINT: &str = "\
@compute @workgroup_size(GROUP)
fn cell_IDENT(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let i = item(gid, groups);
    if i >= params.count {
        return;
    }
    let c = cases[i];
    faces[i] = portalez16_cell(IDENT_pi(c.org.xyz, c.dir.xyz), c.v0.xyz, c.v1.xyz, c.dir.xyz);
}
";

/// The entry point of an octree method: `cell_IDENT`.
pub fn cell_entry_point(m: &OctreeMethod) -> String {
    format!("cell_{}", m.ident())
}

/// What a user's WGSL file (`--wgsl FILE`) must define, with `R` any type it chooses: the ray prepared
/// once (`o`, `d` as the case gives them), then for each tetrahedron (its four vertices, positively
/// oriented, face `i` opposite vertex `i`) and the face the walk entered through (`-1` in the starting
/// tetrahedron) the exit face `0..3`, or `-1` for none. It may call tetwalk's WGSL helpers under their
/// names prefixed with [`USER_PREFIX`] (`tw_face_vertices`, `tw_edge_of`, `tw_leaves`, …); no other
/// name of the module is tetwalk's.
pub const USER_SIGNATURE: &str = "fn user_prepare(o: vec3f, d: vec3f) -> R\n\
     fn user_exit(t: ptr<function, array<vec3f, 4>>, r: R, entry: i32) -> i32";

/// Prefix of every module-scope name of tetwalk's in the module built around a user's WGSL, so that
/// none can clash with theirs.
pub const USER_PREFIX: &str = "tw_";

/// The module with a user's exit-face functions spliced in as method `user`: their source first, so
/// that the compiler's line numbers are theirs, then tetwalk's module and the entry points of
/// [`crate::registry::USER_WGSL`], with every module-scope name of tetwalk's but the entry points
/// prefixed with [`USER_PREFIX`].
pub fn with_user(source: &str) -> String {
    let ours = format!(
        "{COMMITTED}\n// ---- user ----\n\n{}",
        ENTRY_POINTS.replace("IDENT", "user")
    );
    let lines: Vec<&str> = ours.lines().collect();
    let mut names: Vec<String> = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        let entry_point = i > 0 && lines[i - 1].starts_with("@compute");
        if let Some(name) = declared(line).filter(|_| !entry_point)
            && !names.iter().any(|n| n == name)
        {
            names.push(name.to_string());
        }
    }
    let renamed = rename_words(&ours, &names);
    format!("{source}\n// ---- tetwalk ----\n{renamed}")
}

/// The name a module-scope declaration line declares (`fn`, `struct`, `const`, `alias`, `override`
/// or `var`, after any attributes), if it is one; lines inside a body are indented.
fn declared(line: &str) -> Option<&str> {
    let mut rest = line;
    while let Some(r) = rest.strip_prefix('@') {
        // An attribute: its name and any parenthesised arguments.
        let end = r.find([' ', '(']).unwrap_or(r.len());
        rest = r[end..].trim_start();
        if let Some(r) = rest.strip_prefix('(') {
            rest = r.split_once(')')?.1.trim_start();
        }
    }
    let rest = ["fn ", "struct ", "const ", "alias ", "override "]
        .iter()
        .find_map(|k| rest.strip_prefix(k))
        .or_else(|| {
            let r = rest.strip_prefix("var")?;
            Some(
                r.strip_prefix('<')
                    .map_or(r, |r| r.split_once('>').map_or(r, |x| x.1)),
            )
        })?;
    let rest = rest.trim_start();
    let end = rest
        .find(|c: char| !(c.is_alphanumeric() || c == '_'))
        .unwrap_or(rest.len());
    (end > 0).then(|| &rest[..end])
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
