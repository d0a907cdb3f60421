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

// §3.4's formula: the moment in the frame translated to V_f, v' = v - V_f × u.
fn maria17_moment(r: Maria17Ray, vf: vec3f) -> vec3f {
    return r.v - cross3(vf, r.u);
}

// Algorithm 2's fake entry face in the starting tetrahedron, from v' in the frame of V_3.
fn maria17_start(t: ptr<function, array<vec3f, 4>>, m3: vec3f) -> i32 {
    let s = dot3(m3, (*t)[3] - (*t)[2]);
    return select(0, 1, s < 0.0);
}

// Algorithm 1 from entry face e, given v' in the frame of V_f = t[e]: two side products, no branch.
fn maria17_tree(t: ptr<function, array<vec3f, 4>>, e: u32, moment: vec3f) -> i32 {
    let vf = (*t)[e];
    let lambda = maria17_face_vertices(e);
    let s2 = dot3(moment, vf - (*t)[lambda.z]);
    var id = select(0u, 1u, s2 >= 0.0);
    let s = dot3(moment, vf - (*t)[lambda[id]]);
    id = id + select(0u, 1u, s < 0.0);
    return i32(maria17_get_face(e)[id]);
}

fn maria17_exit(t: ptr<function, array<vec3f, 4>>, r: Maria17Ray, entry: i32) -> i32 {
    var e = entry;
    if e < 0 {
        e = maria17_start(t, maria17_moment(r, (*t)[3]));
    }
    return maria17_tree(t, u32(e), maria17_moment(r, (*t)[u32(e)]));
}
