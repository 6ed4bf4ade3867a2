# SPDX-License-Identifier: GPL-3.0-or-later
# Scenes from Python data against the same scenes from their JSON files, bit for bit; errors.
import json
import math
import subprocess

import numpy as np
import pytest

import libshadow


def bits(a):
    """float64 values as their bit patterns: equal bits, not merely equal values (-0.0 != 0.0)."""
    return np.ascontiguousarray(np.asarray(a, dtype=np.float64)).view(np.uint64)


def assert_same_scene(a, b):
    assert a.face_count == b.face_count
    for fa, fb in zip(a.faces, b.faces):
        assert fa.shape == fb.shape
        assert np.array_equal(bits(fa), bits(fb))
    assert np.array_equal(a.face_mesh, b.face_mesh)
    assert np.array_equal(a.face_degenerate, b.face_degenerate)
    assert np.array_equal(a.face_receiver, b.face_receiver)
    assert [(m.name, m.first_face, m.face_count, m.receiver, m.material) for m in a.meshes] == \
           [(m.name, m.first_face, m.face_count, m.receiver, m.material) for m in b.meshes]
    assert len(a.lights) == len(b.lights)
    for la, lb in zip(a.lights, b.lights):
        assert (la.name, la.type, la.intensity) == (lb.name, lb.type, lb.intensity)
        for key in ("to_light", "position", "color"):
            assert np.array_equal(bits(getattr(la, key)), bits(getattr(lb, key)))
    assert len(a.planes) == len(b.planes)
    for pa, pb in zip(a.planes, b.planes):
        assert pa.name == pb.name and pa.window == pb.window
        assert np.array_equal(bits(pa.point), bits(pb.point))
        assert np.array_equal(bits(pa.normal), bits(pb.normal))
    assert [(i.time, i.light_id, i.position.azimuth, i.position.elevation) for i in a.sun_instants] == \
           [(i.time, i.light_id, i.position.azimuth, i.position.elevation) for i in b.sun_instants]


def test_inline_scene_from_python_equals_json(source_dir):
    """examples/sun: inline polygons and a sun block, given as numpy arrays and dicts."""
    path = source_dir / "examples" / "sun" / "scene.json"
    document = json.loads(path.read_text())
    meshes = [{"name": m["name"], "polygons": [np.array(p, dtype=float) for p in m["polygons"]]}
              for m in document["meshes"]]
    from_python = libshadow.scene_from_data(meshes, sun=document["sun"])
    from_file = libshadow.load_scene(str(path))
    assert_same_scene(from_python, from_file)
    assert len(from_file.sun_instants) == 24  # one day, hourly
    assert from_python.source == "<python>"


def test_obj_scene_round_trip_through_python_data(source_dir):
    """examples/default (OBJ meshes, lights, a plane, receivers): scene_to_dict gives data whose scene
    is the file's, and a numpy (faces, n, 3) array is taken as it is."""
    from_file = libshadow.load_scene(str(source_dir / "examples" / "default" / "scene.json"))
    data = libshadow.scene_to_dict(from_file)
    assert_same_scene(libshadow.scene_from_data(**data), from_file)
    quads = np.array([[[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]],
                      [[0, 0, 1], [0.5, 0, 1], [0.5, 0.5, 1], [0, 0.5, 1]]], dtype=float)
    text = json.dumps({"meshes": [{"name": "q", "polygons": quads.tolist()}],
                       "lights": [{"name": "up", "type": "directional", "to_light": [0.1, 0.2, 1.0]}]})
    assert_same_scene(libshadow.scene_from_data({"q": quads},
                                                lights=[libshadow.Light("up", "directional", to_light=[0.1, 0.2, 1.0])]),
                      libshadow.parse_scene(text, "<python>"))


def cli_error(cli, scene, tmp_path):
    run = subprocess.run([cli, "compute", "-q", str(scene), "-o", str(tmp_path / "out")],
                         capture_output=True, text=True)
    assert run.returncode == 2
    prefix = "shadow: error: "
    assert run.stderr.startswith(prefix) and run.stderr.count("\n") == 1
    return run.stderr[len(prefix):].rstrip("\n")


