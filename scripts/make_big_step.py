#!/usr/bin/env python3
"""Writes a large STEP file made of N copies of a real one (instance ids renumbered per copy),
for memory and speed measurements on files of hundreds of MB.

Usage: python3 scripts/make_big_step.py SOURCE.stp COPIES OUT.stp
"""
import re
import sys


def main():
    src, copies, out = sys.argv[1], int(sys.argv[2]), sys.argv[3]
    text = open(src, encoding="latin-1").read()
    head, rest = text.split("DATA;", 1)
    data = rest.rsplit("ENDSEC;", 1)[0]
    ids = [int(m) for m in re.findall(r"#(\d+)", data)]
    stride = max(ids) + 1
    ref = re.compile(r"#(\d+)")
    with open(out, "w", encoding="latin-1") as f:
        f.write(head + "DATA;\n")
        for k in range(copies):
            off = k * stride
            f.write(ref.sub(lambda m: "#" + str(int(m.group(1)) + off), data))
        f.write("ENDSEC;\nEND-ISO-10303-21;\n")


if __name__ == "__main__":
    main()
