// Seed 001's octree, once for every octree method and ray–triangle test: the pipeline's override
// constants OCTREE_METHOD and TRIANGLE_METHOD choose them (their places in tetwalk's registry), through
// octree_pi and triangle_hit.

{{choosers}}
// The exit face and quarter of each cell case (`v0` the lower corner, `v1` the upper), as `4 f + q`,
// or NONE.
@compute @workgroup_size(GROUP)
fn cell_exit(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let i = item(gid, groups);
    if i >= params.count {
        return;
    }
    let c = cases[i];
    faces[i] = portalez16_cell(octree_pi(c.org.xyz, c.dir.xyz), c.v0.xyz, c.v1.xyz, c.dir.xyz);
}

// Seed 001 §4.2.3 from each ray's entry cell (`start`, an address in eq. 3's words; HULL for a ray
// that misses the root), as tetwalk::walk::octree::walk walks, with Brent's cycle detection on the
// cell. Endings: a hit (triangle, `t` as bits), a miss, no exit face, a cycle (period) or the step
// limit, each with the cells visited.
@compute @workgroup_size(GROUP)
fn octree_walk(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let i = item(gid, groups);
    if i >= params.count {
        return;
    }
    let ray = rays[params.item_first + i];
    if ray.start == HULL {
        endings[i] = Ending(LEFT_MESH, 0u, 0u, 0u);
        return;
    }
    let pi = octree_pi(ray.org, ray.dir);
    var a = ray.start;
    var brent = brent_new(vec2u(a, 0u));
    for (var cells = 1u; cells <= params.limit; cells++) {
        let count = octree[a];
        let offset = octree[a + 1u];
        let cell = octree[a + 2u];
        var best = HULL;
        var best_t = 0.0;
        for (var k = 0u; k < count; k++) {
            let tri = octree_tris[offset + k];
            let t = triangle_hit(points[3u * tri].xyz, points[3u * tri + 1u].xyz, points[3u * tri + 2u].xyz, ray.org, ray.dir);
            if accepts(t) && (best == HULL || t < best_t) {
                best = tri;
                best_t = t;
            }
        }
        if best != HULL {
            endings[i] = Ending(HIT, best, bitcast<u32>(best_t), cells);
            return;
        }
        let fq = portalez16_cell(pi, octree_boxes[2u * cell].xyz, octree_boxes[2u * cell + 1u].xyz, ray.dir);
        if fq < 0 {
            endings[i] = Ending(NO_EXIT_FACE, cell, 0u, cells);
            return;
        }
        let f = u32(fq) / 4u;
        let counts = octree[a + 3u];
        var before = 0u;
        for (var g = 0u; g < f; g++) {
            before += (counts >> (4u * g)) & 15u;
        }
        let n = (counts >> (4u * f)) & 15u;
        if n == 0u {
            endings[i] = Ending(LEFT_MESH, cell, 0u, cells);
            return;
        }
        a = octree[a + 4u + before + (n / 4u) * (u32(fq) % 4u)];
        let period = brent_step(&brent, vec2u(a, 0u));
        if period > 0u {
            endings[i] = Ending(CYCLE, octree[a + 2u], period, cells);
            return;
        }
    }
    endings[i] = Ending(STEP_LIMIT, octree[a + 2u], 0u, params.limit);
}
