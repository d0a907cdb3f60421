/* certified.h's speed beside the f32 kernels it replaces, in one harness, on the same cases: an f32
 * Plücker exit test and branch-free Badouel (each face's plane met, the nearest leaving one taken),
 * as photon-transport step functions write them. One core; each kernel over the same cases, the
 * entry face given (a walk's step), every kernel's faces summed so that none is optimised away.
 * Rows: well-shaped tetrahedra with stabbing rays, and rays aimed at an edge and moved by one ulp.
 * Printed: ns per case, certified's ratio to each, and the share of cases certified takes past its
 * f32 stage (a side product f32 could not settle) and to its exact stage (nor could f64).
 *
 *   cc -O3 -I kernels/c -o bench kernels/c/bench.c && ./bench [CASES]        (default 1000000) */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include "certified.h"

/* The next float up (integer arithmetic on the bits: no libm). */
static float nextafterf_local(float x) {
    union { float f; uint32_t u; } v;
    v.f = x;
    v.u += (x >= 0.0f) ? 1 : (uint32_t)-1;
    return v.f;
}

typedef struct {
    float tet[4][3];
    float org[3];
    float dir[3];
    int entry;
} Case;

static uint64_t rng = 0x9e3779b97f4a7c15ull;
static float uniform(void) {
    rng = rng * 6364136223846793005ull + 1442695040888963407ull;
    return (float)(rng >> 40) / 16777216.0f;
}

/* A point of face f (barycentric weights, away from its edges unless `near_edge`). */
static void face_point(const Case *c, int f, int near_edge, float p[3]) {
    static const int fv[4][3] = {{1, 3, 2}, {0, 2, 3}, {0, 3, 1}, {0, 1, 2}};
    float w[3] = {0.2f + uniform(), 0.2f + uniform(), 0.2f + uniform()};
    if (near_edge) w[2] = 0.0f;
    float s = w[0] + w[1] + w[2];
    for (int i = 0; i < 3; i++)
        p[i] = (w[0] * c->tet[fv[f][0]][i] + w[1] * c->tet[fv[f][1]][i] + w[2] * c->tet[fv[f][2]][i]) / s;
}

/* A positively oriented, roughly regular tetrahedron and a ray entering by face `entry`. */
static void make(Case *c, int near_edge) {
    static const float base[4][3] = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
    for (;;) {
        for (int v = 0; v < 4; v++)
            for (int i = 0; i < 3; i++) c->tet[v][i] = base[v][i] + 0.3f * (uniform() - 0.5f);
        float a[3], b[3], d[3];
        for (int i = 0; i < 3; i++) {
            a[i] = c->tet[1][i] - c->tet[0][i];
            b[i] = c->tet[2][i] - c->tet[0][i];
            d[i] = c->tet[3][i] - c->tet[0][i];
        }
        float o = a[0] * (b[1] * d[2] - b[2] * d[1]) - a[1] * (b[0] * d[2] - b[2] * d[0]) + a[2] * (b[0] * d[1] - b[1] * d[0]);
        if (o < 0) { /* orient3d(v0..v3) > 0 is the opposite sign of this determinant */
            break;
        }
        for (int i = 0; i < 3; i++) {
            float t = c->tet[0][i];
            c->tet[0][i] = c->tet[1][i];
            c->tet[1][i] = t;
        }
        break;
    }
    int e = (int)(uniform() * 4) & 3, x = (e + 1 + ((int)(uniform() * 3) % 3)) & 3;
    float p[3], q[3];
    face_point(c, e, 0, p);
    face_point(c, x, near_edge, q);
    for (int i = 0; i < 3; i++) {
        c->dir[i] = q[i] - p[i];
        c->org[i] = p[i] - 0.5f * c->dir[i];
    }
    if (near_edge) c->org[0] = nextafterf_local(c->org[0]);
    c->entry = e;
}

/* f32 Plücker as such codes write it: the side products of the ray with each face's edges; the first
 * face the ray does not enter by whose three are none negative. */