BAD_SCENES = ["bowtie", "huge_coordinate", "index_out_of_range", "malformed", "missing_mesh_file",
              "nan_vertex", "nonplanar", "two_vertex_face", "unknown_key", "unknown_light_type",
              "zero_to_light"]


@pytest.mark.parametrize("name", BAD_SCENES)
def test_input_errors_are_the_cli_s(cli, source_dir, tmp_path, name, monkeypatch):
    """The same file, the same one line: InputError (a ValueError) says what the CLI says."""
    monkeypatch.chdir(source_dir)
    scene = "tests/data/scenes/%s.json" % name
    expected = cli_error(cli, scene, tmp_path)
    with pytest.raises(libshadow.InputError) as caught:
        libshadow.load_scene(scene)
    assert isinstance(caught.value, ValueError)
    assert str(caught.value) == expected


def test_errors_in_python_data_name_the_place():
    square = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]
    up = {"name": "up", "type": "directional", "to_light": [0, 0, 1]}
    with pytest.raises(libshadow.InputError, match=r"^<python>: meshes\[0\]\.polygons\[1\]\[2\]\[2\]: number is not finite$"):
        libshadow.scene_from_data({"a": [square, np.array([[0, 0, 0], [1, 0, 0], [1, 1, math.nan]])]},
                                  lights=[up])
    with pytest.raises(libshadow.InputError, match=r'^study\.py: lights\[0\]\.type: unknown light type "spot"'):
        libshadow.scene_from_data({"a": [square]}, lights=[{"name": "s", "type": "spot"}], name="study.py")
    with pytest.raises(ValueError, match=r'^<python>: meshes\[1\]\.name: mesh name "a" is already used by meshes\[0\]$'):
        libshadow.scene_from_data([{"name": "a", "polygons": [square]}, {"name": "a", "polygons": [square]}],
                                  lights=[up])
    with pytest.raises(libshadow.InputError, match=r"^<python>: lights: the scene has no lights"):
        libshadow.scene_from_data({"a": [square]})
    with pytest.raises(libshadow.InputError, match=r'^<python>: receivers\[0\]: no mesh is named "b"'):
        libshadow.scene_from_data({"a": [square]}, lights=[up], receivers=["b"])


def test_scene_accessors(source_dir):
    scene = libshadow.load_scene(str(source_dir / "examples" / "sun" / "scene.json"))
    assert [m.name for m in scene.meshes] == ["ground", "tower", "block", "house"]
    assert scene.face_vertices(0).shape == (4, 3)
    with pytest.raises(IndexError):
        scene.face_vertices(scene.face_count)
    assert scene.face_source[1].endswith("meshes[1].polygons[0]")
    assert [s.label for s in scene.named_surfaces()] == ["face_%d" % i for i in range(scene.face_count)]
    scene.validate()  # again: harmless
    assert scene.sun is not None and scene.sun.step_minutes == 60


@pytest.mark.parametrize("example", ["energyplus", "cityjson"])
def test_model_scenes_round_trip_with_names_and_kinds(source_dir, example):
    """EnergyPlus and CityJSON models name every face after its surface: scene_to_dict keeps the
    names and kinds, and the scene it gives back is the model's, bit for bit."""
    from_file = libshadow.load_scene(str(source_dir / "examples" / example / "scene.json"))
    assert any(from_file.face_name) and any(from_file.face_kind)
    again = libshadow.scene_from_data(**libshadow.scene_to_dict(from_file))
    assert_same_scene(again, from_file)
    assert again.face_name == from_file.face_name and again.face_kind == from_file.face_kind
    assert [s.label for s in again.named_surfaces()] == [s.label for s in from_file.named_surfaces()]


