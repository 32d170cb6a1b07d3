#!/usr/bin/env python3
"""Frame time of the trim back-end against the mesh back-end (issue 16), in one run.

Usage: python3 scripts/trim_bench.py --cadre CADRE --step STEP_DIR --out DIR
           [--sizes 1920x1080,3840x2160] [--grids 1,10,36] [--frames 20] [--rounds 2]

For each size, each grid (the corpus' largest assembly, trj4_pm2-ec-214: 32 parts and 801
faces, placed GRID × GRID times; 36 × 36 is 1.04 M faces) and pr2db at grid 1, runs
`cadre bench view --method mesh` and `--method trim` (shaded, the viewer's path: a kept
viewport, 2° orbit a frame), and the trim back-end with its per-fragment trim test off
(`--trim-variant no-test`), with its geometry at its least (`--trim-variant least`: one
grid cell per knot span) and with its surfaces evaluated by the vertex shader
(`--trim-variant vertex-eval`), which separate the costs; interleaved over ROUNDS rounds. Writes
DIR/trim_bench.jsonl (every raw figure) and DIR/trim_bench.md (medians, the trim / mesh
ratio and the triangles the trim back-end drew), flushing as it goes so that a run cut short
still leaves what it measured.
"""
import argparse
import json
import os
import statistics
import subprocess
import time

FILES = [("trj4_pm2-ec-214.stp", None), ("pr2db.stp", [1])]


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--cadre", required=True)
    p.add_argument("--step", required=True)
    p.add_argument("--out", required=True)
    p.add_argument("--sizes", default="1920x1080,3840x2160")
    p.add_argument("--grids", default="1,10,36")
    p.add_argument("--frames", type=int, default=20)
    p.add_argument("--rounds", type=int, default=2)
    p.add_argument("--timeout", type=int, default=240, help="seconds per bench run")
    return p.parse_args()


RUNS = [("mesh", "full"), ("trim", "full"), ("trim", "no-test"), ("trim", "least"),
        ("trim", "vertex-eval")]


def bench(args, path, grid, size, method, variant):
    cmd = [args.cadre, "bench", "view", path, "--grid", str(grid), "--size", size,
           "--frames", str(args.frames), "--mode", "shaded", "--method", method,
           "--trim-variant", variant]
    t = time.time()
    try:
        run = subprocess.run(cmd, capture_output=True, text=True, timeout=args.timeout)
    except subprocess.TimeoutExpired:
        return {"error": f"timed out after {args.timeout} s"}
    if run.returncode != 0:
        return {"error": run.stderr.strip()[-400:]}
    out = json.loads(run.stdout.strip().splitlines()[-1])
    out["wall_s"] = time.time() - t
    return out


def main():
    args = parse_args()
    os.makedirs(args.out, exist_ok=True)
    jsonl = open(os.path.join(args.out, "trim_bench.jsonl"), "a")
    md = open(os.path.join(args.out, "trim_bench.md"), "a")
    md.write("| file | grid | size | mesh ms | trim ms | trim / mesh | trim, no trim test | "
             "trim, least geometry | trim, surfaces evaluated per vertex | "
             "trim triangles (mesh's) | faces drawn exactly |\n")
    md.write("|---|---|---|---|---|---|---|---|---|---|---|\n")
    md.flush()
    grids = [int(g) for g in args.grids.split(",")]
    for size in args.sizes.split(","):
        for name, only in FILES:
            path = os.path.join(args.step, name)
            for grid in only or grids:
                times = {run: [] for run in RUNS}
                faces, triangles, mesh_triangles = None, None, None
                for _ in range(args.rounds):
                    for method, variant in RUNS:
                        r = bench(args, path, grid, size, method, variant)
                        r.update({"name": name, "grid": grid, "size": size, "method": method,
                                  "variant": variant})
                        jsonl.write(json.dumps(r) + "\n")
                        jsonl.flush()
                        if "median_frame_ms" in r:
                            times[(method, variant)].append(r["median_frame_ms"])
                            if (method, variant) == ("trim", "full"):
                                faces = r.get("trimmed_faces")
                                triangles = r.get("trim_triangles")
                                mesh_triangles = r.get("triangles")
                med = {k: statistics.median(v) if v else float("nan") for k, v in times.items()}
                mesh, trim = med[("mesh", "full")], med[("trim", "full")]
                md.write(f"| {name} | {grid} | {size} | {mesh:.2f} | {trim:.2f} | "
                         f"{trim / mesh:.2f} | {med[('trim', 'no-test')]:.2f} | "
                         f"{med[('trim', 'least')]:.2f} | {med[('trim', 'vertex-eval')]:.2f} | "
                         f"{triangles} ({mesh_triangles}) | "
                         f"{faces} per placement |\n")
                md.flush()


if __name__ == "__main__":
    main()