static int plucker(const Case *c) {
    static const int fv[4][3] = {{1, 3, 2}, {0, 2, 3}, {0, 3, 1}, {0, 1, 2}};
    const float *o = c->org, *d = c->dir;
    float m[3] = {o[1] * d[2] - o[2] * d[1], o[2] * d[0] - o[0] * d[2], o[0] * d[1] - o[1] * d[0]};
    for (int f = 0; f < 4; f++) {
        if (f == c->entry) continue;
        int ok = 1;
        for (int k = 0; k < 3 && ok; k++) {
            const float *a = c->tet[fv[f][k]], *b = c->tet[fv[f][(k + 1) % 3]];
            float u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
            float v[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
            /* the permuted inner product of (d : m) and (u : v) */
            float s = d[0] * v[0] + d[1] * v[1] + d[2] * v[2] + u[0] * m[0] + u[1] * m[1] + u[2] * m[2];
            ok = s <= 0.0f;
        }
        if (ok) return f;
    }
    return -1;
}

/* Branch-free Badouel: each face's plane met (t = n . (a - o) / n . d), the nearest face the ray
 * leaves through taken with selects, not branches. */
static int badouel(const Case *c) {
    static const int fv[4][3] = {{1, 3, 2}, {0, 2, 3}, {0, 3, 1}, {0, 1, 2}};
    float best = 3.4e38f;
    int face = -1;
    for (int f = 0; f < 4; f++) {
        const float *a = c->tet[fv[f][0]], *b = c->tet[fv[f][1]], *v = c->tet[fv[f][2]];
        float e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {v[0] - a[0], v[1] - a[1], v[2] - a[2]};
        float n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        float den = n[0] * c->dir[0] + n[1] * c->dir[1] + n[2] * c->dir[2];
        float t = (n[0] * (a[0] - c->org[0]) + n[1] * (a[1] - c->org[1]) + n[2] * (a[2] - c->org[2])) / den;
        int take = (den > 0.0f) & (t < best) & (f != c->entry);
        best = take ? t : best;
        face = take ? f : face;
    }
    return face;
}

static int certified(const Case *c) {
    return tetwalk_certified_exit_face((const float (*)[3])c->tet, c->org, c->dir, c->entry);
}

/* How far certified goes on this case: 0 settled in f32, 1 in the f64 filter, 2 exactly (a sign
 * either left unsettled). */
static int stage(const Case *c) {
    static const int lambda[4][3] = {{3, 1, 2}, {2, 0, 3}, {3, 0, 1}, {1, 0, 2}};
    const float (*t)[3] = (const float (*)[3])c->tet;
    int ok = tetwalk_settles(t, c->org, c->dir), most = 0, id = 0;
    for (int k = 0; k < 2; k++) {
        const float *a = t[lambda[c->entry][k == 0 ? 2 : id]], *b = t[c->entry];
        int s = ok ? tetwalk_f32_side(a, b, c->org, c->dir) : 0, at = 0;
        if (s == 0) {
            s = tetwalk_f64_side(a, b, c->org, c->dir);
            at = s != 0 ? 1 : 2;
        }
        if (s == 0) s = tetwalk_sign_det(a, c->org, b, c->org, c->dir);
        most = at > most ? at : most;
        if (s == 0) break;
        id = s > 0;
    }
    return most;
}

static double seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* The fastest of five timings of `k` over the cases, in ns per case; the faces summed in `sum`. */
static double timed(int (*k)(const Case *), const Case *cases, long n, long *sum) {
    double best = 1e30;
    for (int r = 0; r < 5; r++) {
        long s = 0;
        double t0 = seconds();
        for (long i = 0; i < n; i++) s += k(&cases[i]);
        double t = (seconds() - t0) * 1e9 / n;
        if (t < best) best = t;
        *sum += s;
    }
    return best;
}

int main(int argc, char **argv) {
    long n = argc > 1 ? atol(argv[1]) : 1000000;
    Case *cases = malloc(sizeof(Case) * n);
    if (!cases) return 1;
    printf("| row | certified ns | plucker ns | badouel ns | certified / plucker | certified / badouel | past f32 | exact |\n");
    printf("|---|---|---|---|---|---|---|---|\n");
    for (int near = 0; near < 2; near++) {
        long past = 0, exact = 0, sum = 0;
        for (long i = 0; i < n; i++) {
            make(&cases[i], near);
            int s = stage(&cases[i]);
            past += s > 0;
            exact += s > 1;
        }
        double tc = timed(certified, cases, n, &sum), tp = timed(plucker, cases, n, &sum), tb = timed(badouel, cases, n, &sum);
        printf("| %s | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f%% | %.4f%% |\n", near ? "near-edge" : "well", tc, tp, tb, tc / tp, tc / tb, 100.0 * past / n, 100.0 * exact / n);
        if (sum == 42) printf("\n");
    }
    free(cases);
    return 0;
}