def test_load_options(source_dir, tmp_path):
    """orient_outward turns an inward box outward (with warnings); the CLI's option does the same."""
    box = [[[0, 0, 0], [0, 1, 0], [1, 1, 0], [1, 0, 0]], [[0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]],
           [[0, 0, 0], [1, 0, 0], [1, 0, 1], [0, 0, 1]], [[1, 0, 0], [1, 1, 0], [1, 1, 1], [1, 0, 1]],
           [[1, 1, 0], [0, 1, 0], [0, 1, 1], [1, 1, 1]], [[0, 1, 0], [0, 0, 0], [0, 0, 1], [0, 1, 1]]]
    inward = [list(reversed(face)) for face in box]
    up = [{"name": "up", "type": "directional", "to_light": [0, 0, 1]}]
    as_is = libshadow.scene_from_data({"box": inward}, lights=up)
    turned = libshadow.scene_from_data({"box": inward}, lights=up, orient_outward=True)
    outward = libshadow.scene_from_data({"box": box}, lights=up)
    assert not np.array_equal(as_is.faces[0], outward.faces[0])
    for a, b in zip(turned.faces, outward.faces):
        # The same polygon, possibly starting at another vertex.
        assert any(np.array_equal(np.roll(a, k, axis=0), b) for k in range(len(a)))
    assert turned.warnings and all("\n" not in w for w in turned.warnings)


def test_skip_invalid_and_types(tmp_path):
    """skip_invalid=True leaves a bow-tie out (listed with its reason); without it the error names
    the option. Meshes read from CityJSON carry their object type, which type:<T> selects."""
    good = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]
    bowtie = [[3, 0, 0], [4, 1, 0], [4, 0, 0], [3, 1, 0]]
    after = [[6, 0, 0], [7, 0, 0], [6, 1, 0]]
    up = [{"name": "up", "type": "directional", "to_light": [0, 0, 1]}]
    with pytest.raises(ValueError, match=r"intersects itself \(--skip-invalid skips such faces; skip_invalid=True"):
        libshadow.scene_from_data({"m": [good, bowtie, after]}, lights=up)
    scene = libshadow.scene_from_data({"m": [good, bowtie, after]}, lights=up, skip_invalid=True)
    assert scene.face_count == 2
    assert np.array_equal(scene.faces[1], np.array(after, dtype=np.float64))
    assert scene.skipped_faces == [{"name": "", "mesh": "m", "source": "<python>: meshes[0].polygons[1]",
                                    "reason": "face boundary intersects itself"}]
    assert any("skipped (--skip-invalid)" in w for w in scene.warnings)
    city = {"type": "CityJSON", "version": "2.0",
            "CityObjects": {"b": {"type": "Building", "geometry": [{"type": "MultiSurface", "lod": "2",
                                                                     "boundaries": [[[0, 1, 2, 3]]]}]},
                            "t": {"type": "TINRelief", "geometry": [{"type": "MultiSurface", "lod": "1",
                                                                      "boundaries": [[[4, 5, 6]]]}]}},
            "vertices": [[0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1], [-5, -5, 0], [5, -5, 0], [0, 5, 0]]}
    (tmp_path / "c.city.json").write_text(json.dumps(city))
    whole = libshadow.load_scene(str(tmp_path / "c.city.json"))
    assert [m.object_type for m in whole.meshes] == ["Building", "TINRelief"]
    assert list(libshadow.sun_hours_map_faces(whole, ["type:TINRelief"])) == [1]
    typed = libshadow.scene_from_data([{"name": "city", "file": "c.city.json"}], lights=up, base_dir=str(tmp_path),
                                      receivers=["type:TINRelief"])
    assert [m.receiver for m in typed.meshes] == [False, True]
    with pytest.raises(ValueError, match=r'receivers\[0\]: the type "Road" selects no mesh \(the object '
                                         r'types present: Building, TINRelief\)'):
        libshadow.scene_from_data([{"name": "city", "file": "c.city.json"}], lights=up, base_dir=str(tmp_path),
                                  receivers=["type:Road"])
