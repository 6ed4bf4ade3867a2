#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""`shadow render SCENE -o view.svg|view.pdf` (docs/vector-views.md), driven through the binary.

The SVG must be well-formed XML with the promised structure (a <title>, a <g> per face with
data-face-id, a <path> per piece with data-lit and round-trip coordinates inside the image), and
rsvg-convert (librsvg2-bin) must render it to a PNG of the requested size; the PDF must start with
%PDF and end with %%EOF, written without a cairo error (exit status 0); bad input gets exit status
2 and one line naming the option.

Usage: check_vector_view.py SHADOW EXAMPLES_DIR WORK_DIR yes|no   (yes: built with cairo)
Exit status 0 on success, 1 on a failure, 77 (skipped) when rsvg-convert is not installed.
"""

import os
import re
import shutil
import struct
import subprocess
import sys
import xml.etree.ElementTree as ET
import zlib

SVG = "{http://www.w3.org/2000/svg}"
failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAIL:", message)


def run(args):
    return subprocess.run(args, capture_output=True, text=True, timeout=120)


def main():
    shadow, examples, work, with_cairo = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4] == "yes"
    os.makedirs(work, exist_ok=True)
    scene = os.path.join(examples, "default", "scene.json")
    width, height = 320, 200

    svg = os.path.join(work, "view.svg")
    r = run([shadow, "render", scene, "-o", svg, "--width", str(width), "--height", str(height), "-q"])
    check(r.returncode == 0, f"svg: exit status {r.returncode}: {r.stderr.strip()}")
    root = ET.parse(svg).getroot()  # raises (the test fails) when the XML is not well formed
    check(root.tag == SVG + "svg", f"root element is {root.tag}")
    check(root.get("width") == str(width) and root.get("height") == str(height),
          f"size {root.get('width')}x{root.get('height')}")
    title = root.find(SVG + "title")
    check(title is not None and "scene.json" in (title.text or ""), "no <title> naming the scene")
    groups = root.findall(SVG + "g")
    check(len(groups) > 10, f"only {len(groups)} face groups")
    face_ids = [int(g.get("data-face-id")) for g in groups]
    check(len(set(face_ids)) == len(face_ids), "a face has two groups")
    lit = {"0": 0, "1": 0}
    for g in groups:
        for path in g.findall(SVG + "path"):
            lit[path.get("data-lit")] += 1
            numbers = [float(t) for t in re.findall(r"[-+0-9.eE]+", path.get("d"))]
            check(len(numbers) >= 6 and len(numbers) % 2 == 0, "a path with fewer than 3 points")
            for x, y in zip(numbers[0::2], numbers[1::2]):
                check(-1e-6 <= x <= width + 1e-6 and -1e-6 <= y <= height + 1e-6, f"point ({x}, {y}) off the image")
            # 17 significant digits: every coordinate reads back as the double written.
            for t in re.findall(r"[-+0-9.eE]+", path.get("d")):
                check(float(repr(float(t))) == float(t), f"coordinate {t} does not round-trip")
    check(lit["1"] > 0 and lit["0"] > 0, f"lit and shadowed pieces: {lit}")

    # --light 1 (the lamp) changes the split, --edges the strokes; the pieces stay the same.
    svg_lamp = os.path.join(work, "lamp.svg")
    r = run([shadow, "render", scene, "-o", svg_lamp, "--width", str(width), "--height", str(height),
             "--light", "1", "--edges", "-q"])
    check(r.returncode == 0, f"--light 1: exit status {r.returncode}: {r.stderr.strip()}")
    lamp = ET.parse(svg_lamp).getroot()
    check(lamp.find(SVG + "title").text.find("lamp") >= 0, "the title does not name the lamp")
    check(all(g.get("stroke") for g in lamp.findall(SVG + "g")), "--edges: a group without a stroke")

    rsvg = shutil.which("rsvg-convert")
    if rsvg is None:
        print("SKIP: rsvg-convert not found (Debian: librsvg2-bin; scripts/install-deps.sh installs it)")
        return 77 if not failures else 1
    png = os.path.join(work, "view.png")
    r = run([rsvg, svg, "-o", png])
    check(r.returncode == 0, f"rsvg-convert: {r.stderr.strip()}")
    with open(png, "rb") as f:
        head = f.read(24)
    check(head[:8] == b"\x89PNG\r\n\x1a\n", "rsvg-convert did not write a PNG")
    w, h = struct.unpack(">II", head[16:24])
    check((w, h) == (width, height), f"rsvg-convert's PNG is {w}x{h}")

    pdf = os.path.join(work, "view.pdf")
    r = run([shadow, "render", scene, "-o", pdf, "--width", str(width), "--height", str(height), "-q"])
    if with_cairo:
        check(r.returncode == 0, f"pdf: exit status {r.returncode}: {r.stderr.strip()}")
        with open(pdf, "rb") as f:
            data = f.read()
        check(data.startswith(b"%PDF-"), "the PDF does not start with %PDF-")
        check(data.rstrip().endswith(b"%%EOF"), "the PDF does not end with %%EOF")
        check(f"/MediaBox [ 0 0 {width} {height} ]".encode() in data, "the PDF page is not the image's size")
        # The page draws the background and then one filled path per piece, as many as the SVG's.
        painted = 0
        for m in re.finditer(rb"stream\r?\n(.*?)\r?\nendstream", data, re.S):
            try:
                content = zlib.decompress(m.group(1))
            except zlib.error:
                continue  # not a Flate stream (fonts, metadata)
            painted += len(re.findall(rb"(?<![\w.])(?:B\*?|f\*?)(?![\w])", content))
        pieces = sum(len(g.findall(SVG + "path")) for g in groups)
        check(painted == pieces + 1, f"the PDF paints {painted} paths, the SVG has {pieces} pieces + background")
    else:
        check(r.returncode == 3 and "cairo" in r.stderr, f"pdf without cairo: {r.returncode} {r.stderr.strip()}")

    # Bad input: exit status 2 and one line naming the problem.
    bad = run([shadow, "render", scene, "-o", os.path.join(work, "bad.svg"), "--light", "9"])
    check(bad.returncode == 2 and "--light" in bad.stderr and bad.stderr.count("\n") == 1,
          f"--light 9: {bad.returncode} {bad.stderr!r}")
    bad = run([shadow, "render", scene, "-o", os.path.join(work, "bad.svg"), "--eye", "1,2,3", "--target", "1,2,3"])
    check(bad.returncode == 2 and "--eye" in bad.stderr and bad.stderr.count("\n") == 1,
          f"eye = target: {bad.returncode} {bad.stderr!r}")
    bad = run([shadow, "render", scene, "-o", os.path.join(work, "bad.png"), "--light", "0"])
    check(bad.returncode == 2 and "--light" in bad.stderr and bad.stderr.count("\n") == 1,
          f"--light with a PNG: {bad.returncode} {bad.stderr!r}")

    # The vector view's cost bound: more faces than --max-faces is refused at once, in one line
    # that names the count and suggests a PNG, and nothing is written; at the bound it is drawn.
    faces = len(face_ids)  # at least the faces seen above
    bounded = os.path.join(work, "bounded.svg")
    if os.path.exists(bounded):
        os.remove(bounded)
    bad = run([shadow, "render", scene, "-o", bounded, "--max-faces", "10"])
    check(bad.returncode == 2 and "--max-faces" in bad.stderr and "PNG" in bad.stderr
          and "scene.json" in bad.stderr and bad.stderr.count("\n") == 1,
          f"--max-faces 10: {bad.returncode} {bad.stderr!r}")
    check(not os.path.exists(bounded), "--max-faces 10: an SVG was written")
    count = re.search(r"of (\d+) faces", bad.stderr)
    check(count is not None and int(count.group(1)) >= faces, f"--max-faces: no face count in {bad.stderr!r}")
    if count is not None:
        r = run([shadow, "render", scene, "-o", bounded, "--max-faces", count.group(1), "-q",
                 "--width", str(width), "--height", str(height)])
        check(r.returncode == 0 and os.path.exists(bounded), f"--max-faces at the count: {r.returncode} {r.stderr!r}")
    bad = run([shadow, "render", scene, "-o", os.path.join(work, "bad.png"), "--max-faces", "10"])
    check(bad.returncode == 2 and "--max-faces" in bad.stderr and bad.stderr.count("\n") == 1,
          f"--max-faces with a PNG: {bad.returncode} {bad.stderr!r}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
