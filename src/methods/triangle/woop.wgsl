// woop-watertight: Woop, Benthin, Wald 2013, Listing 1 (src/methods/triangle/woop.rs). WGSL has no f64:
// where an edge function is exactly 0 it is recomputed from exact products (Dekker's, in f32), whose
// sign is exact, like the listing's double-precision fallback.

// a + b as a rounded sum and its exact error (Knuth's TwoSum).
fn two_sum(a: f32, b: f32) -> vec2f {
    let x = a + b;
    let bv = x - a;
    let av = x - bv;
    return vec2f(x, (a - av) + (b - bv));
}

// a · b as a rounded product and its exact error (Dekker's, with Veltkamp's split).
fn two_product(a: f32, b: f32) -> vec2f {
    let x = a * b;
    let ca = 4097.0 * a;
    let ah = ca - (ca - a);
    let al = a - ah;
    let cb = 4097.0 * b;
    let bh = cb - (cb - b);
    let bl = b - bh;
    return vec2f(x, al * bl - (((x - ah * bh) - al * bh) - ah * bl));
}

// a·b - c·d from exact products: the four terms summed so that the sign is exact.
fn det2_exact(a: f32, b: f32, c: f32, d: f32) -> f32 {
    let p = two_product(a, b);
    let q = two_product(c, d);
    let hi = two_sum(p.x, -q.x);
    let lo = two_sum(p.y, -q.y);
    let mid = two_sum(hi.y, lo.x);
    let top = two_sum(hi.x, mid.x);
    // Nonoverlapping parts, largest first: the first that is not 0 gives the sign.
    let rest = (top.y + mid.y) + lo.y;
    return top.x + rest;
}

// The listing's per-ray precomputation: the axes and the shear.
struct Sheared {
    k: vec3u,
    s: vec3f,
}

fn woop_shear(d: vec3f) -> Sheared {
    let a = abs(d);
    var kz = 2u;
    if a.x >= a.y && a.x >= a.z {
        kz = 0u;
    } else if a.y >= a.z {
        kz = 1u;
    }
    var kx = (kz + 1u) % 3u;
    var ky = (kz + 2u) % 3u;
    if d[kz] < 0.0 {
        let t = kx;
        kx = ky;
        ky = t;
    }
    return Sheared(vec3u(kx, ky, kz), vec3f(d[kx] / d[kz], d[ky] / d[kz], 1.0 / d[kz]));
}

fn woop_watertight_hit(p0: vec3f, p1: vec3f, p2: vec3f, o: vec3f, d: vec3f) -> f32 {
    let r = woop_shear(d);
    let kx = r.k.x;
    let ky = r.k.y;
    let kz = r.k.z;
    let a = p0 - o;
    let b = p1 - o;
    let c = p2 - o;
    let ax = a[kx] - r.s.x * a[kz];
    let ay = a[ky] - r.s.y * a[kz];
    let bx = b[kx] - r.s.x * b[kz];
    let by = b[ky] - r.s.y * b[kz];
    let cx = c[kx] - r.s.x * c[kz];
    let cy = c[ky] - r.s.y * c[kz];
    var u = cx * by - cy * bx;
    var v = ax * cy - ay * cx;
    var w = bx * ay - by * ax;
    if u == 0.0 || v == 0.0 || w == 0.0 {
        u = det2_exact(cx, by, cy, bx);
        v = det2_exact(ax, cy, ay, cx);
        w = det2_exact(bx, ay, by, ax);
    }
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return NO_HIT;
    }
    let det = u + v + w;
    if det == 0.0 {
        return NO_HIT;
    }
    let t_scaled = u * (r.s.z * a[kz]) + v * (r.s.z * b[kz]) + w * (r.s.z * c[kz]);
    if (t_scaled < 0.0 && det > 0.0) || (t_scaled > 0.0 && det < 0.0) {
        return NO_HIT;
    }
    return t_scaled * (1.0 / det);
}
