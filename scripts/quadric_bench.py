#!/usr/bin/env python3
"""Throughput of the ray-cast quadrics (issue 18): `cadre bench render` on the thesis' scenes
and on generated crowds of spheres, cylinders and cones cut by 0 and 6 planes.

Usage: python3 scripts/quadric_bench.py --cadre BIN [--counts 100000,1000000] [--size 1920x1080]
           [--frames 5] [--out DIR]

Writes the crowd scene files into DIR (default target/quadric_bench), runs each, and prints
one JSON line per run (`cadre bench render`'s object, with the peak resident memory of the
process in MB) and a Markdown table: frame time, the visibility pass's GPU time, and the
cost of 6 planes against none at each count.
"""
import argparse
import json
import os
import subprocess

HERE = os.path.dirname(os.path.abspath(__file__))
SCENES = os.path.join(HERE, "..", "examples", "scenes")


def crowd(count, planes, out):
    # The bundled 10⁶ scene's density: a cube of side 1000 (10⁶ objects), scaled by ∛count.
    extent = 1000.0 * (count / 1e6) ** (1.0 / 3.0)
    path = os.path.join(out, f"crowd-{count}-{planes}.json")
    with open(path, "w") as f:
        json.dump({"generate": [{"count": count, "kinds": ["sphere", "cylinder", "cone"],
                                 "planes": planes, "seed": 1, "extent": extent, "size": 1.5}]}, f)
    return path


def run(args, path):
    # GNU time prints the process's peak resident memory (kB) last on stderr.
    cmd = ["/usr/bin/time", "-f", "%M", args.cadre, "bench", "render", path, "--size", args.size,
           "--frames", str(args.frames)]
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode != 0:
        return {"file": path, "error": done.stderr.strip().splitlines()[-2:]}
    result = json.loads(done.stdout.strip().splitlines()[-1])
    result["peak_mb"] = round(int(done.stderr.strip().splitlines()[-1]) / 1024)
    return result


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--cadre", required=True)
    p.add_argument("--counts", default="100000,1000000")
    p.add_argument("--size", default="1920x1080")
    p.add_argument("--frames", type=int, default=5)
    p.add_argument("--out", default=os.path.join(HERE, "..", "target", "quadric_bench"))
    args = p.parse_args()
    os.makedirs(args.out, exist_ok=True)
    rows = []
    for name in ["teapot", "robot", "dna", "mandala"]:
        r = run(args, os.path.join(SCENES, f"{name}.json"))
        print(json.dumps(r), flush=True)
        rows.append((name, r))
    for count in [int(c) for c in args.counts.split(",")]:
        for planes in (0, 6):
            r = run(args, crowd(count, planes, args.out))
            print(json.dumps(r), flush=True)
            rows.append((f"{count} objects, {planes} planes", r))
    print(f"\n| scene ({args.size}) | frame ms (median) | visibility GPU ms | peak MB |")
    print("|---|---|---|---|")
    for name, r in rows:
        if "error" in r:
            print(f"| {name} | error: {r['error']} | | |")
            continue
        vis = r.get("pass_median_ms", {}).get("visibility")
        print(f"| {name} | {r['median_ms']:.1f} | {vis if vis is None else round(vis, 1)} | {r['peak_mb']} |")


if __name__ == "__main__":
    main()
