#!/usr/bin/env python3
"""Every GPU figure of the renderer's issues in one run, for a lent GPU (issues 14 and 15).

Usage: python3 scripts/gpu_bench.py --new NEW_CADRE [--old OLD_CADRE] --step STEP_DIR --out DIR
           [--tests DIR_OF_TEST_BINARIES]

Writes DIR/gpu_bench.jsonl (every raw figure) and DIR/gpu_bench.md (the tables), flushing as it
goes so that a run cut short still leaves what it measured.

  heavy        the 9,900-instance scene (trj3_s1-ug-214 placed 30 × 30 times, 10.1 M
               triangles) at 1920×1080: `cadre bench view --mode shaded-edges` against
               `--mode shaded` (issue 14: edges within 1.1× of shaded-only), three interleaved
               rounds, and `bench render` (upload + draw + readback) in both modes.
  regression   NEW against OLD (a build from before issue 15's changes) on the 12 files of
               `scripts/compare_render.py` and its 100× scene, 1280×960, interleaved rounds:
               the viewer's frame (`bench view`, shaded with edges), the offscreen frame
               (`bench render`, shaded) and the time to image (`cadre render --mode
               shaded-edges`, each build's default anti-aliasing: 2×2 supersampling on a GPU),
               and the whole folder rendered at 256×192 (one process per build).
  tests        each test binary in DIR run on the GPU (golden images, culling, ...).
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from compare_render import HEAVY, spread  # noqa: E402  (the same files as the comparison)


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--new", required=True)
    p.add_argument("--old")
    p.add_argument("--prev", help="a second build to time on the heavy scene beside NEW")
    p.add_argument("--step", required=True, help="folder of the corpus' STEP files")
    p.add_argument("--out", required=True)
    p.add_argument("--tests", help="folder of test binaries to run on the GPU")
    p.add_argument("--files", type=int, default=12)
    p.add_argument("--rounds", type=int, default=2)
    p.add_argument("--views-only", action="store_true",
                   help="regression: the viewer's frame alone (no offscreen frames, images)")
    p.add_argument("--heavy-grid", default="30", help="instances per side of the heavy scene")
    p.add_argument("--frames", type=int, default=20, help="frames per `bench view` run")
    return p.parse_args()


class Log:
    def __init__(self, out):
        self.jsonl = open(os.path.join(out, "gpu_bench.jsonl"), "a")
        self.md = open(os.path.join(out, "gpu_bench.md"), "a")

    def row(self, measured=None, **extra):
        """One raw figure: what a run printed, with what it was run on."""
        self.jsonl.write(json.dumps({**(measured or {}), **extra}) + "\n")
        self.jsonl.flush()

    def text(self, line):
        print(line, flush=True)
        self.md.write(line + "\n")
        self.md.flush()


def bench(binary, *args, timeout=240):
    """One `cadre bench ...` run: its JSON object, or {"error": ...}."""
    run = subprocess.run([binary, "bench", *args], capture_output=True, text=True,
                         timeout=timeout)
    for line in run.stdout.splitlines():
        if line.startswith("{"):
            return json.loads(line)
    return {"error": run.stderr[-800:]}


def frame_ms(j):
    """The median frame of a `bench view` or `bench render` object."""
    return j.get("median_frame_ms", j.get("median_ms"))


def wall(cmd, timeout=240):
    """Wall time of one process, and whether it succeeded."""
    t = time.perf_counter()
    run = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    return time.perf_counter() - t, run.returncode == 0, run.stderr[-400:]


def med(xs):
    xs = [x for x in xs if x is not None]
    return statistics.median(xs) if xs else None


def fmt(x, digits=1):
    return "—" if x is None else f"{x:.{digits}f}"


def heavy(args, log):
    path = os.path.join(args.step, HEAVY)
    log.text("## The 10 M-triangle scene (issue 14)\n")
    frames = {"shaded-edges": [], "shaded": [], "prev shaded-edges": [], "prev shaded": []}
    builds = [("", args.new)] + ([("prev ", args.prev)] if args.prev else [])
    for r in range(3):
        modes = ("shaded-edges", "shaded") if r % 2 == 0 else ("shaded", "shaded-edges")
        for mode, (tag, binary) in [(m, b) for m in modes for b in builds]:
            j = bench(binary, "view", path, "--grid", args.heavy_grid, "--size", "1920x1080",
                      "--frames", str(args.frames + 10), "--mode", mode)
            log.row(j, kind="heavy_view", round=r, mode=tag + mode)
            frames[tag + mode].append(j.get("median_frame_ms"))
            log.text(f"- round {r}, {tag}{mode}: median frame "
                     f"{fmt(j.get('median_frame_ms'), 2)} ms, "
                     f"pick {fmt(j.get('median_pick_ms'), 2)} ms, hover answer "
                     f"{fmt(j.get('median_hover_answer_ms'), 2)} ms, upload "
                     f"{fmt(j.get('upload_ms'), 1)} ms, {j.get('triangles')} triangles, "
                     f"{j.get('instances')} instances, {j.get('adapter')} {j.get('error', '')}")
    for tag, _ in builds:
        e, s = med(frames[tag + "shaded-edges"]), med(frames[tag + "shaded"])
        if e and s:
            log.text(f"\n**{tag}viewer frame with edges / shaded-only: {e:.2f} / {s:.2f} ms = "
                     f"{e / s:.3f}×** (target ≤ 1.1)\n")
    for grid in ("10", args.heavy_grid):
        for mode in ("shaded", "shaded-edges"):
            j = bench(args.new, "render", path, "--grid", grid, "--size", "1920x1080",
                      "--frames", "5", "--mode", mode)
            log.row(j, kind="heavy_render", grid=grid, mode=mode)
            log.text(f"- bench render grid {grid} {mode}: median "
                     f"{fmt(frame_ms(j), 2)} ms {j.get('error', '')}")
        j = bench(args.new, "view", path, "--grid", grid, "--size", "1920x1080",
                  "--frames", str(args.frames + 10))
        log.row(j, kind="heavy_view_1080", grid=grid)
        log.text(f"- bench view grid {grid} shaded-edges: median "
                 f"{fmt(frame_ms(j), 2)} ms {j.get('error', '')}")


def regression(args, log):
    builds = {"new": args.new, "old": args.old}
    files = [(f, "1") for f in spread(args.step, args.files)]
    files.append((os.path.join(args.step, HEAVY), "10"))
    log.text("\n## NEW against OLD on the GPU (issue 15)\n")
    log.text("| file | view ms old / new | render ms old / new | image s old / new |")
    log.text("|---|---|---|---|")
    ratios = {"view": [], "render": [], "image": []}
    png = os.path.join(args.out, "tmp.png")
    for path, grid in files:
        got = {b: {"view": [], "render": [], "image": []} for b in builds}
        for r in range(args.rounds):
            order = ("old", "new") if r % 2 == 0 else ("new", "old")
            for b in order:
                v = bench(builds[b], "view", path, "--grid", grid, "--size", "1280x960",
                          "--frames", str(args.frames))
                rr = {} if args.views_only else bench(
                    builds[b], "render", path, "--grid", grid, "--size", "1280x960",
                    "--frames", "8")
                log.row(v, kind="view", build=b, file=os.path.basename(path), grid=grid)
                log.row(rr, kind="render", build=b, file=os.path.basename(path), grid=grid)
                got[b]["view"].append(v.get("median_frame_ms"))
                got[b]["render"].append(frame_ms(rr))
                if grid == "1" and not args.views_only:
                    for _ in range(2):
                        s, ok, err = wall([builds[b], "render", path, "-o", png,
                                           "--size", "1280x960", "--mode", "shaded-edges"])
                        log.row(kind="image", build=b, file=os.path.basename(path),
                                seconds=s, ok=ok, err=None if ok else err)
                        got[b]["image"].append(s if ok else None)
        cells = []
        for k in ("view", "render", "image"):
            o, n = med(got["old"][k]), med(got["new"][k])
            digits = 2 if k == "image" else 1
            if o and n:
                ratios[k].append(o / n)
                cells.append(f"{fmt(o, digits)} / {fmt(n, digits)} ({o / n:.2f})")
            else:
                cells.append(f"{fmt(o, digits)} / {fmt(n, digits)}")
        name = os.path.basename(path) + ("" if grid == "1" else f" × {int(grid) ** 2}")
        log.text(f"| {name} | " + " | ".join(cells) + " |")
    log.text("")
    for k, xs in ratios.items():
        if xs:
            log.text(f"- median old / new, {k}: {statistics.median(xs):.2f} "
                     f"(min {min(xs):.2f}, max {max(xs):.2f}, {len(xs)} files)")
    for b in () if args.views_only else ("old", "new", "old", "new"):
        dest = os.path.join(args.out, f"folder_{b}")
        s, ok, err = wall([builds[b], "render", args.step, "-o", dest, "--size", "256x192"],
                          timeout=600)
        # The folder holds files without geometry: the run then ends with an error status
        # after writing every other image, so the status is not the measure.
        images = len([f for f in os.listdir(dest) if f.endswith(".png")])
        log.row(kind="folder", build=b, seconds=s, images=images)
        log.text(f"- whole folder at 256×192, {b}: {s:.2f} s, {images} images")


def run_captured(cmd, timeout):
    """A process's status and output, also when it is killed at `timeout` (status None)."""
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        out, _ = proc.communicate(timeout=timeout)
        return proc.returncode, out
    except subprocess.TimeoutExpired:
        proc.kill()
        out, _ = proc.communicate()
        return None, out


