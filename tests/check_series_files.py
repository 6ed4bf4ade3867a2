#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Reads the series files that test_series (SeriesFiles.Year*) wrote into DIR with Python's own
csv module: exact headers, one energyplus-shading.csv row per time step of the year (8760 for
2026 and 8784 for 2028 hourly, 35040 for 2026 at 15 minutes), time stamps, sunlit.csv rows equal
to the instants above the horizon in report.json, fractions in [0, 1]; series.pvd as XML, and
with VTK's Python module (python3-vtk9) a sample of its files with VTK's .vtp reader.

usage: check_series_files.py DIR
"""
import csv
import json
import os
import sys
import xml.etree.ElementTree as ET

CASES = {  # folder: (year, minutes per step, rows of energyplus-shading.csv)
    "2026-hourly": (2026, 60, 8760),
    "2028-hourly": (2028, 60, 8784),
    "2026-15min": (2026, 15, 35040),
}
HEADER = ["court \"yard\"", "face_1"]  # sunlit.csv: the names as given
EP_HEADER = ["COURT \"YARD\"", "FACE_1"]  # energyplus-shading.csv: as EnergyPlus holds them, upper case


def fail(message):
    print("check_series_files: " + message, file=sys.stderr)
    sys.exit(1)


def check_case(folder, year, step, rows_expected):
    report = json.load(open(os.path.join(folder, "report.json")))
    series = report["series"]
    with open(os.path.join(folder, "energyplus-shading.csv"), newline="") as f:
        rows = list(csv.reader(f))
    if rows[0] != ["Surface Name"] + EP_HEADER:
        fail(f"{folder}: energyplus header {rows[0]!r}")
    body = rows[1:]
    if len(body) != rows_expected:
        fail(f"{folder}: {len(body)} energyplus rows, expected {rows_expected}")
    if series["energyplus"]["rows"] != rows_expected:
        fail(f"{folder}: report.json says {series['energyplus']['rows']} rows")
    first = f"01/01 {step // 60:02d}:{step % 60:02d}" if step < 60 else "01/01 01:00"
    if body[0][0] != first or body[-1][0] != "12/31 24:00":
        fail(f"{folder}: time stamps run {body[0][0]} .. {body[-1][0]}")
    # Every stamp is distinct and has the form MM/DD hh:mm.
    stamps = [r[0] for r in body]
    if len(set(stamps)) != len(stamps):
        fail(f"{folder}: repeated time stamps")
    for r in body:
        if len(r) != 3 or not all(0.0 <= float(v) <= 1.0 for v in r[1:]):
            fail(f"{folder}: bad row {r!r}")
    # Night rows are 0 (the equinox sun of the test sets at 18:00 solar time = UTC here).
    night = [r for r in body if r[0].endswith(" 03:00")]
    if any(float(v) != 0.0 for r in night for v in r[1:]):
        fail(f"{folder}: a night row is not 0")

    with open(os.path.join(folder, "sunlit.csv"), newline="") as f:
        sunlit = list(csv.reader(f))
    if sunlit[0] != ["time"] + HEADER:
        fail(f"{folder}: sunlit header {sunlit[0]!r}")
    if len(sunlit) - 1 != series["above_horizon"]:
        fail(f"{folder}: {len(sunlit) - 1} sunlit rows, report.json says {series['above_horizon']} above the horizon")
    for r in sunlit[1:]:
        if not (len(r[0]) == 20 and r[0].startswith(str(year)) and r[0].endswith("Z")):
            fail(f"{folder}: time {r[0]!r} is not ISO 8601 UTC in {year}")
    lit_rows = sum(1 for r in body if any(float(v) > 0 for v in r[1:]))
    if lit_rows != series["above_horizon"]:
        fail(f"{folder}: {lit_rows} energyplus rows with sun, {series['above_horizon']} instants above the horizon")

    pvd = os.path.join(folder, "series.pvd")
    if not os.path.exists(pvd):
        return 0
    datasets = ET.parse(pvd).getroot().find("Collection").findall("DataSet")
    times = [float(d.get("timestep")) for d in datasets]
    if not datasets or times != sorted(times):
        fail(f"{folder}: series.pvd has {len(datasets)} data sets, times not increasing")
    for d in datasets:
        if not os.path.exists(os.path.join(folder, d.get("file"))):
            fail(f"{folder}: series.pvd names missing {d.get('file')}")
    # VTK's Python module of Debian 12 (9.1) has no .pvd reader (ParaView has its own): the
    # collection is checked as XML above, and a sample of its files with VTK's .vtp reader.
    try:
        from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
    except ImportError:
        print(f"{folder}: no VTK Python module: series.pvd checked as XML only")
        return len(datasets)
    for d in datasets[:: max(1, len(datasets) // 20)]:
        r = vtkXMLPolyDataReader()
        r.SetFileName(os.path.join(folder, d.get("file")))
        r.Update()
        cells = r.GetOutput().GetCellData()
        if r.GetOutput().GetNumberOfCells() != 2 or cells.GetArray("lit_fraction") is None:
            fail(f"{folder}: {d.get('file')} is not the faces with lit_fraction")
    return len(datasets)


def main():
    if len(sys.argv) != 2:
        fail("usage: check_series_files.py DIR")
    for name, (year, step, rows) in CASES.items():
        folder = os.path.join(sys.argv[1], name)
        n = check_case(folder, year, step, rows)
        print(f"{name}: {rows} energyplus rows, series.pvd with {n} data sets: ok")


if __name__ == "__main__":
    main()
