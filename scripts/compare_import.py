#!/usr/bin/env python3
"""Compares two JSON-lines timing files (cadre, OCCT) file by file and in total.

Usage: python3 scripts/compare_import.py cadre.jsonl occt.jsonl
"""
import json
import statistics
import sys


def load(path):
    # OCCT writes its own messages to standard output: keep the JSON lines only.
    rows = (json.loads(line) for line in open(path) if line.startswith("{"))
    return {r["file"]: r for r in rows if r.get("file")}


def main():
    cadre, occt = load(sys.argv[1]), load(sys.argv[2])
    both = sorted(f for f in cadre if "seconds" in cadre[f] and "seconds" in occt.get(f, {}))
    ratios = []
    tc = to = nbytes = 0.0
    for f in both:
        c, o = cadre[f]["seconds"], occt[f]["seconds"]
        tc, to, nbytes = tc + c, to + o, nbytes + cadre[f]["bytes"]
        ratios.append(o / max(c, 1e-9))
    print(f"files timed by both: {len(both)}")
    print(f"total: cadre {tc:.3f} s, OCCT {to:.3f} s, OCCT/cadre = {to / max(tc, 1e-9):.1f}x")
    print(f"throughput: cadre {nbytes / 1e6 / max(tc, 1e-9):.1f} MB/s, OCCT {nbytes / 1e6 / max(to, 1e-9):.1f} MB/s")
    if ratios:
        print(f"per-file speed-up: median {statistics.median(ratios):.1f}x, "
              f"min {min(ratios):.1f}x, max {max(ratios):.1f}x")
    slow = sorted(both, key=lambda f: occt[f]["seconds"] / max(cadre[f]["seconds"], 1e-9))[:5]
    for f in slow:
        print(f"  slowest ratio: {f}: cadre {cadre[f]['seconds']*1e3:.2f} ms, "
              f"OCCT {occt[f]['seconds']*1e3:.2f} ms")
    for f in sorted(cadre):
        if "error" in cadre[f]:
            print(f"  cadre error: {f}: {cadre[f]['error']}")


if __name__ == "__main__":
    main()
