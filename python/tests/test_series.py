# SPDX-License-Identifier: GPL-3.0-or-later
# Sun series from Python: compute_series against one compute per sun (bit for bit), sun hours two
# ways, sunlit.csv and energyplus-shading.csv against the CLI's `shadow series`, write_series.
import csv
import io
import json
import subprocess

import numpy as np
import pytest

import libshadow


@pytest.fixture(scope="module")
def sun_scene(source_dir):
    return libshadow.load_scene(str(source_dir / "examples" / "sun" / "scene.json"))


def test_series_equals_one_compute_per_sun(sun_scene):
    engine = libshadow.ShadowEngine(sun_scene)
    suns = libshadow.sun_series(sun_scene)
    assert suns.hours_per_instant == 1.0 and not suns.explicit_times and suns.all_instants == 24
    series = engine.compute_series(threads=2)
    assert series.instants == len(suns.lights) == len(series.times)
    assert series.lit_area.shape == (len(series.face_id), series.instants)
    per_light = engine.compute(polygons=False, threads=2)
    for column, instant in enumerate(suns.instants):
        light = sun_scene.sun_instants[instant].light_id
        mask = per_light.light_id == light
        assert np.array_equal(per_light.face_id[mask], series.face_id)
        # Bit for bit, as the C++ API promises.
        assert np.array_equal(series.lit_area[:, column].view(np.uint64), per_light.lit_area[mask].view(np.uint64))
        assert np.array_equal(series.lit_fraction[:, column], per_light.lit_fraction[mask])
        assert np.array_equal(series.faces_light[:, column], per_light.faces_light[mask])
    labels, hours = libshadow.sun_hours(series, by="face")
    labels2, hours2 = libshadow.sun_hours(per_light, by="face")
    assert labels == labels2
    assert np.allclose(hours, hours2, rtol=1e-13, atol=1e-13)
    assert not libshadow.sun_hours_error_bound(series).any()
    surfaces = libshadow.surface_series(series)
    assert surfaces["labels"] == labels and np.allclose(surfaces["sun_hours"], hours, rtol=1e-13)
    fast = engine.compute_series(arithmetic="fast")
    bound = libshadow.sun_hours_error_bound(fast)
    assert (np.abs(libshadow.sun_hours(fast, by="face")[1] - hours) <= bound + 1e-12).all()


def test_series_files_equal_the_cli_s(cli, source_dir, tmp_path):
    # The example with its suns where EnergyPlus takes them (mid-hour), for energyplus-shading.csv.
    scene = json.loads((source_dir / "examples" / "sun" / "scene.json").read_text())
    scene["sun"]["energyplus_times"] = True
    scene_path = tmp_path / "scene.json"
    scene_path.write_text(json.dumps(scene))
    subprocess.run([cli, "series", "-q", str(scene_path), "-o", str(tmp_path / "cli"), "-t", "2",
                    "--energyplus-shading"], check=True)
    series = libshadow.ShadowEngine(libshadow.load_scene(str(scene_path))).compute_series(threads=2)
    sunlit = libshadow.sunlit_csv(series)
    assert sunlit == (tmp_path / "cli" / "sunlit.csv").read_bytes().decode()
    rows = list(csv.reader(io.StringIO(sunlit)))
    assert rows[0][0] == "time" and len(rows) == 1 + series.instants
    text, schedule = libshadow.energyplus_shading_csv(series)
    assert schedule["written"] and schedule["rows"] == 8760 and schedule["rows_in_period"] == 24
    assert text == (tmp_path / "cli" / "energyplus-shading.csv").read_bytes().decode()
    # The CLI's --every and --energyplus-shading (examples/sun is no EnergyPlus model).
    paths = libshadow.write_series(series, str(tmp_path / "py"), every=1, energyplus_shading=True)
    assert (tmp_path / "py" / "energyplus-shading.csv").exists()
    libshadow.write_series(series, str(tmp_path / "unasked"))
    assert not (tmp_path / "unasked" / "energyplus-shading.csv").exists()
    assert paths[-1].endswith("report.json")
    assert (tmp_path / "py" / "series.pvd").exists() and (tmp_path / "py" / "faces.vtp").exists()
    ours = json.loads((tmp_path / "py" / "report.json").read_text())
    theirs = json.loads((tmp_path / "cli" / "report.json").read_text())
    for key in theirs:
        if key != "run":
            assert ours[key] == theirs[key], key


