#!/usr/bin/env python3
# Per level, the geometric errors of two builds of the same tree compared node by node (the
# build reports' per-node `error_max`, `hlod build` writes DB.hlod.build.json): pipeline/BUILD_SPEED.md's
# tables of the bottom-up bound and of the simplifier's estimate against the exact measure.
#   usage: scripts/compare_errors.py EXACT.hlod.build.json BOUND.hlod.build.json
# Prints a Markdown table: per level the measured (non-leaf) nodes, the max and the mean of nodes
# of each build, the mean, smallest and largest ratio B / A, and the nodes where B < A (with the largest
# shortfall). Exit status: 0 printed, 2 bad usage, unreadable reports or different trees.
import json
import sys


def main():
    if len(sys.argv) != 3:
        print("usage: compare_errors.py A.build.json B.build.json", file=sys.stderr)
        sys.exit(2)
    try:
        a, b = (json.load(open(path))["nodes"] for path in sys.argv[1:])
    except (OSError, ValueError, KeyError) as e:
        print(f"compare_errors: {e}", file=sys.stderr)
        sys.exit(2)
    if len(a) != len(b):
        print(f"compare_errors: {len(a)} against {len(b)} nodes: not the same tree", file=sys.stderr)
        sys.exit(2)
    levels = {}
    try:
        for x, y in zip(a, b):
            if x["level"] != y["level"] or x["triangles"] != y["triangles"]:
                print(f"compare_errors: node {x['node']} of block {x['block']} differs: not the same tree", file=sys.stderr)
                sys.exit(2)
            if x["error_max"] > 0:
                levels.setdefault(x["level"], []).append((float(x["error_max"]), float(y["error_max"])))
    except (KeyError, TypeError, ValueError) as e:
        print(f"compare_errors: a node without a usable level, triangles or error_max ({e!r})", file=sys.stderr)
        sys.exit(2)
    print("| level | nodes | A max | B max | A mean of nodes | B mean of nodes | B / A: mean | smallest | largest | nodes where B < A (largest shortfall) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for level in sorted(levels):
        pairs = levels[level]
        ratios = [y / x for x, y in pairs]
        short = [(x - y, (x - y) / x) for x, y in pairs if y < x]
        shortfall = f"{len(short)} ({max(s[0] for s in short):.4g}, {100 * max(s[1] for s in short):.2g} %)" if short else "0"
        print(f"| {level} | {len(pairs)} | {max(x for x, _ in pairs):.4g} | {max(y for _, y in pairs):.4g} | "
              f"{sum(x for x, _ in pairs) / len(pairs):.4g} | {sum(y for _, y in pairs) / len(pairs):.4g} | "
              f"{sum(ratios) / len(ratios):.3g} | {min(ratios):.3g} | {max(ratios):.3g} | {shortfall} |")


main()
