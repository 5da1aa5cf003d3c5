#!/usr/bin/env bash
# Memory of a textured PLY as Agisoft Metashape and MeshLab write it (UVs per face), when its
# charts are small (not run by the tests; figures, not assertions). Generates an N x N height
# grid (2 (N-1)^2 triangles) whose charts are K x K quads (K = 1: every quad its own chart, the
# worst case: four UVs per inner vertex), one 256 x 256 PNG, then builds it under --memory-limit
# and prints the read, split and build stage lines and the summary (each with the peak RSS so far).
#
#   bash scripts/bench-ply-seams.sh            # N=1000 K=1 LIMIT=256M HLOD=build/hlod OUT=out/bench-ply-seams
#   N=1415 K=8 LIMIT=1G bash scripts/bench-ply-seams.sh
#   BUILD_FLAGS="--mode bottom-up --bottom-up-error simplifier" (the default here: the quick build);
#   BUILD_FLAGS= (empty) builds with hlod's defaults
set -euo pipefail
cd "$(dirname "$0")/.."
HLOD=${HLOD:-build/hlod}
OUT=${OUT:-out/bench-ply-seams}
N=${N:-1000} K=${K:-1} LIMIT=${LIMIT:-256M}
BUILD_FLAGS=${BUILD_FLAGS---mode bottom-up --bottom-up-error simplifier}
mkdir -p "$OUT"
python3 - "$N" "$K" "$OUT" <<'EOF'
import array, math, struct, sys, zlib
n, k, out = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]

def chunk(tag, data):
    return struct.pack('>I', len(data)) + tag + data + struct.pack('>I', zlib.crc32(tag + data))

rows = b''.join(b'\0' + bytes(c for x in range(256) for c in ((x * 7 + y * 3) & 255, (x * 5) & 255, (y * 11) & 255))
                for y in range(256))
with open(out + '/tex.png', 'wb') as f:
    f.write(b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', 256, 256, 8, 2, 0, 0, 0)) +
            chunk(b'IDAT', zlib.compress(rows)) + chunk(b'IEND', b''))
quads = n - 1
cell = 1.0 / ((quads + k - 1) // k)
with open(out + '/seams.ply', 'wb') as f:
    f.write(('ply\nformat binary_little_endian 1.0\ncomment TextureFile tex.png\nelement vertex %d\n'
             'property float x\nproperty float y\nproperty float z\nelement face %d\n'
             'property list uchar int vertex_indices\nproperty list uchar float texcoord\nend_header\n'
             % (n * n, 2 * quads * quads)).encode())
    v = array.array('f')
    for j in range(n):
        for i in range(n):
            v.extend((i, j, 5 * math.sin(i * 0.05) * math.cos(j * 0.07)))
    f.write(v.tobytes())
    face = struct.Struct('<B3iB6f')
    for j in range(quads):
        row = bytearray()
        for i in range(quads):
            cu, cv = i // k, j // k  # this quad's chart; its UVs fill 90 % of the chart's cell
            uv = lambda a, b: (cell * (cu + 0.9 * (a - cu * k) / k), cell * (cv + 0.9 * (b - cv * k) / k))
            a, b, c, d = j * n + i, j * n + i + 1, (j + 1) * n + i + 1, (j + 1) * n + i
            row += face.pack(3, a, b, c, 6, *uv(i, j), *uv(i + 1, j), *uv(i + 1, j + 1))
            row += face.pack(3, a, c, d, 6, *uv(i, j), *uv(i + 1, j + 1), *uv(i, j + 1))
        f.write(row)
EOF
# shellcheck disable=SC2086
"$HLOD" build "$OUT/seams.ply" -o "$OUT/seams.hlod" --memory-limit "$LIMIT" $BUILD_FLAGS > "$OUT/build.log" 2>&1 ||
    { tail -3 "$OUT/build.log" >&2; exit 1; }
grep -E '^(read|split|build) +[0-9.]+ s|^summary' "$OUT/build.log"
