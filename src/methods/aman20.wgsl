// aman20 (Aman, Demirci, Güdükbay §4, Duff et al. 2017 frame), as src/methods/aman20.rs.

// Algorithm 1, GETEXITFACE: p0 p1 p2 the entry face, p3 the new vertex; the exit face is across p_k.
fn get_exit_face(p: ptr<function, array<vec2f, 4>>) -> u32 {
    var exit = 0u;
    if det2((*p)[3], (*p)[0]) < 0.0 {
        if det2((*p)[3], (*p)[2]) >= 0.0 {
            exit = 1u;
        }
    } else if det2((*p)[3], (*p)[1]) < 0.0 {
        exit = 2u;
    }
    return exit;
}

// §4's exit from the starting tetrahedron, from its four projected vertices: the first face whose
// projected outward cycle has the origin on the left of all three edges, not all on them.
fn start_exit_face(p: ptr<function, array<vec2f, 4>>) -> i32 {
    for (var f = 0u; f < 4u; f++) {
        let v = face_vertices(f);
        var x: vec3f;
        for (var k = 0u; k < 3u; k++) {
            x[k] = det2((*p)[v[k]], (*p)[v[(k + 1u) % 3u]]);
        }
        if leaves(x) {
            return i32(f);
        }
    }
    return NONE;
}

// §4: with an entry face, Algorithm 1 over its vertices (outward cycle reversed) and the opposite
// vertex; without, start_exit_face. `p` holds the four projected vertices.
fn exit_2d(p: ptr<function, array<vec2f, 4>>, entry: i32) -> i32 {
    if entry >= 0 {
        let e = u32(entry);
        let a = face_vertices(e);
        let idx = vec4u(a.x, a.z, a.y, e);
        var q = array<vec2f, 4>((*p)[idx.x], (*p)[idx.y], (*p)[idx.z], (*p)[idx.w]);
        return i32(idx[get_exit_face(&q)]);
    }
    return start_exit_face(p);
}

// The ray origin and the orthonormal basis of Duff et al. 2017 around the unit direction.
struct DuffFrame {
    org: vec3f,
    u: vec3f,
    v: vec3f,
}

fn aman20_prepare(o: vec3f, d: vec3f) -> DuffFrame {
    let n = d / sqrt(dot3(d, d));
    let sign = select(1.0, -1.0, (bitcast<u32>(n.z) >> 31u) == 1u);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    let u = vec3f(sign * n.x * (n.x * a) + 1.0, sign * b, -sign * n.x);
    let v = vec3f(b, n.y * (n.y * a) + sign, -n.y);
    return DuffFrame(o, u, v);
}

// Algorithm 2's projection: (u · (p - o), v · (p - o)).
fn aman20_project(r: DuffFrame, p: vec3f) -> vec2f {
    let q = p - r.org;
    return vec2f(dot3(r.u, q), dot3(r.v, q));
}

fn aman20_exit(t: ptr<function, array<vec3f, 4>>, r: DuffFrame, entry: i32) -> i32 {
    var p: array<vec2f, 4>;
    for (var k = 0u; k < 4u; k++) {
        p[k] = aman20_project(r, (*t)[k]);
    }
    return exit_2d(&p, entry);
}
