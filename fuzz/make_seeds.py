#!/usr/bin/env python3
"""Writes the hand-made seeds of fuzz/corpus (small valid and near-valid files of each format,
with the harness's selector byte in front where it takes one). The other seeds are copies of
small test files and programs; see docs/fuzzing.md. Run from the repository root."""
import io
import struct
import zipfile
from pathlib import Path

CORPUS = Path("fuzz/corpus")
TETRA_V = [(0, 0, 0), (10, 0, 0), (0, 10, 0), (0, 0, 10)]
TETRA_F = [(0, 2, 1), (0, 1, 3), (1, 2, 3), (0, 3, 2)]


def put(harness, name, data, prefix=None):
    d = CORPUS / harness
    d.mkdir(parents=True, exist_ok=True)
    if isinstance(data, str):
        data = data.encode()
    if prefix is not None:
        data = bytes([prefix]) + data
    (d / name).write_bytes(data)


def stl_binary(v, f):
    out = bytearray(b"seed".ljust(80, b" ")) + struct.pack("<I", len(f))
    for t in f:
        out += struct.pack("<3f", 0, 0, 0)
        for i in t:
            out += struct.pack("<3f", *v[i])
        out += b"\0\0"
    return bytes(out)


def stl_ascii(v, f):
    s = "solid seed\n"
    for t in f:
        s += " facet normal 0 0 0\n  outer loop\n"
        for i in t:
            s += "   vertex %g %g %g\n" % v[i]
        s += "  endloop\n endfacet\n"
    return s + "endsolid seed\n"


def ply_ascii(v, f):
    s = ("ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\n"
         "property float z\nelement face %d\nproperty list uchar int vertex_indices\n"
         "end_header\n" % (len(v), len(f)))
    s += "".join("%g %g %g\n" % p for p in v)
    return s + "".join("3 %d %d %d\n" % t for t in f)


def ply_binary(v, f, endian):
    e = "<" if endian == "little" else ">"
    s = ("ply\nformat binary_%s_endian 1.0\nelement vertex %d\nproperty double x\n"
         "property double y\nproperty double z\nelement face %d\n"
         "property list uchar uint vertex_indices\nend_header\n" % (endian, len(v), len(f)))
    out = bytearray(s.encode())
    for p in v:
        out += struct.pack(e + "3d", *p)
    for t in f:
        out += struct.pack(e + "B3I", 3, *t)
    return bytes(out)


def off(v, f):
    return ("OFF\n%d %d 0\n" % (len(v), len(f)) + "".join("%g %g %g\n" % p for p in v) +
            "".join("3 %d %d %d\n" % t for t in f))


def obj(v, f):
    return "".join("v %g %g %g\n" % p for p in v) + "".join(
        "f %d %d %d\n" % tuple(i + 1 for i in t) for t in f)


def model_xml(resources, build, unit="millimeter"):
    return ('<?xml version="1.0" encoding="UTF-8"?>\n<model unit="%s" xml:lang="en-US" '
            'xmlns="http://schemas.microsoft.com/3dmanufacturing/core/2015/02">\n'
            '<resources>%s</resources>\n<build>%s</build>\n</model>\n' % (unit, resources, build))


def model_3mf(resources, build, unit="millimeter"):
    xml = model_xml(resources, build, unit)
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("[Content_Types].xml",
                   '<?xml version="1.0" encoding="UTF-8"?>\n<Types xmlns="http://schemas.openxml'
                   'formats.org/package/2006/content-types"><Default Extension="rels" '
                   'ContentType="application/vnd.openxmlformats-package.relationships+xml"/>'
                   '<Default Extension="model" ContentType="application/vnd.ms-package.'
                   '3dmanufacturing-3dmodel+xml"/></Types>')
        z.writestr("_rels/.rels",
                   '<?xml version="1.0" encoding="UTF-8"?>\n<Relationships xmlns="http://schemas.'
                   'openxmlformats.org/package/2006/relationships"><Relationship Target="/3D/'
                   '3dmodel.model" Id="rel0" Type="http://schemas.microsoft.com/3dmanufacturing/'
                   '2013/01/3dmodel"/></Relationships>')
        z.writestr("3D/3dmodel.model", xml)
    return buf.getvalue()


