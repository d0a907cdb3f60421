/* Each stage of certified.h on side products, for checking against an exact oracle: per record of 12
 * floats (a, b, o, d) on standard input, the signs of det[a - o, b - o, d] that the f32 stage, the
 * f64 filter and the exact expansions decide (0: not settled; the exact one 0 at a true zero), one
 * line "f32 f64 exact" each. TETWALK_FTZ=1 runs it with subnormals flushed and read as zero (x86).
 *
 *   cc -O3 -I kernels/c -o signs kernels/c/signs.c */
#include <stdio.h>
#include <stdlib.h>
#if defined(__SSE__)
#include <xmmintrin.h>
#endif
#include "certified.h"

int main(void) {
    float v[12];
#if defined(__SSE__)
    const char *ftz = getenv("TETWALK_FTZ");
    if (ftz && ftz[0] == '1') _mm_setcsr(_mm_getcsr() | 0x8040);
#endif
    while (fread(v, sizeof v, 1, stdin) == 1) {
        const float *a = v, *b = v + 3, *o = v + 6, *d = v + 9;
        /* The f32 stage as the exit face asks it: gated inputs go past it. */
        const float t[4][3] = {{a[0], a[1], a[2]}, {b[0], b[1], b[2]}, {b[0], b[1], b[2]}, {b[0], b[1], b[2]}};
        int f32 = tetwalk_settles(t, o, d) ? tetwalk_f32_side(a, b, o, d) : 0;
        printf("%d %d %d\n", f32, tetwalk_f64_side(a, b, o, d), tetwalk_sign_det(a, o, b, o, d));
    }
    return 0;
}
