#!/usr/bin/env bash
# The two-sided error on thin triangles (not run by the tests; figures, not assertions): builds a
# flat fan and a cone fan of N triangles around one vertex (radius 100; the cone's apex 30 above
# its rim), as a filled hole is triangulated, and a capped cylinder of CYL triangles (CYL/4
# segments, 300 long, radius 50: long thin sides, fanned caps), each with `-j 1`, and prints the
# user CPU-s and peak RSS of each (pipeline/CLOSEST_POINT.md "Thin triangles and coinciding
# surfaces" has the figures of stop 51 and 52).
#
#   bash scripts/bench-fans.sh                  # N="5000 10000 50000" CYL="20000 88000" HLOD=build/hlod OUT=out/bench-fans
set -euo pipefail
cd "$(dirname "$0")/.."
HLOD=${HLOD:-build/hlod}
OUT=${OUT:-out/bench-fans}
N=${N:-5000 10000 50000} CYL=${CYL:-20000 88000}
mkdir -p "$OUT"
generate() {  # KIND COUNT FILE
    python3 - "$@" <<'PY'
import math, struct, sys
kind, n, path = sys.argv[1], int(sys.argv[2]), sys.argv[3]
V, F = [], []
if kind in ('disc', 'cone'):
    V.append((0, 0, 0 if kind == 'disc' else 30))
    V += [(100 * math.cos(2 * math.pi * i / n), 100 * math.sin(2 * math.pi * i / n), 0) for i in range(n)]
    F = [(0, 1 + i, 1 + (i + 1) % n) for i in range(n)]
else:  # a cylinder of n / 4 segments: two side triangles and two cap triangles each
    s = n // 4
    V = [(50 * math.cos(2 * math.pi * i / s), 50 * math.sin(2 * math.pi * i / s), z) for z in (0, 300) for i in range(s)]
    V += [(0, 0, 0), (0, 0, 300)]
    for i in range(s):
        j = (i + 1) % s
        F += [(i, j, s + j), (i, s + j, s + i), (2 * s, j, i), (2 * s + 1, s + i, s + j)]
with open(path, 'wb') as f:
    f.write(f"ply\nformat binary_little_endian 1.0\nelement vertex {len(V)}\nproperty float x\nproperty float y\n"
            f"property float z\nelement face {len(F)}\nproperty list uchar int vertex_indices\nend_header\n".encode())
    for v in V: f.write(struct.pack('<3f', *v))
    for t in F: f.write(struct.pack('<B3i', 3, *t))
PY
}
run() {  # NAME PLY
    /usr/bin/time -f "$1: %U user CPU-s, %M KiB peak" "$HLOD" build "$2" -o "$OUT/$1.hlod" -j 1 > /dev/null 2> "$OUT/$1.log" ||
        { echo "$1: build failed, see $OUT/$1.log"; return 1; }
    tail -n 1 "$OUT/$1.log"
}
for n in $N; do
    for kind in disc cone; do generate "$kind" "$n" "$OUT/$kind$n.ply" && run "$kind$n" "$OUT/$kind$n.ply"; done
done
for n in $CYL; do generate cylinder "$n" "$OUT/cylinder$n.ply" && run "cylinder$n" "$OUT/cylinder$n.ply"; done
