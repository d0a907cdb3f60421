#!/usr/bin/env python3
"""Embree 4 (through the `embreex` binding, `pip install embreex`) answering tetwalk's closed-mesh
cases: reads `gen-cases --shape ...` lines on standard input, writes one answer per case for
`tetwalk judge CASES ANSWERS`: `{"line": n, "tri": i, "t": t}` for Embree's nearest hit, or
`{"line": n, "tri": null}` for a miss.

    --robust   build each scene with RTC_SCENE_FLAG_ROBUST (embreex's own default); without it, the
               scene has Embree's default flags (RTC_SCENE_FLAG_NONE), as Embree's C API and Mitsuba 3
               build theirs.
"""
import json
import sys

import numpy as np
from embreex import rtcore_scene as rtcs
from embreex.mesh_construction import TriangleMesh


def main():
    robust = "--robust" in sys.argv[1:]
    out = sys.stdout
    for n, line in enumerate(sys.stdin, 1):
        if not line.strip():
            continue
        case = json.loads(line)
        tris = np.array(case["tris"], dtype=np.float32)
        scene = rtcs.EmbreeScene(robust=robust)
        TriangleMesh(scene, tris)
        org = np.array([case["org"]], dtype=np.float32)
        d = np.array([case["dir"]], dtype=np.float32)
        hit = scene.run(org, d, output=1)
        prim = int(hit["primID"][0])
        if int(hit["geomID"][0]) < 0 or prim < 0:
            answer = {"line": n, "tri": None}
        else:
            # tfar is the f32 t Embree found, along the direction as given (not normalized).
            answer = {"line": n, "tri": prim, "t": float(hit["tfar"][0])}
        out.write(json.dumps(answer) + "\n")


if __name__ == "__main__":
    main()
