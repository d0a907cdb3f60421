// aman20-scaled (Aman, Demirci, Güdükbay §4.1, eqs. 1-3), as src/methods/aman20.rs; builds on
// aman20.wgsl.

// The scaled basis with the component indices of eq. 3: max, min, other.
struct ScaledFrame {
    org: vec3f,
    u: vec3f,
    v: vec3f,
    idx: vec3u,
}

fn aman20_scaled_prepare(o: vec3f, n: vec3f) -> ScaledFrame {
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
    return ScaledFrame(o, u, v, vec3u(mx, mn, other));
}

// Eq. 3: 3 sub, 3 mul, 3 add.
fn aman20_scaled_project(f: ScaledFrame, p: vec3f) -> vec2f {
    let q = p - f.org;
    let mx = f.idx.x;
    let mn = f.idx.y;
    let ot = f.idx.z;
    let x = f.u[mx] * q[mx] + f.u[ot] * q[ot];
    let y = (f.v[mx] * q[mx] + f.v[ot] * q[ot]) + f.v[mn] * q[mn];
    return vec2f(x, y);
}

fn aman20_scaled_exit(t: ptr<function, array<vec3f, 4>>, r: ScaledFrame, entry: i32) -> i32 {
    var p: array<vec2f, 4>;
    for (var k = 0u; k < 4u; k++) {
        p[k] = aman20_scaled_project(r, (*t)[k]);
    }
    return exit_2d(&p, entry);
}
