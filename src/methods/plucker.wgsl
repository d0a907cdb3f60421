// plucker (Lagae & Dutré 2008 after Platis & Theoharis 2003), as src/methods/plucker.rs.

// The ray as a Plücker line {u : v} = {d : o × d}, once per ray.
struct PluckerRay {
    u: vec3f,
    v: vec3f,
}

fn plucker_prepare(o: vec3f, d: vec3f) -> PluckerRay {
    return PluckerRay(d, cross3(o, d));
}

// Side product of the ray with the line a -> b, {b - a : a × b}.
fn side(r: PluckerRay, a: vec3f, b: vec3f) -> f32 {
    let e = b - a;
    return ((dot3(r.u, cross3(a, b)) + r.v.x * e.x) + r.v.y * e.y) + r.v.z * e.z;
}

// The first face, in index order, whose three edges all turn the right way.
fn exit_by_sides(s: ptr<function, array<f32, 6>>) -> i32 {
    for (var f = 0u; f < 4u; f++) {
        let v = face_vertices(f);
        var x: vec3f;
        for (var k = 0u; k < 3u; k++) {
            let e = edge_of(v[k], v[(k + 1u) % 3u]);
            x[k] = f32(e.y) * (*s)[e.x];
        }
        if leaves(x) {
            return i32(f);
        }
    }
    return NONE;
}

fn plucker_exit(t: ptr<function, array<vec3f, 4>>, r: PluckerRay, entry: i32) -> i32 {
    var s: array<f32, 6>;
    for (var e = 0u; e < 6u; e++) {
        let p = edge_points(e);
        s[e] = side(r, (*t)[p.x], (*t)[p.y]);
    }
    return exit_by_sides(&s);
}
