// ms06 (Marmitt & Slusallek 2006), as src/methods/ms06.rs; builds on plucker.wgsl.

fn ms06_prepare(o: vec3f, d: vec3f) -> PluckerRay {
    return plucker_prepare(o, d);
}

fn ms06_exit(t: ptr<function, array<vec3f, 4>>, r: PluckerRay, entry: i32) -> i32 {
    if entry < 0 {
        return plucker_exit(t, r, entry);
    }
    let e = u32(entry);
    let a = face_vertices(e);
    let s0 = side(r, (*t)[a.x], (*t)[e]);
    let s1 = side(r, (*t)[a.y], (*t)[e]);
    if s0 >= 0.0 && s1 <= 0.0 {
        return i32(a.z);
    }
    let s2 = side(r, (*t)[a.z], (*t)[e]);
    if s1 >= 0.0 && s2 <= 0.0 {
        return i32(a.x);
    }
    if s2 >= 0.0 && s0 <= 0.0 {
        return i32(a.y);
    }
    return NONE;
}
