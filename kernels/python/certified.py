"""certified.h from numpy: the exit faces of whole arrays of cases through a shared library built
from the header (kernels/c/batch.c), here answering tetwalk's binary records as an answerer
(docs/answerers.md) so that tetwalk judges it as it judges any kernel.

    cc -O3 -shared -fPIC -I kernels/c -o libtetwalk_certified.so kernels/c/batch.c
    tetwalk stress --answerer 'python3 kernels/python/certified.py ./libtetwalk_certified.so' \\
        --answerer-format binary --answerer-claims --fail-on claims
"""
import ctypes
import sys

import numpy as np

CASE = np.dtype([("line", "<u4"), ("tet", "<f4", (4, 3)), ("org", "<f4", 3), ("dir", "<f4", 3), ("entry", "<i4")])
ANSWER = np.dtype([("line", "<u4"), ("face", "<i4")])


def load(path):
    """The library's batch function: faces = exit_faces(tets (n, 4, 3), orgs (n, 3), dirs (n, 3), entries (n,))."""
    lib = ctypes.CDLL(path)
    f = lib.tetwalk_certified_exit_faces
    f.restype = None
    ptr = np.ctypeslib.ndpointer
    f.argtypes = [ctypes.c_int64, ptr(np.float32, flags="C"), ptr(np.float32, flags="C"),
                  ptr(np.float32, flags="C"), ptr(np.int32, flags="C"), ptr(np.int32, flags="C")]

    def exit_faces(tets, orgs, dirs, entries):
        out = np.empty(len(entries), np.int32)
        f(len(entries), np.ascontiguousarray(tets, np.float32), np.ascontiguousarray(orgs, np.float32),
          np.ascontiguousarray(dirs, np.float32), np.ascontiguousarray(entries, np.int32), out)
        return out

    return exit_faces


def main():
    exit_faces = load(sys.argv[1])
    inp, out = sys.stdin.buffer, sys.stdout.buffer
    while True:
        head = inp.read(4)
        if len(head) < 4:
            return
        n = int(np.frombuffer(head, "<u4")[0])
        cases = np.frombuffer(inp.read(n * CASE.itemsize), CASE)
        answers = np.empty(n, ANSWER)
        answers["line"] = cases["line"]
        answers["face"] = exit_faces(cases["tet"], cases["org"], cases["dir"], cases["entry"])
        out.write(answers.tobytes())
        out.flush()


if __name__ == "__main__":
    main()
