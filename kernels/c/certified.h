/* certified.h — tetwalk's `certified` exit face, never wrong, for C99, C++, CUDA/HIP and OpenCL C.
 *
 * SPDX-License-Identifier: MIT OR Apache-2.0
 * Copyright (c) 2026 the tetwalk authors. Permission is granted to use, copy, modify and distribute
 * this file under the terms of the MIT licence or the Apache License 2.0, at your choice.
 *
 * One header, no dependencies, no allocation. It gives the face through which a ray leaves a
 * positively oriented tetrahedron (face i opposite vertex i; orient3d(v0, v1, v2, v3) > 0 as
 * tetwalk states it), for f32 inputs, exactly: Maria et al. 2017's Algorithm 1 (Tables 1 and 2)
 * with every side product's sign certified — computed in f32 beside a forward error bound, then
 * where that cannot settle it in double beside the same bound for double, and decided exactly
 * (floating-point expansions, as Shewchuk's predicates compute them) where neither can; ties broken by the Simulation of Simplicity of tetwalk's `exact` walk, so
 * that walks through a mesh are consistent (tetrahedra sharing a face agree on it) and end.
 *
 *   int tetwalk_certified_exit_face(const float tet[4][3], const float org[3],
 *                                   const float dir[3], int entry);
 *
 * `entry`: the face the ray entered by (0..3), or -1 where none is known (a walk's first
 * tetrahedron). Returns the exit face 0..3, or -1 where the line misses the tetrahedron (or the
 * input is not finite, or the direction is zero). With TETWALK_CERTIFIED_NO_EXACT defined (a shader,
 * a device build that leaves the exact stage out) it returns TETWALK_CERTIFIED_UNSETTLED where a
 * sign is not settled in f32: finish that case on the host with this header as it is.
 *
 *   int tetwalk_certified_step(const tetwalk_mesh *m, int32_t tet, const float org[3],
 *                              const float dir[3], int entry, int32_t *next, int *next_entry);
 *   int tetwalk_certified_walk(const tetwalk_mesh *m, int32_t tet, const float org[3],
 *                              const float dir[3], int32_t max_steps, int32_t *end, int *face);
 *
 * Sound as C compilers compile it (the derivation: tetwalk's src/methods/certified.md, the FLUSHING
 * column, and docs/fix.md):
 *  - contraction on or off (-ffp-contract=fast|on|off, -mfma, CUDA's default fmad): a fused
 *    multiply-add performs a subset of the roundings the f32 bound covers, and the exact stage
 *    multiplies only where the product is exact;
 *  - subnormals flushed or not (FTZ/DAZ, CUDA -ftz=true): the f32 stage sends any input with a
 *    nonzero coordinate below 2^-102 (or a subnormal direction component) to the exact stage, where
 *    every value is zero or a normal double (integer multiples of 2^-447, below 2^390), and f32
 *    inputs are widened to double by integer arithmetic, so that DAZ cannot read one as zero;
 *  - not covered, and refused at compile time where the compiler says so: x87 extended precision
 *    (FLT_EVAL_METHOD != 0), -ffast-math and its parts (__FAST_MATH__, __ASSOCIATIVE_MATH__,
 *    __FINITE_MATH_ONLY__), -funsafe-math-optimizations, and rounding other than to nearest.
 */
#ifndef TETWALK_CERTIFIED_H
#define TETWALK_CERTIFIED_H

#if defined(__FAST_MATH__) || defined(__ASSOCIATIVE_MATH__) || defined(__FINITE_MATH_ONLY__) && __FINITE_MATH_ONLY__
#error "certified.h: -ffast-math, -fassociative-math and -ffinite-math-only reorder or drop the roundings its proof counts"
#endif
#if defined(__FLT_EVAL_METHOD__) && __FLT_EVAL_METHOD__ != 0
#error "certified.h: floats evaluated in wider precision (FLT_EVAL_METHOD != 0, x87): build with SSE (-mfpmath=sse)"
#endif

