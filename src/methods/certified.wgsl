// certified (tetwalk's own), the f32 stage of src/methods/certified.rs: Maria et al.'s Algorithm 1 (all
// six signs in the starting tetrahedron) with each side product's sign certified by the GPU bound
// (CERTIFIED_A, CERTIFIED_MU, CERTIFIED_C and CERTIFIED_TINY are generated from the Rust constants
// certified::{GPU, TINY}; derivation in src/methods/certified.md: any rounding within one ulp, subnormals
// flushed or not, fused or not). A sign the bound cannot settle, a non-finite side product, or a gated
// input (a nonzero coordinate below CERTIFIED_TINY, a subnormal direction component), returns
// UNSETTLED, and the CPU finishes that case or ray exactly.

struct CertifiedRay {
    o: vec3f,
    d: vec3f,
    settles: bool,
}

// A nonzero magnitude below `limit`, on the bits (a GPU that flushes may compare a subnormal as zero).
fn certified_below(v: vec3f, limit: f32) -> bool {
    let b = bitcast<vec3u>(v) & vec3u(0x7fffffffu);
    return any(b != vec3u(0u) & b < vec3u(bitcast<u32>(limit)));
}

fn certified_prepare(o: vec3f, d: vec3f) -> CertifiedRay {
    return CertifiedRay(o, d, !(certified_below(o, CERTIFIED_TINY) || certified_below(d, 0x1p-126f)));
}

// Side products with edges ending at b: det[a - o, b - o, d] = (a - b) · ((b - o) × d).
struct Apex {
    b: vec3f,
    w: vec3f,
    m: vec3f,
}

fn apex(b: vec3f, r: CertifiedRay) -> Apex {
    let q = b - r.o;
    let d = r.d;
    let x1 = q.y * d.z;
    let x2 = q.z * d.y;
    let y1 = q.z * d.x;
    let y2 = q.x * d.z;
    let z1 = q.x * d.y;
    let z2 = q.y * d.x;
    let m = vec3f(abs(x1) + abs(x2), abs(y1) + abs(y2), abs(z1) + abs(z2));
    return Apex(b, vec3f(x1 - x2, y1 - y2, z1 - z2), m + vec3f(CERTIFIED_MU));
}

// +1 or -1 when the bound settles the sign, else 0.
fn certified_side(p: Apex, a: vec3f, r: CertifiedRay) -> i32 {
    let e = a - p.b;
    let det = e.x * p.w.x + e.y * p.w.y + e.z * p.w.z;
    let permanent = abs(e.x) * p.m.x + abs(e.y) * p.m.y + abs(e.z) * p.m.z;
    let bound = CERTIFIED_A * permanent + CERTIFIED_C;
    // Finite: a rounding that is not monotone could leave an overflowed det beside a finite bound.
    if abs(det) > bound && abs(det) <= MAX_F32 {
        return select(-1, 1, det > 0.0);
    }
    return 0;
}

fn certified_exit(t: ptr<function, array<vec3f, 4>>, r: CertifiedRay, entry: i32) -> i32 {
    if !r.settles {
        return UNSETTLED;
    }
    for (var k = 0u; k < 4u; k++) {
        if certified_below((*t)[k], CERTIFIED_TINY) {
            return UNSETTLED;
        }
    }
    if entry >= 0 {
        let e = u32(entry);
        let p = apex((*t)[e], r);
        let lambda = maria17_face_vertices(e);
        let s2 = certified_side(p, (*t)[lambda.z], r);
        if s2 == 0 {
            return UNSETTLED;
        }
        var id = select(0u, 1u, s2 > 0);
        let s = certified_side(p, (*t)[lambda[id]], r);
        if s == 0 {
            return UNSETTLED;
        }
        id = id + select(0u, 1u, s < 0);
        return i32(maria17_get_face(e)[id]);
    }
    var s: array<f32, 6>;
    for (var k = 0u; k < 6u; k++) {
        let ab = edge_points(k);
        let sign = certified_side(apex((*t)[ab.y], r), (*t)[ab.x], r);
        if sign == 0 {
            return UNSETTLED;
        }
        s[k] = f32(sign);
    }
    for (var f = 0u; f < 4u; f++) {
        let v = face_vertices(f);
        var x: vec3f;
        for (var k = 0u; k < 3u; k++) {
            let e = edge_of(v[k], v[(k + 1u) % 3u]);
            x[k] = f32(e.y) * s[e.x];
        }
        if leaves(x) {
            return i32(f);
        }
    }
    // The perturbed line passes beside the tetrahedron: the CPU answers as exact does.
    return UNSETTLED;
}
