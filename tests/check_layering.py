#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The layering check (docs/architecture.md): libshadow's components and the folders inside them
depend on each other one way.

Components (libshadow/<component>/, each its own CMake target with its own private include path):

    render, baselines, testing  ->  io  ->  compute

compute never includes VTK, nlohmann_json, or a header of io, render, baselines or testing; io
never includes render's. Inside compute, the stages:

    sunmap, views -> engine -> planes, arealight, fast -> exact -> core -> geometry
    every folder -> runtime (the scheduler and its threads), common (errors, numbers in messages)
    radiosity -> arealight, core, geometry  (form factors through the extended-light machinery)
    validation -> exact (face shape only), core, geometry;  lighting, sun -> geometry

and in io:  writers -> readers -> compute's validation, exact (face shape only), core, geometry, sun;
writers also -> lighting; jobs (the series job) -> nothing internal but itself. render -> compute's
geometry, io's writers/vtk_errors.hpp.

Reads every #include under libshadow/ and fails, listing each offending line, when a folder
includes one that the tables below do not allow (a folder may always include itself), when a
compute source includes a forbidden library or another component's header, or when a public
header (any libshadow/*/include or libshadow/include) includes CGAL, VTK, Clipper, Embree or an
internal header. A folder the tables do not know is an error (add it to the table).

Usage: check_layering.py [REPOSITORY_ROOT]   (default: the repository holding this script)
       check_layering.py --self-test          (the checks against small made-up trees)
Exit status: 0 clean, 1 violations found, 2 usage error.
"""

import os
import re
import sys

# component -> folder -> the folders it may include with "folder/name.hpp" (besides itself).
# A component whose sources sit flat in src/ is listed under the folder "" (render, baselines,
# testing); they reach compute's internal headers through libshadow::compute_internal.
COMPUTE = {
    "engine": {"arealight", "planes", "fast", "exact", "core", "geometry"},
    "arealight": {"exact", "core", "geometry"},
    "sunmap": {"engine", "exact", "core", "geometry"},
    "views": {"engine", "exact", "core", "geometry"},
    "radiosity": {"arealight", "core", "geometry"},
    "planes": {"exact", "core", "geometry"},
    "exact": {"core", "geometry"},
    "fast": {"core", "geometry"},
    "core": {"geometry"},
    "geometry": set(),
    "runtime": set(),
    "validation": {"exact", "core", "geometry"},
    "scene": {"core", "geometry"},
    "sun": {"geometry"},
    "lighting": {"geometry"},
    "common": set(),
    "irradiance": {"geometry"},
}
ALLOWED = {
    "compute": COMPUTE,
    "io": {
        "readers": {"validation", "exact", "core", "geometry", "sun"},
        "writers": {"readers", "lighting", "core", "geometry"},
        "jobs": set(),  # the series job: public headers only
    },
    "render": {"": {"geometry", "writers"}},
    "baselines": {"": {"core", "geometry"}},
    "testing": {"": set()},
}

# The thread runtime (runtime/: the scheduler, its pool of threads, the library's pthread_once) and
# common/ (errors, numbers in messages) are below every stage: any folder of any component may
# include them, and they include no other folder.
BASE_FOLDERS = {"runtime", "common"}

# Narrower than a whole folder: (folder, included folder) -> the only headers of it allowed.
# Validation and the readers need exact predicates for a face's shape and nothing else of the
# exact engine.
ONLY_HEADERS = {
    ("validation", "exact"): {"exact/face_shape.hpp"},
    ("readers", "exact"): {"exact/face_shape.hpp"},
    ("", "writers"): {"writers/vtk_errors.hpp"},  # render: VTK's errors as one line, from io
}

# Third-party headers that must stay out of every public header (users never pay for them).
FORBIDDEN_PUBLIC = re.compile(r"^(CGAL/|vtk|polyclipping/|clipper|embree\d*/|rtcore)", re.IGNORECASE)
# Libraries the compute component never includes: file formats belong to io.
FORBIDDEN_COMPUTE = re.compile(r"^(vtk|nlohmann/|cairo|embree\d*/)", re.IGNORECASE)

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


def public_headers(lib, component):
    """The names (`shadow/x.hpp`) of a component's public headers."""
    root = os.path.join(lib, component, "include")
    if not os.path.isdir(root):
        return set()
    return {os.path.relpath(p, root).replace(os.sep, "/") for p in source_files(root)}


def internal_folders():
    folders = set()
    for table in ALLOWED.values():
        for own, allowed in table.items():
            folders |= {own} | allowed
    return folders - {""}


