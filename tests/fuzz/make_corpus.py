#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Writes the seed corpus of the fuzz targets (tests/fuzz/corpus/<target>/): a few ordinary
inputs and the hostile ones (coordinates near +-1e308, NaN/Inf, NUL bytes in OBJ lines, huge
vertex indices, deeply nested JSON, a zero light direction, ...). Deterministic; rerun after
editing and commit the files. Inputs that reproduce a defect not fixed yet go to
tests/fuzz/known/ instead (see its README), out of the replay tests.
Usage: python3 tests/fuzz/make_corpus.py"""
import json
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))


def write(target, name, data):
    folder = os.path.join(HERE, "corpus", target)
    os.makedirs(folder, exist_ok=True)
    if isinstance(data, str):
        data = data.encode("utf-8", "surrogatepass")
    with open(os.path.join(folder, name), "wb") as f:
        f.write(data)


def scene(meshes, lights, planes=None):
    doc = {"meshes": meshes, "lights": lights}
    if planes is not None:
        doc["planes"] = planes
    return json.dumps(doc)


GROUND = [[0, 0, 0], [4, 0, 0], [4, 4, 0], [0, 4, 0]]
ROOF = [[1, 1, 2], [3, 1, 2], [3, 3, 2], [1, 3, 2]]
SUN = {"name": "sun", "type": "directional", "to_light": [0.4, 0.3, 0.85]}
LAMP = {"name": "lamp", "type": "point", "position": [2, 2, 5]}

# ---- fuzz_scene: scene JSON text ----------------------------------------------------------------
# A sun block instead of lights (docs/scene-format.md): a period, and times with offsets.
write("fuzz_scene", "sun_period.json", json.dumps(
    {"meshes": [{"name": "ground", "polygons": [GROUND]}, {"name": "roof", "polygons": [ROOF]}],
     "sun": {"latitude": 52.52, "longitude": 13.405, "time_zone": "UTC+01:00", "start": "2026-06-21",
             "end": "2026-06-22", "step_minutes": 30, "north_axis": 30, "min_elevation": 2}}))
write("fuzz_scene", "sun_times.json", json.dumps(
    {"meshes": [{"name": "ground", "polygons": [GROUND]}], "lights": [LAMP],
     "sun": {"latitude": -33.9, "longitude": 151.2, "utc_offset": 10, "pressure": 990, "temperature": 18,
             "times": ["2026-12-21T12:00:00", "2026-12-21T03:00:00Z", "2026-12-21T14:30:00.5+10:00"]}}))
write("fuzz_scene", "ground_and_roof.json",
      scene([{"name": "ground", "polygons": [GROUND]}, {"name": "roof", "polygons": [ROOF]}], [SUN, LAMP],
            [{"name": "floor", "point": [0, 0, 0], "normal": [0, 0, 1]}]))
write("fuzz_scene", "receivers_and_materials.json",
      json.dumps({"meshes": [{"name": "a", "polygons": [GROUND]}, {"name": "b", "polygons": [ROOF]}],
                  "receivers": ["a"], "lights": [SUN]}))
write("fuzz_scene", "concave_l.json",
      scene([{"name": "l", "polygons": [[[0, 0, 0], [2, 0, 0], [2, 1, 0], [1, 1, 0], [1, 2, 0], [0, 2, 0]]]}], [SUN]))
write("fuzz_scene", "near_1e308.json",
      scene([{"name": "big", "polygons": [[[-1.7e308, 0, 0], [1.7e308, 0, 0], [0, 1.7e308, 0]]]}], [SUN]))
write("fuzz_scene", "overflow_to_inf.json",
      '{"meshes": [{"name": "m", "polygons": [[[0,0,0],[1e400,0,0],[0,1,0]]]}], "lights": []}')
write("fuzz_scene", "nan_literal.json",
      '{"meshes": [{"name": "m", "polygons": [[[NaN,0,0],[1,0,0],[0,1,0]]]}], "lights": []}')
write("fuzz_scene", "infinity_literal.json",
      '{"meshes": [{"name": "m", "polygons": [[[0,0,0],[1,0,0],[0,1,0]]]}],'
      ' "lights": [{"name": "s", "type": "directional", "to_light": [Infinity, 0, 1]}]}')
write("fuzz_scene", "zero_light_direction.json",
      scene([{"name": "g", "polygons": [GROUND]}], [{"name": "s", "type": "directional", "to_light": [0, 0, 0]}]))
write("fuzz_scene", "zero_plane_normal.json",
      scene([{"name": "g", "polygons": [GROUND]}], [SUN], [{"name": "p", "point": [0, 0, 0], "normal": [0, 0, 0]}]))
write("fuzz_scene", "unknown_light_type.json",
      scene([{"name": "g", "polygons": [GROUND]}], [{"name": "s", "type": "laser", "to_light": [0, 0, 1]}]))
write("fuzz_scene", "deeply_nested_arrays.json", '{"meshes": ' + "[" * 100000 + "]" * 100000 + "}")
write("fuzz_scene", "deeply_nested_objects.json", '{"a":' * 20000 + "1" + "}" * 20000)
write("fuzz_scene", "bowtie.json",
      scene([{"name": "b", "polygons": [[[0, 0, 0], [1, 1, 0], [1, 0, 0], [0, 1, 0]]]}], [SUN]))
write("fuzz_scene", "collinear.json", scene([{"name": "c", "polygons": [[[0, 0, 0], [1, 0, 0], [2, 0, 0]]]}], [SUN]))
write("fuzz_scene", "two_vertices.json", scene([{"name": "c", "polygons": [[[0, 0, 0], [1, 0, 0]]]}], [SUN]))
write("fuzz_scene", "nonplanar.json", scene([{"name": "n", "polygons": [[[0, 0, 0], [1, 0, 0], [1, 1, 1], [0, 1, 0]]]}], [SUN]))
write("fuzz_scene", "wrong_types.json",
      '{"meshes": [{"name": 7, "polygons": "x"}], "lights": [{"name": "s", "type": "point", "position": [1, 2]}]}')
write("fuzz_scene", "nul_in_string.json",
      '{"meshes": [{"name": "a\\u0000b", "polygons": [[[0,0,0],[1,0,0],[0,1,0]]]}], "lights": []}')
write("fuzz_scene", "raw_nul_bytes.json", b'{"meshes": [\x00], "lights": []}')
write("fuzz_scene", "empty.json", "")
write("fuzz_scene", "truncated.json", '{"meshes": [{"name": "m", "polygons": [[[0,0')
write("fuzz_scene", "huge_integer.json",
      '{"meshes": [{"name": "m", "polygons": [[[0,0,0],[123456789012345678901234567890,0,0],[0,1,0]]]}], "lights": []}')

# ---- fuzz_obj: OBJ text -------------------------------------------------------------------------
write("fuzz_obj", "quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n")
write("fuzz_obj", "index_forms.obj",
      "# comment\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 3/1/1\nf 1//1 2//1 3//1\nf -3 -2 -1\n"
      "o name\ng group\nusemtl x\ns off\n")
write("fuzz_obj", "crlf_and_continuation.obj", "v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 \\\n3\r\n")
write("fuzz_obj", "huge_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999999\n")
write("fuzz_obj", "huge_negative_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -9223372036854775808\n")
write("fuzz_obj", "index_max_int.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 2147483648\nf 1 2 4294967296\n")
write("fuzz_obj", "index_zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n")
write("fuzz_obj", "nul_in_line.obj", b"v 0 0 0\nv 1\x00 0 0\nv 0 1 0\nf 1 2\x003\n")
write("fuzz_obj", "nul_only.obj", b"\x00\x00\x00\n\x00")
write("fuzz_obj", "nan_inf.obj", "v nan 0 0\nv inf 0 0\nv -inf 1 0\nv NaN(123) 0 0\nf 1 2 3\n")
write("fuzz_obj", "near_1e308.obj", "v -1.7976931348623157e308 0 0\nv 1.7976931348623157e308 0 0\nv 0 1e308 0\nf 1 2 3\n")
write("fuzz_obj", "overflow.obj", "v 1e400 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n")
write("fuzz_obj", "denormals.obj", "v 4.9e-324 0 0\nv 0 4.9e-324 0\nv 0 0 0\nf 1 2 3\n")
write("fuzz_obj", "two_vertex_face.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n")
write("fuzz_obj", "garbage_numbers.obj", "v 1.2.3 0x10 --4\nv 1e 2 3\nv +.5 -.5 .5e1\nf 1/ /2 3//\n")
write("fuzz_obj", "missing_coordinates.obj", "v 1 2\nv\nf\n")
write("fuzz_obj", "long_line.obj", "v " + "1" * 5000 + " 0 0\n")
write("fuzz_obj", "empty.obj", "")

# ---- fuzz_engine: bytes decoded by fuzz_engine.cpp ----------------------------------------------
# header: bit 0 point light, (faces - 1) << 1; light: 3 coordinates; per face: shape byte
# ((vertices - 3) + 6 * kind; kind 0: z = c, 1: x = c, 2: y = c, 3: free 3D, 4: z = (a u + b w)/4 + c),
# c, a, b, then per vertex u, w (and a third coordinate for kind 3). Coordinates are int8 / 4.


def q(x):
    return struct.pack("b", int(round(x * 4)))


def face(kind, vertices, c=0.0, a=0, b=0):
    out = bytes([(len(vertices) - 3) + 6 * kind]) + q(c) + struct.pack("b", a) + struct.pack("b", b)
    for v in vertices:
        out += b"".join(q(x) for x in v)
    return out


def engine(point, light, faces):
    return bytes([(1 if point else 0) | ((len(faces) - 1) << 1)]) + b"".join(q(x) for x in light) + b"".join(faces)


SQUARE = [(0, 0), (8, 0), (8, 8), (0, 8)]
SMALL = [(2, 2), (5, 2), (5, 5), (2, 5)]
write("fuzz_engine", "square_under_square_sun.bin",
      engine(False, (1, 0.5, 4), [face(0, SQUARE), face(0, SMALL, c=3)]))
write("fuzz_engine", "square_under_square_lamp.bin",
      engine(True, (4, 4, 10), [face(0, SQUARE), face(0, SMALL, c=3)]))
write("fuzz_engine", "wall_and_ground.bin",
      engine(False, (-2, -1, 3), [face(0, SQUARE), face(1, [(1, 0), (6, 0), (6, 4), (1, 4)], c=3),
                                   face(2, [(1, 0), (1, 4), (6, 4), (6, 0)], c=5)]))
write("fuzz_engine", "concave_l_over_ground.bin",
      engine(False, (0.25, 0.5, 2), [face(0, SQUARE), face(0, [(1, 1), (5, 1), (5, 3), (3, 3), (3, 6), (1, 6)], c=2)]))
write("fuzz_engine", "octagon_and_sloped_roof.bin",
      engine(True, (2, 3, 12), [face(0, [(3, 0), (6, 0), (9, 3), (9, 6), (6, 9), (3, 9), (0, 6), (0, 3)]),
                                face(4, [(1, 1), (6, 1), (6, 6), (1, 6)], c=4, a=1, b=-1)]))
write("fuzz_engine", "triangles_free.bin",
      engine(False, (0.5, 0.25, 1), [face(3, [(0, 0, 0), (10, 0, 1), (0, 10, 2)]),
                                     face(3, [(2, 2, 5), (6, 2, 4), (2, 6, 6)])]))
write("fuzz_engine", "zero_light_direction.bin", engine(False, (0, 0, 0), [face(0, SQUARE), face(0, SMALL, c=3)]))
write("fuzz_engine", "lamp_in_the_plane.bin", engine(True, (10, 10, 0), [face(0, SQUARE), face(0, SMALL, c=3)]))
write("fuzz_engine", "lamp_on_a_vertex.bin", engine(True, (2, 2, 3), [face(0, SQUARE), face(0, SMALL, c=3)]))
write("fuzz_engine", "grazing_sun.bin", engine(False, (31, 0, 0.25), [face(0, SQUARE), face(0, SMALL, c=3)]))
write("fuzz_engine", "coplanar_overlap.bin", engine(False, (0, 0, 1), [face(0, SQUARE), face(0, SMALL, c=0)]))
write("fuzz_engine", "degenerate_face.bin",
      engine(False, (0, 0, 1), [face(0, SQUARE), face(0, [(1, 1), (1, 1), (1, 1)], c=2)]))
write("fuzz_engine", "bowtie.bin", engine(False, (0, 0, 1), [face(0, [(0, 0), (4, 4), (4, 0), (0, 4)])]))
write("fuzz_engine", "thin_sliver_caster.bin",
      engine(False, (1, 1, 8), [face(0, SQUARE), face(0, [(1, 1), (7, 1.25), (1, 1.5)], c=2)]))
write("fuzz_engine", "extreme_coordinates.bin",
      engine(True, (-32, 31.75, 31.75), [face(0, [(-32, -32), (31.75, -32), (31.75, 31.75), (-32, 31.75)]),
                                         face(0, SMALL, c=-32)]))
write("fuzz_engine", "empty.bin", b"")

# --- fuzz_energyplus: IDF and epJSON text -> the EnergyPlus reader -> validate_scene ---------------
EXAMPLE = os.path.join(HERE, "..", "..", "examples", "energyplus")
for name in ("box-office.idf", "box-office.epJSON"):
    with open(os.path.join(EXAMPLE, name), "rb") as example:
        write("fuzz_energyplus", "example_" + name.replace("-", "_").replace(".", "_"), example.read())
HEAD = "Version, 24.1;\nZone, Z, 30, 1, 2, 0;\n"
WALL = ("BuildingSurface:Detailed, W, Wall, C, Z, , Outdoors, , SunExposed, WindExposed, , 4,\n"
        "  0,0,3, 0,0,0, 4,0,0, 4,0,3;\n")


def window(name, points, base="W"):
    return ("FenestrationSurface:Detailed, %s, Window, G, %s, , , , 1, %d,\n  %s;\n"
            % (name, base, len(points), ", ".join("%r,%r,%r" % p for p in points)))


write("fuzz_energyplus", "door_on_the_floor_line.idf",
      HEAD + WALL + window("D", [(1, 0, 2), (1, 0, 0), (2, 0, 0), (2, 0, 2)]))
write("fuzz_energyplus", "windows_touching.idf",
      HEAD + WALL + window("A", [(1, 0, 2), (1, 0, 1), (2, 0, 1), (2, 0, 2)])
      + window("B", [(2, 0, 2), (2, 0, 1), (3, 0, 1), (3, 0, 2)]))
write("fuzz_energyplus", "window_as_big_as_its_wall.idf",
      HEAD + WALL + window("A", [(0, 0, 3), (0, 0, 0), (4, 0, 0), (4, 0, 3)]))
write("fuzz_energyplus", "window_sticking_out_by_rounding.idf",
      HEAD + WALL + window("A", [(3, 0, 2), (3, 0, 1), (4.000000001, 0, 1), (4.000000001, 0, 2)]))
write("fuzz_energyplus", "window_overlapping.idf",
      HEAD + WALL + window("A", [(1, 0, 2), (1, 0, 1), (2, 0, 1), (2, 0, 2)])
      + window("B", [(1.5, 0, 2), (1.5, 0, 1), (3, 0, 1), (3, 0, 2)]))
write("fuzz_energyplus", "window_reversed.idf",
      HEAD + WALL + window("A", [(1, 0, 1), (1, 0, 2), (2, 0, 2), (2, 0, 1)]))
write("fuzz_energyplus", "bowtie_wall_with_window.idf",
      HEAD + "BuildingSurface:Detailed, W, Wall, C, Z, , Outdoors, , SunExposed, WindExposed, , 4,\n"
      "  0,0,3, 4,0,0, 0,0,0, 4,0,3;\n" + window("A", [(1, 0, 2), (1, 0, 1), (2, 0, 1), (2, 0, 2)]))
write("fuzz_energyplus", "zero_area_wall_with_window.idf",
      HEAD + "BuildingSurface:Detailed, W, Wall, C, Z, , Outdoors, , SunExposed, WindExposed, , 3,\n"
      "  0,0,0, 1,0,0, 2,0,0;\n" + window("A", [(0.5, 0, 0), (1, 0, 0), (1.5, 0, 0)]))
write("fuzz_energyplus", "huge_coordinates.idf",
      HEAD + "Shading:Site:Detailed, S, , 3, 1e150,0,0, -1e150,0,0, 0,1e150,1e150;\n"
      "Shading:Site:Detailed, T, , 3, 1e300,0,0, 0,1,0, 0,0,1;\n")
write("fuzz_energyplus", "not_numbers.idf",
      HEAD + "Shading:Site:Detailed, S, , 3, nan,0,0, inf,0,0, 0x10,1e999,-0;\n")
write("fuzz_energyplus", "unterminated.idf", HEAD + "Shading:Site:Detailed, S, , 3, 0,0,0, 1,0,0, 1,0,1")
write("fuzz_energyplus", "comments_and_blank_objects.idf",
      "! only a comment\n;;\n,;\nZone,Z;!x\nShading:Building:Detailed,S,,autocalculate,0,0,0,1,0,0,1,0,1,,,;\n")
write("fuzz_energyplus", "simple_forms_and_shades.idf",
      HEAD + "GlobalGeometryRules, LowerLeftCorner, Clockwise, Relative, Relative, World;\n"
      "Building, B, 15;\nWall:Exterior, E, C, Z, , 180, 90, 0, 0, 0, 6, 3;\n"
      "Roof, R, C, Z, , 0, 0, 0, 0, 3, 6, 4;\nWindow, G, C, E, , 1, 1, 1, 2, 1;\n"
      "Door, D, C, E, 1, 4, 0, 1, 2;\nShading:Overhang, O, G, 0.2, 45, 0.5, 0.5, 1;\n"
      "Shading:Fin:Projection, F, G, 0.1, 0.2, 0.3, 120, 0.5, 0.1, 0.2, 0.3, 60, 0.5;\n"
      "Shading:Site, S, 200, 30, 5, -10, 0, 8, 3;\nShading:Building, T, 90, 90, 7, 0, 0, 2, 2;\n"
      "Site:Location, L, 48.1, 11.6, 1, 520;\nRunPeriod, R1, 12, 1, , 1, 31, ;\nTimestep, 7;\n")
write("fuzz_energyplus", "epjson_wrong_types.epJSON",
      json.dumps({"Zone": {"Z": {}}, "BuildingSurface:Detailed": {"W": {
          "surface_type": "Wall", "zone_name": "Z", "outside_boundary_condition": "Outdoors",
          "number_of_vertices": [3], "vertices": [{"vertex_x_coordinate": True}, 5, None]}},
          "Shading:Site:Detailed": []}))
write("fuzz_energyplus", "epjson_not_an_object.epJSON", "[1, 2, 3]")
write("fuzz_energyplus", "empty.idf", "")
# Found by fuzz_energyplus: a vertex count too large for an integer was converted to one (UB).
write("fuzz_energyplus", "vertex_count_1e150.idf", HEAD + "Shading:Site:Detailed, S, , 1e150, 0,0,0, 1,0,0, 0,1,0;\n")
write("fuzz_energyplus", "window_beyond_range.idf",
      HEAD + WALL + "Window, G, C, W, , 1, 1, 1, 1e308, 1;\nZone, Y, 0, 1e308, 0, 0;\n"
      "Shading:Zone:Detailed, O, W, , 3, 1e308,0,0, 0,1,0, 0,0,1;\n")
# Found by fuzz_energyplus: a version number too large for an int overflowed (UB).
write("fuzz_energyplus", "version_2400000001.idf",
      "Version, 2400000001;\nZone, Z;\nShading:Site:Detailed, S, , 3, 0,0,0, 1,0,0, 0,1,0;\n")
# Issue 30: an object name written twice in one class (JSON keeps one: the first object was
# lost without a word), a class written twice, a name given as a number, a number beyond a
# double, bytes that are not UTF-8, a version that is no version number.
SHADE = {"vertices": [{"vertex_x_coordinate": x, "vertex_y_coordinate": 0, "vertex_z_coordinate": z}
                      for x, z in ((0, 0), (1, 0), (1, 1))]}
write("fuzz_energyplus", "epjson_name_twice.epJSON",
      '{"Shading:Site:Detailed": {"Fence": %s, "Fence": %s}}' % (json.dumps(SHADE), json.dumps(SHADE)))
write("fuzz_energyplus", "epjson_class_twice.epJSON",
      '{"Zone": {"A": {}}, "Zone": {"B": {}}, "Shading:Site:Detailed": {"S": %s}}' % json.dumps(SHADE))
write("fuzz_energyplus", "epjson_zone_name_a_number.epJSON",
      json.dumps({"Zone": {"17": {}}, "BuildingSurface:Detailed": {"W": dict(
          SHADE, surface_type="Wall", zone_name=17, outside_boundary_condition="Outdoors")}}))
write("fuzz_energyplus", "epjson_overflow.epJSON", '{"Zone": {"Z": {"x_origin": 1e999}}}')
write("fuzz_energyplus", "epjson_not_utf8.epJSON", b'{"Zone": {"Z\xff\xfe": {}}}')
write("fuzz_energyplus", "version_abc.idf", "Version, abc;\nZone, Z;\nShading:Site:Detailed, S, , 3, 0,0,0, 1,0,0, 0,1,0;\n")