def mesh_object(oid, v, f):
    return ('<object id="%d" type="model"><mesh><vertices>%s</vertices><triangles>%s'
            '</triangles></mesh></object>' % (
                oid, "".join('<vertex x="%g" y="%g" z="%g"/>' % p for p in v),
                "".join('<triangle v1="%d" v2="%d" v3="%d"/>' % t for t in f)))


def main():
    cube_v = [(x, y, z) for z in (0, 5) for y in (0, 5) for x in (0, 5)]
    cube_f = [(0, 2, 1), (1, 2, 3), (4, 5, 6), (5, 7, 6), (0, 1, 4), (1, 5, 4), (2, 6, 3),
              (3, 6, 7), (0, 4, 2), (2, 4, 6), (1, 3, 5), (3, 7, 5)]
    put("fuzz_stl", "seed-tetra.bin.stl", stl_binary(TETRA_V, TETRA_F))
    put("fuzz_stl", "seed-cube.bin.stl", stl_binary(cube_v, cube_f))
    put("fuzz_stl", "seed-tetra.ascii.stl", stl_ascii(TETRA_V, TETRA_F))
    put("fuzz_obj", "seed-tetra.obj", obj(TETRA_V, TETRA_F))
    put("fuzz_obj", "seed-quads.obj",
        obj(cube_v, []) + "vn 0 0 1\nvt 0 0\ng box\nusemtl a\nf 1 2 4 3\nf 5/1 6/1 8/1 7/1\n"
        "f 1//1 2//1 6//1 5//1\nf -1 -2 -3\nl 1 2\np 3\n")
    put("fuzz_ply_off", "seed-tetra.ascii.ply", ply_ascii(TETRA_V, TETRA_F), prefix=0)
    put("fuzz_ply_off", "seed-tetra.le.ply", ply_binary(TETRA_V, TETRA_F, "little"), prefix=0)
    put("fuzz_ply_off", "seed-tetra.be.ply", ply_binary(TETRA_V, TETRA_F, "big"), prefix=0)
    put("fuzz_ply_off", "seed-cube.off", off(cube_v, cube_f), prefix=1)
    put("fuzz_ply_off", "seed-quad.off",
        "OFF\n# comment\n4 1 4\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3 255 0 0\n", prefix=1)
    put("fuzz_ply_off", "seed-color.off",
        "COFF\n3 1 0\n0 0 0 1 1 1 1\n1 0 0 1 1 1 1\n0 1 0 1 1 1 1\n3 0 1 2\n", prefix=1)
    tet = mesh_object(1, TETRA_V, TETRA_F)
    put("fuzz_3mf", "seed-tetra.3mf", model_3mf(tet, '<item objectid="1"/>'))
    # fuzz_3mf packs any input that is not a zip as the model XML of a 3MF.
    put("fuzz_3mf", "seed-inch.model",
        model_xml(tet, '<item objectid="1" transform="1 0 0 0 1 0 0 0 1 5 5 0"/>', "inch"))
    put("fuzz_3mf", "seed-tetra.model", model_xml(tet, '<item objectid="1"/>'))
    put("fuzz_3mf", "seed-components.model", model_xml(
        tet + '<object id="2" type="model"><components><component objectid="1"/>'
        '<component objectid="1" transform="0 1 0 -1 0 0 0 0 1 20 0 0"/></components></object>'
        '<object id="3" type="model"><components><component objectid="2"/><component '
        'objectid="2" transform="1 0 0 0 1 0 0 0 1 0 0 30"/></components></object>',
        '<item objectid="3"/><item objectid="1" transform="2 0 0 0 2 0 0 0 2 0 50 0"/>'))


if __name__ == "__main__":
    main()
