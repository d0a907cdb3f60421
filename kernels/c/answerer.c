/* certified.h through tetwalk's answerer protocol in binary records (docs/answerers.md): per batch a
 * uint32 count, then that many 80-byte exit-face cases, each beginning with its number; per case the
 * number and the int32 exit face back (-1: none). How CI and tests judge the header as any kernel is:
 *
 *   cc -O3 -I kernels/c -o certified kernels/c/answerer.c
 *   tetwalk stress --answerer ./certified --answerer-format binary --answerer-claims --fail-on claims
 *
 * With TETWALK_FTZ=1 in its environment (x86 with SSE) it answers with subnormals flushed to zero
 * and read as zero (MXCSR's FTZ and DAZ), as a GPU or a -ffast-math program around it may run. */
#include <stdio.h>
#include <stdlib.h>
#if defined(__SSE__)
#include <xmmintrin.h>
#endif
#include "certified.h"

typedef struct {
    uint32_t line;
    float tet[4][3];
    float org[3];
    float dir[3];
    int32_t entry;
} Case;

typedef struct {
    uint32_t line;
    int32_t face;
} Answer;

int main(void) {
    uint32_t n;
    Case c;
#if defined(__SSE__)
    const char *ftz = getenv("TETWALK_FTZ");
    if (ftz && ftz[0] == '1') _mm_setcsr(_mm_getcsr() | 0x8040); /* FTZ (bit 15) and DAZ (bit 6) */
#endif
    while (fread(&n, sizeof n, 1, stdin) == 1) {
        for (uint32_t i = 0; i < n; i++) {
            if (fread(&c, sizeof c, 1, stdin) != 1) return 1;
            Answer a = {c.line, tetwalk_certified_exit_face((const float (*)[3])c.tet, c.org, c.dir, c.entry)};
            fwrite(&a, sizeof a, 1, stdout);
        }
        fflush(stdout);
    }
    return 0;
}
