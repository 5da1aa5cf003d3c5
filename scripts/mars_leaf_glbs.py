#!/usr/bin/env python3
"""Extract the leaf tiles of the shared Mars tileset (B1) as GLB files, for `hlod build DIR`.

Usage: scripts/mars_leaf_glbs.py [TILESET_DIR] OUT_DIR
Each leaf b3dm (a tile with content and no children) holds one GLB after its 28-byte header and
its feature and batch tables (3D Tiles 1.0, Batched 3D Model); the GLB is written as is, named
NNN_TILE.glb in tileset order sorted by path. The tiles' transforms are ignored (the textures,
which pipeline/TEXTURE_SIZE.md measures, do not depend on them). Exit 2 on bad arguments or a
missing or malformed tileset.
"""
import json
import os
import struct
import sys


def main(argv):
    if len(argv) not in (2, 3):
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    root = argv[1] if len(argv) == 3 else os.path.join(os.path.dirname(__file__), '..', '..', 'shared', 'datasets',
                                                       'B1_jpl_mars_landform_3dtiles', 'tileset')
    out = argv[-1]
    try:
        tileset = json.load(open(os.path.join(root, 'tileset.json')))
        leaves = []
        stack = [tileset['root']]
        while stack:
            tile = stack.pop()
            content = tile.get('content', {})
            uri = content.get('uri') or content.get('url')
            if not tile.get('children') and uri:
                leaves.append(os.path.join(root, uri))
            stack.extend(tile.get('children', []))
        os.makedirs(out, exist_ok=True)
        for i, path in enumerate(sorted(leaves)):
            data = open(path, 'rb').read()
            magic, _, length, ftj, ftb, btj, btb = struct.unpack('<4sIIIIII', data[:28])
            if magic != b'b3dm' or length > len(data):
                raise ValueError(path + ': not a b3dm tile')
            name = '%03d_%s.glb' % (i, os.path.splitext(os.path.basename(path))[0])
            open(os.path.join(out, name), 'wb').write(data[28 + ftj + ftb + btj + btb:length])
    except (OSError, ValueError, KeyError, struct.error) as e:
        print('mars_leaf_glbs: %s' % e, file=sys.stderr)
        return 2
    print('mars_leaf_glbs: %d leaf tiles written to %s' % (len(leaves), out))
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
