// maria17-translated (§3.4's order of operations), as src/methods/maria17.rs; builds on maria17.wgsl.

fn maria17_translated_prepare(o: vec3f, d: vec3f) -> Ray {
    return Ray(o, d);
}

// v' = (o - V_f) × u: 3 subtractions, 6 multiplications and 3 subtractions.
fn maria17_translated_moment(r: Ray, vf: vec3f) -> vec3f {
    return cross3(r.o - vf, r.d);
}

fn maria17_translated_exit(t: ptr<function, array<vec3f, 4>>, r: Ray, entry: i32) -> i32 {
    var e = entry;
    if e < 0 {
        e = maria17_start(t, maria17_translated_moment(r, (*t)[3]));
    }
    return maria17_tree(t, u32(e), maria17_translated_moment(r, (*t)[u32(e)]));
}
