#!/usr/bin/env python3
"""Meshes every STEP file with cadre and with OCCT (BRepMesh, parallel) in the same run, and
compares speed, triangle counts and mesh quality against the corpus reference.

Usage: python3 scripts/compare_mesh.py [FOLDER_OR_FILES...] [--cadre PATH]
           [--deflection-rel 0.001] [--angle 0.5] [--jobs 1] [--timeout 300]
           [--reference reference.jsonl] [--corrections FILE|none] [--tol 0.002]
           [--json-out FILE] [--only-cadre]
  FOLDER defaults to ../shared/corpus/step, the reference to reference.jsonl beside that folder,
  --cadre to ${CARGO_TARGET_DIR:-target}/release/cadre.
  --only-cadre skips OCCT (quality runs at fine settings: --deflection-rel 0.0002 --angle 0.1).
  --time-key picks the figure of cadre's JSON timed against OCCT (default "seconds").
Needs: pip install cadquery-ocp-novtk (unless --only-cadre)

Per file: `cadre mesh FILE -o TMP.glb --deflection-rel R --angle A --json` (one JSON object on
standard output: triangles, area, volume, boundary_edges, nonmanifold_edges, seconds = import +
mesh, faces, failed_faces), then scripts/occt_mesh.py's worker with --parallel (read_s + mesh_s).
A cadre failure, crash or timeout is recorded for that file and counts as failing every quality
criterion; it never stops the run.

Quality, against reference.jsonl (OCCT's exact figures), within --tol (0.2 %):
  area    |mesh area - area| / area, over the files OCCT reads (no occt_error);
  volume  |mesh volume - volume| / volume, over the files with volume > 0;
  closed  0 boundary edges (of solids and closed shells; open sheets' borders are
          open_boundary_edges), over the files with solids > 0.
The same criteria are shown for OCCT's own mesh, for scale.

--corrections (default crates/cadre-mesh/tests/data/reference_corrections.jsonl, as the corpus
test uses) replaces the reference's area or volume where OCCT's default integration rule is
measurably wrong, and marks the files whose shape OCCT misreads: the quality lines then also
give the figures without those files. --corrections none scores against reference.jsonl as is.
"""
import argparse
import concurrent.futures
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

SCRIPTS = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(SCRIPTS)
sys.path.insert(0, SCRIPTS)
sys.dont_write_bytecode = True  # no __pycache__ in scripts/
import occt_mesh  # noqa: E402  (imports OCP only in its worker)


