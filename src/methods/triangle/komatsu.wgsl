// komatsu-packet: seed 004 eq. 3 (src/methods/triangle/komatsu.rs). A GPU thread answers one ray: the
// packet's terms (N·S, -S × E2, S × E1) are computed by the same expressions in each thread.

fn komatsu_packet_hit(p0: vec3f, p1: vec3f, p2: vec3f, o: vec3f, d: vec3f) -> f32 {
    let p = precompute(p0, p1, p2);
    let s = o - p.p0;
    let ns = dot3(p.n, s);
    let a = -cross3(s, p.e2);
    let b = cross3(s, p.e1);
    let r = -1.0 / dot3(p.n, d);
    let u = r * dot3(d, a);
    if u < 0.0 {
        return NO_HIT;
    }
    let v = r * dot3(d, b);
    if v < 0.0 || u + v > 1.0 {
        return NO_HIT;
    }
    return r * ns;
}
