# SPDX-License-Identifier: GPL-3.0-or-later
# The module on hostile input and under signals (issue 30, items 12-14): never a crash, a
# TypeError for a wrong type, a ValueError or IndexError in words for a wrong value, Ctrl-C
# within about a second, a clean exit while a computation runs in another thread. Whatever
# could crash runs in a subprocess. test_hostile.py passes hostile values to every entry point.
import math
import os
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

import libshadow

SITE = dict(latitude=52.52, longitude=13.405, elevation=34.0)

# A city and suns sized so that each long call below takes far longer than the few seconds the
# tests allow for it to end once interrupted (tens of seconds on two cores), while the tests
# themselves stay short: they interrupt it half a second in.
PRELUDE = textwrap.dedent("""
    import sys, threading, time
    import libshadow

    def suns(n):
        out = []
        for k in range(n):
            t = 0.2 + 0.6 * k / max(n - 1, 1)
            out.append(libshadow.SunHoursInstant(
                libshadow.Light(type="directional", to_light=[t - 0.5, 0.3 * (1 - t), 0.6 + 0.2 * t]), 1.0))
        return out

    def long_sun_hours_map():
        scene = libshadow.make_city(300, 250.0, 7)
        engine = libshadow.ShadowEngine(scene, threads=2)
        instants = suns(400)
        return lambda: libshadow.compute_sun_hours_map(engine, faces=[0], instants=instants, threads=2)

    def long_compute():
        scene = libshadow.make_city(3000, 900.0, 11, lights=[
            libshadow.Light(type="directional", to_light=[0.4 + 0.01 * k, 0.3, 0.2]) for k in range(12)])
        return lambda: libshadow.compute_shadows(scene, threads=2, planes=False)

    def long_engine():
        # Faces of 4,002 vertices, turned so that none is exactly planar in doubles: their exact
        # preparation takes about 15 s in all on two cores.
        import numpy as np
        c, s = np.cos(0.3), np.sin(0.3)
        turn = np.linalg.qr(np.array([[c, -0.8 * s, 0.6 * s], [s, 0.8 * c, -0.6 * c], [0, 0.6, 0.8]]))[0]
        x = np.repeat(np.arange(2001), 2)[1:-1] * 0.1
        y = np.tile([0.0, 0.0, 0.5, 0.5], 1000)
        comb = np.column_stack([np.append(x, [200.0, 0.0]), np.append(y, [-0.1, -0.1]), np.zeros(4002)])
        faces = [(comb + [0.0, 0.0, float(k)]) @ turn.T for k in range(240)]
        scene = libshadow.scene_from_data({"combs": faces}, lights=[
            {"name": "sun", "type": "directional", "to_light": [0.3, 0.2, 1.0]}])
        return lambda: libshadow.ShadowEngine(scene, threads=2)
""")


def run_script(body, timeout=60, signals_after_start=(), env=None):
    """Runs PRELUDE + body in a fresh interpreter. The script prints "started" when its long call
    begins; each number in signals_after_start is a delay after that (or after the previous
    signal) before a SIGINT is sent. Returns (returncode, stdout, stderr, seconds from the first
    SIGINT to the process's end)."""
    script = PRELUDE + textwrap.dedent(body)
    proc = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, env=env or os.environ.copy())
    first_signal = None
    try:
        if signals_after_start:
            line = proc.stdout.readline()
            assert line.strip() == "started", (line, proc.stderr.read() if proc.poll() is not None else "")
            for delay in signals_after_start:
                time.sleep(delay)
                if proc.poll() is not None:
                    break
                if first_signal is None:
                    first_signal = time.monotonic()
                proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        proc.kill()
        out, err = proc.communicate()
        pytest.fail("the script did not end within %d s; stderr: %s" % (timeout, err[-2000:]))
    ended = time.monotonic()
    return proc.returncode, out, err, (ended - first_signal) if first_signal is not None else None


# ---- item 12: no crash ---------------------------------------------------------------------------

@pytest.mark.parametrize("call", [
    "libshadow.ShadowEngine(None)",
    "libshadow.compute_shadows(None)",
    "libshadow.compute_plane_shadows(None)",
    "libshadow.add_sun_lights(None, libshadow.SunPeriod(libshadow.SolarSite(0, 0), times=[0]))",
    "libshadow.replace_sun_lights(None, libshadow.SunPeriod(libshadow.SolarSite(0, 0), times=[0]))",
    "libshadow.sun_series(None)",
    "libshadow.solar_position(None, 0)",
    "libshadow.compute_sun_hours_map(None)",
    "libshadow.write_outputs(None, '/tmp/x')",
])
def test_none_for_an_object_is_a_type_error_not_a_crash(call):
    code, out, err, _ = run_script("""
        try:
            %s
        except TypeError as e:
            print("TypeError:", e)
    """ % call, timeout=60)
    assert code == 0, (code, err[-2000:])
    assert out.startswith("TypeError:") and len(out.strip()) > len("TypeError:"), out


def test_a_daemon_thread_still_computing_at_exit_ends_cleanly():
    code, out, err, _ = run_script("""
        run = long_sun_hours_map()
        junk = [[k] for k in range(1000000)]  # a finalization that takes a while
        threading.Thread(target=run, daemon=True).start()
        time.sleep(0.5)
        print("leaving")
    """, timeout=60)
    assert code == 0, (code, err[-2000:])
    assert "FATAL" not in err and "terminate" not in err, err[-2000:]
    assert out.strip() == "leaving"


