// Helpers shared by the methods' WGSL, with the operation order of src/methods/mod.rs's `Plain`
// arithmetic (sums left to right). f32 only: whatever the shader compiler contracts or reorders is what
// the GPU backend measures.

// A ray as prepared by the methods that keep it as it is.
struct Ray {
    o: vec3f,
    d: vec3f,
}

fn dot3(a: vec3f, b: vec3f) -> f32 {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

fn cross3(a: vec3f, b: vec3f) -> vec3f {
    return vec3f(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

fn det2(a: vec2f, b: vec2f) -> f32 {
    return a.x * b.y - a.y * b.x;
}

// Whether a face is left, from the signs along its outward cycle: all >= 0 and not all zero.
fn leaves(s: vec3f) -> bool {
    return all(s >= vec3f(0.0)) && any(s != vec3f(0.0));
}

// Edge index and direction (+1, or -1 when it runs j -> i) of the edge joining vertices i and j.
fn edge_of(i: u32, j: u32) -> vec2i {
    return vec2i(edge_index(min(i, j), max(i, j)), select(1, -1, i > j));
}

// Whether a hit a ray-triangle method reports at t counts: 0 < t < infinity
// (tetwalk::methods::triangle::accepts).
fn accepts(t: f32) -> bool {
    return t > 0.0 && t <= MAX_F32;
}
