// stp (Lagae & Dutré 2008), as src/methods/stp.rs.

fn stp_prepare(o: vec3f, d: vec3f) -> Ray {
    return Ray(o, d);
}

fn stp_exit(t: ptr<function, array<vec3f, 4>>, r: Ray, entry: i32) -> i32 {
    var rel: array<vec3f, 4>;
    for (var i = 0u; i < 4u; i++) {
        rel[i] = (*t)[i] - r.o;
    }
    var known: array<f32, 6>;
    var have: array<bool, 6>;
    for (var f = 3; f >= 0; f--) {
        let v = face_vertices(u32(f));
        var ok = true;
        var nonzero = false;
        for (var k = 0u; k < 3u; k++) {
            let e = edge_of(v[k], v[(k + 1u) % 3u]);
            if !have[e.x] {
                let p = edge_points(u32(e.x));
                known[e.x] = dot3(r.d, cross3(rel[p.x], rel[p.y]));
                have[e.x] = true;
            }
            let s = f32(e.y) * known[e.x];
            if s < 0.0 {
                ok = false;
                break;
            }
            nonzero = nonzero || s != 0.0;
        }
        if ok && nonzero {
            return f;
        }
    }
    return NONE;
}
