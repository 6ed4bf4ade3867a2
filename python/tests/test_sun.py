# SPDX-License-Identifier: GPL-3.0-or-later
# The sun from Python: the SPA paper's example, the CLI's `shadow sun`, times in every form, sun
# periods and sun hours (an unobstructed roof against a count of the suns above the horizon).
import datetime
import json
import subprocess

import numpy as np
import pytest

import libshadow

# Reda & Andreas (2004), NREL/TP-560-34302, the example of its appendix: Golden, Colorado,
# 2003-10-17 12:30:30 local time (UTC-7), delta_t 67 s.
SPA_SITE = dict(latitude=39.742476, longitude=-105.1786, elevation=1830.14, pressure=820.0, temperature=11.0)


def test_spa_paper_example():
    site = libshadow.SolarSite(**SPA_SITE)
    sun = libshadow.solar_position(site, "2003-10-17T12:30:30-07:00", delta_t=67.0)
    assert sun.zenith == pytest.approx(50.11162, abs=1e-5)
    assert sun.azimuth == pytest.approx(194.34024, abs=1e-5)
    assert sun.elevation == pytest.approx(90.0 - sun.zenith, abs=1e-12)
    assert np.linalg.norm(sun.to_light) == pytest.approx(1.0)


def test_times_in_every_form_agree():
    site = libshadow.SolarSite(**SPA_SITE)
    seconds = libshadow.parse_iso8601("2003-10-17T19:30:30Z")
    assert libshadow.format_iso8601_utc(seconds) == "2003-10-17T19:30:30Z"
    assert libshadow.parse_iso8601("2003-10-17T12:30:30", local_offset_minutes=-420) == seconds
    aware = datetime.datetime(2003, 10, 17, 12, 30, 30, tzinfo=datetime.timezone(datetime.timedelta(hours=-7)))
    forms = [seconds, "2003-10-17T12:30:30-07:00", aware]
    positions = [libshadow.solar_position(site, t, delta_t=67.0) for t in forms]
    assert len({(p.zenith, p.azimuth) for p in positions}) == 1
    with pytest.raises(ValueError):
        libshadow.parse_iso8601("2026-02-30T12:00:00Z")
    with pytest.raises(ValueError, match="naive"):
        libshadow.solar_position(site, datetime.datetime(2003, 10, 17, 12, 30, 30))
    assert libshadow.parse_utc_offset("UTC+05:30") == 330 and libshadow.parse_utc_offset("Europe/Paris") is None


def test_solar_position_equals_the_cli(cli):
    args = ["--latitude", "52.52", "--longitude", "13.405", "--elevation", "34", "--time", "2026-06-21T10:15:00Z",
            "--north-axis", "20"]
    out = json.loads(subprocess.run([cli, "sun", *args], check=True, capture_output=True, text=True).stdout)
    sun = libshadow.solar_position(libshadow.SolarSite(52.52, 13.405, 34.0), "2026-06-21T10:15:00Z", north_axis=20.0)
    assert sun.elevation == out["elevation"] and sun.azimuth == out["azimuth"] and sun.zenith == out["zenith"]
    assert sun.to_light.tolist() == out["to_light"]
    many = libshadow.solar_positions(libshadow.SolarSite(52.52, 13.405, 34.0),
                                     ["2026-06-21T10:15:00Z", "2026-06-21T22:15:00Z"], north_axis=20.0)
    assert many["elevation"][0] == sun.elevation and many["elevation"][1] < 0
    assert many["to_light"].shape == (2, 3)


def test_sun_period_and_its_errors():
    period = libshadow.SunPeriod(libshadow.SolarSite(52.52, 13.405), utc_offset_hours=1.0,
                                 start="2026-06-21", end="2026-06-22", step_minutes=30)
    instants = libshadow.expand_sun_period(period)
    assert len(instants) == 2 * 48
    assert all(b.time - a.time == 1800 for a, b in zip(instants, instants[1:]))
    assert instants[0].time == libshadow.parse_iso8601("2026-06-21T00:00:00+01:00")
    assert all(i.light_id is None for i in instants)
    period.step_minutes = 7
    with pytest.raises(libshadow.InputError, match="step_minutes"):
        libshadow.check_sun_period(period, "study.py")


