// tetwalk_certified_exit_face: the face (0..3, face i opposite vertex i) through which the ray
// org + t dir, t >= 0, leaves the positively oriented tetrahedron t, entered through face `entry`
// (-1 where none is known), certified by the f32 bound of tetwalk's src/methods/certified.md (any
// rounding within one ulp, fused or not, subnormals flushed or not); UNSETTLED (-2) where f32 cannot
// settle a sign, the line only touches the tetrahedron or misses it, or an input is gated: the host
// finishes that case with kernels/c/certified.h (tetwalk_certified_exit_face). SPDX-License-Identifier:
// MIT OR Apache-2.0.
fn tetwalk_certified_exit_face(t: array<vec3f, 4>, org: vec3f, dir: vec3f, entry: i32) -> i32 {
    var tet = t;
    return certified_exit(&tet, certified_prepare(org, dir), entry);
}

// One case: the four vertices (w unused), the origin and direction (w unused), the entry face in x.
struct TetwalkCase {
    v: array<vec4f, 4>,
    org: vec4f,
    dir: vec4f,
    entry: vec4i,
}

@group(0) @binding(0) var<storage, read> tetwalk_cases: array<TetwalkCase>;
@group(0) @binding(1) var<storage, read_write> tetwalk_faces: array<i32>;

// The function called once per case: faces[i] for cases[i].
@compute @workgroup_size(64)
fn tetwalk_certified_main(@builtin(global_invocation_id) id: vec3u) {
    let i = id.x;
    if i >= arrayLength(&tetwalk_cases) {
        return;
    }
    let c = tetwalk_cases[i];
    let t = array<vec3f, 4>(c.v[0].xyz, c.v[1].xyz, c.v[2].xyz, c.v[3].xyz);
    tetwalk_faces[i] = tetwalk_certified_exit_face(t, c.org.xyz, c.dir.xyz, c.entry.x);
}
