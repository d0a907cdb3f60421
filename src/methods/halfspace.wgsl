// halfspace (Lagae & Dutré 2008), as src/methods/halfspace.rs.

fn halfspace_prepare(o: vec3f, d: vec3f) -> Ray {
    return Ray(o, d);
}

fn halfspace_exit(t: ptr<function, array<vec3f, 4>>, r: Ray, entry: i32) -> i32 {
    let o = r.o;
    let d = r.d;
    var n: array<vec3f, 4>;
    var nd: array<f32, 4>;
    var candidates = 0u;
    var only = NONE;
    for (var f = 0u; f < 4u; f++) {
        n[f] = face_normal(t, f);
        nd[f] = dot3(n[f], d);
        if nd[f] > 0.0 {
            candidates += 1u;
            only = i32(f);
        }
    }
    if candidates == 1u {
        return only;
    }
    for (var f = 0u; f < 4u; f++) {
        if !(nd[f] > 0.0) {
            continue;
        }
        let tt = dot3(n[f], (*t)[face_vertices(f).x] - o) / nd[f];
        let p = vec3f(d.x * tt + o.x, d.y * tt + o.y, d.z * tt + o.z);
        var inside = true;
        for (var g = 0u; g < 4u; g++) {
            if g != f && nd[g] > 0.0 && !(dot3(n[g], p - (*t)[face_vertices(g).x]) <= 0.0) {
                inside = false;
            }
        }
        if inside {
            return i32(f);
        }
    }
    return NONE;
}