def check_component_sources(lib, repo, component, table, other_public):
    """Quoted includes between folders; for compute also the forbidden libraries and headers."""
    problems = []
    src = os.path.join(lib, component, "src")
    if not os.path.isdir(src):
        return problems
    flat = "" in table
    folders = {d for d in os.listdir(src) if os.path.isdir(os.path.join(src, d))}
    if not flat:
        for folder in sorted(folders - table.keys()):
            problems.append(f"libshadow/{component}/src/{folder}/: a folder the layering table does not know "
                            f"(add it to ALLOWED in tests/check_layering.py and to docs/architecture.md)")
    known = internal_folders() | folders
    for path in source_files(src):
        rel = os.path.relpath(path, src)
        parts = rel.split(os.sep)
        own = "" if flat else (parts[0] if len(parts) > 1 else None)
        for number, kind, target in includes(path):
            where = f"{os.path.relpath(path, repo)}:{number}: #include {kind}{target}{'>' if kind == '<' else kind}"
            if component == "compute" and FORBIDDEN_COMPUTE.match(target):
                problems.append(f"{where}: compute may not include VTK, nlohmann_json, cairo or Embree "
                                f"(file formats belong to io)")
                continue
            if kind == "<":
                if target in other_public:
                    problems.append(f"{where}: {component} may not include {other_public[target]}'s header")
                continue
            target_folder = target.split("/")[0] if "/" in target else None
            if ".." in target.split("/"):
                problems.append(f"{where}: include libshadow's internal headers by folder/name, not by '..'")
                continue
            if target_folder is None or target_folder not in known:
                continue  # same-folder header or not one of libshadow's folders
            if own is None:
                problems.append(f"{where}: a file directly in libshadow/{component}/src (put it in a folder)")
                continue
            if target_folder == own or (target_folder in BASE_FOLDERS and own not in BASE_FOLDERS):
                continue
            allowed = table.get(own, set())
            if target_folder not in allowed:
                may = ", ".join(sorted(allowed)) or "no other folder"
                name = f"{component}/{own}/" if own else f"{component}"
                problems.append(f"{where}: {name} may not include {target_folder}/ ({name} may include: {may})")
                continue
            only = ONLY_HEADERS.get((own, target_folder))
            if only is not None and target not in only:
                problems.append(f"{where}: {own}/ may include only {', '.join(sorted(only))} of {target_folder}/")
    return problems


# component -> the components whose public headers it may not include.
NOT_ABOVE = {
    "compute": ("io", "render", "baselines", "testing"),
    "io": ("render", "baselines", "testing"),
}


def check_tree(repo):
    lib = os.path.join(repo, "libshadow")
    problems = []
    for d in sorted(os.listdir(lib)):
        if os.path.isdir(os.path.join(lib, d)) and d not in ALLOWED and d != "include":
            problems.append(f"libshadow/{d}/: a component the layering table does not know "
                            f"(add it to ALLOWED in tests/check_layering.py and to docs/architecture.md)")
    for component, table in ALLOWED.items():
        other_public = {}
        for above in NOT_ABOVE.get(component, ()):
            for header in public_headers(lib, above):
                other_public[header] = above
        problems += check_component_sources(lib, repo, component, table, other_public)
        # The component's public headers: no third-party heavyweights, no internals, no headers of
        # the components above it.
        include_dir = os.path.join(lib, component, "include")
        if os.path.isdir(include_dir):
            problems += check_public(include_dir, repo, other_public, component)
    if os.path.isdir(os.path.join(lib, "include")):
        problems += check_public(os.path.join(lib, "include"), repo, {}, "umbrella")
    return problems


def check_public(include_dir, repo, other_public, component):
    problems = []
    internal = internal_folders()
    for path in source_files(include_dir):
        for number, kind, target in includes(path):
            where = f"{os.path.relpath(path, repo)}:{number}: #include {kind}{target}{'>' if kind == '<' else kind}"
            if FORBIDDEN_PUBLIC.match(target):
                problems.append(f"{where}: a public header may not include CGAL, VTK, Clipper or Embree")
            elif component == "compute" and FORBIDDEN_COMPUTE.match(target):
                problems.append(f"{where}: compute may not include VTK, nlohmann_json, cairo or Embree")
            elif target in other_public:
                problems.append(f"{where}: {component} may not include {other_public[target]}'s header")
            elif target.split("/")[0] in internal and "/" in target:
                problems.append(f"{where}: a public header may not include libshadow's internal headers")
    return problems


