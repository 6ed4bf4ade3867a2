# SPDX-License-Identifier: GPL-3.0-or-later
# Hypothesis over the module's entry points with hostile values (issue 30): None, wrong types, NaN,
# infinities, huge, negative and out-of-range numbers. Only TypeError, ValueError, IndexError,
# OverflowError or OSError may come out; a crash ends the run. Derandomized, 60 examples per
# test, a few seconds in all. Skipped without python3-hypothesis.
import math

import numpy as np
import pytest

import libshadow

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

SITE = dict(latitude=52.52, longitude=13.405, elevation=34.0)


@pytest.fixture(scope="module")
def sun_result(source_dir):
    scene = libshadow.load_scene(str(source_dir / "examples" / "sun" / "scene.json"))
    return libshadow.compute_shadows(scene, polygons=False, planes=False)


HOSTILE = st.one_of(
    st.none(), st.booleans(), st.integers(min_value=-2**70, max_value=2**70),
    st.sampled_from([0, -1, 1, 2**31, 2**63, -2**63, 2**64]),
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([math.nan, math.inf, -math.inf, 1e308, -1e308, 5e-324, -0.0]),
    st.text(max_size=6), st.binary(max_size=4), st.lists(st.floats(), max_size=4),
    st.just(object()), st.just(np.array([math.nan, 1.0, 2.0])),
)
# What a bad argument may raise: never a crash, never pybind11's RuntimeError "Unable to cast".
ALLOWED = (TypeError, ValueError, IndexError, OverflowError, OSError)
FUZZ = settings(derandomize=True, max_examples=60, deadline=None, database=None,
                suppress_health_check=list(HealthCheck))


def tolerant(call, *args, **kwargs):
    try:
        return call(*args, **kwargs)
    except ALLOWED:
        return None


@pytest.fixture(scope="module")
def tiny():
    return libshadow.scene_from_data(
        {"ground": [[[-5, -5, 0], [5, -5, 0], [5, 5, 0], [-5, 5, 0]]],
         "box": [[[0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]]]},
        lights=[{"name": "sun", "type": "directional", "to_light": [0.3, 0.2, 1.0]}],
        planes=[{"name": "floor", "point": [0, 0, -1], "normal": [0, 0, 1]}])


@FUZZ
@given(st.sampled_from(["latitude", "longitude", "elevation", "pressure", "temperature"]), HOSTILE)
def test_hostile_sites(field, value):
    kwargs = dict(SITE)
    kwargs[field] = value
    site = tolerant(libshadow.SolarSite, **kwargs)
    if site is not None:  # then every field is in range
        assert -90 <= site.latitude <= 90 and -180 <= site.longitude <= 180
        assert all(math.isfinite(v) for v in (site.elevation, site.pressure, site.temperature))
    site = libshadow.SolarSite(**SITE)
    if tolerant(setattr, site, field, value) is None and getattr(site, field) != SITE.get(field, getattr(site, field)):
        assert getattr(site, field) == value  # set, and then it was in range
    assert -90 <= site.latitude <= 90 and math.isfinite(site.elevation)


@FUZZ
@given(HOSTILE, HOSTILE, HOSTILE)
def test_hostile_solar_positions(time_value, north_axis, delta_t):
    site = libshadow.SolarSite(**SITE)
    sun = tolerant(libshadow.solar_position, site, time_value, north_axis, delta_t)
    if sun is not None:
        assert math.isfinite(sun.zenith) and math.isfinite(sun.azimuth)
    tolerant(libshadow.solar_positions, site, [time_value])
    tolerant(libshadow.format_iso8601_utc, time_value)
    tolerant(libshadow.parse_iso8601, time_value)
    tolerant(libshadow.parse_iso8601, "2026-06-21T12:00:00", time_value)
    tolerant(libshadow.sun_to_light, time_value, north_axis, delta_t)


@FUZZ
@given(HOSTILE)
def test_hostile_face_ids(tiny, face_id):
    for call in (tiny.face_label, tiny.face_vertices):
        value = tolerant(call, face_id)
        if value is not None:
            assert isinstance(face_id, (int, np.integer)) and 0 <= face_id < tiny.face_count


@FUZZ
@given(HOSTILE, HOSTILE, HOSTILE, HOSTILE, HOSTILE)
def test_hostile_compute_options(tiny, threads, lights, arithmetic, plane_window, tile_casters):
    # Up to 1024 threads are allowed and would all be started: a small count stands for them.
    if isinstance(threads, int) and not isinstance(threads, bool) and 2 < threads <= 1024:
        threads = 2
    result = tolerant(libshadow.compute_shadows, tiny, threads=threads, lights=lights, arithmetic=arithmetic,
                      plane_window=plane_window, tile_casters=tile_casters)
    if result is not None:
        assert len(result) > 0 and np.isfinite(result.lit_area).all()
    tolerant(libshadow.compute_plane_shadows, tiny, 1, lights, plane_window)
    tolerant(libshadow.ShadowEngine, threads)
    tolerant(libshadow.ShadowEngine, tiny, threads)


@FUZZ
@given(HOSTILE, HOSTILE, HOSTILE, HOSTILE)
def test_hostile_lights(tiny, name, to_light, position, intensity):
    for kind in ("directional", "point", name):
        light = tolerant(libshadow.Light, name if isinstance(name, str) else "x", kind, to_light, position,
                         intensity)
        if light is not None:
            engine = libshadow.ShadowEngine(tiny, threads=1)
            tolerant(engine.compute_light, light, 0, threads=1)
            tolerant(libshadow.compute_sun_hours_map, engine, faces=[0],
                     instants=[libshadow.SunHoursInstant(light, 1.0)], threads=1)
            tolerant(lambda: libshadow.SunHoursInstant(light, intensity))


@FUZZ
@given(HOSTILE, HOSTILE)
def test_hostile_sun_hours(sun_result, weight, by):
    hours = tolerant(libshadow.sun_hours, sun_result, weight)
    if hours is not None:
        assert np.isfinite(hours[1]).all() and (hours[1] >= 0).all()
    tolerant(libshadow.sun_hours, sun_result, by=by)
    tolerant(libshadow.sun_hours, weight)


@FUZZ
@given(HOSTILE, HOSTILE, st.lists(HOSTILE, max_size=4))
def test_hostile_scene_data(x, name, polygon):
    tolerant(libshadow.scene_from_data, {"m": [[[0, 0, 0], [1, 0, 0], [x, 1, 0]]]})
    tolerant(libshadow.scene_from_data, {"m": [polygon]})
    tolerant(libshadow.parse_scene, name if isinstance(name, str) else "{}", "hostile.json")
    tolerant(libshadow.make_city, 2, x, 1)