def parse_args(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("inputs", nargs="*", help="STEP files or folders (default: the corpus)")
    p.add_argument("--cadre", help="cadre binary (default: ${CARGO_TARGET_DIR:-target}/release/cadre)")
    p.add_argument("--deflection-rel", type=float, default=0.001,
                   help="linear deflection as a fraction of the bounding box diagonal")
    p.add_argument("--angle", type=float, default=0.5, help="angular deflection (radians)")
    p.add_argument("--jobs", type=int, default=1, help="files processed at once (1 for timings)")
    p.add_argument("--timeout", type=float, default=300.0, help="seconds per file and per tool")
    p.add_argument("--reference", help="reference.jsonl (default: beside the STEP folder)")
    p.add_argument("--corrections", help="reference corrections JSONL, or 'none' (default: the "
                   "corpus test's crates/cadre-mesh/tests/data/reference_corrections.jsonl)")
    p.add_argument("--tol", type=float, default=0.002, help="relative tolerance of area / volume")
    p.add_argument("--json-out", help="write every record and the summary to this JSON file")
    p.add_argument("--only-cadre", action="store_true", help="skip OCCT")
    p.add_argument("--time-key", default="seconds",
                   help="key of cadre's JSON compared with OCCT's read_s + mesh_s")
    return p.parse_args(argv)


# ----------------------------------------------------------------------------- running


def parse_json_output(text):
    """The JSON object a tool printed: the whole output, else the last line that is one."""
    text = text.strip()
    try:
        obj = json.loads(text)
        if isinstance(obj, dict):
            return obj
    except ValueError:
        pass
    for line in reversed(text.splitlines()):
        if line.startswith("{"):
            try:
                return json.loads(line)
            except ValueError:
                continue
    return None


def run_cadre(cadre, path, glb, rel, angle, timeout, time_key="seconds"):
    cmd = [cadre, "mesh", path, "-o", glb, "--deflection-rel", repr(rel), "--angle", repr(angle),
           "--json"]
    t0 = time.perf_counter()
    try:
        proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                              timeout=timeout, text=True, errors="replace")
    except subprocess.TimeoutExpired:
        return {"error": f"timeout after {timeout:g} s"}
    except OSError as ex:
        return {"error": f"cannot run {cadre}: {ex}"[:200]}
    wall = time.perf_counter() - t0
    rec = parse_json_output(proc.stdout) or {}
    rec["wall_s"] = round(wall, 4)
    # A file with nothing to mesh makes `cadre mesh -o` fail (no empty output is written) after
    # its JSON report, which says so: measured, with nothing in it, not a failure.
    empty = proc.returncode == 1 and rec.get("empty") is True
    if proc.returncode != 0 and not empty:
        why = (f"crashed (signal {-proc.returncode})" if proc.returncode < 0
               else f"exit {proc.returncode}")
        lines = [ln.strip() for ln in proc.stderr.splitlines() if ln.strip()]
        # clap and anyhow put the cause on the first line ("error: ..."), panics on the last.
        msg = next((ln for ln in lines if ln.lower().startswith("error")), lines[-1] if lines else "")
        rec["error"] = (why + (": " + msg if msg else ""))[:200]
    elif "triangles" not in rec or time_key not in rec:
        rec["error"] = f"no JSON with triangles and {time_key} on standard output"
    else:
        rec["seconds"] = rec[time_key]  # the time compared (the key given by --time-key)
    return rec


def list_files(inputs):
    return occt_mesh.list_files(inputs)


# ----------------------------------------------------------------------------- scoring


def rel_err(value, ref):
    if value is None or ref is None or ref == 0:
        return None
    return abs(value - ref) / abs(ref)


def ok(rec):
    return rec is not None and "error" not in rec


def count(value):
    """A count that cadre may give as a number or as the list of the items."""
    if isinstance(value, (list, tuple)):
        return len(value)
    return int(value or 0)


def quality(rows, side, tol):
    """Per criterion: (passed, counted, failing [(file, detail)]) for side 'cadre' or 'occt'."""
    keys = {"cadre": ("area", "volume"), "occt": ("mesh_area", "mesh_volume")}[side]
    # Per criterion: passed, counted, failing, and passed / counted without misread files.
    out = {k: [0, 0, [], 0, 0] for k in ("area", "volume", "closed")}

    def tally(k, passed, file, detail, misread):
        out[k][1] += 1
        out[k][0] += passed
        if not misread:
            out[k][4] += 1
            out[k][3] += passed
        if not passed:
            out[k][2].append((file, detail))

    for row in rows:
        ref, rec = row.get("ref"), row.get(side)
        if ref is None:
            continue
        good = ok(rec)
        misread = bool(ref.get("occt_misreads"))
        if "occt_error" not in ref and ref.get("area"):
            e = rel_err(rec.get(keys[0]), ref["area"]) if good else None
            tally("area", e is not None and e <= tol, row["file"], e, misread)
        if (ref.get("volume") or 0) > 0:
            e = rel_err(rec.get(keys[1]), ref["volume"]) if good else None
            tally("volume", e is not None and e <= tol, row["file"], e, misread)
        if (ref.get("solids") or 0) > 0:
            b = rec.get("boundary_edges") if good else None
            tally("closed", b == 0, row["file"], b, misread)
    return out


def fmt_pct(e):
    return "   -   " if e is None else f"{100 * e:7.3f}"


