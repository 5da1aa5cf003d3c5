#!/usr/bin/env python3
"""Extract the leaf tiles of the shared Mars tileset (B1) as GLB files, for `hlod build DIR`.

Usage: scripts/mars_leaf_glbs.py [--obj] [TILESET_DIR] OUT_DIR
Each leaf b3dm (a tile with content and no children) holds one GLB after its 28-byte header and
its feature and batch tables (3D Tiles 1.0, Batched 3D Model); the GLB is written as is, named
NNN_TILE.glb in tileset order sorted by path. A root transform other than the identity is
refused; the other tiles' transforms are ignored (the textures, which pipeline/TEXTURE_SIZE.md
measures, do not depend on them). With --obj the leaves become
one mesh instead, OUT_DIR/mars.obj (y up, as glTF: build it with --up y) with mars.mtl and one
JPEG per leaf: the terrain as one scan, its ragged outline partly on its bounding box (B1's tiles share one
frame: an identity root transform, none below it, no RTC_CENTER; a file that has one is refused).
Exit 2 on bad arguments or a missing or malformed tileset.
"""
import json
import os
import struct
import sys


def glb_mesh(glb, path):
    """POSITION, TEXCOORD_0 and triangle indices of a leaf GLB's one primitive, and its JPEG."""
    json_length = struct.unpack('<I', glb[12:16])[0]
    doc = json.loads(glb[20:20 + json_length])
    binary = glb[20 + json_length + 8:]
    if any('matrix' in n or 'translation' in n or 'rotation' in n or 'scale' in n for n in doc.get('nodes', [])):
        raise ValueError(path + ': a node transform (not merged)')
    if len(doc['meshes']) != 1 or len(doc['meshes'][0]['primitives']) != 1 or len(doc['images']) != 1:
        raise ValueError(path + ': not one mesh of one primitive and one image (not merged)')
    primitive = doc['meshes'][0]['primitives'][0]

    def accessor(index, width):
        a = doc['accessors'][index]
        view = doc['bufferViews'][a['bufferView']]
        start = view.get('byteOffset', 0) + a.get('byteOffset', 0)
        code = {5126: 'f', 5125: 'I', 5123: 'H', 5121: 'B'}[a['componentType']]
        if (width > 1 and code != 'f') or a.get('normalized') or a.get('sparse') or \
                view.get('byteStride', width * struct.calcsize(code)) != width * struct.calcsize(code):
            raise ValueError(path + ': an interleaved, quantized or sparse accessor (not merged)')
        values = struct.unpack_from('<%d%s' % (a['count'] * width, code), binary, start)
        return [values[k:k + width] for k in range(0, len(values), width)]

    image = doc['bufferViews'][doc['images'][0]['bufferView']]
    jpeg = binary[image.get('byteOffset', 0):image.get('byteOffset', 0) + image['byteLength']]
    indices = [i[0] for i in accessor(primitive['indices'], 1)]
    return accessor(primitive['attributes']['POSITION'], 3), accessor(primitive['attributes']['TEXCOORD_0'], 2), indices, jpeg


def write_obj(glbs, out):
    with open(os.path.join(out, 'mars.obj'), 'w') as obj, open(os.path.join(out, 'mars.mtl'), 'w') as mtl:
        obj.write('mtllib mars.mtl\n')
        base = 1
        for i, (name, glb) in enumerate(glbs):
            positions, uvs, indices, jpeg = glb_mesh(glb, name)
            with open(os.path.join(out, 'leaf_%03d.jpg' % i), 'wb') as image:
                image.write(jpeg)
            mtl.write('newmtl leaf_%03d\nKd 1 1 1\nmap_Kd leaf_%03d.jpg\n' % (i, i))
            obj.writelines('v %.9g %.9g %.9g\n' % p for p in positions)
            obj.writelines('vt %.9g %.9g\n' % (u, 1 - v) for u, v in uvs)  # OBJ's v runs up
            obj.write('usemtl leaf_%03d\n' % i)
            for t in range(0, len(indices) - 2, 3):
                a, b, c = (base + k for k in indices[t:t + 3])
                obj.write('f %d/%d %d/%d %d/%d\n' % (a, a, b, b, c, c))
            base += len(positions)


def main(argv):
    as_obj = '--obj' in argv[1:]
    argv = [a for a in argv if a != '--obj']
    if len(argv) not in (2, 3):
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    root = argv[1] if len(argv) == 3 else os.path.join(os.path.dirname(__file__), '..', '..', 'shared', 'datasets',
                                                       'B1_jpl_mars_landform_3dtiles', 'tileset')
    out = argv[-1]
    try:
        tileset = json.load(open(os.path.join(root, 'tileset.json')))
        if tileset['root'].get('transform', [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]) != [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]:
            raise ValueError('the root tile has a transform (not merged)')
        leaves = []
        stack = [tileset['root']]
        while stack:
            tile = stack.pop()
            content = tile.get('content', {})
            uri = content.get('uri') or content.get('url')
            if not tile.get('children') and uri:
                leaves.append(os.path.join(root, uri))
            if tile is not tileset['root'] and 'transform' in tile and as_obj:
                raise ValueError('a tile below the root has a transform (not merged)')
            stack.extend(tile.get('children', []))
        os.makedirs(out, exist_ok=True)
        glbs = []
        for i, path in enumerate(sorted(leaves)):
            data = open(path, 'rb').read()
            magic, _, length, ftj, ftb, btj, btb = struct.unpack('<4sIIIIII', data[:28])
            if magic != b'b3dm' or length > len(data):
                raise ValueError(path + ': not a b3dm tile')
            if as_obj and 'RTC_CENTER' in json.loads(data[28:28 + ftj] or b'{}'):
                raise ValueError(path + ': RTC_CENTER (not merged)')
            name = '%03d_%s.glb' % (i, os.path.splitext(os.path.basename(path))[0])
            glbs.append((path, data[28 + ftj + ftb + btj + btb:length]))
            if not as_obj:
                open(os.path.join(out, name), 'wb').write(glbs[-1][1])
        if as_obj:
            write_obj(glbs, out)
    except (OSError, ValueError, KeyError, IndexError, struct.error) as e:
        print('mars_leaf_glbs: %s' % e, file=sys.stderr)
        return 2
    print('mars_leaf_glbs: %d leaf tiles written to %s%s' % (len(leaves), out, ' as mars.obj' if as_obj else ''))
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
