/* An exit-face kernel as photon-transport and volume-rendering codes write it: f32 Plücker side
 * products with an absolute epsilon, its own face numbering (its face j holds vertices j, j+1, j+2
 * mod 4, so it is opposite vertex j+3), the entry face skipped. Written for tetwalk's answerer
 * protocol in binary records (docs/answerers.md): per batch a uint32 count, then that many 80-byte
 * cases, each beginning with its number; per case an 8-byte answer back, the case's number and the
 * int32 face (-1: none). Under --faces (auto or given) the entry face comes in this kernel's own
 * numbering.
 *
 *   cc -O2 -o plucker_eps plucker_eps.c
 *   tetwalk stress --answerer ./plucker_eps --answerer-format binary --faces auto */
#include <stdint.h>
#include <stdio.h>

#define EPS 1e-6f

typedef struct {
    uint32_t line; /* the case's number, echoed in its answer */
    float tet[4][3];
    float org[3];
    float dir[3];
    int32_t entry; /* in this kernel's numbering (--faces), or -1 */
} Case;

typedef struct {
    uint32_t line;
    int32_t face;
} Answer;

static void sub(const float *a, const float *b, float *out) {
    out[0] = a[0] - b[0];
    out[1] = a[1] - b[1];
    out[2] = a[2] - b[2];
}

/* d . ((p - o) x (q - o)): the side of the line (o, d) from the edge p -> q. */
static float side(const float *o, const float *d, const float *p, const float *q) {
    float a[3], b[3];
    sub(p, o, a);
    sub(q, o, b);
    float c0 = a[1] * b[2] - a[2] * b[1];
    float c1 = a[2] * b[0] - a[0] * b[2];
    float c2 = a[0] * b[1] - a[1] * b[0];
    return d[0] * c0 + d[1] * c1 + d[2] * c2;
}

/* The exit face in this kernel's numbering, or -1. */
static int32_t exit_face(const Case *c) {
    int32_t skip = c->entry; /* its own numbering: -1 skips none */
    for (int j = 0; j < 4; j++) {
        if (j == skip) continue;
        const float *a = c->tet[j % 4], *b = c->tet[(j + 1) % 4], *v = c->tet[(j + 2) % 4];
        const float *apex = c->tet[(j + 3) % 4];
        /* Order the face so that its normal points away from the opposite vertex. */
        float e1[3], e2[3], w[3];
        sub(b, a, e1);
        sub(v, a, e2);
        sub(apex, a, w);
        float n0 = e1[1] * e2[2] - e1[2] * e2[1];
        float n1 = e1[2] * e2[0] - e1[0] * e2[2];
        float n2 = e1[0] * e2[1] - e1[1] * e2[0];
        if (n0 * w[0] + n1 * w[1] + n2 * w[2] > 0) {
            const float *t = b;
            b = v;
            v = t;
        }
        float s0 = side(c->org, c->dir, a, b);
        float s1 = side(c->org, c->dir, b, v);
        float s2 = side(c->org, c->dir, v, a);
        if (s0 >= -EPS && s1 >= -EPS && s2 >= -EPS && s0 + s1 + s2 > 0) return j;
    }
    return -1;
}

int main(void) {
    uint32_t n;
    Case c;
    while (fread(&n, sizeof n, 1, stdin) == 1) {
        for (uint32_t i = 0; i < n; i++) {
            if (fread(&c, sizeof c, 1, stdin) != 1) return 1;
            Answer a = {c.line, exit_face(&c)};
            fwrite(&a, sizeof a, 1, stdout);
        }
        fflush(stdout);
    }
    return 0;
}
