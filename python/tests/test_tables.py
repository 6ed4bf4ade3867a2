# SPDX-License-Identifier: GPL-3.0-or-later
# Results as tables (docs/python.md): SeriesResult.to_pandas with unique face columns, per surface,
# object and mesh, its UTC index and the site's local time; sun hours per object (CityJSON
# buildings with their parts, EnergyPlus zones) against the CLI's sun_hours_by_object.csv; the
# progress callback's values; the public names in docstrings. pandas is a test dependency
# (scripts/install-deps.sh --tests).
import csv
import datetime
import io
import json
import subprocess

import numpy as np
import pandas as pd
import pytest

import libshadow

# A room whose south wall has a window and a door (the wall comes in pieces around them), and a
# second zone beside it; the sun of one equinox day in Chicago.
IDF = """Version, 9.6;
Building, Two rooms, 0;
GlobalGeometryRules, UpperLeftCorner, Counterclockwise, Relative;
Zone, Zn001;
Zone, Zn002;
BuildingSurface:Detailed, Zn001:Wall001, Wall, C, Zn001, , Outdoors, , SunExposed, WindExposed, , 4,
  0,0,3, 0,0,0, 10,0,0, 10,0,3;
BuildingSurface:Detailed, Zn001:Roof001, Roof, C, Zn001, , Outdoors, , SunExposed, WindExposed, , 4,
  0,8,3, 0,0,3, 10,0,3, 10,8,3;
FenestrationSurface:Detailed, Zn001:Wall001:Win001, Window, G, Zn001:Wall001, , , , 1, 4,
  1,0,2.5, 1,0,1, 4,0,1, 4,0,2.5;
FenestrationSurface:Detailed, Zn001:Wall001:Door001, Door, D, Zn001:Wall001, , , , 1, 4,
  6,0,2.2, 6,0,0, 7,0,0, 7,0,2.2;
BuildingSurface:Detailed, Zn002:Wall001, Wall, C, Zn002, , Outdoors, , SunExposed, WindExposed, , 4,
  10,0,6, 10,0,0, 20,0,0, 20,0,6;
BuildingSurface:Detailed, Zn002:Roof001, Roof, C, Zn002, , Outdoors, , SunExposed, WindExposed, , 4,
  10,8,6, 10,0,6, 20,0,6, 20,8,6;
"""
SUN = {"latitude": 41.98, "longitude": -87.92, "utc_offset": -6, "start": "2026-03-20", "end": "2026-03-20",
       "step_minutes": 60}


def box(vertices, x0, y0, x1, y1, h):
    """Walls and roof of a box as a CityJSON MultiSurface (outward), vertices in millimetres."""
    def v(x, y, z):
        vertices.append([x * 1000, y * 1000, z * 1000])
        return len(vertices) - 1
    rings = [[(x0, y0, 0), (x1, y0, 0), (x1, y0, h), (x0, y0, h)], [(x1, y0, 0), (x1, y1, 0), (x1, y1, h), (x1, y0, h)],
             [(x1, y1, 0), (x0, y1, 0), (x0, y1, h), (x1, y1, h)], [(x0, y1, 0), (x0, y0, 0), (x0, y0, h), (x0, y1, h)],
             [(x0, y0, h), (x1, y0, h), (x1, y1, h), (x0, y1, h)]]
    return {"type": "MultiSurface", "lod": "2", "boundaries": [[[v(*p) for p in ring]] for ring in rings]}


@pytest.fixture(scope="module")
def default_scene(source_dir):
    return libshadow.load_scene(str(source_dir / "examples" / "default" / "scene.json"))


@pytest.fixture(scope="module")
def rooms(tmp_path_factory):
    folder = tmp_path_factory.mktemp("rooms")
    (folder / "rooms.idf").write_text(IDF)
    scene = libshadow.scene_from_data([{"name": "house", "file": "rooms.idf"}], sun=SUN, name="scene.json",
                                      base_dir=str(folder))
    return folder, scene


@pytest.fixture(scope="module")
def city(tmp_path_factory):
    folder = tmp_path_factory.mktemp("city")
    vertices = []
    objects = {
        "B1": {"type": "Building", "children": ["B1-low", "B1-high"]},
        "B1-low": {"type": "BuildingPart", "parents": ["B1"], "geometry": [box(vertices, 0, 0, 10, 10, 6)]},
        "B1-high": {"type": "BuildingPart", "parents": ["B1"], "geometry": [box(vertices, 11, 0, 21, 10, 12)]},
        "B2": {"type": "Building", "geometry": [box(vertices, 0, 20, 8, 28, 9)]},
    }
    first = len(vertices)
    vertices += [[-20000, -20000, 0], [40000, -20000, 0], [40000, 40000, 0], [-20000, 40000, 0]]
    objects["T"] = {"type": "TINRelief", "geometry": [{"type": "MultiSurface", "lod": "1",
                                                       "boundaries": [[[first, first + 1, first + 2, first + 3]]]}]}
    (folder / "city.city.json").write_text(json.dumps({
        "type": "CityJSON", "version": "2.0", "transform": {"scale": [0.001] * 3, "translate": [0, 0, 0]},
        "CityObjects": objects, "vertices": vertices}))
    scene_json = {"meshes": [{"name": "city", "file": "city.city.json"}],
                  "sun": dict(SUN, latitude=52.0, longitude=4.4, utc_offset=1)}
    (folder / "scene.json").write_text(json.dumps(scene_json))
    return folder, libshadow.load_scene(str(folder / "scene.json"))


