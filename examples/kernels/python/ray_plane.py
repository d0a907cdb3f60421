"""An exit-face kernel in numpy, as a Python ray-marching code writes it: each face's plane met in
float32 (t = n . (a - o) / n . d over the faces the ray leaves through), the nearest one taken, the
entry face skipped. Batches come and go in tetwalk's binary records (docs/answerers.md), read with
one numpy.frombuffer each: per batch a uint32 count, then that many 80-byte cases, each beginning
with its number; per case the number and an int32 face back (-1: none).

    tetwalk stress --answerer 'python3 examples/kernels/python/ray_plane.py' --answerer-format binary
"""
import sys

import numpy as np

CASE = np.dtype([("line", "<u4"), ("tet", "<f4", (4, 3)), ("org", "<f4", 3), ("dir", "<f4", 3), ("entry", "<i4")])
ANSWER = np.dtype([("line", "<u4"), ("face", "<i4")])
# Face i is opposite vertex i (the case's numbering).
FACES = np.array([[1, 3, 2], [0, 2, 3], [0, 3, 1], [0, 1, 2]])


def exit_faces(c):
    tet, o, d = c["tet"], c["org"], c["dir"]
    t = np.full((len(c), 4), np.inf, dtype=np.float32)
    for f in range(4):
        a, b, v = (tet[:, FACES[f, k]] for k in range(3))
        n = np.cross(b - a, v - a)
        away = np.einsum("ij,ij->i", n, tet[:, f] - a) > 0
        n[away] = -n[away]
        den = np.einsum("ij,ij->i", n, d)
        with np.errstate(divide="ignore", invalid="ignore"):
            tf = np.einsum("ij,ij->i", n, a - o) / den
        leaves = (den > 0) & (c["entry"] != f)
        t[leaves, f] = tf[leaves]
    face = np.argmin(t, axis=1).astype("<i4")
    face[~np.isfinite(t.min(axis=1))] = -1
    return face


def main():
    inp, out = sys.stdin.buffer, sys.stdout.buffer
    while True:
        head = inp.read(4)
        if len(head) < 4:
            return
        n = int(np.frombuffer(head, "<u4")[0])
        cases = np.frombuffer(inp.read(n * CASE.itemsize), CASE)
        answers = np.empty(n, ANSWER)
        answers["line"], answers["face"] = cases["line"], exit_faces(cases)
        out.write(answers.tobytes())
        out.flush()


if __name__ == "__main__":
    main()
