# SPDX-License-Identifier: GPL-3.0-or-later
"""Opens a `series.pvd` with ParaView's own PVD reader (pvpython) and checks that ParaView sees
it as an animation: the expected number of time steps, increasing, and at a middle time step the
faces with a `lit_fraction` in [0, 1]. Prints "check_series_pvd: ok" on success.

usage: pvpython.sh check_series_pvd.py SERIES.pvd TIME_STEPS
"""
import sys

from paraview import servermanager
from paraview.simple import PVDReader

path, expected = sys.argv[1], int(sys.argv[2])
reader = PVDReader(FileName=path)
reader.UpdatePipelineInformation()
times = list(reader.TimestepValues)
if len(times) != expected or times != sorted(times):
    print(f"check_series_pvd: {len(times)} time steps (expected {expected}), increasing: {times == sorted(times)}")
    sys.exit(1)
reader.UpdatePipeline(times[len(times) // 2])
data = servermanager.Fetch(reader)
fraction = data.GetCellData().GetArray("lit_fraction")
if data.GetNumberOfCells() == 0 or fraction is None:
    print("check_series_pvd: no faces with lit_fraction at the middle time step")
    sys.exit(1)
values = [fraction.GetValue(i) for i in range(fraction.GetNumberOfTuples())]
if not all(0.0 <= v <= 1.0 for v in values):
    print(f"check_series_pvd: lit_fraction out of [0, 1]: {values}")
    sys.exit(1)
print(f"check_series_pvd: ok ({len(times)} time steps from {times[0]} to {times[-1]} h)")
