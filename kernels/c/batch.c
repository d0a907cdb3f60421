/* certified.h as a shared library for callers in other languages (numpy through ctypes: see
 * kernels/python/certified.py): the exit faces of n cases at once, arrays of float32 and int32.
 *
 *   cc -O3 -shared -fPIC -I kernels/c -o libtetwalk_certified.so kernels/c/batch.c */
#include "certified.h"

#if defined(_WIN32)
#define TETWALK_EXPORT __declspec(dllexport)
#else
#define TETWALK_EXPORT __attribute__((visibility("default")))
#endif

/* out[i] = the exit face of case i (tets: n x 4 x 3, orgs and dirs: n x 3, entries: n, -1 for none). */
TETWALK_EXPORT void tetwalk_certified_exit_faces(int64_t n, const float *tets, const float *orgs, const float *dirs, const int32_t *entries, int32_t *out) {
    for (int64_t i = 0; i < n; i++)
        out[i] = tetwalk_certified_exit_face((const float (*)[3])(tets + 12 * i), orgs + 3 * i, dirs + 3 * i, entries[i]);
}