def test_ctrl_c_during_join_and_at_exit_ends_cleanly():
    # The first SIGINT interrupts join(); the second one the interpreter's wait for the thread
    # at exit: the computation is then stopped, and the process ends without an abort.
    code, out, err, seconds = run_script("""
        run = long_sun_hours_map()
        junk = [[k] for k in range(1000000)]  # a finalization that takes a while
        t = threading.Thread(target=run)
        t.start()
        print("started", flush=True)
        t.join()
    """, timeout=60, signals_after_start=(0.5, 1.0))
    assert code not in (-signal.SIGABRT, 134, -signal.SIGSEGV, 139), (code, err[-2000:])
    assert "FATAL" not in err and "terminate called" not in err, err[-2000:]
    assert "KeyboardInterrupt" in err
    assert seconds < 10, seconds


# ---- item 13: Ctrl-C within about a second -------------------------------------------------------

@pytest.mark.parametrize("maker", ["long_sun_hours_map", "long_compute", "long_engine"])
def test_ctrl_c_stops_a_long_call(maker):
    code, out, err, seconds = run_script("""
        run = %s()
        print("started", flush=True)
        t0 = time.monotonic()
        try:
            run()
            print("finished", time.monotonic() - t0)
        except KeyboardInterrupt:
            print("interrupted", time.monotonic() - t0)
    """ % maker, timeout=60, signals_after_start=(0.5,))
    assert code == 0, (code, err[-2000:])
    assert out.startswith("interrupted"), out
    # About a second: the progress hook checks every 100 ms, the items between their steps.
    assert seconds < 3, seconds


# ---- item 14: arguments in words ----------------------------------------------------------------

def test_float_times_are_utc_seconds_rounded_down():
    site = libshadow.SolarSite(**SITE)
    whole = libshadow.solar_position(site, 1782036900)
    for t in (1782036900.0, 1782036900.75, np.float64(1782036900.5), np.longdouble(1782036900.0),
              np.array(1782036900.25), np.int64(1782036900)):
        sun = libshadow.solar_position(site, t)
        assert (sun.zenith, sun.azimuth) == (whole.zenith, whole.azimuth), t
    many = libshadow.solar_positions(site, np.array([1782036900.0, 1782036900.0 + 3600.0]))
    assert many["zenith"][0] == whole.zenith and many["zenith"].shape == (2,)
    for bad in (math.nan, math.inf, -math.inf, 1e300):
        with pytest.raises(ValueError, match="time"):
            libshadow.solar_position(site, bad)
    for bad in (None, [1.0], b"2026", True):
        with pytest.raises(TypeError, match="time"):
            libshadow.solar_position(site, bad)


@pytest.mark.parametrize("field,value", [("latitude", 91.0), ("latitude", math.nan), ("latitude", 1e308),
                                         ("longitude", -181.0), ("elevation", math.inf), ("pressure", -1.0),
                                         ("temperature", -300.0)])
def test_a_site_out_of_range_is_a_value_error(field, value):
    kwargs = dict(SITE)
    kwargs[field] = value
    with pytest.raises(ValueError, match=field):
        libshadow.SolarSite(**kwargs)
    site = libshadow.SolarSite(**SITE)
    before = getattr(site, field)
    with pytest.raises(ValueError, match=field):
        setattr(site, field, value)
    assert getattr(site, field) == before


def test_solar_position_checks_north_axis_and_delta_t():
    site = libshadow.SolarSite(**SITE)
    with pytest.raises(ValueError, match="north_axis"):
        libshadow.solar_position(site, 0, north_axis=math.nan)
    with pytest.raises(ValueError, match="delta_t"):
        libshadow.solar_position(site, 0, delta_t=1e300)


@pytest.fixture(scope="module")
def sun_scene(source_dir):
    return libshadow.load_scene(str(source_dir / "examples" / "sun" / "scene.json"))


@pytest.fixture(scope="module")
def sun_result(sun_scene):
    return libshadow.compute_shadows(sun_scene, polygons=False, planes=False)


@pytest.mark.parametrize("weight", [-1.0, math.nan, math.inf, -1e-300])
def test_sun_hours_refuses_a_negative_or_nan_weight(sun_scene, sun_result, weight):
    series = libshadow.ShadowEngine(sun_scene).compute_series()
    for result in (sun_result, series):
        with pytest.raises(ValueError, match="hours_per_instant"):
            libshadow.sun_hours(result, hours_per_instant=weight)
    with pytest.raises(TypeError, match="hours_per_instant"):
        libshadow.sun_hours(sun_result, hours_per_instant="2")
    labels, hours = libshadow.sun_hours(sun_result, hours_per_instant=0)
    assert len(labels) > 0 and (hours == 0).all()


def test_face_ids_out_of_range_are_index_errors_in_words(sun_scene):
    n = sun_scene.face_count
    engine = libshadow.ShadowEngine(sun_scene)
    for call in (sun_scene.face_label, sun_scene.face_vertices, engine.face_area):
        for bad in (n, -1, 2**80, np.int64(n + 5)):
            with pytest.raises(IndexError, match=r"face_id -?\d+ is out of range \(the scene has %d faces: 0 to %d\)"
                               % (n, n - 1)):
                call(bad)
        with pytest.raises(TypeError, match="face_id"):
            call(1.5)
    assert sun_scene.face_label(np.int64(0)) == sun_scene.face_label(0)
