// A user's exit-face function for `tetwalk --wgsl`: Platis & Theoharis' Plücker test, self-contained,
// in the operation order of tetwalk's `plucker` (so the two agree bit for bit where nothing is fused).

struct MyPluckerRay {
    u: vec3f,
    v: vec3f,
}

fn my_cross(a: vec3f, b: vec3f) -> vec3f {
    return vec3f(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

// Side product of the ray with the line a -> b.
fn my_side(r: MyPluckerRay, a: vec3f, b: vec3f) -> f32 {
    let m = my_cross(a, b);
    let e = b - a;
    return (((r.u.x * m.x + r.u.y * m.y) + r.u.z * m.z) + r.v.x * e.x + r.v.y * e.y) + r.v.z * e.z;
}

fn user_prepare(o: vec3f, d: vec3f) -> MyPluckerRay {
    return MyPluckerRay(d, my_cross(o, d));
}

// Face i is opposite vertex i; its vertices counterclockwise seen from outside.
const MY_FACES = array<vec3u, 4>(vec3u(1u, 3u, 2u), vec3u(0u, 2u, 3u), vec3u(0u, 3u, 1u), vec3u(0u, 1u, 2u));

fn user_exit(t: ptr<function, array<vec3f, 4>>, r: MyPluckerRay, entry: i32) -> i32 {
    var faces = MY_FACES;
    for (var f = 0u; f < 4u; f++) {
        let v = faces[f];
        let s = vec3f(
            my_side(r, (*t)[v.x], (*t)[v.y]),
            my_side(r, (*t)[v.y], (*t)[v.z]),
            my_side(r, (*t)[v.z], (*t)[v.x]),
        );
        if all(s >= vec3f(0.0)) && any(s != vec3f(0.0)) {
            return i32(f);
        }
    }
    return -1;
}