def test_series_with_other_lights_and_errors(sun_scene):
    engine = libshadow.ShadowEngine(sun_scene)
    lights = [libshadow.Light("a", to_light=[0, 0, 1]), libshadow.Light("b", to_light=[1, 0, 1])]
    series = engine.compute_series(lights=lights)
    assert series.instants == 2 and len(series.times) == 0
    roof = sun_scene.meshes[1].first_face
    row = series.face_id.tolist().index(roof)
    assert series.lit_fraction[row].tolist() == [1.0, 1.0]
    with pytest.raises(libshadow.InputError, match=r"lights\[1\]"):
        engine.compute_series(lights=[lights[0], libshadow.Light("zero", to_light=[0, 0, 0])])
    with pytest.raises(libshadow.InputError):
        engine.compute_series(threads=5000)
    plain = libshadow.scene_from_data({"g": [[[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]]},
                                      lights=[{"name": "up", "type": "directional", "to_light": [0, 0, 1]}])
    with pytest.raises(libshadow.InputError):
        libshadow.ShadowEngine(plain).compute_series()  # no sun block: name the lights


def test_series_tile_options(sun_scene):
    engine = libshadow.ShadowEngine(sun_scene)
    whole = engine.compute_series(threads=2, tile_casters=0)
    calls = []
    tiled = engine.compute_series(threads=2, tile_casters=1, progress=lambda done, total: calls.append((done, total)))
    assert whole.stats["tiled_receivers"] == 0
    assert tiled.stats["tiled_receivers"] > 0 and tiled.stats["tiles"] >= 2 * tiled.stats["tiled_receivers"]
    # Exact tiles change no bit; progress never goes back and ends at every instant.
    assert np.array_equal(whole.lit_area.view(np.uint64), tiled.lit_area.view(np.uint64))
    assert np.array_equal(whole.lit_fraction, tiled.lit_fraction)
    assert np.array_equal(whole.faces_light, tiled.faces_light)
    assert calls and calls[-1] == (tiled.instants, tiled.instants)
    assert all(a[0] <= b[0] and a[1] == b[1] for a, b in zip(calls, calls[1:]))
    # The fast path: its own threshold, and the tiled areas within the untiled ones' bounds.
    fast_whole = engine.compute_series(threads=2, arithmetic="fast", fast_tile_casters=0)
    fast_tiled = engine.compute_series(threads=2, arithmetic="fast", fast_tile_casters=1)
    assert fast_whole.stats["tiled_receivers"] == 0 and fast_tiled.stats["tiled_receivers"] > 0
    for fast in (fast_whole, fast_tiled):
        assert (np.abs(fast.lit_area - whole.lit_area) <= fast.lit_area_error_bound).all()
    # The defaults are compute's, and a negative threshold is refused by the binding.
    assert engine.compute_series(threads=2).stats["tiled_receivers"] == 0
    with pytest.raises(TypeError):
        engine.compute_series(tile_casters=-1)


def test_series_to_pandas(sun_scene):
    series = libshadow.ShadowEngine(sun_scene).compute_series(threads=2)
    try:
        import pandas  # noqa: F401  (optional)
    except ImportError:
        with pytest.raises(ImportError, match="pandas"):
            series.to_pandas()
        return
    frame = series.to_pandas()
    assert frame.shape == (series.instants, len(series.face_id))
    assert str(frame.index[0].tz) == "UTC"
    assert frame.index[0].value // 10**9 == series.times[0]
    assert np.array_equal(frame.to_numpy().T, series.lit_fraction)