def summarize(rows, args):
    s = {"files": len(rows)}
    cadre_ok = [r for r in rows if ok(r["cadre"])]
    s["cadre_ok"], s["cadre_failed"] = len(cadre_ok), len(rows) - len(cadre_ok)
    s["cadre_total_s"] = sum(r["cadre"]["seconds"] for r in cadre_ok)
    s["cadre_triangles"] = sum(r["cadre"]["triangles"] for r in cadre_ok)
    s["cadre_failed_faces"] = sum(count(r["cadre"].get("failed_faces")) for r in cadre_ok)
    s["cadre_nonmanifold_files"] = sum(1 for r in cadre_ok if r["cadre"].get("nonmanifold_edges"))
    s["cadre_misoriented_files"] = sum(1 for r in cadre_ok if r["cadre"].get("misoriented_edges"))
    if not args.only_cadre:
        occt_ok = [r for r in rows if ok(r["occt"])]
        s["occt_ok"], s["occt_failed"] = len(occt_ok), len(rows) - len(occt_ok)
        both = [r for r in rows if ok(r["cadre"]) and ok(r["occt"])]
        s["both_ok"] = len(both)
        tc = sum(r["cadre"]["seconds"] for r in both)
        tr = sum(r["occt"]["read_s"] for r in both)
        tm = sum(r["occt"]["mesh_s"] for r in both)
        s.update(both_cadre_s=tc, both_occt_read_s=tr, both_occt_mesh_s=tm,
                 occt_over_cadre=(tr + tm) / max(tc, 1e-9))
        ratios = [(r["occt"]["read_s"] + r["occt"]["mesh_s"]) / max(r["cadre"]["seconds"], 1e-9)
                  for r in both]
        if ratios:
            s["speedup_median"] = statistics.median(ratios)
            s["speedup_min"], s["speedup_max"] = min(ratios), max(ratios)
        nc = sum(r["cadre"]["triangles"] for r in both)
        no = sum(r["occt"]["triangles"] for r in both)
        s.update(both_cadre_triangles=nc, both_occt_triangles=no,
                 triangles_cadre_over_occt=nc / max(no, 1))
    s["quality"] = {}
    for side in ("cadre",) + (() if args.only_cadre else ("occt",)):
        q = quality(rows, side, args.tol)
        s["quality"][side] = {k: {"passed": v[0], "counted": v[1],
                                  "failing": [f for f, _ in v[2]],
                                  "passed_read_right": v[3], "counted_read_right": v[4]}
                              for k, v in q.items()}
    return s


def print_table(rows, args):
    occt = not args.only_cadre
    head = f"{'file':32} {'c.tris':>8} "
    head += f"{'o.tris':>8} {'c.s':>8} {'o.s':>8} {'o/c':>6} " if occt else f"{'c.s':>8} "
    head += f"{'c.area%':>7} {'c.vol%':>7} {'c.bnd':>6} {'c.nm':>5} {'c.ff':>4}"
    head += f" {'o.area%':>7} {'o.bnd':>6}" if occt else ""
    print(head)
    for r in rows:
        c, o, ref = r["cadre"], r.get("occt"), r.get("ref") or {}
        line = f"{r['file'][:32]:32} "
        line += f"{c['triangles']:8d} " if ok(c) else f"{'FAIL':>8} "
        if occt:
            line += f"{o['triangles']:8d} " if ok(o) else f"{'FAIL':>8} "
        line += f"{c['seconds']:8.4f} " if ok(c) else f"{'-':>8} "
        if occt:
            line += f"{o['read_s'] + o['mesh_s']:8.4f} " if ok(o) else f"{'-':>8} "
            if ok(c) and ok(o):
                line += f"{(o['read_s'] + o['mesh_s']) / max(c['seconds'], 1e-9):6.1f} "
            else:
                line += f"{'-':>6} "
        if ok(c):
            line += f"{fmt_pct(rel_err(c.get('area'), ref.get('area')))} "
            line += f"{fmt_pct(rel_err(c.get('volume'), ref.get('volume')))} "
            line += f"{c.get('boundary_edges', '-'):>6} {c.get('nonmanifold_edges', '-'):>5} "
            line += f"{count(c.get('failed_faces')):>4}"
        else:
            line += f"{'':>7} {'':>7} {'':>6} {'':>5} {'':>4}"
        if occt:
            if ok(o):
                line += f" {fmt_pct(rel_err(o.get('mesh_area'), ref.get('area')))}"
                line += f" {o.get('boundary_edges', '-'):>6}"
            else:
                line += f" {'':>7} {'':>6}"
        notes = []
        if not ok(c):
            notes.append("cadre: " + c["error"][:70])
        if occt and not ok(o):
            notes.append("occt: " + o["error"][:50])
        print(line + ("  " + "; ".join(notes) if notes else ""))


