#!/usr/bin/env python3
"""Time to image and frame time without a GPU: cadre against Open CASCADE's own viewer, both on
Mesa's llvmpipe, measured in one run (issue 15).

Usage: python3 scripts/compare_render.py [--corpus ../shared/corpus/step] [--files N]
           [--size 1280x960] [--frames 10] [--cadre target/release/cadre] [--out DIR]
Needs: `cargo build --release`, `pip install cadquery-ocp-novtk` (module OCP), Xvfb (the
OCCT side draws through GLX; `../shared/tools/occt_render.py` is that side and documents its
figures). cadre draws on lavapipe (Vulkan), OCCT on GL llvmpipe: the same rasterizer.

Files: N corpus files spread over the corpus' sizes (every len/N-th by size), and the 100×
scene (trj3_s1-ug-214 placed 10 × 10 times). For each, in this order, alternating sides per
figure so that a noisy machine loads both alike:
  frame        the viewer's frame after a 2° orbit: OCCT `frame_ms` (Redraw) against
               `cadre bench view` (kept viewport, no readback); shaded with B-Rep edges, 1×.
  pixmap       an offscreen draw read back: OCCT `pixmap_ms` (ToPixMap) against
               `cadre bench render --mode shaded-edges` (no supersampling).
  image        one process making one PNG, each side's defaults: OCCT's GL context
               (`setup_s`, once per process) + `to_image_s` (read, mesh, display, first
               redraw, dump) against the wall time of `cadre render --mode shaded-edges`
               (its default anti-aliasing: edge smoothing of the 1× image on a CPU adapter,
               2×2 supersampling on a GPU; GPU start-up and exit included).
  image_aa     the same, anti-aliased both: OCCT `--msaa 4` against cadre's default.
  image_1x     the same, matched: OCCT without AA against cadre `--supersample 1
               --deflection-rel 0.001` (OCCT's deflection here).
Ratios are OCCT time / cadre time: above 1 = cadre faster. Prints a Markdown table and the
median ratio of each figure; every raw figure goes to DIR/compare_render.jsonl.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
SHARED = os.path.normpath(os.path.join(HERE, "..", "..", "shared"))
HEAVY = "trj3_s1-ug-214.stp"


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--corpus", default=os.path.join(SHARED, "corpus", "step"))
    p.add_argument("--files", type=int, default=12, help="corpus files, spread over sizes")
    p.add_argument("--size", default="1280x960")
    p.add_argument("--frames", type=int, default=10)
    p.add_argument("--cadre", default=os.path.join(HERE, "..", "target", "release", "cadre"))
    p.add_argument("--out", default="/tmp/compare_render")
    p.add_argument("--display", default=":93", help="X display for Xvfb")
    return p.parse_args()


def spread(corpus, n):
    """n files every len/n-th by size (largest first), skipping none."""
    files = sorted(
        (os.path.join(corpus, f) for f in os.listdir(corpus)
         if f.lower().endswith((".stp", ".step"))),
        key=os.path.getsize, reverse=True)
    step = max(len(files) // n, 1)
    return files[::step][:n]


def occt(files, args, extra):
    """One occt_render.py process over `files`; its JSON lines by file name."""
    cmd = [sys.executable, os.path.join(SHARED, "tools", "occt_render.py"), *files,
           "--out-dir", os.path.join(args.out, "occt"), "--size", args.size,
           "--frames", str(args.frames), *extra]
    env = dict(os.environ, DISPLAY=args.display)
    run = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=3600)
    rows = {}
    for line in run.stdout.splitlines():
        if line.startswith("{"):
            row = json.loads(line)
            rows[row["file"]] = row
    if not rows:
        raise SystemExit(f"occt_render.py gave nothing:\n{run.stderr[-2000:]}")
    # The GL context is made once per process, with the first file: every one-image
    # process pays it.
    setup = next(r["setup_s"] for r in rows.values() if r.get("setup_s") is not None)
    for r in rows.values():
        r["setup_once_s"] = setup
    return rows


def cadre_json(args, *cmd):
    run = subprocess.run([args.cadre, *cmd], capture_output=True, text=True, timeout=3600)
    if run.returncode != 0:
        return None
    return json.loads(run.stdout)


def cadre_image(args, path, *extra):
    """Wall seconds of one `cadre render` process (best of 3), or None if it fails."""
    out = os.path.join(args.out, "cadre", os.path.splitext(os.path.basename(path))[0] + ".png")
    best = None
    for _ in range(3):
        t = time.perf_counter()
        run = subprocess.run([args.cadre, "render", path, "-o", out, "--size", args.size,
                              "--mode", "shaded-edges", *extra],
                             capture_output=True, text=True, timeout=3600)
        dt = time.perf_counter() - t
        if run.returncode != 0:
            return None
        best = dt if best is None else min(best, dt)
    return best


def ratio(a, b):
    return None if a is None or b is None or b <= 0 else a / b


def fmt(x, digits=2):
    return "—" if x is None else f"{x:.{digits}f}"


def main():
    args = parse_args()
    os.makedirs(os.path.join(args.out, "occt"), exist_ok=True)
    os.makedirs(os.path.join(args.out, "cadre"), exist_ok=True)
    xvfb = subprocess.Popen(["Xvfb", args.display, "-screen", "0", "1920x1200x24"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    time.sleep(1.0)
    try:
        files = spread(args.corpus, args.files)
        heavy = os.path.join(args.corpus, HEAVY)
        rows = []
        for path, grid in [(f, 1) for f in files] + [(heavy, 10)]:
            name = os.path.basename(path) + (" × 100" if grid == 10 else "")
            row = {"file": name, "bytes": os.path.getsize(path)}
            # Frame and pixmap: OCCT first, then cadre, per file.
            o = occt([path], args, ["--grid", str(grid)]).get(os.path.basename(path), {})
            v = cadre_json(args, "bench", "view", path, "--grid", str(grid), "--size", args.size,
                           "--frames", str(args.frames))
            r = cadre_json(args, "bench", "render", path, "--grid", str(grid), "--size",
                           args.size, "--frames", str(min(args.frames, 5)),
                           "--mode", "shaded-edges")
            row["occt_frame_ms"] = o.get("frame_ms")
            row["cadre_frame_ms"] = v and v["median_frame_ms"]
            row["occt_pixmap_ms"] = o.get("pixmap_ms")
            row["cadre_pixmap_ms"] = r and r["median_ms"]
            row["triangles_occt"] = o.get("triangles")
            row["triangles_cadre"] = v and v["triangles"]
            if grid == 1:
                row["occt_image_s"] = o.get("to_image_s") and o["to_image_s"] + o["setup_once_s"]
                row["cadre_image_s"] = cadre_image(args, path)
                aa = occt([path], args, ["--msaa", "4", "--frames", "1"]).get(os.path.basename(path), {})
                row["occt_image_aa_s"] = aa.get("to_image_s") and aa["to_image_s"] + aa["setup_once_s"]
                row["cadre_image_1x_s"] = cadre_image(args, path, "--supersample", "1",
                                                      "--deflection-rel", "0.001")
            rows.append(row)
            print(json.dumps(row), file=sys.stderr)
    finally:
        xvfb.terminate()
    with open(os.path.join(args.out, "compare_render.jsonl"), "w") as f:
        for row in rows:
            f.write(json.dumps(row) + "\n")
    report(rows)


def report(rows):
    figures = [
        ("frame", "occt_frame_ms", "cadre_frame_ms"),
        ("pixmap", "occt_pixmap_ms", "cadre_pixmap_ms"),
        ("image", "occt_image_s", "cadre_image_s"),
        ("image_aa", "occt_image_aa_s", "cadre_image_s"),
        ("image_1x", "occt_image_s", "cadre_image_1x_s"),
    ]
    print("| file | frame ms OCCT / cadre (ratio) | pixmap ms | image s (default) | "
          "image s (AA: OCCT MSAA 4 vs cadre default) | image s (1×, matched) |")
    print("|---|---|---|---|---|---|")
    ratios = {f: [] for f, _, _ in figures}
    for row in rows:
        cells = []
        for name, o, c in figures:
            q = ratio(row.get(o), row.get(c))
            if q is not None:
                ratios[name].append(q)
            digits = 0 if name in ("frame", "pixmap") else 2
            cells.append(f"{fmt(row.get(o), digits)} / {fmt(row.get(c), digits)} ({fmt(q)})"
                         if row.get(o) is not None or row.get(c) is not None else "")
        print(f"| {row['file']} | " + " | ".join(cells) + " |")
    print()
    for name, values in ratios.items():
        if values:
            print(f"median OCCT / cadre, {name}: {statistics.median(values):.2f} "
                  f"(min {min(values):.2f}, max {max(values):.2f}, {len(values)} files)")


if __name__ == "__main__":
    main()
