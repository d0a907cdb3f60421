// portalez16 and portalez16-direction (Portalez & Duguet 2016, seed 001), as src/methods/portalez16.rs:
// the ray's Plücker coordinates (eq. 1, two readings), the orientations against axis-parallel lines
// (eqs. 4-5), the exit face (eqs. 6-8) and the neighbour among four (eqs. 9-10). The tables are
// PORTALEZ16_OUT_FACES and PORTALEZ16_NEIGHBOR, generated from the Rust ones, four and two bits an entry.

// Eq. 1 as printed: P = o, Q = o + d.
fn portalez16_pi(o: vec3f, d: vec3f) -> array<f32, 6> {
    let q = o + d;
    return array<f32, 6>(q.x * o.y - o.x * q.y, q.x * o.z - o.x * q.z, q.x - o.x, q.y * o.z - o.y * q.z, q.z - o.z, o.y - q.y);
}

// Eq. 1 with Q - P = d substituted.
fn portalez16_direction_pi(o: vec3f, d: vec3f) -> array<f32, 6> {
    return array<f32, 6>(d.x * o.y - o.x * d.y, d.x * o.z - o.x * d.z, d.x, d.y * o.z - o.y * d.z, d.z, -d.y);
}

// Eqs. 4-6: the table index, bit k set where the k-th orientation is negative.
fn portalez16_index(pi: array<f32, 6>, p: vec3f) -> u32 {
    let x = (pi[4] * p.y + pi[5] * p.z) + pi[3];
    let y = (pi[2] * p.z - pi[1]) - pi[4] * p.x;
    let z = (pi[0] - pi[2] * p.y) - pi[5] * p.x;
    return select(0u, 1u, x < 0.0) | select(0u, 2u, y < 0.0) | select(0u, 4u, z < 0.0);
}

// The exit face f and quarter q of the box [lo, hi] as 4 f + q, or NONE where eq. 8 gives 7.
fn portalez16_cell(pi: array<f32, 6>, lo: vec3f, hi: vec3f, d: vec3f) -> i32 {
    let up = d > vec3f(0.0);
    let v = select(0u, 1u, up.x) | select(0u, 2u, up.y) | select(0u, 4u, up.z);
    let corner = select(lo, hi, up);
    let f = (PORTALEZ16_OUT_FACES[v] >> (4u * portalez16_index(pi, corner))) & 15u;
    if f == 7u {
        return NONE;
    }
    let axis = PORTALEZ16_FACE_AXIS[f];
    var centre = (lo + hi) * 0.5;
    centre[axis] = select(lo[axis], hi[axis], PORTALEZ16_FACE_HIGH[f] == 1u);
    let q = (PORTALEZ16_NEIGHBOR[f] >> (2u * portalez16_index(pi, centre))) & 3u;
    return i32(4u * f + q);
}