def test_sun_hours_of_an_unobstructed_roof(source_dir):
    """The tower's roof (30 m, the highest face, horizontal) is lit by every sun above the horizon:
    its sun hours are the number of hourly instants whose sun is up, counted here from
    solar_position directly."""
    scene = libshadow.load_scene(str(source_dir / "examples" / "sun" / "scene.json"))
    result = libshadow.compute_shadows(scene, threads=2, polygons=False)
    site = scene.sun.site
    times = ["2026-06-21T%02d:00:00+01:00" % h for h in range(24)]
    up = int((libshadow.solar_positions(site, times)["elevation"] > scene.sun.min_elevation).sum())
    assert 15 <= up <= 18  # Berlin at midsummer: about 16.8 hours of daylight
    labels, hours = libshadow.sun_hours(result, by="face")
    roof = scene.meshes[1].first_face
    assert np.abs(scene.face_vertices(roof)[:, 2] - 30.0).max() == 0
    assert hours[labels.index("face_%d" % roof)] == pytest.approx(up * 1.0, abs=1e-12)
    # The ground is shadowed for part of the day; no face has more hours than suns.
    assert (hours <= up + 1e-9).all() and hours.min() < up
    surface_labels, surface_hours = libshadow.sun_hours(result)
    assert surface_labels == labels and np.allclose(surface_hours, hours, rtol=1e-14)
    partial = libshadow.compute_shadows(scene, lights=[0], polygons=False)
    with pytest.raises(ValueError, match="lacks"):
        libshadow.sun_hours(partial)


def test_python_sun_block_equals_the_file_one(source_dir):
    """A sun block given as a SunPeriod (and as a dict with datetimes) gives the file's suns."""
    from_file = libshadow.load_scene(str(source_dir / "examples" / "sun" / "scene.json"))
    square = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]
    from_period = libshadow.scene_from_data({"g": [square]}, sun=from_file.sun)
    assert [(i.time, i.position.azimuth, i.light_id) for i in from_period.sun_instants] == \
           [(i.time, i.position.azimuth, i.light_id) for i in from_file.sun_instants]
    tz = datetime.timezone(datetime.timedelta(hours=1))
    times = [datetime.datetime(2026, 6, 21, h, 0, tzinfo=tz) for h in (9, 12, 15)]
    by_times = libshadow.scene_from_data({"g": [square]}, sun={"latitude": 52.52, "longitude": 13.405,
                                                               "elevation": 34, "times": times})
    expected = [i for i in from_file.sun_instants if i.time in {libshadow.parse_iso8601(t.isoformat()) for t in times}]
    assert [i.position.azimuth for i in by_times.sun_instants] == [i.position.azimuth for i in expected]
    assert len(by_times.lights) == 3


def test_add_sun_lights_returns_a_new_scene():
    square = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]
    scene = libshadow.scene_from_data({"g": [square]}, lights=[{"name": "lamp", "type": "point", "position": [0, 0, 5]}])
    period = libshadow.SunPeriod(libshadow.SolarSite(52.52, 13.405), utc_offset_hours=1.0,
                                 start="2026-06-21", end="2026-06-21", step_minutes=60)
    with_suns = libshadow.add_sun_lights(scene, period)
    assert len(scene.lights) == 1 and scene.sun is None
    up = [i for i in with_suns.sun_instants if i.light_id is not None]
    assert len(with_suns.lights) == 1 + len(up) and all(i.light_id >= 1 for i in up)
    assert with_suns.lights[up[0].light_id].name == libshadow.sun_light_name(up[0].time)
    result = libshadow.compute_shadows(with_suns, polygons=False)
    labels, hours = libshadow.sun_hours(result, by="face")
    assert hours[0] == pytest.approx(len(up))  # a lone square, lit by every sun up


