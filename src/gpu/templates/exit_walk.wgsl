// The entry points of exit-face method `{{ident}}`: the exit face of each case, and the bounded walk of
// each ray from its starting tetrahedron with Brent's cycle detection on (tetrahedron, entry face),
// as tetwalk::walk::walk does, the ray prepared once.
@compute @workgroup_size(GROUP)
fn exit_{{ident}}(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let i = item(gid, groups);
    if i >= params.count {
        return;
    }
    let c = cases[i];
    var t = array<vec3f, 4>(c.v0.xyz, c.v1.xyz, c.v2.xyz, c.v3.xyz);
    faces[i] = {{ident}}_exit(&t, {{ident}}_prepare(c.org.xyz, c.dir.xyz), c.entry);
}

@compute @workgroup_size(GROUP)
fn walk_{{ident}}(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let i = item(gid, groups);
    if i >= params.count {
        return;
    }
    let ray = rays[params.item_first + i];
    let r = {{ident}}_prepare(ray.org, ray.dir);
    var tet = ray.start;
    var entry = NONE;
    var brent = brent_new(vec2u(tet, u32(entry)));
    for (var steps = 1u; steps <= params.limit; steps++) {
        let c = cells[tet];
        var t = array<vec3f, 4>(c.v0, c.v1, c.v2, c.v3);
        let f = {{ident}}_exit(&t, r, entry);
        if f == UNSETTLED {
            endings[i] = Ending(FLAGGED, tet, 0u, steps);
            return;
        }
        if f < 0 {
            endings[i] = Ending(NO_EXIT_FACE, tet, 0u, steps);
            return;
        }
        let fu = u32(f);
        let info = faceinfo[tet];
        if ((info >> (8u + fu)) & 1u) == 1u {
            endings[i] = Ending(HIT, tet, fu, steps);
            return;
        }
        let next = neighbor(c, fu);
        if next == HULL {
            endings[i] = Ending(LEFT_MESH, tet, fu, steps);
            return;
        }
        entry = i32((info >> (2u * fu)) & 3u);
        tet = next;
        let period = brent_step(&brent, vec2u(tet, u32(entry)));
        if period > 0u {
            endings[i] = Ending(CYCLE, tet, period, steps);
            return;
        }
    }
    endings[i] = Ending(STEP_LIMIT, tet, 0u, params.limit);
}
