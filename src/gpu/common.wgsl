// Helpers shared by the methods' WGSL, with the operation order of src/methods/mod.rs's `Plain`
// arithmetic (sums left to right). f32 only: whatever the shader compiler contracts or reorders is what
// the GPU backend measures.

// A ray as prepared by the methods that keep it as it is.
struct Ray {
    o: vec3f,
    d: vec3f,
}

fn dot3(a: vec3f, b: vec3f) -> f32 {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

fn cross3(a: vec3f, b: vec3f) -> vec3f {
    return vec3f(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

fn det2(a: vec2f, b: vec2f) -> f32 {
    return a.x * b.y - a.y * b.x;
}

// Whether a hit a ray-triangle method reports at t counts: 0 < t < infinity
// (tetwalk::methods::triangle::accepts).
fn accepts(t: f32) -> bool {
    return t > 0.0 && t <= MAX_F32;
}

// The item a thread answers, numbered across the 2-D grid of workgroups.
fn item(gid: vec3u, groups: vec3u) -> u32 {
    return gid.x + gid.y * groups.x * GROUP;
}

// The neighbour across face f.
fn neighbor(c: Cell, f: u32) -> u32 {
    return select(select(c.n0, c.n1, f == 1u), select(c.n2, c.n3, f == 3u), f >= 2u);
}

// Brent's cycle detection over a walk's states (tetrahedron and entry face; tetrahedron and the vertex
// across its exit face; an octree cell's address): the one loop of it in WGSL, as tetwalk::walk's
// Brent is in Rust.
struct Brent {
    saved: vec2u,
    power: u32,
    lam: u32,
}

fn brent_new(s: vec2u) -> Brent {
    return Brent(s, 1u, 0u);
}

// Feed the next state: the cycle's period once a state repeats, else 0.
fn brent_step(b: ptr<function, Brent>, s: vec2u) -> u32 {
    (*b).lam += 1u;
    if all(s == (*b).saved) {
        return (*b).lam;
    }
    if (*b).lam == (*b).power {
        (*b).saved = s;
        (*b).power *= 2u;
        (*b).lam = 0u;
    }
    return 0u;
}

// Add `steps` to the dispatch's sum (counters 1 and 2, low and high words).
fn add_steps(steps: u32) {
    let low = atomicAdd(&counters[1], steps);
    if low + steps < low {
        atomicAdd(&counters[2], 1u);
    }
}

// Ending `e` of item `i` beside the reference walk's ending of the same ray, kept on the GPU, `e` ending
// in the mesh's terms as `kind` on face `x` of tetrahedron `tet`: the steps summed, and every ending not settled here as ending where the reference ends sent back
// as it was written, with the reference's ending (counter 0 counts them), for the CPU to judge exactly
// (tetwalk::walk::same_result).
// Settled here: both leave the mesh, or both hit the same face of the same tetrahedron; everything else
// goes back (a walk flagged on either side, a hit on another face, every other ending), so the counts
// are the CPU's, ray for ray.
fn settle(i: u32, e: Ending, kind: u32, tet: u32, x: u32) {
    let r = reference[params.first + i];
    add_steps(e.steps);
    let both_left = kind == LEFT_MESH && r.kind == LEFT_MESH;
    let same_face = kind == HIT && r.kind == HIT && tet == r.tet && x == r.x;
    if !(both_left || same_face) {
        send(i, e, vec3u(r.kind, r.tet, r.x));
    }
}

// Send item `i`'s ending `e` back (counter 0 counts them) beside reference ending `r` (kind, tet, x).
fn send(i: u32, e: Ending, r: vec3u) {
    let k = atomicAdd(&counters[0], 1u);
    sent[k] = Sent(params.first + i, e.kind, e.tet, e.x, e.steps, r.x, r.y, r.z);
}

// The reference walk's endings of a dispatch, kept on the GPU and not read back: their steps summed
// (counters 1 and 2, low and high words), and each ray the walk flagged (a step its f32 stage could not
// settle) sent back (counter 0 counts them) for the CPU to walk, whose ending then replaces it there.
@compute @workgroup_size(GROUP)
fn hold_endings(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let i = item(gid, groups);
    if i >= params.count {
        return;
    }
    let e = endings[i];
    add_steps(e.steps);
    if e.kind == FLAGGED {
        send(i, e, vec3u(e.kind, e.tet, e.x));
    }
}

// Each walk of a dispatch settled beside the reference walk (its endings are the mesh's).
@compute @workgroup_size(GROUP)
fn compare_endings(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let i = item(gid, groups);
    if i >= params.count {
        return;
    }
    let e = endings[i];
    settle(i, e, e.kind, e.tet, e.x);
}

// Each nearest hit of a dispatch (a ray–triangle search, an octree walk: a hit names a triangle) settled
// beside the reference walk, a hit on triangle k taken as the constrained face it came from, named from
// the side the reference walk names it from: `hit_faces[k]` holds (tetrahedron, face) of both sides.
@compute @workgroup_size(GROUP)
fn compare_hits(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let i = item(gid, groups);
    if i >= params.count {
        return;
    }
    let e = endings[i];
    var at = vec2u(e.tet, e.x);
    if e.kind == HIT {
        let sides = hit_faces[e.tet];
        let r = reference[params.first + i];
        at = select(sides.xy, sides.zw, all(sides.zw == vec2u(r.tet, r.x)));
    }
    settle(i, e, e.kind, at.x, at.y);
}
