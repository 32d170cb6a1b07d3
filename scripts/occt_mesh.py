#!/usr/bin/env python3
"""Times Open CASCADE's STEP read + transfer and BRepMesh tessellation per file, and measures the
mesh it makes: one JSON line per file, the OCCT side of `scripts/compare_mesh.py`.

Usage: python3 scripts/occt_mesh.py FOLDER_OR_FILES... [--deflection-rel 0.001] [--angle 0.5]
           [--parallel] [--jobs N] [--timeout 300] [--no-edges] [--out FILE.jsonl]
Needs: pip install cadquery-ocp-novtk

Per file, as ../shared/tools/occt_reference.py does for `occt_mesh`: read + transfer with
STEPControl_Reader (read_s), bounding box diagonal (BRepBndLib), then
BRepMesh_IncrementalMesh(shape, rel x diagonal, False, angle, parallel) (mesh_s). Triangles are
counted over every face occurrence the explorer visits (a part instanced three times counts three
times), so single-threaded figures match reference.jsonl's `occt_mesh.triangles`.

Output keys: file, read_s, mesh_s, triangles, mesh_area (sum of triangle areas in world
coordinates), faces (face occurrences), failed_faces (occurrences without a triangulation),
solids, mesh_volume (volume enclosed by the triangles of each solid, absolute value per solid,
summed), and, unless --no-edges, edge counts after welding nodes by position (1e-9 x diagonal),
like `cadre mesh --json`: each shell of a solid and each closed shell outside solids is welded on
its own and gives boundary_edges (used by one triangle: 0 when watertight), nonmanifold_edges
(more than two) and misoriented_edges (twice in the same direction); open shells and loose faces
give open_boundary_edges (their natural border). A file with no geometry gets 0 triangles; a file
OCCT fails on gets "error" (exception, crash or timeout).

Each file runs in its own subprocess (with --timeout) so that a crash or a hang in OCCT costs one
file, not the run; --jobs runs that many files at once (keep 1 for timings).
"""
import argparse
import concurrent.futures
import glob
import json
import os
import subprocess
import sys
import time

HERE = os.path.abspath(__file__)


