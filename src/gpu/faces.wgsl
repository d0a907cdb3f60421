// A tetrahedron's faces and edges, over the tables before it (face_vertices, edge_points,
// edge_index): what every exit-face method and `tetwalk export-kernel` build on.

// Whether a face is left, from the signs along its outward cycle: all >= 0 and not all zero.
fn leaves(s: vec3f) -> bool {
    return all(s >= vec3f(0.0)) && any(s != vec3f(0.0));
}

// Edge index and direction (+1, or -1 when it runs j -> i) of the edge joining vertices i and j.
fn edge_of(i: u32, j: u32) -> vec2i {
    return vec2i(edge_index(min(i, j), max(i, j)), select(1, -1, i > j));
}
