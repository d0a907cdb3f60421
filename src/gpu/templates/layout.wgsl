// The walk of method `{{ident}}` over layout `{{kind}}`, as tetwalk::walk::layouts::walk_layout does: the
// source's four vertices projected, §4's start, then per tetrahedron one vertex fetched (decoded from
// the xor-sum), projected, Algorithm 1, and the next tetrahedron decoded; Brent's detection on
// (tetrahedron, vertex across the exit face).
@compute @workgroup_size(GROUP)
fn layout_{{ident}}_{{kind}}(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let i = item(gid, groups);
    if i >= params.count {
        return;
    }
    let ray = layout_rays[i];
    let r = {{ident}}_prepare(ray.org, ray.dir);
    var p4: array<vec2f, 4>;
    for (var k = 0u; k < 4u; k++) {
        p4[k] = {{ident}}_project(r, points[ray.vertices[k]].xyz);
    }
    let f0 = start_exit_face(&p4);
    if f0 < 0 {
        endings[i] = Ending(NO_EXIT_FACE, ray.start, 0u, 1u);
        return;
    }
    let f = u32(f0);
    let fv = face_vertices(f);
    var idx = vec3u(ray.vertices[fv.x], ray.vertices[fv.y], ray.vertices[fv.z]);
    var p = array<vec2f, 3>(p4[fv.x], p4[fv.y], p4[fv.z]);
    var tet = ray.start;
    var next = ray.neighbors[f];
    var across = ray.vertices[f];
    var brent = brent_new(vec2u(tet, 0xffffffffu));
    var steps = 1u;
    loop {
        if (next & STOP) != 0u {
            endings[i] = Ending(select(HIT, LEFT_MESH, next == (STOP | BOUNDARY)), tet, across, steps);
            return;
        }
        let period = brent_step(&brent, vec2u(tet, across));
        if period > 0u {
            endings[i] = Ending(CYCLE, next, period, steps);
            return;
        }
        if steps >= params.limit {
            endings[i] = Ending(STEP_LIMIT, next, 0u, steps);
            return;
        }
        let prev = tet;
        tet = next;
        steps += 1u;
        let fourth = idx.x ^ idx.y ^ idx.z ^ {{kind}}_vx(tet);
        let p3 = {{ident}}_project(r, points[fourth].xyz);
        var q = array<vec2f, 4>(p[0], p[1], p[2], p3);
        let k = get_exit_face(&q);
        across = idx[k];
        next = {{kind}}_next(tet, prev, vec4u(idx, fourth), across);
        idx[k] = fourth;
        p[k] = p3;
    }
}
