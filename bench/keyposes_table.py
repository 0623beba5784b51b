#!/usr/bin/env python3
"""The key poses' table (docs/keyposes.md): for every .bvh clip under ../shared/data, mapped on its
own, the RMS joint-angle error of the clip rebuilt from its N key poses (`motionmap keyposes`,
slerp per joint between them) beside the error of N evenly spaced frames.

usage: keyposes_table.py MOTIONMAP_BINARY SHARED_DATA_DIR [N] [--method M]
"""
import json
import os
import subprocess
import sys


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    binary, data = sys.argv[1], sys.argv[2]
    rest = sys.argv[3:]
    count = rest.pop(0) if rest and not rest[0].startswith("-") else "8"
    clips = sorted(os.path.join(root, f) for root, _, files in os.walk(data) for f in files
                   if f.endswith(".bvh"))
    print(f"| clip | frames | {count} key poses | {count} evenly spaced | key poses lower |")
    print("|---|---:|---:|---:|:---:|")
    lower = 0
    for path in clips:
        p = subprocess.run([binary, "keyposes", path, "-n", count, "--json", "-q", *rest],
                           capture_output=True, text=True)
        if p.returncode != 0:
            print(f"| {os.path.relpath(path, data)} | | failed: {p.stderr.strip()[:80]} | | |")
            continue
        c = json.loads(p.stdout)["clips"][0]
        ours, even = c["rms_degrees"], c["uniform_rms_degrees"]
        exact = ours == 0 and even == 0
        lower += ours < even
        verdict = "(both exact)" if exact else "yes" if ours < even else "**no**"
        print(f"| {os.path.relpath(path, data)} | {c['last'] - c['first'] + 1} | {ours:.2f}° | "
              f"{even:.2f}° | {verdict} |")
    print(f"\nlower on {lower} of {len(clips)} clips")


if __name__ == "__main__":
    main()
