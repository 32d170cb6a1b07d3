#!/usr/bin/env python3
"""Times Open CASCADE's STEP read + transfer (no meshing) per file: one JSON line per file with
the best time over the repeats, mirroring `cadre bench import`.

Usage: python3 scripts/occt_import.py FOLDER [--repeat N]
Needs: pip install cadquery-ocp-novtk
"""
import glob
import json
import os
import sys
import time

from OCP.IFSelect import IFSelect_RetDone
from OCP.STEPControl import STEPControl_Reader


def main():
    folder = sys.argv[1]
    repeat = int(sys.argv[sys.argv.index("--repeat") + 1]) if "--repeat" in sys.argv else 3
    paths = [folder] if os.path.isfile(folder) else sorted(glob.glob(os.path.join(folder, "*")))
    for path in paths:
        rec = {"file": os.path.basename(path), "bytes": os.path.getsize(path)}
        best = float("inf")
        try:
            for _ in range(max(1, repeat)):
                t0 = time.perf_counter()
                reader = STEPControl_Reader()
                if reader.ReadFile(path) != IFSelect_RetDone:
                    raise RuntimeError("read failed")
                reader.TransferRoots()
                reader.OneShape()
                best = min(best, time.perf_counter() - t0)
            rec["seconds"] = best
        except Exception as ex:  # one bad file must not stop the survey
            rec["error"] = repr(ex)[:200]
        print(json.dumps(rec), flush=True)


if __name__ == "__main__":
    main()