#if defined(__OPENCL_VERSION__)
typedef int int32_t;
typedef uint uint32_t;
typedef ulong uint64_t;
#define TETWALK_FN static inline
#elif defined(__CUDACC__) || defined(__HIPCC__)
#include <stdint.h>
#define TETWALK_FN static inline __host__ __device__
#else
#include <stdint.h>
#define TETWALK_FN static inline
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* What a shader build returns for a case whose signs f32 cannot settle (the host finishes it). */
#define TETWALK_CERTIFIED_UNSETTLED (-2)

/* A mesh as tetwalk's scenes hold it: points, tetrahedra (four point indices, positively oriented)
 * and neighbours (neighbor[t][i] across face i, opposite vertex i; -1 on the hull). */
typedef struct {
    const float (*points)[3];
    const int32_t (*tets)[4];
    const int32_t (*neighbors)[4];
} tetwalk_mesh;

/* The tables, declared where they are used (file-scope arrays are not visible to CUDA device code
 * or OpenCL kernels): tetwalk's tet.rs, face i's vertices counterclockwise seen from outside, and
 * the six edges; Maria et al.'s Table 2 (each entry face's vertices, lambda) and Table 1 (the exit
 * face by entry face and local identifier), as tetwalk's maria17.rs has them. */
#define TETWALK_FACES const int tetwalk_faces[4][3] = {{1, 3, 2}, {0, 2, 3}, {0, 3, 1}, {0, 1, 2}}
#define TETWALK_EDGES const int tetwalk_edges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}}
#define TETWALK_LAMBDA const int tetwalk_lambda[4][3] = {{3, 1, 2}, {2, 0, 3}, {3, 0, 1}, {1, 0, 2}}
#define TETWALK_GET_FACE const int tetwalk_get_face[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}}

/* The edge joining vertices i and j (its index among TETWALK_EDGES), and whether it runs j -> i. */
TETWALK_FN int tetwalk_edge_of(int i, int j, int *reversed) {
    TETWALK_EDGES;
    for (int e = 0; e < 6; e++) {
        if (tetwalk_edges[e][0] == i && tetwalk_edges[e][1] == j) { *reversed = 0; return e; }
        if (tetwalk_edges[e][0] == j && tetwalk_edges[e][1] == i) { *reversed = 1; return e; }
    }
    *reversed = 0;
    return 0;
}

/* ---- f32 bits ---- */

TETWALK_FN uint32_t tetwalk_bits(float x) {
#if defined(__OPENCL_VERSION__)
    return as_uint(x);
#else
    union { float f; uint32_t u; } v;
    v.f = x;
    return v.u;
#endif
}

/* |x|, its sign bit cleared (no libm, and exact whatever the environment). */
TETWALK_FN float tetwalk_abs(float x) {
#if defined(__OPENCL_VERSION__)
    return as_float(as_uint(x) & 0x7fffffffu);
#else
    union { float f; uint32_t u; } v;
    v.f = x;
    v.u &= 0x7fffffffu;
    return v.f;
#endif
}

/* The bound's constants (certified.md, FLUSHING: u = 2^-24, every absolute error 2^-126). */
#define TETWALK_A 4.76837158203125e-7f     /* 2^-21 */
#define TETWALK_MU 1.9721522630525295e-31f /* 2^-102 */
#define TETWALK_C 1.8807909613156600e-37f  /* 2^-122 */
#define TETWALK_TINY_BITS 0x0c800000u      /* 2^-102's bits: nonzero coordinates below it are gated */
#define TETWALK_MAX 3.40282347e38f

/* Whether a nonzero coordinate of v lies below 2^-102 in magnitude (on the bits: a flushing processor
 * compares a subnormal as zero). */
TETWALK_FN int tetwalk_tiny(const float v[3], uint32_t limit) {
    for (int i = 0; i < 3; i++) {
        uint32_t b = tetwalk_bits(v[i]) & 0x7fffffffu;
        if (b != 0 && b < limit) return 1;
    }
    return 0;
}

/* Whether the f32 stage may settle signs for this tetrahedron and ray: unless a vertex or the origin
 * has a nonzero coordinate below 2^-102 or the direction a subnormal one (certified.md, "gated"). */
TETWALK_FN int tetwalk_settles(const float tet[4][3], const float org[3], const float dir[3]) {
    if (tetwalk_tiny(org, TETWALK_TINY_BITS) || tetwalk_tiny(dir, 0x00800000u)) return 0;
    for (int v = 0; v < 4; v++)
        if (tetwalk_tiny(tet[v], TETWALK_TINY_BITS)) return 0;
    return 1;
}

