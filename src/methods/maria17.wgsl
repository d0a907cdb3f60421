// maria17 (Maria, Horna, Aveneau 2017, Algorithms 1-2), as src/methods/maria17.rs; Tables 1 and 2 are
// generated from the Rust ones (maria17_face_vertices, maria17_get_face).

// The ray as Plücker line {u : v} = {d : o × d}, once per ray.
struct Maria17Ray {
    u: vec3f,
    v: vec3f,
}

fn maria17_prepare(o: vec3f, d: vec3f) -> Maria17Ray {
    return Maria17Ray(d, cross3(o, d));
}

// §3.4: the moment in the frame translated to V_f, v' = v - V_f × u.
fn maria17_moment(r: Maria17Ray, vf: vec3f) -> vec3f {
    return r.v - cross3(vf, r.u);
}

fn maria17_exit(t: ptr<function, array<vec3f, 4>>, r: Maria17Ray, entry: i32) -> i32 {
    var e = entry;
    if e < 0 {
        let vf = (*t)[3];
        let s = dot3(maria17_moment(r, vf), vf - (*t)[2]);
        e = select(0, 1, s < 0.0);
    }
    let eu = u32(e);
    let vf = (*t)[eu];
    let moment = maria17_moment(r, vf);
    let lambda = maria17_face_vertices(eu);
    let s2 = dot3(moment, vf - (*t)[lambda.z]);
    var id = select(0u, 1u, s2 >= 0.0);
    let s = dot3(moment, vf - (*t)[lambda[id]]);
    id = id + select(0u, 1u, s < 0.0);
    return i32(maria17_get_face(eu)[id]);
}
