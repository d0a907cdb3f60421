// The entry points of ray–triangle method `{{ident}}`: hit_{{ident}} answers one (ray, triangle) pair per
// item (the ray's `start` names the triangle, three `points` each), nearest_{{ident}} one ray's nearest
// hit among the first `params.limit` triangles, every one tried, as
// tetwalk::methods::triangle::nearest keeps it (the first with the smallest accepted `t`). The answer
// is an Ending: HIT with the triangle and the bits of `t`, or LEFT_MESH for none.
@compute @workgroup_size(GROUP)
fn hit_{{ident}}(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let i = item(gid, groups);
    if i >= params.count {
        return;
    }
    let ray = rays[params.item_first + i];
    let k = 3u * ray.start;
    let t = {{ident}}_hit(points[k].xyz, points[k + 1u].xyz, points[k + 2u].xyz, ray.org, ray.dir);
    if accepts(t) {
        endings[i] = Ending(HIT, ray.start, bitcast<u32>(t), 1u);
    } else {
        endings[i] = Ending(LEFT_MESH, ray.start, 0u, 1u);
    }
}

@compute @workgroup_size(GROUP)
fn nearest_{{ident}}(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let i = item(gid, groups);
    if i >= params.count {
        return;
    }
    let ray = rays[params.item_first + i];
    var best = HULL;
    var best_t = 0.0;
    for (var k = 0u; k < params.limit; k++) {
        let t = {{ident}}_hit(points[3u * k].xyz, points[3u * k + 1u].xyz, points[3u * k + 2u].xyz, ray.org, ray.dir);
        if accepts(t) && (best == HULL || t < best_t) {
            best = k;
            best_t = t;
        }
    }
    if best == HULL {
        endings[i] = Ending(LEFT_MESH, 0u, 0u, params.limit);
    } else {
        endings[i] = Ending(HIT, best, bitcast<u32>(best_t), params.limit);
    }
}
