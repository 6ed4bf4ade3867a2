#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The layering check (docs/architecture.md): dependencies between libshadow's folders run one way.

    sunmap -> engine -> planes -> exact -> core -> geometry  (sunmap also -> exact, core, geometry)
    engine -> arealight -> exact, core, geometry
    views -> engine, exact, core, geometry  (as sunmap)
    engine -> fast -> core -> geometry
    scene -> exact (face shape check only), core, geometry;  output -> arealight, lighting, core, geometry
    lighting -> geometry;  baselines -> core, geometry;  scene -> sun -> geometry

Reads every `#include "folder/..."` in libshadow/src and fails, listing each offending line, when
a folder includes one that the table below does not allow (a folder may always include itself).
Also fails when a public header (libshadow/include) includes a CGAL, VTK, Clipper or Embree header,
or an internal header of libshadow/src. Folders of the table that do not exist yet are fine;
a folder under libshadow/src that is not in the table is an error (add it to the table).

Usage: check_layering.py [REPOSITORY_ROOT]   (default: the repository holding this script)
       check_layering.py --self-test          (the checks against small made-up trees)
Exit status: 0 clean, 1 violations found, 2 usage error.
"""

import os
import re
import sys

# folder -> the folders it may include (besides itself). The engine side of the layout, and why
# each arrow exists, is in docs/architecture.md.
ALLOWED = {
    "engine": {"arealight", "planes", "fast", "exact", "core", "geometry"},
    "arealight": {"exact", "core", "geometry"},
    "sunmap": {"engine", "exact", "core", "geometry"},
    "views": {"engine", "exact", "core", "geometry"},
    "planes": {"exact", "core", "geometry"},
    "exact": {"core", "geometry"},
    "fast": {"core", "geometry"},
    "core": {"geometry"},
    "geometry": set(),
    "scene": {"exact", "core", "geometry", "sun"},
    "sun": {"geometry"},
    "output": {"arealight", "lighting", "core", "geometry"},
    "lighting": {"geometry"},
    "baselines": {"core", "geometry"},
}

# Narrower than a whole folder: (folder, included folder) -> the only headers of it allowed.
# Validation needs exact predicates for a face's shape and nothing else of the exact engine.
ONLY_HEADERS = {
    ("scene", "exact"): {"exact/face_shape.hpp"},
}

# Third-party headers that must stay out of the public API (users never pay for them).
FORBIDDEN_PUBLIC = re.compile(
    r"^(CGAL/|vtk|polyclipping/|clipper|embree\d*/|rtcore)", re.IGNORECASE)

INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]')
SOURCE_SUFFIXES = (".hpp", ".cpp", ".h", ".hh", ".cc", ".cxx", ".hxx", ".inl", ".ipp", ".tpp")


def source_files(root):
    for folder, dirs, files in os.walk(root):
        dirs.sort()
        for name in sorted(files):
            if name.endswith(SOURCE_SUFFIXES):
                yield os.path.join(folder, name)


def includes(path):
    """(line number, '<' or '"', included path) for each #include of `path`."""
    with open(path, encoding="utf-8", errors="replace") as f:
        for number, line in enumerate(f, 1):
            match = INCLUDE.match(line)
            if match:
                yield number, match.group(1), match.group(2)


def check_sources(src, repo):
    problems = []
    folders = {d for d in os.listdir(src) if os.path.isdir(os.path.join(src, d))}
    for folder in sorted(folders - ALLOWED.keys()):
        problems.append(f"libshadow/src/{folder}/: a folder the layering table does not know "
                        f"(add it to ALLOWED in tests/check_layering.py and to docs/architecture.md)")
    for path in source_files(src):
        rel = os.path.relpath(path, src)
        parts = rel.split(os.sep)
        own = parts[0] if len(parts) > 1 else None  # None: a file directly in libshadow/src
        for number, kind, target in includes(path):
            if kind != '"':
                continue
            target_folder = target.split("/")[0] if "/" in target else None
            where = f"{os.path.relpath(path, repo)}:{number}: #include \"{target}\""
            if ".." in target.split("/"):
                problems.append(f"{where}: include libshadow/src headers by folder/name, not by '..'")
                continue
            if target_folder is None or target_folder not in folders | ALLOWED.keys():
                continue  # same-folder header or not one of libshadow's folders
            if own is None or target_folder == own:
                continue
            allowed = ALLOWED.get(own, set())
            if target_folder not in allowed:
                may = ", ".join(sorted(allowed)) or "no other folder"
                problems.append(f"{where}: {own}/ may not include {target_folder}/ ({own}/ may include: {may})")
                continue
            only = ONLY_HEADERS.get((own, target_folder))
            if only is not None and target not in only:
                problems.append(f"{where}: {own}/ may include only {', '.join(sorted(only))} of {target_folder}/")
    return problems