/* The f32 stage: the sign of det[a - o, b - o, d] = (a - b) . ((b - o) x d) where it clears its
 * bound (certified.md steps 1-9), else 0. */
TETWALK_FN int tetwalk_f32_side(const float a[3], const float b[3], const float o[3], const float d[3]) {
    float q[3] = {b[0] - o[0], b[1] - o[1], b[2] - o[2]};
    float e[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    float det = 0.0f, perm = 0.0f;
    for (int i = 0; i < 3; i++) {
        int j = (i + 1) % 3, k = (i + 2) % 3;
        float p1 = q[j] * d[k], p2 = q[k] * d[j];
        float w = p1 - p2;
        float m = (tetwalk_abs(p1) + tetwalk_abs(p2)) + TETWALK_MU;
        det = det + e[i] * w;
        perm = perm + tetwalk_abs(e[i]) * m;
    }
    float bound = TETWALK_A * perm + TETWALK_C;
    float ad = tetwalk_abs(det);
    if (ad > bound && ad <= TETWALK_MAX) return det > 0.0f ? 1 : -1;
    return 0;
}

/* ---- The exact stage: floating-point expansions ---- */

#ifndef TETWALK_CERTIFIED_NO_EXACT

/* An f32 widened to double exactly, by integer arithmetic for a subnormal (DAZ reads one as zero). */
TETWALK_FN double tetwalk_wide(float x) {
    uint32_t b = tetwalk_bits(x);
    if ((b & 0x7f800000u) != 0) return (double)x;
    /* 2^-149, from its bits (874 = 1023 - 149 the biased exponent). */
#if defined(__OPENCL_VERSION__)
    double step = as_double(0x36a0000000000000ul);
#else
    union { uint64_t u; double f; } two;
    two.u = 0x36a0000000000000ull;
    double step = two.f;
#endif
    double m = (double)(int32_t)(b & 0x007fffffu) * step;
    return (b >> 31) ? -m : m;
}

/* h with the low 29 bits of its significand cleared: its top 24 bits (h a normal double). */
TETWALK_FN double tetwalk_top24(double h) {
#if defined(__OPENCL_VERSION__)
    return as_double(as_ulong(h) & 0xffffffffe0000000ul);
#else
    union { double f; uint64_t u; } v;
    v.f = h;
    v.u &= 0xffffffffe0000000ull;
    return v.f;
#endif
}

/* s + err = a + b exactly (Knuth's two-sum; no multiplication, so nothing to contract). */
TETWALK_FN void tetwalk_two_sum(double a, double b, double *s, double *err) {
    double x = a + b, bv = x - a, av = x - bv;
    *s = x;
    *err = (a - av) + (b - bv);
}

/* An expansion: nonoverlapping doubles, increasing in magnitude, zeros left out (Shewchuk's
 * grow_expansion_zeroelim); at most 64 terms (the largest sum below has 48). */
typedef struct {
    double e[64];
    int n;
} tetwalk_expansion;

TETWALK_FN void tetwalk_grow(tetwalk_expansion *x, double b) {
    double q = b, s, err;
    int k = 0;
    for (int i = 0; i < x->n; i++) {
        tetwalk_two_sum(q, x->e[i], &s, &err);
        if (err != 0.0) x->e[k++] = err;
        q = s;
    }
    if (q != 0.0 && k < 64) x->e[k++] = q;
    x->n = k;
}

/* Adds sign * x * y * z exactly: x y is exact in double (48 bits), split into two 24-bit halves,
 * each times z exact again. Every value is an integer multiple of 2^-447: zero or a normal double. */
TETWALK_FN void tetwalk_add_triple(tetwalk_expansion *s, int sign, float x, float y, float z) {
    double h = tetwalk_wide(x) * tetwalk_wide(y);
    double hi = tetwalk_top24(h), lo = h - hi, wz = tetwalk_wide(z);
    tetwalk_grow(s, sign * (hi * wz));
    tetwalk_grow(s, sign * (lo * wz));
}

/* Adds sign * det[x, y, z] (rows), six triple products. */
TETWALK_FN void tetwalk_add_det(tetwalk_expansion *s, int sign, const float x[3], const float y[3], const float z[3]) {
    for (int i = 0; i < 3; i++) {
        int j = (i + 1) % 3, k = (i + 2) % 3;
        tetwalk_add_triple(s, sign, x[i], y[j], z[k]);
        tetwalk_add_triple(s, -sign, x[i], y[k], z[j]);
    }
}

TETWALK_FN int tetwalk_sign_of(const tetwalk_expansion *s) {
    return s->n == 0 ? 0 : (s->e[s->n - 1] > 0.0 ? 1 : -1);
}

/* The sign of det[a - b, c - d, e], exactly (multilinear: four determinants of the inputs). */
TETWALK_FN int tetwalk_sign_det(const float a[3], const float b[3], const float c[3], const float d[3], const float e[3]) {
    tetwalk_expansion s;
    s.n = 0;
    tetwalk_add_det(&s, 1, a, c, e);
    tetwalk_add_det(&s, -1, a, d, e);
    tetwalk_add_det(&s, -1, b, c, e);
    tetwalk_add_det(&s, 1, b, d, e);
    return tetwalk_sign_of(&s);
}

/* The sign of ((p - q) x r)[axis], exactly (four products, each exact in double). */
TETWALK_FN int tetwalk_sign_cross(const float p[3], const float q[3], const float r[3], int axis) {
    int j = (axis + 1) % 3, k = (axis + 2) % 3;
    tetwalk_expansion s;
    s.n = 0;
    tetwalk_grow(&s, tetwalk_wide(p[j]) * tetwalk_wide(r[k]));
    tetwalk_grow(&s, -(tetwalk_wide(q[j]) * tetwalk_wide(r[k])));
    tetwalk_grow(&s, -(tetwalk_wide(p[k]) * tetwalk_wide(r[j])));
    tetwalk_grow(&s, tetwalk_wide(q[k]) * tetwalk_wide(r[j]));
    return tetwalk_sign_of(&s);
}

/* The f64 filter: certified.md's steps 1-9 in double on the inputs widened exactly, with u = 2^-53
 * and no absolute error at all — every value computed from f32 inputs is an integer multiple of
 * 2^-447 (differences of multiples of 2^-149, products of those), so it is zero or a normal double
 * and nothing underflows, flushed or not — hence the constants A = 8u = 2^-50, mu = C = 0
 * (conditions (R), (M), (C) with eta = 0); contraction performs a subset of the roundings. The sign
 * of det[a - o, b - o, d] where it clears the bound, else 0. */
TETWALK_FN int tetwalk_f64_side(const float a[3], const float b[3], const float o[3], const float d[3]) {
    double q[3], e[3], dd[3], det = 0.0, perm = 0.0;
    for (int i = 0; i < 3; i++) {
        double oi = tetwalk_wide(o[i]), bi = tetwalk_wide(b[i]);
        q[i] = bi - oi;
        e[i] = tetwalk_wide(a[i]) - bi;
        dd[i] = tetwalk_wide(d[i]);
    }
    for (int i = 0; i < 3; i++) {
        int j = (i + 1) % 3, k = (i + 2) % 3;
        double p1 = q[j] * dd[k], p2 = q[k] * dd[j];
        double w = p1 - p2, m = (p1 < 0 ? -p1 : p1) + (p2 < 0 ? -p2 : p2);
        det = det + e[i] * w;
        perm = perm + (e[i] < 0 ? -e[i] : e[i]) * m;
    }
    double bound = 8.8817841970012523e-16 * perm; /* 2^-50 */
    if (det > bound) return 1;
    if (-det > bound) return -1;
    return 0;
}

/* The side product det[a - o, b - o, d]'s sign: certified (f32 where it settles, then the f64
 * filter, then exactly). */
TETWALK_FN int tetwalk_side(const float a[3], const float b[3], const float o[3], const float d[3], int f32_ok) {
    int s = f32_ok ? tetwalk_f32_side(a, b, o, d) : 0;
    if (s == 0) s = tetwalk_f64_side(a, b, o, d);
    return s != 0 ? s : tetwalk_sign_det(a, o, b, o, d);
}


/* tetwalk's `exact` exit face where no entry face is used: the line's exact exit faces, the tie
 * broken by perturbing the origin to o + eps x + eps^2 y + eps^3 z (exact::perturbed_exit); a line
 * that only touches the tetrahedron gets its first exact exit face; -1 where the line misses it or
 * the tetrahedron is flat. */
TETWALK_FN int tetwalk_perturbed_exit(const float tet[4][3], const float o[3], const float d[3]) {
    TETWALK_FACES;
    TETWALK_EDGES;
    tetwalk_expansion s;
    s.n = 0;
    tetwalk_add_det(&s, 1, tet[0], tet[1], tet[2]);
    tetwalk_add_det(&s, -1, tet[3], tet[1], tet[2]);
    tetwalk_add_det(&s, -1, tet[0], tet[3], tet[2]);
    tetwalk_add_det(&s, -1, tet[0], tet[1], tet[3]);
    int orient = tetwalk_sign_of(&s); /* orient3d(v0, v1, v2, v3) = det[v0 - v3, v1 - v3, v2 - v3] */
    if (orient == 0) return -1;
    int side[6], normal[4];
    for (int e = 0; e < 6; e++)
        side[e] = tetwalk_sign_det(tet[tetwalk_edges[e][0]], o, tet[tetwalk_edges[e][1]], o, d);
    for (int f = 0; f < 4; f++) {
        const int *v = tetwalk_faces[f];
        normal[f] = orient * tetwalk_sign_det(tet[v[1]], tet[v[0]], tet[v[2]], tet[v[0]], d);
    }
    int first_exit = -1;
    for (int pass = 0; pass < 2; pass++) {
        for (int f = 0; f < 4; f++) {
            if (normal[f] <= 0) continue;
            int ok = 1;
            for (int k = 0; k < 3; k++) {
                int rev, e = tetwalk_edge_of(tetwalk_faces[f][k], tetwalk_faces[f][(k + 1) % 3], &rev);
                int c = orient * (rev ? -side[e] : side[e]);
                if (pass == 0 ? c < 0 : c <= 0) ok = 0;
            }
            if (!ok) continue;
            if (pass == 1) return f;
            if (first_exit < 0) first_exit = f;
        }
        if (pass == 0) {
            if (first_exit < 0) return -1; /* no exact exit face: the line misses */
            /* The perturbation: a zero side product takes the first nonzero of -((b - a) x d). */
            for (int e = 0; e < 6; e++) {
                if (side[e] != 0) continue;
                const float *a = tet[tetwalk_edges[e][0]], *b = tet[tetwalk_edges[e][1]];
                for (int axis = 0; axis < 3 && side[e] == 0; axis++)
                    side[e] = -tetwalk_sign_cross(b, a, d, axis);
            }
        }
    }
    return first_exit; /* touches only: the first exact exit face, as `exact` answers */
}

#endif /* TETWALK_CERTIFIED_NO_EXACT */


TETWALK_FN int tetwalk_finite(const float v[3]) {
    for (int i = 0; i < 3; i++)
        if ((tetwalk_bits(v[i]) & 0x7f800000u) == 0x7f800000u) return 0;
    return 1;
}

#ifndef TETWALK_CERTIFIED_NO_EXACT
#define TETWALK_TIE(tet, org, dir) tetwalk_perturbed_exit(tet, org, dir)
#define TETWALK_SIDE(a, b, o, d, ok) tetwalk_side(a, b, o, d, ok)
#else
#define TETWALK_TIE(tet, org, dir) TETWALK_CERTIFIED_UNSETTLED
#define TETWALK_SIDE(a, b, o, d, ok) ((ok) ? tetwalk_f32_side(a, b, o, d) : 0)
#endif

/* The exit face (module comment). Entry given: Algorithm 1, the side products of the ray with the
 * edges V_k -> V_f (V_f the entry face's complement vertex); none: all six side products, the face
 * whose cycle they all turn (Platis & Theoharis); at a tie (a sign exactly zero) `exact`'s answer. */
TETWALK_FN int tetwalk_certified_exit_face(const float tet[4][3], const float org[3], const float dir[3], int entry) {
    TETWALK_FACES;
    TETWALK_EDGES;
    TETWALK_LAMBDA;
    TETWALK_GET_FACE;
    /* A zero direction on the bits (a flushing processor compares a subnormal as zero). */
    int zero = (tetwalk_bits(dir[0]) | tetwalk_bits(dir[1]) | tetwalk_bits(dir[2])) << 1 == 0;
    if (!tetwalk_finite(org) || !tetwalk_finite(dir) || zero) return -1;
    for (int v = 0; v < 4; v++)
        if (!tetwalk_finite(tet[v])) return -1;
    int ok = tetwalk_settles(tet, org, dir);
    if (entry >= 0 && entry < 4) {
        const float *apex = tet[entry];
        const int *l = tetwalk_lambda[entry];
        int s = TETWALK_SIDE(tet[l[2]], apex, org, dir, ok);
        if (s == 0) return TETWALK_TIE(tet, org, dir);
        int id = s > 0;
        int t = TETWALK_SIDE(tet[l[id]], apex, org, dir, ok);
        if (t == 0) return TETWALK_TIE(tet, org, dir);
        return tetwalk_get_face[entry][id + (t < 0)];
    }
    int side[6];
    for (int e = 0; e < 6; e++) {
        side[e] = TETWALK_SIDE(tet[tetwalk_edges[e][0]], tet[tetwalk_edges[e][1]], org, dir, ok);
        if (side[e] == 0) return TETWALK_TIE(tet, org, dir);
    }
    for (int f = 0; f < 4; f++) {
        int pass = 1;
        for (int k = 0; k < 3; k++) {
            int rev, e = tetwalk_edge_of(tetwalk_faces[f][k], tetwalk_faces[f][(k + 1) % 3], &rev);
            if (rev ? side[e] > 0 : side[e] < 0) pass = 0;
        }
        if (pass) return f;
    }
    return TETWALK_TIE(tet, org, dir);
}

/* One walk step in `m`: the exit face of tetrahedron `tet` (entered by `entry`, or -1), the
 * tetrahedron beyond it in `*next` (-1 past the hull) and the face it is entered by there in
 * `*next_entry`. Returns the exit face, -1 (no exit face) or TETWALK_CERTIFIED_UNSETTLED. */
TETWALK_FN int tetwalk_certified_step(const tetwalk_mesh *m, int32_t tet, const float org[3], const float dir[3], int entry, int32_t *next, int *next_entry) {
    float t[4][3];
    for (int v = 0; v < 4; v++)
        for (int i = 0; i < 3; i++) t[v][i] = m->points[m->tets[tet][v]][i];
    int f = tetwalk_certified_exit_face((const float (*)[3])t, org, dir, entry);
    *next = -1;
    *next_entry = -1;
    if (f < 0) return f;
    int32_t n = m->neighbors[tet][f];
    *next = n;
    if (n >= 0) {
        /* The neighbour's face opposite its vertex that is not on the shared face. */
        for (int v = 0; v < 4; v++) {
            int32_t p = m->tets[n][v], shared = 0;
            for (int k = 0; k < 4; k++)
                if (k != f && m->tets[tet][k] == p) shared = 1;
            if (!shared) *next_entry = v;
        }
    }
    return f;
}

/* A whole walk from tetrahedron `tet` (holding the origin): at most `max_steps` steps; the last
 * tetrahedron in `*end` and its exit face in `*face`. Returns 0 where it left the mesh (`*face` the
 * hull face), 1 where it ran out of steps, -1 where a step had no exit face, or
 * TETWALK_CERTIFIED_UNSETTLED. */
TETWALK_FN int tetwalk_certified_walk(const tetwalk_mesh *m, int32_t tet, const float org[3], const float dir[3], int32_t max_steps, int32_t *end, int *face) {
    int entry = -1;
    for (int32_t s = 0; s < max_steps; s++) {
        int32_t next;
        int next_entry;
        int f = tetwalk_certified_step(m, tet, org, dir, entry, &next, &next_entry);
        *end = tet;
        *face = f;
        if (f < 0) return f;
        if (next < 0) return 0;
        tet = next;
        entry = next_entry;
    }
    return 1;
}

#ifdef __cplusplus
}
#endif

#endif /* TETWALK_CERTIFIED_H */