def parse_args(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("inputs", nargs="+", help="STEP files or folders of STEP files")
    p.add_argument("--deflection-rel", type=float, default=0.001,
                   help="linear deflection as a fraction of the bounding box diagonal")
    p.add_argument("--angle", type=float, default=0.5, help="angular deflection (radians)")
    p.add_argument("--parallel", action="store_true", help="BRepMesh in parallel mode")
    p.add_argument("--jobs", type=int, default=1, help="files processed at once")
    p.add_argument("--timeout", type=float, default=300.0, help="seconds per file")
    p.add_argument("--no-edges", action="store_true",
                   help="skip the boundary / non-manifold edge count")
    p.add_argument("--out", help="write the JSON lines here (default: standard output)")
    p.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    return p.parse_args(argv)


def list_files(inputs):
    paths = []
    for item in inputs:
        if os.path.isdir(item):
            paths += sorted(f for f in glob.glob(os.path.join(item, "*")) if os.path.isfile(f))
        else:
            paths.append(item)
    return paths


# ----------------------------------------------------------------------------- worker side


def edge_census(tris):
    """(boundary, non-manifold, misoriented) edge counts of one welded group of triangles given
    as triples of node keys: edges used once, more than twice, twice in the same direction."""
    uses = {}
    for a, b, c in tris:
        if a == b or b == c or c == a:
            continue  # collapsed by the weld (pole of a sphere, degenerate edge)
        for u, v in ((a, b), (b, c), (c, a)):
            k, d = ((u, v), 1) if u < v else ((v, u), -1)
            n, s = uses.get(k, (0, 0))
            uses[k] = (n + 1, s + d)
    boundary = nonmanifold = misoriented = 0
    for n, s in uses.values():
        if n == 1:
            boundary += 1
        elif n > 2:
            nonmanifold += 1
        elif s != 0:
            misoriented += 1
    return boundary, nonmanifold, misoriented


def measure(path, rel, angle, parallel, edges):
    """Reads, meshes and measures one file in this process; returns the record."""
    from OCP.BRep import BRep_Tool
    from OCP.BRepBndLib import BRepBndLib
    from OCP.BRepMesh import BRepMesh_IncrementalMesh
    from OCP.Bnd import Bnd_Box
    from OCP.IFSelect import IFSelect_RetDone
    from OCP.STEPControl import STEPControl_Reader
    from OCP.TopAbs import TopAbs_FACE, TopAbs_REVERSED, TopAbs_SHELL, TopAbs_SOLID
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopLoc import TopLoc_Location
    from OCP.TopoDS import TopoDS

    rec = {"file": os.path.basename(path)}
    t0 = time.perf_counter()
    reader = STEPControl_Reader()
    if reader.ReadFile(path) != IFSelect_RetDone:
        raise RuntimeError("read failed")
    reader.TransferRoots()
    shape = reader.OneShape()
    rec["read_s"] = round(time.perf_counter() - t0, 4)

    box = Bnd_Box()
    BRepBndLib.Add_s(shape, box, False)
    if box.IsVoid():  # no geometry at all: nothing to mesh, as the reference records it
        diag = 0.0
        rec["deflection"] = 0.0
        rec["mesh_s"] = 0.0
    else:
        a, b = box.CornerMin(), box.CornerMax()
        diag = a.Distance(b)
        rec["deflection"] = diag * rel
        t1 = time.perf_counter()
        BRepMesh_IncrementalMesh(shape, diag * rel, False, angle, parallel)
        rec["mesh_s"] = round(time.perf_counter() - t1, 4)

    quantum = max(diag, 1e-300) * 1e-9
    stats = {"triangles": 0, "area": 0.0, "faces": 0, "failed": 0}

    def face_triangles(face, want_keys, want_volume):
        """Triangles of one face occurrence: adds count and area; returns (welded key triples,
        signed volume contribution)."""
        stats["faces"] += 1
        loc = TopLoc_Location()
        tri = BRep_Tool.Triangulation_s(face, loc)
        if tri is None or tri.NbTriangles() == 0:
            stats["failed"] += 1
            return [], 0.0
        trsf = loc.Transformation()
        m = [[trsf.Value(r, c) for c in (1, 2, 3, 4)] for r in (1, 2, 3)]
        pts = [None]
        for i in range(1, tri.NbNodes() + 1):
            p = tri.Node(i)
            x, y, z = p.X(), p.Y(), p.Z()
            pts.append((m[0][0] * x + m[0][1] * y + m[0][2] * z + m[0][3],
                        m[1][0] * x + m[1][1] * y + m[1][2] * z + m[1][3],
                        m[2][0] * x + m[2][1] * y + m[2][2] * z + m[2][3]))
        flip = (face.Orientation() == TopAbs_REVERSED) != trsf.IsNegative()
        keys = [None] + [(round(p[0] / quantum), round(p[1] / quantum), round(p[2] / quantum))
                         for p in pts[1:]] if want_keys else None
        n = tri.NbTriangles()
        area = vol = 0.0
        out = []
        for i in range(1, n + 1):
            i1, i2, i3 = tri.Triangle(i).Get()
            if flip:
                i2, i3 = i3, i2
            p1, p2, p3 = pts[i1], pts[i2], pts[i3]
            ux, uy, uz = p2[0] - p1[0], p2[1] - p1[1], p2[2] - p1[2]
            vx, vy, vz = p3[0] - p1[0], p3[1] - p1[1], p3[2] - p1[2]
            cx, cy, cz = uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx
            area += (cx * cx + cy * cy + cz * cz) ** 0.5
            if want_volume:
                # (p1 . (p2 x p3)) = p1 . ((p2 - p1) x (p3 - p1))
                vol += p1[0] * cx + p1[1] * cy + p1[2] * cz
            if want_keys:
                out.append((keys[i1], keys[i2], keys[i3]))
        stats["triangles"] += n
        stats["area"] += 0.5 * area
        return out, vol / 6.0

    closed = [0, 0, 0]  # boundary, non-manifold, misoriented edges of solids and closed shells
    open_boundary = 0  # natural border of open shells and loose faces
    volume = 0.0
    nsolids = 0

    def faces_of(shape_, want_volume):
        group, vol = [], 0.0
        fx = TopExp_Explorer(shape_, TopAbs_FACE)
        while fx.More():
            t, v = face_triangles(TopoDS.Face(fx.Current()), edges, want_volume)
            group += t
            vol += v
            fx.Next()
        return group, vol

    def add_closed(group):
        if edges:
            for i, n in enumerate(edge_census(group)):
                closed[i] += n

    ex = TopExp_Explorer(shape, TopAbs_SOLID)
    while ex.More():  # solids: each shell welded on its own
        nsolids += 1
        solid_volume = 0.0
        sx = TopExp_Explorer(ex.Current(), TopAbs_SHELL)
        while sx.More():
            group, v = faces_of(sx.Current(), True)
            solid_volume += v
            add_closed(group)
            sx.Next()
        volume += abs(solid_volume)
        ex.Next()
    sx = TopExp_Explorer(shape, TopAbs_SHELL, TopAbs_SOLID)
    while sx.More():  # shells outside solids: closed ones count as solids' do
        group, _ = faces_of(sx.Current(), False)
        if BRep_Tool.IsClosed_s(sx.Current()):
            add_closed(group)
        elif edges:
            open_boundary += edge_census(group)[0]
        sx.Next()
    fx = TopExp_Explorer(shape, TopAbs_FACE, TopAbs_SHELL)
    while fx.More():  # loose faces, each on its own
        group, _ = face_triangles(TopoDS.Face(fx.Current()), edges, False)
        if edges:
            open_boundary += edge_census(group)[0]
        fx.Next()

    rec["triangles"] = stats["triangles"]
    rec["mesh_area"] = stats["area"]
    rec["faces"] = stats["faces"]
    rec["failed_faces"] = stats["failed"]
    rec["solids"] = nsolids
    rec["mesh_volume"] = volume
    if edges:
        rec["boundary_edges"], rec["nonmanifold_edges"], rec["misoriented_edges"] = closed
        rec["open_boundary_edges"] = open_boundary
    return rec


def warm_up(parallel):
    """Pays OCCT's one-time costs (STEP protocol set-up, BRepMesh thread pool) outside the timed
    region: an application pays them once, not per file."""
    from OCP.BRepMesh import BRepMesh_IncrementalMesh
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeSphere
    from OCP.STEPControl import STEPControl_Reader

    STEPControl_Reader()
    BRepMesh_IncrementalMesh(BRepPrimAPI_MakeSphere(1.0).Shape(), 0.01, False, 0.5, parallel)


def worker(args):
    path = args.inputs[0]
    try:
        warm_up(args.parallel)
        rec = measure(path, args.deflection_rel, args.angle, args.parallel, not args.no_edges)
    except Exception as ex:  # OCCT raises Standard_Failure subclasses as Python exceptions
        rec = {"file": os.path.basename(path), "error": repr(ex)[:200]}
    # OCCT writes its own messages to standard output, maybe without a final newline.
    sys.stdout.write("\n" + json.dumps(rec) + "\n")
    sys.stdout.flush()


# ----------------------------------------------------------------------------- driver side


def run_one(path, rel=0.001, angle=0.5, parallel=False, timeout=300.0, edges=True):
    """Measures one file in a fresh Python process; always returns a record (with "error" when
    OCCT failed, crashed or timed out)."""
    cmd = [sys.executable, HERE, "--worker", path, "--deflection-rel", repr(rel),
           "--angle", repr(angle), "--timeout", repr(timeout)]
    if parallel:
        cmd.append("--parallel")
    if not edges:
        cmd.append("--no-edges")
    name = os.path.basename(path)
    t0 = time.perf_counter()
    try:
        proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                              timeout=timeout, text=True, errors="replace")
    except subprocess.TimeoutExpired:
        return {"file": name, "error": f"timeout after {timeout:g} s"}
    wall = time.perf_counter() - t0
    rec = None
    for line in proc.stdout.splitlines():
        if line.startswith("{"):
            try:
                rec = json.loads(line)
            except ValueError:
                pass
    if rec is None:
        why = (f"crashed (signal {-proc.returncode})" if proc.returncode < 0
               else f"exited {proc.returncode} without a result")
        tail = proc.stderr.strip().splitlines()[-1:] if proc.stderr.strip() else []
        return {"file": name, "error": (why + (": " + tail[0] if tail else ""))[:200]}
    rec["wall_s"] = round(wall, 4)
    return rec


def main():
    args = parse_args(sys.argv[1:])
    if args.worker:
        worker(args)
        return
    paths = list_files(args.inputs)
    out = open(args.out, "w") if args.out else sys.stdout

    def one(path):
        return run_one(path, args.deflection_rel, args.angle, args.parallel, args.timeout,
                       not args.no_edges)

    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        for rec in pool.map(one, paths):  # in file order
            out.write(json.dumps(rec) + "\n")
            out.flush()
            if args.out:
                state = rec.get("error") or f"{rec['triangles']} triangles"
                print(f"{rec['file']}: {state}", file=sys.stderr, flush=True)
    if args.out:
        out.close()


if __name__ == "__main__":
    main()
