# SPDX-License-Identifier: GPL-3.0-or-later
# Weather files and irradiation from Python (docs/irradiance.md): read_epw's arrays, and
# irradiance() on an open roof against the weather file's own numbers.
import math

import numpy as np
import pytest

import libshadow


def _epw(path, dni=600, dhi=100):
    lines = ["LOCATION,Testtown,XX,FRA,test,000001,48.0,2.0,1.0,0.0", "DESIGN CONDITIONS,0",
             "TYPICAL/EXTREME PERIODS,0", "GROUND TEMPERATURES,0", "HOLIDAYS/DAYLIGHT SAVINGS,No,0,0,0",
             "COMMENTS 1,written by test_irradiance.py", "COMMENTS 2,", "DATA PERIODS,1,1,Data,Monday, 6/21,6/21"]
    for h in range(1, 25):
        day = 6 <= h <= 19
        lines.append(f"2021,6,21,{h},60,x,15,10,70,100000,0,0,300,9999,{dni if day else 0},{dhi if day else 0},"
                     "0,0,0,0,180,2,5,5,20,77777,9,999999999,10,0.1,0,88,999,0,0")
    path.write_text("\n".join(lines) + "\n")
    return str(path)


def test_read_epw(tmp_path):
    w = libshadow.read_epw(_epw(tmp_path / "day.epw"))
    assert len(w) == 24 and w.city == "Testtown" and w.latitude == 48.0 and w.time_zone_hours == 1.0
    assert list(w.hour[:3]) == [1, 2, 3]
    assert np.isnan(w.global_horizontal).all()  # 9999: missing
    assert w.direct_normal[12] == 600.0 and w.diffuse_horizontal[0] == 0.0
    assert libshadow.format_iso8601_utc(int(w.start_utc[0])) == "2021-06-20T23:00:00Z"
    with pytest.raises(libshadow.InputError, match="line 1"):
        bad = tmp_path / "bad.epw"
        bad.write_text("nothing\n")
        libshadow.read_epw(str(bad))
    assert w.warnings == []
    # Global horizontal missing (9999): no diffuse-above-global warning can be decided; a
    # global of 0 under a diffuse of 100 is one.
    odd = tmp_path / "odd.epw"
    odd.write_text(open(_epw(tmp_path / "day2.epw")).read().replace(",9999,600,100,", ",0,600,100,"))
    warnings = libshadow.read_epw(str(odd)).warnings
    assert len(warnings) == 1 and "diffuse horizontal 100 Wh/m2 exceeds global horizontal 0" in warnings[0], warnings
    # Records that stop before DATA PERIODS' end: a day or less missing is a warning (more, an error).
    cut = tmp_path / "cut.epw"
    cut.write_text("\n".join(open(_epw(tmp_path / "day3.epw")).read().split("\n")[:20]) + "\n")
    cut_read = libshadow.read_epw(str(cut))
    assert len(cut_read) == 12 and len(cut_read.warnings) == 1 and "12 hours missing" in cut_read.warnings[0]


def test_irradiance_open_roof(tmp_path):
    w = libshadow.read_epw(_epw(tmp_path / "day.epw"))
    scene = libshadow.scene_from_data([{"name": "roof", "polygons": [[[0, 0, 0], [4, 0, 0], [4, 4, 0], [0, 4, 0]]]}],
                                      lights=[{"name": "up", "type": "directional", "to_light": [0, 0, 1]}])
    r = libshadow.irradiance(scene, w, sky="isotropic", threads=1, hourly=True)
    assert list(r["face_id"]) == [0]
    assert r["sky_view_factor"][0] == 1.0
    assert r["sky_diffuse"][0] == pytest.approx(14 * 100 / 1000, abs=1e-12)  # the day's DHI
    assert r["ground_reflected"][0] == 0.0 and r["ground_reflectance"] == 0.2
    assert r["total"][0] == pytest.approx(r["direct"][0] + r["sky_diffuse"][0], abs=1e-12)
    assert r["monthly_total"].shape == (1, 12) and r["monthly_total"][0, 5] == pytest.approx(r["total"][0])
    hourly = r["hourly"]
    assert hourly["direct"].shape == (1, 24)
    assert hourly["direct"].sum() / 1000 == pytest.approx(r["direct"][0], abs=1e-12)
    # The direct part at noon's mid-hour: DNI x sin(elevation) of the SPA's sun then.
    site = libshadow.SolarSite(latitude=48.0, longitude=2.0, elevation=0.0)
    sun = libshadow.solar_position(site, int(w.start_utc[12]) + 1800)
    assert hourly["direct"][0, 12] == pytest.approx(600 * math.sin(math.radians(sun.elevation)), abs=1e-9)
    with pytest.raises(libshadow.InputError):
        libshadow.irradiance(scene, w, sky_patches=100)
    pd = pytest.importorskip("pandas")
    frame = r.to_pandas()
    assert list(frame.index) == [0] and frame.loc[0, "total"] == r["total"][0] and frame.loc[0, "jun"] == r["monthly_total"][0, 5]


