// ray-plane (Lagae & Dutré 2008 after Garrity 1990), as src/methods/ray_plane.rs.

fn ray_plane_prepare(o: vec3f, d: vec3f) -> Ray {
    return Ray(o, d);
}

fn face_normal(t: ptr<function, array<vec3f, 4>>, f: u32) -> vec3f {
    let v = face_vertices(f);
    let a = (*t)[v.x];
    return cross3((*t)[v.y] - a, (*t)[v.z] - a);
}

fn ray_plane_exit(t: ptr<function, array<vec3f, 4>>, r: Ray, entry: i32) -> i32 {
    var best = NONE;
    var bt = 0.0;
    for (var f = 0u; f < 4u; f++) {
        let n = face_normal(t, f);
        let nd = dot3(n, r.d);
        if nd > 0.0 {
            let a = (*t)[face_vertices(f).x];
            let tt = dot3(n, a - r.o) / nd;
            if best == NONE || tt < bt {
                best = i32(f);
                bt = tt;
            }
        }
    }
    return best;
}