def self_test():
    """Runs the checks on small made-up trees: a clean one passes, each kind of violation is found."""
    import tempfile

    def problems(files):
        with tempfile.TemporaryDirectory(prefix="check-layering-") as root:
            for rel, text in files.items():
                path = os.path.join(root, rel)
                os.makedirs(os.path.dirname(path), exist_ok=True)
                with open(path, "w", encoding="utf-8") as f:
                    f.write(text)
            return check_tree(root)

    clean = {
        "libshadow/include/shadow/shadow.hpp": "#include <shadow/scene.hpp>\n#include <shadow/output.hpp>\n",
        "libshadow/compute/include/shadow/scene.hpp": "#include <glm/vec3.hpp>\n#include <vector>\n",
        "libshadow/compute/src/geometry/newell_normal.hpp": "#include <glm/vec3.hpp>\n",
        "libshadow/compute/src/core/culling.hpp": '#include "geometry/newell_normal.hpp"\n',
        "libshadow/compute/src/exact/exact_receiver.cpp": '#include "core/culling.hpp"\n#include "exact/kernel.hpp"\n',
        "libshadow/compute/src/engine/shadow_engine.cpp": '#include "fast/fast_receiver.hpp"\n#include <shadow/scene.hpp>\n',
        "libshadow/compute/src/validation/validate.cpp": '#include "exact/face_shape.hpp"\n',
        "libshadow/io/include/shadow/output.hpp": "#include <shadow/scene.hpp>\n",
        "libshadow/io/src/readers/scene_json.cpp": '#include <nlohmann/json.hpp>\n#include "core/culling.hpp"\n',
        "libshadow/io/src/writers/vtp.cpp": '#include <vtkPolyData.h>\n#include "readers/scene_json.hpp"\n',
        "libshadow/render/src/camera.cpp": '#include "geometry/newell_normal.hpp"\n#include <shadow/output.hpp>\n',
    }
    failures = []
    if problems(clean):
        failures.append(f"a clean tree was flagged: {problems(clean)}")
    C = "libshadow/compute/src/"
    cases = {
        "exact includes fast": (C + "exact/x.cpp", '#include "fast/fast_receiver.hpp"\n', "may not include fast/"),
        "exact includes validation": (C + "exact/x.cpp", '  # include "validation/validate.hpp"\n', "may not include validation/"),
        "validation includes the exact engine": (C + "validation/x.cpp", '#include "exact/kernel.hpp"\n', "only exact/face_shape.hpp"),
        "planes includes engine": (C + "planes/x.cpp", '#include "engine/e.hpp"\n', "may not include engine/"),
        "compute includes a reader": (C + "core/x.cpp", '#include "readers/scene_json.hpp"\n', "may not include readers/"),
        "compute includes VTK": (C + "core/x.cpp", "#include <vtkPolyData.h>\n", "compute may not include VTK"),
        "compute includes nlohmann": (C + "sun/x.cpp", "#include <nlohmann/json.hpp>\n", "compute may not include VTK"),
        "compute includes nlohmann by quotes": (C + "sun/x.cpp", '#include "nlohmann/json.hpp"\n', "compute may not include VTK"),
        "compute includes an io header": (C + "engine/x.cpp", "#include <shadow/output.hpp>\n", "may not include io's header"),
        "compute public header includes io": ("libshadow/compute/include/shadow/x.hpp", "#include <shadow/output.hpp>\n",
                                              "may not include io's header"),
        "readers include writers": ("libshadow/io/src/readers/x.cpp", '#include "writers/vtp.hpp"\n', "may not include writers/"),
        "unknown folder": (C + "misc/x.cpp", "", "a folder the layering table does not know"),
        "unknown component": ("libshadow/extra/src/x.cpp", "", "a component the layering table does not know"),
        "relative include": (C + "core/x.cpp", '#include "../exact/kernel.hpp"\n', "not by '..'"),
        "CGAL in a public header": ("libshadow/io/include/shadow/x.hpp", "#include <CGAL/Epeck.h>\n", "CGAL, VTK"),
        "VTK in a public header": ("libshadow/include/shadow/x.hpp", "#include <vtkPolyData.h>\n", "CGAL, VTK"),
        "Clipper in a public header": ("libshadow/compute/include/shadow/x.hpp", "#include <polyclipping/clipper.hpp>\n", "CGAL, VTK"),
        "Embree in a public header": ("libshadow/compute/include/shadow/x.hpp", "#include <embree3/rtcore.h>\n", "CGAL, VTK"),
        "internal header in a public one": ("libshadow/io/include/shadow/x.hpp", '#include "core/culling.hpp"\n', "internal headers"),
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
    if not os.path.isdir(os.path.join(repo, "libshadow", "compute")):
        print(f"check_layering: {repo}/libshadow/compute: no such directory (give the repository root)",
              file=sys.stderr)
        return 2
    problems = check_tree(repo)
    if problems:
        print(f"check_layering: {len(problems)} layering violation(s):")
        for p in problems:
            print("  " + p)
        return 1
    print("check_layering: ok (components and folders include one way; compute is free of VTK and "
          "JSON; public headers are free of CGAL, VTK, Clipper and Embree)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
