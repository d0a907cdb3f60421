// tetwalk's exit-face methods as WGSL compute, the same algorithms, operation order and face numbering
// as src/methods/*.rs (face i opposite vertex i, tetrahedra positively oriented). f32 only: whatever
// the shader compiler contracts or reorders is what this backend measures.

const NONE: i32 = -1;

struct Params {
    method: u32,
    count: u32,
    offset: u32,
    max_steps: u32,
    start: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}

// One exit-face case.
struct Case {
    v0: vec4f,
    v1: vec4f,
    v2: vec4f,
    v3: vec4f,
    org: vec4f,
    dir: vec4f,
    entry: i32,
    pad0: i32,
    pad1: i32,
    pad2: i32,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> cases: array<Case>;
@group(0) @binding(2) var<storage, read_write> faces: array<i32>;
// The walk: rays (org, dir), mesh points, tetrahedra, neighbours, mirror faces and constrained bits.
@group(0) @binding(3) var<storage, read> rays: array<vec4f>;
@group(0) @binding(4) var<storage, read> points: array<vec4f>;
@group(0) @binding(5) var<storage, read> tets: array<vec4u>;
@group(0) @binding(6) var<storage, read> neighbors: array<vec4u>;
// Bits 0-7: mirror face of each face (2 bits each); bits 8-11: constrained faces.
@group(0) @binding(7) var<storage, read> faceinfo: array<u32>;
@group(0) @binding(8) var<storage, read_write> outcomes: array<vec4u>;

fn face_vertices(f: u32) -> vec3u {
    switch f {
        case 0u: { return vec3u(1u, 3u, 2u); }
        case 1u: { return vec3u(0u, 2u, 3u); }
        case 2u: { return vec3u(0u, 3u, 1u); }
        default: { return vec3u(0u, 1u, 2u); }
    }
}

fn dot3(a: vec3f, b: vec3f) -> f32 {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

fn cross3(a: vec3f, b: vec3f) -> vec3f {
    return vec3f(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

// ---- ray-plane and halfspace (Lagae & Dutré 2008) ----

fn face_normal(t: ptr<function, array<vec3f, 4>>, f: u32) -> vec3f {
    let v = face_vertices(f);
    let a = (*t)[v.x];
    return cross3((*t)[v.y] - a, (*t)[v.z] - a);
}

fn ray_plane(t: ptr<function, array<vec3f, 4>>, o: vec3f, d: vec3f) -> i32 {
    var best = NONE;
    var bt = 0.0;
    for (var f = 0u; f < 4u; f++) {
        let n = face_normal(t, f);
        let nd = dot3(n, d);
        if nd > 0.0 {
            let a = (*t)[face_vertices(f).x];
            let tt = dot3(n, a - o) / nd;
            if best == NONE || tt < bt {
                best = i32(f);
                bt = tt;
            }
        }
    }
    return best;
}

fn halfspace(t: ptr<function, array<vec3f, 4>>, o: vec3f, d: vec3f) -> i32 {
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

// ---- Plücker side products: plucker, ms06 ----

// Side product of the ray {d : o × d} with the line a → b, {b - a : a × b}.
fn side(d: vec3f, m: vec3f, a: vec3f, b: vec3f) -> f32 {
    let e = b - a;
    return ((dot3(d, cross3(a, b)) + m.x * e.x) + m.y * e.y) + m.z * e.z;
}

// Edge index and direction of (i, j) in EDGES = 01 02 03 12 13 23.
fn edge_of(i: u32, j: u32) -> vec2i {
    let lo = min(i, j);
    let hi = max(i, j);
    var e = 0;
    if lo == 0u { e = i32(hi) - 1; } else if lo == 1u { e = i32(hi) + 1; } else { e = 5; }
    return vec2i(e, select(1, -1, i > j));
}

fn edge_points(e: u32) -> vec2u {
    switch e {
        case 0u: { return vec2u(0u, 1u); }
        case 1u: { return vec2u(0u, 2u); }
        case 2u: { return vec2u(0u, 3u); }
        case 3u: { return vec2u(1u, 2u); }
        case 4u: { return vec2u(1u, 3u); }
        default: { return vec2u(2u, 3u); }
    }
}

fn exit_by_sides(s: ptr<function, array<f32, 6>>) -> i32 {
    for (var f = 0u; f < 4u; f++) {
        let v = face_vertices(f);
        var all_ge = true;
        var any_ne = false;
        for (var k = 0u; k < 3u; k++) {
            let e = edge_of(v[k], v[(k + 1u) % 3u]);
            let x = f32(e.y) * (*s)[e.x];
            all_ge = all_ge && x >= 0.0;
            any_ne = any_ne || x != 0.0;
        }
        if all_ge && any_ne {
            return i32(f);
        }
    }
    return NONE;
}

fn plucker(t: ptr<function, array<vec3f, 4>>, o: vec3f, d: vec3f) -> i32 {
    let m = cross3(o, d);
    var s: array<f32, 6>;
    for (var e = 0u; e < 6u; e++) {
        let p = edge_points(e);
        s[e] = side(d, m, (*t)[p.x], (*t)[p.y]);
    }
    return exit_by_sides(&s);
}

fn ms06(t: ptr<function, array<vec3f, 4>>, o: vec3f, d: vec3f, entry: i32) -> i32 {
    if entry < 0 {
        return plucker(t, o, d);
    }
    let m = cross3(o, d);
    let e = u32(entry);
    let a = face_vertices(e);
    let s0 = side(d, m, (*t)[a.x], (*t)[e]);
    let s1 = side(d, m, (*t)[a.y], (*t)[e]);
    if s0 >= 0.0 && s1 <= 0.0 {
        return i32(a.z);
    }
    let s2 = side(d, m, (*t)[a.z], (*t)[e]);
    if s1 >= 0.0 && s2 <= 0.0 {
        return i32(a.x);
    }
    if s2 >= 0.0 && s0 <= 0.0 {
        return i32(a.y);
    }
    return NONE;
}

// ---- stp (Lagae & Dutré 2008) ----

fn stp(t: ptr<function, array<vec3f, 4>>, o: vec3f, d: vec3f) -> i32 {
    var rel: array<vec3f, 4>;
    for (var i = 0u; i < 4u; i++) {
        rel[i] = (*t)[i] - o;
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
                known[e.x] = dot3(d, cross3(rel[p.x], rel[p.y]));
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

// ---- maria17 (Maria, Horna, Aveneau 2017) ----

fn maria_vertices(f: u32) -> vec3u {
    switch f {
        case 0u: { return vec3u(3u, 1u, 2u); }
        case 1u: { return vec3u(2u, 0u, 3u); }
        case 2u: { return vec3u(3u, 0u, 1u); }
        default: { return vec3u(1u, 0u, 2u); }
    }
}

fn maria_get_face(f: u32) -> vec3u {
    switch f {
        case 0u: { return vec3u(1u, 2u, 3u); }
        case 1u: { return vec3u(0u, 3u, 2u); }
        case 2u: { return vec3u(0u, 1u, 3u); }
        default: { return vec3u(0u, 2u, 1u); }
    }
}

fn maria17(t: ptr<function, array<vec3f, 4>>, o: vec3f, d: vec3f, entry: i32) -> i32 {
    let v = cross3(o, d);
    var e = entry;
    if e < 0 {
        let vf = (*t)[3];
        let moment = v - cross3(vf, d);
        let s = dot3(moment, vf - (*t)[2]);
        e = select(0, 1, s < 0.0);
    }
    let eu = u32(e);
    let vf = (*t)[eu];
    let moment = v - cross3(vf, d);
    let lambda = maria_vertices(eu);
    let s2 = dot3(moment, vf - (*t)[lambda.z]);
    var id = select(0u, 1u, s2 >= 0.0);
    let s = dot3(moment, vf - (*t)[lambda[id]]);
    id = id + select(0u, 1u, s < 0.0);
    return i32(maria_get_face(eu)[id]);
}

// ---- aman20 and aman20-scaled (Aman, Demirci, Güdükbay) ----

fn det2(a: vec2f, b: vec2f) -> f32 {
    return a.x * b.y - a.y * b.x;
}

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

// The 2-D frame: u and v (for the scaled basis only the used components are nonzero).
struct Frame {
    u: vec3f,
    v: vec3f,
    idx: vec3u, // max, min, other (scaled basis)
    scaled: bool,
}

fn duff_frame(d: vec3f) -> Frame {
    let n = d / sqrt(dot3(d, d));
    let sign = select(1.0, -1.0, (bitcast<u32>(n.z) >> 31u) == 1u);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    let u = vec3f(sign * n.x * (n.x * a) + 1.0, sign * b, -sign * n.x);
    let v = vec3f(b, n.y * (n.y * a) + sign, -n.y);
    return Frame(u, v, vec3u(0u), false);
}

fn scaled_frame(n: vec3f) -> Frame {
    let m = abs(n);
    var mx = 2u;
    if m.x >= m.y && m.x >= m.z { mx = 0u; } else if m.y >= m.z { mx = 1u; }
    var mn = 3u;
    for (var i = 0u; i < 3u; i++) {
        if i != mx && (mn == 3u || m[i] < m[mn]) {
            mn = i;
        }
    }
    let other = 3u - mx - mn;
    let p = (mn + 1u) % 3u;
    let q = (mn + 2u) % 3u;
    var u = vec3f(0.0);
    u[p] = n[q] / n[mx];
    u[q] = -n[p] / n[mx];
    let t = cross3(n, u);
    let v = t / abs(t[mn]);
    return Frame(u, v, vec3u(mx, mn, other), true);
}

fn project(f: Frame, p: vec3f, o: vec3f) -> vec2f {
    let q = p - o;
    if f.scaled {
        let mx = f.idx.x;
        let mn = f.idx.y;
        let ot = f.idx.z;
        let x = f.u[mx] * q[mx] + f.u[ot] * q[ot];
        let y = (f.v[mx] * q[mx] + f.v[ot] * q[ot]) + f.v[mn] * q[mn];
        return vec2f(x, y);
    }
    return vec2f(dot3(f.u, q), dot3(f.v, q));
}

fn aman20(t: ptr<function, array<vec3f, 4>>, o: vec3f, d: vec3f, entry: i32, scaled: bool) -> i32 {
    var fr: Frame;
    if scaled { fr = scaled_frame(d); } else { fr = duff_frame(d); }
    if entry >= 0 {
        let e = u32(entry);
        let a = face_vertices(e);
        let idx = vec4u(a.x, a.z, a.y, e);
        var p: array<vec2f, 4>;
        for (var k = 0u; k < 4u; k++) {
            p[k] = project(fr, (*t)[idx[k]], o);
        }
        return i32(idx[get_exit_face(&p)]);
    }
    var p: array<vec2f, 4>;
    for (var k = 0u; k < 4u; k++) {
        p[k] = project(fr, (*t)[k], o);
    }
    for (var f = 0u; f < 4u; f++) {
        let v = face_vertices(f);
        var all_ge = true;
        var any_ne = false;
        for (var k = 0u; k < 3u; k++) {
            let x = det2(p[v[k]], p[v[(k + 1u) % 3u]]);
            all_ge = all_ge && x >= 0.0;
            any_ne = any_ne || x != 0.0;
        }
        if all_ge && any_ne {
            return i32(f);
        }
    }
    return NONE;
}

// Method ids follow tetwalk::gpu::GPU_METHODS.
fn exit_face(method: u32, t: ptr<function, array<vec3f, 4>>, o: vec3f, d: vec3f, entry: i32) -> i32 {
    switch method {
        case 0u: { return ray_plane(t, o, d); }
        case 1u: { return halfspace(t, o, d); }
        case 2u: { return plucker(t, o, d); }
        case 3u: { return stp(t, o, d); }
        case 4u: { return ms06(t, o, d, entry); }
        case 5u: { return maria17(t, o, d, entry); }
        case 6u: { return aman20(t, o, d, entry, false); }
        default: { return aman20(t, o, d, entry, true); }
    }
}

@compute @workgroup_size(64)
fn exit_cases(@builtin(global_invocation_id) gid: vec3u) {
    let i = gid.x + params.offset;
    if gid.x >= params.count {
        return;
    }
    let c = cases[i];
    var t = array<vec3f, 4>(c.v0.xyz, c.v1.xyz, c.v2.xyz, c.v3.xyz);
    faces[i] = exit_face(params.method, &t, c.org.xyz, c.dir.xyz, c.entry);
}

// Outcome kinds, as tetwalk::walk::Outcome.
const HIT: u32 = 0u;
const LEFT_MESH: u32 = 1u;
const NO_EXIT_FACE: u32 = 2u;
const CYCLE: u32 = 3u;
const STEP_LIMIT: u32 = 4u;
const HULL: u32 = 0xffffffffu;

// The bounded walk: (kind, tetrahedron, face or cycle period, steps) per ray; Brent's cycle detection
// on (tetrahedron, entry face), as on the CPU.
@compute @workgroup_size(64)
fn walk_rays(@builtin(global_invocation_id) gid: vec3u) {
    let i = gid.x + params.offset;
    if gid.x >= params.count {
        return;
    }
    let o = rays[2u * i].xyz;
    let d = rays[2u * i + 1u].xyz;
    var tet = params.start;
    var entry = NONE;
    var saved_tet = tet;
    var saved_entry = entry;
    var power = 1u;
    var lam = 0u;
    for (var steps = 1u; steps <= params.max_steps; steps++) {
        let vi = tets[tet];
        var t = array<vec3f, 4>(points[vi.x].xyz, points[vi.y].xyz, points[vi.z].xyz, points[vi.w].xyz);
        let f = exit_face(params.method, &t, o, d, entry);
        if f < 0 {
            outcomes[i] = vec4u(NO_EXIT_FACE, tet, 0u, steps);
            return;
        }
        let fu = u32(f);
        let info = faceinfo[tet];
        if ((info >> (8u + fu)) & 1u) == 1u {
            outcomes[i] = vec4u(HIT, tet, fu, steps);
            return;
        }
        let next = neighbors[tet][fu];
        if next == HULL {
            outcomes[i] = vec4u(LEFT_MESH, tet, fu, steps);
            return;
        }
        entry = i32((info >> (2u * fu)) & 3u);
        tet = next;
        lam += 1u;
        if tet == saved_tet && entry == saved_entry {
            outcomes[i] = vec4u(CYCLE, tet, lam, steps);
            return;
        }
        if lam == power {
            saved_tet = tet;
            saved_entry = entry;
            power = power * 2u;
            lam = 0u;
        }
    }
    outcomes[i] = vec4u(STEP_LIMIT, tet, 0u, params.max_steps);
}