def print_summary(rows, s, args):
    print()
    print(f"settings: --deflection-rel {args.deflection_rel:g} --angle {args.angle:g}, "
          f"jobs {args.jobs}, machine {os.cpu_count()} cores")
    print(f"files: {s['files']}; cadre meshed {s['cadre_ok']}, failed {s['cadre_failed']}"
          + ("" if args.only_cadre else f"; OCCT meshed {s['occt_ok']}, failed {s['occt_failed']}"))
    if args.only_cadre:
        print(f"cadre: total {s['cadre_total_s']:.3f} s (import + mesh), "
              f"{s['cadre_triangles']} triangles")
    else:
        print(f"files meshed by both: {s['both_ok']}")
        print(f"total time: cadre {s['both_cadre_s']:.3f} s (import + mesh), OCCT "
              f"{s['both_occt_read_s'] + s['both_occt_mesh_s']:.3f} s (read "
              f"{s['both_occt_read_s']:.3f} + mesh {s['both_occt_mesh_s']:.3f}), "
              f"OCCT/cadre = {s['occt_over_cadre']:.2f}x")
        if "speedup_median" in s:
            print(f"per-file speed-up OCCT/cadre: median {s['speedup_median']:.2f}x, "
                  f"min {s['speedup_min']:.2f}x, max {s['speedup_max']:.2f}x")
        print(f"triangles: cadre {s['both_cadre_triangles']}, OCCT {s['both_occt_triangles']}, "
              f"cadre/OCCT = {s['triangles_cadre_over_occt']:.2f}")
    print(f"cadre failed faces: {s['cadre_failed_faces']}; files with non-manifold edges: "
          f"{s['cadre_nonmanifold_files']}, with misoriented edges: {s['cadre_misoriented_files']}")
    tol = f"{100 * args.tol:g} %"
    labels = {"area": f"area within {tol} (files OCCT reads)",
              "volume": f"volume within {tol} (files with volume > 0)",
              "closed": "0 boundary edges (files with solids)"}
    sides = list(s["quality"])
    print(f"quality vs reference:{'':26}" + "".join(f"{side:>18}" for side in sides))
    for k, label in labels.items():
        cells = []
        for side in sides:
            q = s["quality"][side][k]
            frac = q["passed"] / q["counted"] if q["counted"] else 0.0
            cells.append(f"{q['passed']:4d}/{q['counted']:<4d} {100 * frac:5.1f}%")
        print(f"  {label:45}" + "".join(f"{c:>18}" for c in cells))
        if any(s["quality"][side][k]["counted_read_right"] != s["quality"][side][k]["counted"]
               for side in sides):
            cells = []
            for side in sides:
                q = s["quality"][side][k]
                a, b = q["passed_read_right"], q["counted_read_right"]
                cells.append(f"{a:4d}/{b:<4d} {100 * a / max(b, 1):5.1f}%")
            print(f"  {'  without files OCCT misreads':45}" + "".join(f"{c:>18}" for c in cells))
    # What to look at next: cadre's worst offenders per criterion.
    q = quality(rows, "cadre", args.tol)
    for k, (_, _, failing, _, _) in q.items():
        if not failing:
            continue
        worst = sorted(failing, key=lambda fd: -(float("inf") if fd[1] is None else fd[1]))[:10]
        shown = ", ".join(f"{f} ({'fail' if d is None else (f'{100 * d:.2f}%' if k != 'closed' else d)})"
                          for f, d in worst)
        print(f"  cadre failing {k} ({len(failing)}): {shown}")