def test_face_columns_are_unique(rooms):
    _, scene = rooms
    series = libshadow.ShadowEngine(scene).compute_series(threads=2)
    frame = series.to_pandas()
    labels = [scene.face_label(int(f)) for f in series.face_id]
    pieces = labels.count("Zn001:Wall001")
    assert pieces >= 3  # the wall cut around its window and door
    assert frame.columns.is_unique and len(frame.columns) == len(series.face_id)
    wall = [c for c in frame.columns if c.startswith("Zn001:Wall001#")]
    assert wall == ["Zn001:Wall001#%d" % k for k in range(1, pieces + 1)]
    assert "Zn001:Wall001:Win001" in frame.columns and "Zn001:Wall001:Door001" in frame.columns
    assert "Zn001:Roof001" in frame.columns  # a face alone keeps its label
    assert np.array_equal(frame.to_numpy().T, series.lit_fraction)
    assert libshadow.unique_face_labels(scene, series.face_id) == list(frame.columns)


def test_tables_per_surface_object_and_mesh(rooms):
    _, scene = rooms
    series = libshadow.ShadowEngine(scene).compute_series(threads=2)
    surfaces = libshadow.surface_series(series)
    by_surface = series.to_pandas(by="surface")
    # sunlit.csv's columns and values.
    header = next(csv.reader(io.StringIO(libshadow.sunlit_csv(series))))
    assert list(by_surface.columns) == header[1:] == surfaces["labels"]
    assert np.array_equal(by_surface.to_numpy().T, surfaces["lit_fraction"])
    by_object = series.to_pandas(by="object", values="lit_area")
    assert list(by_object.columns) == ["house/Zn001", "house/Zn002"]
    zone_rows = scene.face_mesh[series.face_id.astype(np.int64)]
    first_zone = [m.name for m in scene.meshes].index("house/Zn001")
    assert np.allclose(by_object["house/Zn001"].to_numpy(), series.lit_area[zone_rows == first_zone].sum(axis=0),
                       rtol=1e-14)
    fraction = series.to_pandas(by="mesh")
    assert list(fraction.columns) == ["house/Zn001", "house/Zn002"]
    assert ((fraction.to_numpy() >= 0) & (fraction.to_numpy() <= 1)).all()
    with pytest.raises(ValueError, match="by must be"):
        series.to_pandas(by="zone")
    with pytest.raises(ValueError, match="values must be"):
        series.to_pandas(values="area")