def test_sun_hours_map_agrees_with_the_per_instant_results(source_dir, tmp_path):
    """The exact map's hours per face (hour_area / area) against sun_hours from one compute per
    sun light; its cells tile each face; the tower's roof is one cell lit by every sun."""
    document = json.loads((source_dir / "examples" / "sun" / "scene.json").read_text())
    scene = libshadow.scene_from_data(document["meshes"], sun=document["sun"], sun_hours_map=["ground", "tower"])
    assert [scene.meshes[i].name for i in scene.sun_hours_map] == ["ground", "tower"]
    faces = libshadow.sun_hours_map_faces(scene)
    assert faces == list(range(0, 6))  # the ground's face and the tower's five
    engine = libshadow.ShadowEngine(scene)
    calls = []
    hours_map = libshadow.compute_sun_hours_map(engine, progress=lambda d, t: calls.append(d))
    assert calls
    instants = libshadow.sun_hours_instants(scene)
    assert hours_map.total_hours == pytest.approx(sum(i.hours for i in instants))
    of_series = libshadow.sun_hours_instants(libshadow.sun_series(scene))
    assert [i.hours for i in of_series] == [i.hours for i in instants]
    assert [i.light.name for i in of_series] == [i.light.name for i in instants]
    assert hours_map.face_id.tolist() == faces
    labels, hours = libshadow.sun_hours(engine.compute(polygons=False), by="face")
    per_face = dict(zip(labels, hours))
    for f, area, hour_area in zip(hours_map.face_id, hours_map.area, hours_map.hour_area):
        assert hour_area / area == pytest.approx(per_face["face_%d" % f], rel=1e-12, abs=1e-12)
    for f, area, dropped in zip(hours_map.face_id, hours_map.area, hours_map.dropped_area):
        cells = hours_map.cell_face_id == f
        assert hours_map.cell_area[cells].sum() + dropped == pytest.approx(area, rel=1e-12)
    roof = scene.meshes[1].first_face
    roof_cells = hours_map.sun_hours[hours_map.cell_face_id == roof]
    assert roof_cells.tolist() == [hours_map.total_hours]
    assert len(hours_map.cell_polygons) == len(hours_map)
    libshadow.write_sun_hours_vtp(hours_map, str(tmp_path / "sun_hours.vtp"))
    assert (tmp_path / "sun_hours.vtp").stat().st_size > 0
    with pytest.raises(libshadow.InputError):
        libshadow.compute_sun_hours_map(engine, faces=[scene.face_count])
    with pytest.raises(libshadow.InputError):
        libshadow.sun_hours_map_faces(scene, ["no such mesh"])


def test_replace_sun_lights_returns_a_new_scene(source_dir):
    scene = libshadow.load_scene(str(source_dir / "examples" / "sun" / "scene.json"))
    winter = libshadow.SunPeriod(scene.sun.site, utc_offset_hours=1.0, start="2026-12-21", end="2026-12-21",
                                 step_minutes=60)
    replaced = libshadow.replace_sun_lights(scene, winter)
    assert len(scene.lights) == sum(1 for i in scene.sun_instants if i.light_id is not None)  # unchanged
    up = [i for i in replaced.sun_instants if i.light_id is not None]
    assert len(replaced.lights) == len(up) < len(scene.lights)  # shorter days
    assert replaced.sun.start == "2026-12-21"
    assert all(replaced.lights[i.light_id].name == libshadow.sun_light_name(i.time) for i in up)