def tests(args, log):
    """Each test binary but its GL-backend tests, then those alone with a short timeout (the
    first lent H200 run saw the golden binary time out at 300 s)."""
    log.text("\n## Test binaries on the GPU\n")
    names = sorted(os.listdir(args.tests))
    runs = [(n, ["--skip", "gl_backend"], 60) for n in names]
    runs += [(n, ["gl_backend"], 30) for n in ("golden", "sections") if n in names]
    for name, extra, timeout in runs:
        binary = os.path.join(args.tests, name)
        t = time.perf_counter()
        status, out = run_captured([binary, "--test-threads", "4", *extra], timeout)
        tail = out[-1500:]
        ok = status == 0
        label = f"{name} {' '.join(extra)}"
        log.row(kind="test", name=label, ok=ok, status=status,
                seconds=time.perf_counter() - t, tail=tail)
        summary = [ln for ln in tail.splitlines() if ln.startswith("test result")]
        verdict = "ok" if ok else ("TIMED OUT" if status is None else "FAILED")
        log.text(f"- {label}: {verdict} {summary[-1] if summary else ''}")
        if not ok:
            log.text("```\n" + tail + "\n```")


def main():
    args = parse_args()
    os.makedirs(args.out, exist_ok=True)
    log = Log(args.out)
    heavy(args, log)
    if args.old:
        regression(args, log)
    if args.tests:
        tests(args, log)


if __name__ == "__main__":
    sys.exit(main())