def test_index_is_utc_and_converts_to_local_time(rooms):
    _, scene = rooms
    series = libshadow.ShadowEngine(scene).compute_series(threads=2)
    frame = series.to_pandas(by="surface")
    assert frame.index.name == "time" and str(frame.index.tz) == "UTC"
    assert [t.value // 10**9 for t in frame.index] == list(series.times)
    zone = libshadow.site_timezone(scene)
    assert zone.utcoffset(None) == datetime.timedelta(hours=-6) and str(zone) == "UTC-06:00"
    local = frame.tz_convert(zone)
    assert local.index[0] == frame.index[0]  # the same instants
    first = datetime.datetime.fromtimestamp(series.times[0], datetime.timezone.utc)
    assert local.index[0].hour == (first.hour - 6) % 24
    assert local.index[0].date() == datetime.date(2026, 3, 20)  # the sun block's day, local time
    # Lights that are not the scene's suns: instants by number.
    other = libshadow.ShadowEngine(scene).compute_series(lights=[libshadow.Light("up", to_light=[0, 0, 1])])
    assert other.to_pandas().index.name == "instant"
    with pytest.raises(ValueError, match="no sun"):
        libshadow.site_timezone(libshadow.scene_from_data({"g": [[[0, 0, 0], [1, 0, 0], [1, 1, 0]]]},
                                                          lights=[libshadow.Light("up", to_light=[0, 0, 1])]))


def test_sun_hours_per_object_rolls_parts_up(city, cli, tmp_path):
    folder, scene = city
    meshes = {m.name: m for m in scene.meshes}
    assert meshes["city/B1-low"].object_type == "BuildingPart"
    assert meshes["city/B1-low"].parent == "city/B1" and meshes["city/B1-low"].parent_type == "Building"
    assert meshes["city/B1-low"].scene_mesh == "city"
    assert meshes["city/B2"].object_type == "Building" and meshes["city/B2"].parent == ""
    objects = scene.objects()
    assert [(o.id, o.type, [scene.meshes[m].name for m in o.meshes]) for o in objects] == [
        ("city/B1", "Building", ["city/B1-low", "city/B1-high"]), ("city/B2", "Building", ["city/B2"]),
        ("city/T", "TINRelief", ["city/T"])]
    assert [o.id for o in scene.objects(per_mesh=True)] == ["city/B1-low", "city/B1-high", "city/B2", "city/T"]

    engine = libshadow.ShadowEngine(scene)
    series = engine.compute_series(threads=2)
    table = libshadow.object_sun_hours(series)
    assert table["ids"] == ["city/B1", "city/B2", "city/T"] and table["types"] == ["Building", "Building", "TINRelief"]
    assert table["faces"].tolist() == [10, 5, 1]
    # The area-weighted mean of the faces' sun hours.
    face_labels, face_hours = libshadow.sun_hours(series, by="face")
    rows = scene.face_mesh[series.face_id.astype(np.int64)]
    b1 = np.isin(rows, table["meshes"][0])
    assert np.isclose(table["sun_hours"][0], (face_hours[b1] * series.area[b1]).sum() / series.area[b1].sum(),
                      rtol=1e-12)
    assert np.allclose(table["sunlit_area_hours"], table["sun_hours"] * table["area"], rtol=1e-13)
    # The same numbers as sun_hours(..., by="object") of a series and of one compute per sun, and
    # by="mesh" as before.
    ids, hours = libshadow.sun_hours(series, by="object")
    assert ids == table["ids"] and np.array_equal(hours, table["sun_hours"])
    per_light = engine.compute(polygons=False, threads=2)
    ids2, hours2 = libshadow.sun_hours(per_light, by="object")
    assert ids2 == ids and np.allclose(hours2, hours, rtol=1e-12)
    mesh_ids, mesh_hours = libshadow.sun_hours(series, by="mesh")
    mesh_ids2, mesh_hours2 = libshadow.sun_hours(per_light, by="mesh")
    assert mesh_ids == mesh_ids2 == ["city/B1-low", "city/B1-high", "city/B2", "city/T"]
    assert np.allclose(mesh_hours, mesh_hours2, rtol=1e-12)
    # The CLI writes the same file.
    subprocess.run([cli, "series", "-q", str(folder / "scene.json"), "-o", str(tmp_path / "out"), "-t", "2",
                    "--every", "0"], check=True)
    text = libshadow.sun_hours_by_object_csv(series)
    assert text == (tmp_path / "out" / "sun_hours_by_object.csv").read_bytes().decode()
    rows = list(csv.reader(io.StringIO(text)))
    assert rows[0] == ["object", "type", "faces", "area", "sun_hours", "sunlit_area_hours"]
    assert [float(r[4]) for r in rows[1:]] == table["sun_hours"].tolist()
    report = json.loads((tmp_path / "out" / "report.json").read_text())
    assert [o["id"] for o in report["series"]["objects"]] == ids
    assert [o["sun_hours"] for o in report["series"]["objects"]] == table["sun_hours"].tolist()


def test_zones_are_objects(rooms, tmp_path):
    _, scene = rooms
    series = libshadow.ShadowEngine(scene).compute_series(threads=2)
    table = libshadow.object_sun_hours(series)
    assert table["ids"] == ["house/Zn001", "house/Zn002"] and table["types"] == ["zone", "zone"]
    libshadow.write_series(series, str(tmp_path / "out"), every=0)
    assert (tmp_path / "out" / "sun_hours_by_object.csv").read_text().splitlines()[1].startswith("house/Zn001,zone,")


def test_progress_reports_each_value_once(rooms, default_scene):
    _, scene = rooms
    for run in (lambda p: libshadow.ShadowEngine(scene).compute_series(threads=2, progress=p),
                lambda p: libshadow.ShadowEngine(scene).compute_series(threads=1, progress=p),
                lambda p: libshadow.compute_shadows(default_scene, threads=2, progress=p),
                lambda p: libshadow.compute_shadows(default_scene, threads=1, progress=p)):
        calls = []
        run(lambda done, total: calls.append((done, total)))
        assert calls and calls[-1][0] == calls[-1][1]
        assert len(calls) == len(set(calls)), calls
        assert all(a[0] < b[0] for a, b in zip(calls, calls[1:])), calls


def test_public_names_in_docstrings():
    assert libshadow.SeriesResult.__module__ == "libshadow" and libshadow.Scene.__module__ == "libshadow"
    assert "-> libshadow.SeriesResult" in libshadow.ShadowEngine.compute_series.__doc__
    assert libshadow.InputError.__module__ == "libshadow"
    for name in dir(libshadow):
        thing = getattr(libshadow, name)
        docs = [getattr(thing, "__doc__", None) or ""]
        if isinstance(thing, type):
            docs += [getattr(getattr(thing, a), "__doc__", None) or "" for a in dir(thing) if not a.startswith("__")]
        for doc in docs:
            assert "anonymous namespace" not in doc and "shadow::" not in doc, (name, doc[:200])
