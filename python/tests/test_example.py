# SPDX-License-Identifier: GPL-3.0-or-later
# docs/python.md's worked example (examples/python/facade_sun_hours.py), run without the plot, and
# what its numbers must be: the slab's roof (the highest face) is lit by every sun up, the north
# facade sees no sun at the December solstice, the lower row's roof is in the slab's winter shadow.
import importlib.util

import numpy as np

import libshadow


def load_example(source_dir):
    path = source_dir / "examples" / "python" / "facade_sun_hours.py"
    spec = importlib.util.spec_from_file_location("facade_sun_hours", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_facade_sun_hours_example(source_dir):
    example = load_example(source_dir)
    table = example.facade_sun_hours()
    assert list(table) == list(example.DAYS)
    for label, day in example.DAYS.items():
        names, hours = table[label]
        period = libshadow.SunPeriod(libshadow.SolarSite(52.52, 13.405, 34.0), utc_offset_hours=1.0,
                                     start=day, end=day, step_minutes=15)
        up = sum(1 for i in libshadow.expand_sun_period(period) if i.position.elevation > 0)
        hour = dict(zip(names, hours))
        assert abs(hour["slab roof"] - up * 0.25) < 1e-9, label
        assert all(h <= up * 0.25 + 1e-9 for h in hours)
    december = dict(zip(*table["December solstice"]))
    assert december["slab north"] == 0 and december["row north"] == 0
    assert december["row roof"] < december["slab roof"] / 2
    june = dict(zip(*table["June solstice"]))
    assert june["slab north"] > 0
    assert np.isclose(june["slab roof"], june["row roof"])