def main():
    args = parse_args(sys.argv[1:])
    inputs = args.inputs or [os.path.join(REPO, "..", "shared", "corpus", "step")]
    paths = list_files(inputs)
    if not paths:
        sys.exit(f"no STEP files in {' '.join(inputs)}")
    cadre = args.cadre or os.path.join(os.environ.get("CARGO_TARGET_DIR")
                                       or os.path.join(REPO, "target"), "release", "cadre")
    if not os.path.isfile(cadre):
        sys.exit(f"no cadre binary at {cadre} (cargo build --release -p cadre, or --cadre PATH)")
    ref_path = args.reference
    if ref_path is None:
        first = inputs[0] if os.path.isdir(inputs[0]) else os.path.dirname(inputs[0])
        for cand in (os.path.join(os.path.dirname(os.path.abspath(first)), "reference.jsonl"),
                     os.path.join(REPO, "..", "shared", "corpus", "reference.jsonl")):
            if os.path.isfile(cand):
                ref_path = cand
                break
    reference = {}
    if ref_path:
        for line in open(ref_path):
            if line.startswith("{"):
                r = json.loads(line)
                reference[r["file"]] = r
    else:
        print("warning: no reference.jsonl: quality not scored", file=sys.stderr)
    corr_path = args.corrections or os.path.join(
        REPO, "crates", "cadre-mesh", "tests", "data", "reference_corrections.jsonl")
    if corr_path != "none" and reference:
        for line in open(corr_path):
            if not line.startswith("{"):
                continue
            c = json.loads(line)
            r = reference.get(c["file"])
            if r is None:
                continue
            for k in ("area", "volume", "occt_misreads"):
                if k in c:
                    r[k] = c[k]

    tmp = tempfile.mkdtemp(prefix="compare-mesh-")
    n = len(paths)

    def one(item):
        i, path = item
        name = os.path.basename(path)
        glb = os.path.join(tmp, f"{i}.glb")
        row = {"file": name, "ref": reference.get(name)}
        row["cadre"] = run_cadre(cadre, path, glb, args.deflection_rel, args.angle, args.timeout,
                                 args.time_key)
        if os.path.exists(glb):
            os.remove(glb)
        if not args.only_cadre:
            row["occt"] = occt_mesh.run_one(path, args.deflection_rel, args.angle, True,
                                            args.timeout, True)
        state = row["cadre"].get("error") or f"{row['cadre']['triangles']} triangles"
        print(f"[{i + 1}/{n}] {name}: cadre {state}", file=sys.stderr, flush=True)
        return row

    try:
        with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
            rows = list(pool.map(one, enumerate(paths)))
    finally:
        shutil.rmtree(tmp, ignore_errors=True)

    print_table(rows, args)
    summary = summarize(rows, args)
    print_summary(rows, summary, args)
    if args.json_out:
        settings = {"deflection_rel": args.deflection_rel, "angle": args.angle, "jobs": args.jobs,
                    "tol": args.tol, "cadre": cadre, "cores": os.cpu_count(),
                    "reference": ref_path, "corrections": corr_path,
                    "only_cadre": args.only_cadre,
                    "time_key": args.time_key}
        slim = [{k: v for k, v in r.items() if k != "ref"} for r in rows]
        with open(args.json_out, "w") as f:
            json.dump({"settings": settings, "summary": summary, "files": slim}, f, indent=1)


if __name__ == "__main__":
    main()