def check_public(include_dir, src, repo):
    problems = []
    internal = {d for d in os.listdir(src) if os.path.isdir(os.path.join(src, d))} | ALLOWED.keys()
    for path in source_files(include_dir):
        for number, kind, target in includes(path):
            where = f"{os.path.relpath(path, repo)}:{number}: #include {kind}{target}{'>' if kind == '<' else kind}"
            if FORBIDDEN_PUBLIC.match(target):
                problems.append(f"{where}: a public header may not include CGAL, VTK, Clipper or Embree")
            elif target.split("/")[0] in internal and "/" in target:
                problems.append(f"{where}: a public header may not include libshadow's internal headers")
    return problems


def self_test():
    """Runs the checks on small made-up trees: a clean one passes, each kind of violation is found."""
    import tempfile

    def tree(files):
        root = tempfile.mkdtemp(prefix="check-layering-")
        for rel, text in files.items():
            path = os.path.join(root, rel)
            os.makedirs(os.path.dirname(path), exist_ok=True)
            with open(path, "w", encoding="utf-8") as f:
                f.write(text)
        return root

    def problems(files):
        root = tree(files)
        src = os.path.join(root, "libshadow", "src")
        return check_sources(src, root) + check_public(os.path.join(root, "libshadow", "include"), src, root)

    clean = {
        "libshadow/include/shadow/scene.hpp": "#include <glm/vec3.hpp>\n#include <vector>\n",
        "libshadow/src/geometry/newell_normal.hpp": "#include <glm/vec3.hpp>\n",
        "libshadow/src/core/culling.hpp": '#include "geometry/newell_normal.hpp"\n',
        "libshadow/src/exact/exact_receiver.cpp": '#include "core/culling.hpp"\n#include "exact/kernel.hpp"\n',
        "libshadow/src/engine/shadow_engine.cpp": '#include "fast/fast_receiver.hpp"\n#include "exact/kernel.hpp"\n',
        "libshadow/src/scene/validate.cpp": '#include "exact/face_shape.hpp"\n',
    }
    failures = []
    if problems(clean):
        failures.append(f"a clean tree was flagged: {problems(clean)}")
    cases = {
        "exact includes fast": ("libshadow/src/exact/x.cpp", '#include "fast/fast_receiver.hpp"\n', "exact/ may not include fast/"),
        "exact includes scene": ("libshadow/src/exact/x.cpp", '  # include "scene/validate.hpp"\n', "exact/ may not include scene/"),
        "scene includes the exact engine": ("libshadow/src/scene/x.cpp", '#include "exact/kernel.hpp"\n', "only exact/face_shape.hpp"),
        "planes includes engine": ("libshadow/src/planes/x.cpp", '#include "engine/e.hpp"\n', "planes/ may not include engine/"),
        "unknown folder": ("libshadow/src/misc/x.cpp", "", "a folder the layering table does not know"),
        "relative include": ("libshadow/src/core/x.cpp", '#include "../exact/kernel.hpp"\n', "not by '..'"),
        "CGAL in a public header": ("libshadow/include/shadow/x.hpp", "#include <CGAL/Epeck.h>\n", "CGAL, VTK"),
        "VTK in a public header": ("libshadow/include/shadow/x.hpp", "#include <vtkPolyData.h>\n", "CGAL, VTK"),
        "Clipper in a public header": ("libshadow/include/shadow/x.hpp", "#include <polyclipping/clipper.hpp>\n", "CGAL, VTK"),
        "Embree in a public header": ("libshadow/include/shadow/x.hpp", "#include <embree3/rtcore.h>\n", "CGAL, VTK"),
        "internal header in a public one": ("libshadow/include/shadow/x.hpp", '#include "core/culling.hpp"\n', "internal headers"),
    }
    for name, (rel, text, expected) in cases.items():
        found = problems({**clean, rel: text})
        if len(found) != 1 or expected not in found[0]:
            failures.append(f"{name}: expected one problem with '{expected}', got {found}")
    for f in failures:
        print("check_layering self-test: FAIL " + f)
    if not failures:
        print(f"check_layering self-test: ok (a clean tree passes, {len(cases)} kinds of violation found)")
    return 1 if failures else 0


def main(argv):
    if argv[1:] == ["--self-test"]:
        return self_test()
    if len(argv) > 2:
        print("usage: check_layering.py [REPOSITORY_ROOT] | --self-test", file=sys.stderr)
        return 2
    repo = os.path.abspath(argv[1] if len(argv) == 2 else os.path.join(os.path.dirname(__file__), ".."))
    src = os.path.join(repo, "libshadow", "src")
    include_dir = os.path.join(repo, "libshadow", "include")
    for d in (src, include_dir):
        if not os.path.isdir(d):
            print(f"check_layering: {d}: no such directory (give the repository root)", file=sys.stderr)
            return 2
    problems = check_sources(src, repo) + check_public(include_dir, src, repo)
    if problems:
        print(f"check_layering: {len(problems)} layering violation(s):")
        for p in problems:
            print("  " + p)
        return 1
    print("check_layering: ok (every include follows the layering table; public headers are "
          "free of CGAL, VTK, Clipper and Embree)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
