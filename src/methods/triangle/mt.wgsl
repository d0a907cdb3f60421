// mt and mt-two-sided: Möller & Trumbore 1997 as seed 004 eq. 1 reads (src/methods/triangle/mt.rs).
// Each returns the t of the hit it reports, or NO_HIT.

fn mt_hit(p0: vec3f, p1: vec3f, p2: vec3f, o: vec3f, d: vec3f) -> f32 {
    let e1 = p1 - p0;
    let e2 = p2 - p0;
    let pvec = cross3(d, e2);
    let det = dot3(e1, pvec);
    if det < 0.0 {
        return NO_HIT;
    }
    let tvec = o - p0;
    let u = dot3(tvec, pvec);
    if u < 0.0 || u > det {
        return NO_HIT;
    }
    let qvec = cross3(tvec, e1);
    let v = dot3(d, qvec);
    if v < 0.0 || u + v > det {
        return NO_HIT;
    }
    return dot3(e2, qvec) * (1.0 / det);
}

fn mt_two_sided_hit(p0: vec3f, p1: vec3f, p2: vec3f, o: vec3f, d: vec3f) -> f32 {
    let e1 = p1 - p0;
    let e2 = p2 - p0;
    let pvec = cross3(d, e2);
    let inv_det = 1.0 / dot3(e1, pvec);
    let tvec = o - p0;
    let u = dot3(tvec, pvec) * inv_det;
    if u < 0.0 || u > 1.0 {
        return NO_HIT;
    }
    let qvec = cross3(tvec, e1);
    let v = dot3(d, qvec) * inv_det;
    if v < 0.0 || u + v > 1.0 {
        return NO_HIT;
    }
    return dot3(e2, qvec) * inv_det;
}
