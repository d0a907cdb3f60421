// mt-precomputed: seed 004 eq. 2 (src/methods/triangle/mt_precomputed.rs). A GPU thread answers one ray,
// so the triangle's terms are computed where they are used, by the same expressions.

struct Precomputed {
    p0: vec3f,
    e1: vec3f,
    e2: vec3f,
    n: vec3f,
}

fn precompute(p0: vec3f, p1: vec3f, p2: vec3f) -> Precomputed {
    let e1 = p1 - p0;
    let e2 = p2 - p0;
    return Precomputed(p0, e1, e2, cross3(e1, e2));
}

fn barycentric_inside(u: f32, v: f32) -> bool {
    return u >= 0.0 && v >= 0.0 && u + v <= 1.0;
}

fn mt_precomputed_hit(p0: vec3f, p1: vec3f, p2: vec3f, o: vec3f, d: vec3f) -> f32 {
    let p = precompute(p0, p1, p2);
    let r = -1.0 / dot3(p.n, d);
    let s = o - p.p0;
    let ds = cross3(d, s);
    let u = r * -dot3(ds, p.e2);
    let v = r * dot3(ds, p.e1);
    if barycentric_inside(u, v) {
        return r * dot3(p.n, s);
    }
    return NO_HIT;
}
