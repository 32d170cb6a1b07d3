#!/usr/bin/env python3
"""Exactness of the trim and mesh back-ends on every file of a folder (issue 16).

Usage: python3 scripts/verify_corpus.py --cadre CADRE --step STEP_DIR --out DIR
           [--methods trim,mesh] [--zoom 1,10,100,1000] [--size 160x120] [--timeout 600]
           [--cracks exact|fast] [--no-silhouette-fill]

Runs `cadre verify FILE --json --method M` on each STEP file (4 views × the zooms; the face-id
image against the CPU ray caster of the exact B-Rep) and writes DIR/verify_corpus.jsonl (one
object per file and method, as `cadre verify --json` prints it, or an "error") and
DIR/verify_corpus.md: per method and zoom, the files and views compared, those with any
disagreement away from 0.5 px of a true boundary, the worst share with its file and view,
the largest silhouette error in pixels, and the share of covered pixels left unverified.
With --cracks (trim only; issue 17), each view is also drawn with the crack pass off and the
summary adds the crack pixels against the ray caster before and after the fill, their
totals and the files left with any; --no-silhouette-fill leaves out the fill's silhouette
rule (as `cadre render --no-silhouette-fill`).
Flushes as it goes, so a run cut short still leaves what it measured.
"""
import argparse
import json
import os
import subprocess
import time


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--cadre", required=True)
    p.add_argument("--step", required=True)
    p.add_argument("--out", required=True)
    p.add_argument("--methods", default="trim,mesh")
    p.add_argument("--zoom", default="1,10,100,1000")
    p.add_argument("--size", default="160x120")
    p.add_argument("--timeout", type=int, default=600, help="seconds per file and method")
    p.add_argument("--cracks", default=None, help="exact or fast: count crack pixels")
    p.add_argument("--no-silhouette-fill", action="store_true",
                   help="the crack fill without its silhouette rule (with --cracks)")
    return p.parse_args()


def verify(args, path, method):
    cmd = [args.cadre, "verify", path, "--json", "--method", method,
           "--zoom", args.zoom, "--size", args.size]
    if args.cracks and method == "trim":
        cmd += ["--cracks", args.cracks]
        if args.no_silhouette_fill:
            cmd += ["--no-silhouette-fill"]
    start = time.time()
    try:
        run = subprocess.run(cmd, capture_output=True, text=True, timeout=args.timeout)
    except subprocess.TimeoutExpired:
        return {"file": path, "method": method, "error": f"timed out after {args.timeout} s"}
    seconds = time.time() - start
    if run.returncode != 0:
        tail = run.stderr.strip().splitlines()[-1:] or ["(no message)"]
        return {"file": path, "method": method, "error": tail[0]}
    result = json.loads(run.stdout.strip().splitlines()[-1])
    result["seconds"] = round(seconds, 2)
    return result


def summary(results, methods, zooms):
    lines = ["| method | zoom | views | views with any disagreement | worst share (file, view) "
             "| worst silhouette px | unverified share (mean) |",
             "|---|---|---|---|---|---|---|"]
    for method in methods:
        for zoom in zooms:
            views = [(r["file"], v) for r in results
                     if r.get("method") == method and "views" in r
                     for v in r["views"] if float(v["zoom"]) == zoom and v["compared"] > 0]
            if not views:
                continue
            bad = [x for x in views if x[1]["disagree_share"] > 0]
            worst = max(views, key=lambda x: x[1]["disagree_share"])
            sil = max(v["silhouette_px"] for _, v in views)
            unverified = sum(v["unverified_share"] for _, v in views) / len(views)
            lines.append(
                f"| {method} | {zoom:g}× | {len(views)} | {len(bad)} | "
                f"{100 * worst[1]['disagree_share']:.3f} % "
                f"({os.path.basename(worst[0])}, {worst[1]['view']}) | {sil:.1f} | "
                f"{100 * unverified:.2f} % |")
    crack_lines = ["", "| zoom | views | crack pixels before | after | views with cracks after "
                   "(file, view: before → after) |", "|---|---|---|---|---|"]
    any_cracks = False
    for zoom in zooms:
        views = [(r["file"], v) for r in results
                 if r.get("method") == "trim" and "views" in r
                 for v in r["views"] if float(v["zoom"]) == zoom
                 and v.get("cracks_before") is not None]
        if not views:
            continue
        any_cracks = True
        before = sum(v["cracks_before"] for _, v in views)
        after = sum(v["cracks_after"] for _, v in views)
        left = [f"{os.path.basename(f)} {v['view']}: {v['cracks_before']} → {v['cracks_after']}"
                for f, v in views if v["cracks_after"] > 0]
        crack_lines.append(f"| {zoom:g}× | {len(views)} | {before} | {after} | "
                           + ("; ".join(left) or "none") + " |")
    if any_cracks:
        lines += crack_lines
    errors = [r for r in results if "error" in r]
    lines.append("")
    lines.append(f"{len(errors)} runs failed" + (":" if errors else "."))
    for r in errors:
        lines.append(f"- {os.path.basename(r['file'])} ({r['method']}): {r['error']}")
    return "\n".join(lines) + "\n"


def main():
    args = parse_args()
    os.makedirs(args.out, exist_ok=True)
    methods = args.methods.split(",")
    zooms = [float(z) for z in args.zoom.split(",")]
    files = sorted(f for f in os.listdir(args.step)
                   if f.lower().endswith((".stp", ".step")))
    results = []
    with open(os.path.join(args.out, "verify_corpus.jsonl"), "w") as log:
        for k, name in enumerate(files):
            for method in methods:
                r = verify(args, os.path.join(args.step, name), method)
                results.append(r)
                log.write(json.dumps(r) + "\n")
                log.flush()
                print(f"[{k + 1}/{len(files)}] {name} {method}: "
                      + (r["error"] if "error" in r else
                         f"{max(v['disagree_share'] for v in r['views']) * 100:.3f} % worst, "
                         f"{r['seconds']} s"), flush=True)
            with open(os.path.join(args.out, "verify_corpus.md"), "w") as md:
                md.write(summary(results, methods, zooms))


if __name__ == "__main__":
    main()
