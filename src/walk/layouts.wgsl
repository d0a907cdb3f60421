// Seed 003's compact layouts on the GPU, as src/walk/layouts.rs and src/mesh/layout.rs walk them: each
// layout is an array of u32 words, LAYOUT_WORDS per tetrahedron (generated from the Rust structs).

// Rank of vertex index x among a tetrahedron's four (0 for the smallest).
fn rank(v: vec4u, x: u32) -> u32 {
    return u32(v.x < x) + u32(v.y < x) + u32(v.z < x) + u32(v.w < x);
}

// Tet32 (Figure 2): v0 v1 v2, the xor-sum, four neighbours (across v0, v1, v2, the fourth).
fn tet32_vx(t: u32) -> u32 {
    return layout_words[t * TET32_WORDS + 3u];
}

// Algorithm 3 (GETNEXTTET32): the neighbour across vertex `across`.
fn tet32_next(t: u32, prev: u32, all: vec4u, across: u32) -> u32 {
    let b = t * TET32_WORDS;
    var next = layout_words[b + 7u];
    for (var i = 0u; i < 3u; i++) {
        if across == layout_words[b + i] {
            next = layout_words[b + 4u + i];
        }
    }
    return next;
}

// Tet20 (Figure 3): the xor-sum, the neighbours sorted by the index of the vertex they are across.
fn tet20_vx(t: u32) -> u32 {
    return layout_words[t * TET20_WORDS];
}

// Algorithm 5 (GETNEXTTET20): the neighbour at the exit vertex's rank.
fn tet20_next(t: u32, prev: u32, all: vec4u, across: u32) -> u32 {
    return layout_words[t * TET20_WORDS + 1u + rank(all, across)];
}

// Tet16 (Figure 4): the xor-sum and NX_j = N_j xor N_3 over Tet20's sorted neighbours.
fn tet16_vx(t: u32) -> u32 {
    return layout_words[t * TET16_WORDS];
}

// Algorithm 7 (GETNEXTTET16): from the previous tetrahedron (at the rank of the newly fetched vertex,
// all.w) to the one at the exit vertex's rank.
fn tet16_next(t: u32, prev: u32, all: vec4u, across: u32) -> u32 {
    let b = t * TET16_WORDS + 1u;
    let order_a = rank(all, all.w);
    let order_b = rank(all, across);
    var next = prev;
    if order_a != 3u {
        next ^= layout_words[b + order_a];
    }
    if order_b != 3u {
        next ^= layout_words[b + order_b];
    }
    return next;
}
