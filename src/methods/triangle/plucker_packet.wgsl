// plucker-packet: Benthin 2006's packet test as seed 004 describes it
// (src/methods/triangle/plucker_packet.rs); the packet's terms computed in each thread.

fn plucker_packet_hit(p0: vec3f, p1: vec3f, p2: vec3f, o: vec3f, d: vec3f) -> f32 {
    let n = cross3(p1 - p0, p2 - p0);
    let a = p0 - o;
    let b = p1 - o;
    let c = p2 - o;
    let na = dot3(n, a);
    let s = vec3f(dot3(d, cross3(a, b)), dot3(d, cross3(b, c)), dot3(d, cross3(c, a)));
    if all(s >= vec3f(0.0)) || all(s <= vec3f(0.0)) {
        return na / dot3(n, d);
    }
    return NO_HIT;
}