def test_pressure_zero_is_the_airless_position(cli):
    """NREL's SPA takes 0 to 5000 millibars; 0 asks for the geometric sun, without refraction:
    a SolarSite, a sun period (checked and expanded) and `shadow sun --pressure 0` agree."""
    airless = libshadow.SolarSite(39.742476, -105.1786, 1830.14, pressure=0.0, temperature=11.0)
    with_air = libshadow.SolarSite(**SPA_SITE)
    time = "2003-10-17T12:30:30-07:00"
    sun = libshadow.solar_position(airless, time, delta_t=67.0)
    lifted = libshadow.solar_position(with_air, time, delta_t=67.0)
    assert 0.01 < lifted.elevation - sun.elevation < 0.02  # 820 mbar lift it by about 0.0163 degrees
    assert sun.azimuth == lifted.azimuth
    out = json.loads(subprocess.run([cli, "sun", "--latitude", "39.742476", "--longitude", "-105.1786",
                                     "--elevation", "1830.14", "--pressure", "0", "--temperature", "11",
                                     "--delta-t", "67", "--time", time], check=True, capture_output=True,
                                    text=True).stdout)
    assert out["elevation"] == sun.elevation and out["azimuth"] == sun.azimuth
    period = libshadow.SunPeriod(airless, utc_offset_hours=-7.0, start="2003-10-17", end="2003-10-17",
                                 step_minutes=60)
    libshadow.check_sun_period(period, "study.py")
    noon = [i for i in libshadow.expand_sun_period(period)
            if i.time == libshadow.parse_iso8601("2003-10-17T12:00:00-07:00")][0]
    direct = libshadow.solar_position(airless, "2003-10-17T12:00:00-07:00")
    assert noon.position.elevation == direct.elevation
    square = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]
    scene = libshadow.scene_from_data({"g": [square]}, sun=period)
    assert scene.sun.site.pressure == 0.0 and len(scene.lights) > 0


def test_sun_hours_levels_alone_match_the_full_map(source_dir, tmp_path):
    """levels=[...] gives the threshold map: each level's exact area equals the full map's cells
    with at least that many hours; levels_only=True computes it alone with the same areas, bit
    for bit, and no full cells; it is written as sun_hours_levels.vtp."""
    document = json.loads((source_dir / "examples" / "sun" / "scene.json").read_text())
    scene = libshadow.scene_from_data(document["meshes"], sun=document["sun"], sun_hours_map=["ground"])
    engine = libshadow.ShadowEngine(scene)
    levels = [6, 2, 4]
    full = libshadow.compute_sun_hours_map(engine, levels=levels, threads=1)
    alone = libshadow.compute_sun_hours_map(engine, levels=levels, levels_only=True, threads=1)
    assert full.full and not alone.full
    assert full.levels.tolist() == [2, 4, 6] and alone.levels.tolist() == [2, 4, 6]
    assert len(alone) == 0 and len(full) > 0
    assert alone.level_areas.tolist() == full.level_areas.tolist()  # bit for bit
    assert alone.face_level_areas.shape == (len(alone.face_id), 3)
    assert alone.face_level_areas.sum(axis=0).tolist() == pytest.approx(alone.level_areas.tolist(), rel=1e-15)
    for k, h in enumerate(full.levels):
        at_least = full.cell_area[full.sun_hours >= h].sum()
        assert full.level_areas[k] == pytest.approx(at_least, rel=1e-12)
        cells = alone.level_cell_area[alone.level >= h].sum() + alone.dropped_area.sum()
        assert alone.level_areas[k] == pytest.approx(cells, rel=1e-9, abs=1e-9)
    assert 0 < alone.level_areas[2] <= alone.level_areas[1] <= alone.level_areas[0] <= alone.area.sum()
    assert len(alone.level_cell_polygons) == len(alone.level) == len(alone.level_region_id) == len(alone.level_cell_face_id)
    libshadow.write_sun_hours_levels_vtp(alone, str(tmp_path / "sun_hours_levels.vtp"), scene)
    assert (tmp_path / "sun_hours_levels.vtp").stat().st_size > 0
    # A cap on the exact boundaries held: lit regions computed again, the same areas bit for bit.
    capped = libshadow.compute_sun_hours_map(engine, levels=levels, levels_only=True, held_segments=0, threads=2)
    assert capped.level_areas.tolist() == alone.level_areas.tolist()
    assert capped.face_level_areas.tolist() == alone.face_level_areas.tolist()
    for bad, problem in (({"held_segments": 10}, "needs levels_only"),
                         ({"levels_only": True, "held_segments": -1}, "must be 0 to"),
                         ({"levels_only": True, "held_segments": 10**13}, "must be 0 to")):
        with pytest.raises(libshadow.InputError, match="held_segments.*" + problem):
            libshadow.compute_sun_hours_map(engine, levels=levels, **bad)
    with pytest.raises(libshadow.InputError):
        libshadow.compute_sun_hours_map(engine, levels_only=True)
    with pytest.raises(libshadow.InputError):
        libshadow.compute_sun_hours_map(engine, levels=[-1])
