# SPDX-License-Identifier: GPL-3.0-or-later
"""libshadow.form_factor and libshadow.radiosity (docs/radiosity.md)."""
import math

import libshadow


def _squares(*extra):
    floor = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]
    ceiling = [[0, 0, 1], [0, 1, 1], [1, 1, 1], [1, 0, 1]]
    return libshadow.scene_from_data(meshes=[{"name": "m", "polygons": [floor, ceiling, *extra]}],
                                     lights=[{"name": "sun", "type": "directional", "to_light": [0, 0, 1]}])


def test_form_factor_of_parallel_squares_is_howells():
    f = libshadow.form_factor(_squares(), 0, 1, tolerance=1e-6, threads=1)
    assert abs(f["value"] - 0.1998249) < 1e-6
    assert f["error"] < 1e-6


def test_radiosity_furnace():
    room = [
        [[0, 0, 1], [0, 1, 1], [1, 1, 1], [1, 0, 1]], [[1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 0]],
        [[0, 0, 0], [0, 0, 1], [1, 0, 1], [1, 0, 0]], [[0, 1, 0], [1, 1, 0], [1, 1, 1], [0, 1, 1]],
        [[1, 0, 0], [1, 0, 1], [1, 1, 1], [1, 1, 0]], [[0, 0, 0], [0, 1, 0], [0, 1, 1], [0, 0, 1]],
    ]
    # Fronts inward: flip those whose normal points away from the centre.
    def inward(p):
        n = [0.0, 0.0, 0.0]
        for i in range(len(p)):
            a, b = p[i], p[(i + 1) % len(p)]
            n[0] += (a[1] - b[1]) * (a[2] + b[2])
            n[1] += (a[2] - b[2]) * (a[0] + b[0])
            n[2] += (a[0] - b[0]) * (a[1] + b[1])
        return p if sum(n[k] * (0.5 - p[0][k]) for k in range(3)) > 0 else p[::-1]
    scene = libshadow.scene_from_data(
        meshes=[{"name": "room", "material": "grey", "polygons": [inward(p) for p in room]}],
        materials=[{"name": "grey", "reflectance": 0.5, "emittance": 4}])
    r = libshadow.radiosity(scene, max_element_area=0.25, tolerance=1e-5, threads=2)
    assert r["converged"]
    assert all(abs(b - 8.0) < 8e-3 for b in r["elements"]["radiosity"])
    assert r["elements"]["triangles"].shape == (len(r["elements"]["radiosity"]), 3, 3)
    assert math.isclose(r["emitted_power"] + r["direct_power"],
                        r["absorbed_power"] + r["escaped_power"] + r["unshot_power"], rel_tol=1e-9)
    assert scene.materials[0].reflectance == 0.5 and scene.materials[0].emittance == 4
    # Grey: every channel is the scalar solution.
    assert not r["colour"]
    assert r["elements"]["radiosity_rgb"].shape == (len(r["elements"]["radiosity"]), 3)
    assert all(abs(row[1] - b) < 1e-12 for row, b in zip(r["elements"]["radiosity_rgb"], r["elements"]["radiosity"]))
    # In colour each channel is its own furnace: B_c = E / (1 - rho_c).
    coloured = libshadow.scene_from_data(
        meshes=[{"name": "room", "material": "tinted", "polygons": [inward(p) for p in room]}],
        materials=[{"name": "tinted", "reflectance": [0.25, 0.5, 0.75], "emittance": 4}])
    c = libshadow.radiosity(coloured, max_element_area=0.25, tolerance=1e-5, threads=2)
    assert c["colour"]
    for k, rho in enumerate((0.25, 0.5, 0.75)):
        assert all(abs(row[k] - 4 / (1 - rho)) < 2e-3 * 4 / (1 - rho) for row in c["faces"]["radiosity_rgb"])


def test_hierarchical_radiosity_agrees_with_shooting():
    # A floor under the sun and a box on it: the box's faces get the floor's reflected light.
    floor = [[-10, -10, 0], [10, -10, 0], [10, 10, 0], [-10, 10, 0]]
    box = [
        [[-1, -1, 3], [1, -1, 3], [1, 1, 3], [-1, 1, 3]], [[-1, -1, 0], [1, -1, 0], [1, -1, 3], [-1, -1, 3]],
        [[-1, 1, 0], [-1, 1, 3], [1, 1, 3], [1, 1, 0]], [[1, -1, 0], [1, 1, 0], [1, 1, 3], [1, -1, 3]],
        [[-1, -1, 0], [-1, -1, 3], [-1, 1, 3], [-1, 1, 0]],
    ]
    scene = libshadow.scene_from_data(
        meshes=[{"name": "floor", "material": "ground", "polygons": [floor]},
                {"name": "box", "material": "walls", "polygons": box}],
        materials=[{"name": "ground", "reflectance": 0.2}, {"name": "walls", "reflectance": 0.3}],
        lights=[{"name": "sun", "type": "directional", "to_light": [0.4, -0.6, 0.8], "intensity": 800}])
    shooting = libshadow.radiosity(scene, max_element_area=1.0, tolerance=1e-4, threads=2, method="shooting")
    hierarchical = libshadow.radiosity(scene, max_element_area=1.0, tolerance=1e-4, threads=2, method="hierarchical",
                                       link_separation=0.25)
    assert shooting["method"] == "shooting" and hierarchical["method"] == "hierarchical"
    # One light: its share is all of the direct irradiance.
    by_light = shooting["faces"]["direct_irradiance_by_light"]
    assert by_light.shape == (6, 1)
    assert all(abs(by_light[f][0] - shooting["faces"]["direct_irradiance"][f]) < 1e-12 for f in range(6))
    assert hierarchical["near_links"] > 0 and hierarchical["iterations"] > 0
    # Face 1, the roof, sees nothing above it; the four walls see the floor.
    assert shooting["faces"]["irradiance"][1] == shooting["faces"]["direct_irradiance"][1]
    for face in range(2, 6):
        a = shooting["faces"]["irradiance"][face] - shooting["faces"]["direct_irradiance"][face]
        b = hierarchical["faces"]["irradiance"][face] - hierarchical["faces"]["direct_irradiance"][face]
        assert a > 0 and abs(a - b) < 0.03 * a, (face, a, b)
    try:
        libshadow.radiosity(scene, method="fast")
    except ValueError as e:
        assert "method" in str(e)
    else:
        raise AssertionError("an unknown method must be a ValueError")