def test_irradiance_scene_without_lights(tmp_path):
    # A scene for irradiance needs no lights (its suns come from the weather file), as
    # `shadow irradiance` reads it: require_lights=False on every loader; by default still refused.
    w = libshadow.read_epw(_epw(tmp_path / "day.epw"))
    text = '{"meshes": [{"name": "roof", "polygons": [[[0,0,0],[4,0,0],[4,4,0],[0,4,0]]]}]}'
    (tmp_path / "roof.json").write_text(text)
    with pytest.raises(libshadow.InputError, match="lights"):
        libshadow.load_scene(str(tmp_path / "roof.json"))
    scenes = [libshadow.load_scene(str(tmp_path / "roof.json"), require_lights=False),
              libshadow.parse_scene(text, require_lights=False),
              libshadow.scene_from_data({"roof": [[[0, 0, 0], [4, 0, 0], [4, 4, 0], [0, 4, 0]]]}, require_lights=False)]
    totals = [libshadow.irradiance(s, w, sky="isotropic", threads=1)["total"][0] for s in scenes]
    assert all(len(s.lights) == 0 for s in scenes)
    assert totals[0] > 0 and totals == [totals[0]] * 3
    with pytest.raises(libshadow.InputError, match="no lights"):
        libshadow.scene_from_data({"roof": [[[0, 0, 0], [4, 0, 0], [4, 4, 0], [0, 4, 0]]]})
    # Wrong types: TypeError, as docs/python.md promises (was AttributeError).
    with pytest.raises(TypeError):
        libshadow.scene_to_dict(None)
    with pytest.raises(TypeError):
        libshadow.surface_series(None)
    # NaN is not "not given" from Python: it was taken silently as the default reflectance.
    with pytest.raises(libshadow.InputError, match="ground_reflectance"):
        libshadow.irradiance(scenes[0], w, ground_reflectance=float("nan"))


def _tmy3(path):
    lines = ['1,"Testtown, test",XX,1.0,48.0,2.0,0.0',
             "Date (MM/DD/YYYY),Time (HH:MM),GHI (W/m^2),DNI (W/m^2),DHI (W/m^2),Alb (unitless)"]
    for h in range(1, 25):
        day = 6 <= h <= 19
        lines.append(f"06/21/2021,{h:02d}:00,-9900,{600 if day else 0},{100 if day else 0},0.25")
    path.write_text("\n".join(lines) + "\n")
    return str(path)


def test_read_tmy3_matches_epw(tmp_path):
    t = libshadow.read_weather(_tmy3(tmp_path / "day.csv"))
    e = libshadow.read_epw(_epw(tmp_path / "day.epw"))
    assert t.city == "Testtown, test" and len(t) == 24
    assert (t.start_utc == e.start_utc).all() and (t.direct_normal == e.direct_normal).all()
    assert np.isnan(t.global_horizontal).all() and (t.albedo == 0.25).all()
    assert libshadow.read_tmy3(str(tmp_path / "day.csv")).latitude == 48.0
    with pytest.raises(libshadow.InputError, match="line 2: no column named 'Date"):
        bad = tmp_path / "bad.csv"
        bad.write_text("1,Site,XX,0,10,20,5\nwhen,GHI (W/m^2)\n")
        libshadow.read_weather(str(bad))


def test_ground_view_of_a_wall_on_the_ground(tmp_path):
    # A wall standing on a ground face 200 m wide: the mesh named "ground" is the ground, so the
    # wall sees half the world below it as ground (sky + ground = 1); marking another mesh as the
    # ground instead (ground=[...]) leaves the ground face hiding it all.
    w = libshadow.read_epw(_epw(tmp_path / "day.epw"))
    scene = libshadow.scene_from_data(
        [{"name": "ground", "polygons": [[[-100, -100, 0], [100, -100, 0], [100, 100, 0], [-100, 100, 0]]]},
         {"name": "wall", "polygons": [[[0, 0, 0], [4, 0, 0], [4, 0, 3], [0, 0, 3]]]}],
        lights=[{"name": "up", "type": "directional", "to_light": [0, 0, 1]}])
    r = libshadow.irradiance(scene, w, threads=1, ground_reflectance=0.2)
    assert list(r["face_id"]) == [0, 1] and list(r["ground"]) == [1, 0]
    assert r["ground_view_factor"][0] == 0.0
    assert r["ground_view_factor"][1] == pytest.approx(0.5, abs=1e-15)
    assert r["sky_view_factor"][1] + r["ground_view_factor"][1] == pytest.approx(1.0, abs=1e-15)
    assert r["ground_reflected"][1] > 0.0
    other = libshadow.irradiance(scene, w, threads=1, ground_reflectance=0.2, ground=["wall"])
    assert list(other["ground"]) == [0, 1]
    assert other["ground_view_factor"][0] == 0.0  # ground faces: (1 - cos tilt) / 2, 0 when flat
    none = libshadow.irradiance(scene, w, threads=1, ground_reflectance=0.2, ground=[])
    assert none["ground_view_factor"][1] == 0.0 and none["ground_reflected"][1] == 0.0
    with pytest.raises(libshadow.InputError, match="ground"):
        libshadow.irradiance(scene, w, ground=["street"])
