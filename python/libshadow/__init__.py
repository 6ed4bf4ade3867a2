# SPDX-License-Identifier: GPL-3.0-or-later
"""libshadow: exact object-space shadows, from Python.

Load a scene (``load_scene``) or build one from Python data (``scene_from_data``), compute
(``compute_shadows`` or ``ShadowEngine(scene).compute()``) and read the per-face results as numpy
arrays named as in the C++ structs (``result.face_id``, ``result.lit_area``, ...). Bad input
raises ``InputError``, a ``ValueError`` whose message is the CLI's one line ``FILE: PLACE: PROBLEM``.
See docs/python.md.
"""

import json as _json
import math as _math
import os as _os

import numpy as _np

from ._libshadow import (  # noqa: F401  (the public API)
    InputError,
    Light,
    Material,
    Mesh,
    NamedSurface,
    OutputError,
    Plane,
    PlaneShadow,
    Scene,
    SceneObject,
    Weather,
    SeriesResult,
    ShadowEngine,
    ShadowResult,
    SolarSite,
    SunHoursInstant,
    SunHoursMap,
    SunInstant,
    SunPeriod,
    SunPosition,
    SunSeries,
    __version__,
    add_sun_lights,
    check_sun_period,
    compute_plane_shadows,
    compute_shadows,
    compute_sun_hours_map,
    energyplus_shading_csv,
    expand_sun_period,
    form_factor,
    format_iso8601_utc,
    hours_per_instant,
    load_scene,
    make_city,
    parse_iso8601,
    parse_scene,
    parse_utc_offset,
    read_epw,
    read_tmy3,
    read_weather,
    radiosity,
    replace_sun_lights,
    solar_position,
    sun_hours_instants,
    sun_hours_map_faces,
    sun_light_name,
    sun_series,
    sun_to_light,
    sunlit_csv,
    write_outputs,
    write_series,
    write_sun_hours_levels_vtp,
    write_sun_hours_vtp,
)
from . import _libshadow

__all__ = [
    "InputError", "OutputError", "Light", "Material", "Mesh", "NamedSurface", "Plane", "PlaneShadow",
    "Scene", "ShadowEngine", "ShadowResult", "SolarSite", "SunHoursInstant", "SunHoursMap", "SunInstant", "SunPeriod", "SunPosition",
    "add_sun_lights", "check_sun_period", "compute_plane_shadows", "compute_shadows", "expand_sun_period", "format_iso8601_utc",
    "load_scene", "make_city", "parse_iso8601", "parse_scene", "parse_utc_offset", "replace_sun_lights", "solar_position",
    "solar_positions", "sun_hours", "sun_light_name", "sun_to_light", "write_outputs",
    "compute_sun_hours_map", "sun_hours_instants", "sun_hours_map_faces", "write_sun_hours_vtp",
    "write_sun_hours_levels_vtp",
    "SeriesResult", "SunSeries", "sun_series", "hours_per_instant", "sun_hours_error_bound", "surface_series",
    "sunlit_csv", "energyplus_shading_csv", "write_series",
    "SceneObject", "object_sun_hours", "sun_hours_by_object_csv", "unique_face_labels", "site_timezone",
    "scene_from_data", "scene_to_dict", "fragments", "__version__",
    "Weather", "read_epw", "read_tmy3", "read_weather", "irradiance", "IrradianceResult", "form_factor", "radiosity",
]


# ---- scenes from Python data ---------------------------------------------------------------------

def _plain(value, place, problems):
    """`value` as JSON-ready Python data: numpy arrays and scalars become lists and floats (exactly:
    float64 -> float is the identity, and json writes the shortest text that reads back to the same
    double). A non-finite number cannot be written to JSON: its place is remembered instead."""
    if isinstance(value, _np.ndarray):
        if value.dtype.kind == "O":  # ragged or mixed: element by element
            return _plain(value.tolist(), place, problems)
        if value.dtype.kind == "f" and not _np.isfinite(value).all():
            bad = tuple(int(i) for i in _np.argwhere(~_np.isfinite(value))[0])
            problems.append(place + "".join("[%d]" % i for i in bad))
        return value.tolist()
    if isinstance(value, _np.generic):
        value = value.item()
    if isinstance(value, float):
        if not _math.isfinite(value):
            problems.append(place)
        return value
    if isinstance(value, dict):
        return {str(k): _plain(v, place + "." + str(k) if place else str(k), problems) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v, "%s[%d]" % (place, i), problems) for i, v in enumerate(value)]
    if hasattr(value, "isoformat"):  # datetime: ISO 8601 text, with its offset when it has one
        return value.isoformat()
    return value


def scene_from_data(meshes, lights=None, planes=None, receivers=None, materials=None, sun=None,
                    camera=None, name="<python>", base_dir=None, planarity_tolerance=1e-6,
                    sun_hours_map=None, orient_outward=False, cityjson_lod="", skip_invalid=False,
                    require_lights=True):
    """A validated Scene from Python data laid out like the scene file (docs/scene-format.md).

    meshes: a list of dicts ``{"name": ..., "polygons": ...}`` (or ``"file"``: an OBJ path, relative to
    ``base_dir``, OBJ, CityJSON or EnergyPlus; ``"material"``, ``"transform"``, ``"up_axis"``,
    ``"orient"``), or a dict ``{name: polygons}``. Polygons are a list of (n, 3) sequences or numpy
    arrays, or of dicts ``{"vertices", "name", "kind", "holes"}``, or one (faces, n, 3) array.
    lights: dicts ``{"name", "type": "directional"|"point", "to_light"|"position", "intensity", "color"}``
    or ``Light`` objects. planes: dicts ``{"name", "point", "normal", "window"}``. receivers: mesh
    names. materials, camera: as in the file. sun: the sun block as a dict (times may be aware
    datetimes) or a ``SunPeriod``. sun_hours_map: names of the meshes that get the exact
    sun-hours map. receivers and sun_hours_map also take ``"<mesh>/<id>"`` and ``"type:<T>"`` (a
    CityJSON object type). skip_invalid: leave out faces that fail validation (``Scene.skipped_faces``).
    require_lights=False: a scene without lights is accepted (for ``irradiance()``, whose suns come
    from the weather).

    The scene is read and validated by the same code as a scene file, so it is the same scene bit
    for bit, and errors are the CLI's: ``InputError`` naming ``name`` and the place (``meshes[0].polygons[2]``).
    """
    document = {"meshes": _meshes_data(meshes)}
    if lights is not None:
        document["lights"] = [_light_data(l) for l in lights]
    elif sun is None and require_lights:
        document["lights"] = []
    if planes is not None:
        document["planes"] = list(planes)
    if receivers is not None:
        document["receivers"] = list(receivers)
    if materials is not None:
        document["materials"] = list(materials)
    if sun is not None:
        document["sun"] = _sun_data(sun)
    if camera is not None:
        document["camera"] = camera
    if sun_hours_map is not None:
        document["sun_hours_map"] = list(sun_hours_map)
    problems = []
    document = _plain(document, "", problems)
    if problems:
        raise InputError("%s: %s: number is not finite" % (name, problems[0]))
    text = _json.dumps(document, allow_nan=False)
    # Mesh files are found relative to the directory of the name given to the parser; errors
    # name it as given (no directory unless base_dir asks for one).
    source = name if base_dir is None else _os.path.join(str(base_dir), name)
    return parse_scene(text, source, planarity_tolerance, orient_outward, cityjson_lod, skip_invalid,
                       require_lights)


def _meshes_data(meshes):
    if isinstance(meshes, dict):
        return [{"name": k, "polygons": _polygons_data(v)} for k, v in meshes.items()]
    out = []
    for m in meshes:
        if isinstance(m, dict):
            m = dict(m)
            if "polygons" in m:
                m["polygons"] = _polygons_data(m["polygons"])
            out.append(m)
        else:
            out.append(m)
    return out


def _polygons_data(polygons):
    if isinstance(polygons, _np.ndarray):
        return polygons  # (faces, n, 3): _plain turns it into lists
    return [p for p in polygons]


def _light_data(light):
    if isinstance(light, Light):
        d = {"name": light.name, "type": light.type}
        if light.type == "directional":
            d["to_light"] = light.to_light
        else:
            d["position"] = light.position
        d["intensity"] = light.intensity
        d["color"] = light.color
        return d
    return light


def _sun_data(sun):
    if isinstance(sun, SunPeriod):
        d = {"latitude": sun.site.latitude, "longitude": sun.site.longitude, "elevation": sun.site.elevation,
             "pressure": sun.site.pressure, "temperature": sun.site.temperature,
             "north_axis": sun.north_axis, "min_elevation": sun.min_elevation, "delta_t": sun.delta_t,
             "utc_offset": sun.utc_offset_hours}
        if sun.times:
            d["times"] = [format_iso8601_utc(t) for t in sun.times]
        else:
            d.update({"start": sun.start, "end": sun.end, "step_minutes": sun.step_minutes,
                      "energyplus_times": sun.energyplus_times})
        return d
    return sun


def scene_to_dict(scene):
    """The scene as Python data in the layout scene_from_data takes (inline polygons as numpy arrays;
    faces are those after validation, consecutive duplicate vertices removed, with their names and
    kinds; the camera and a CityJSON model's origin, which do not change the shadows, are left out)."""
    if not isinstance(scene, Scene):
        raise TypeError("scene_to_dict: expected a libshadow.Scene, got %s" % type(scene).__name__)
    meshes = []
    faces = scene.faces
    names, kinds = scene.face_name, scene.face_kind
    for m in scene.meshes:
        polygons = []
        for f in range(m.first_face, m.first_face + m.face_count):
            if names[f] or kinds[f]:  # a named surface: the object form keeps its name and kind
                p = {"vertices": faces[f]}
                if names[f]:
                    p["name"] = names[f]
                if kinds[f]:
                    p["kind"] = kinds[f]
                polygons.append(p)
            else:
                polygons.append(faces[f])
        d = {"name": m.name, "polygons": polygons}
        if m.material:
            d["material"] = m.material
        if m.orient_outward:
            d["orient"] = "outward"
        meshes.append(d)
    sun_lights = {i.light_id for i in scene.sun_instants if i.light_id is not None}
    lights = []
    for i, l in enumerate(scene.lights):
        if i in sun_lights:
            continue
        lights.append(_light_data(l))
    out = {"meshes": meshes, "lights": lights,
           "planes": [{"name": p.name, "point": p.point, "normal": p.normal,
                       **({"window": p.window} if p.window > 0 else {})} for p in scene.planes]}
    if scene.materials:
        out["materials"] = [{"name": x.name, "k_a": x.k_a, "k_d": x.k_d, "k_s": x.k_s, "shininess": x.shininess,
                             "color": x.color, "specular_color": x.specular_color} for x in scene.materials]
    if not all(m.receiver for m in scene.meshes):
        out["receivers"] = [m.name for m in scene.meshes if m.receiver]
    if scene.sun is not None:
        out["sun"] = _sun_data(scene.sun)
    if scene.sun_hours_map:
        out["sun_hours_map"] = [scene.meshes[i].name for i in scene.sun_hours_map]
    return out


# ---- results -----------------------------------------------------------------------------------

class Fragments:
    """The lit and shadowed polygons of a result, one entry per simple polygon, ordered by face,
    light and fragment_id: arrays ``face_id``, ``light_id``, ``fragment_id``, ``lit``, ``area`` and
    ``polygons`` (a list of (n, 3) float64 arrays, oriented like their faces)."""

    def __init__(self, result):
        self.face_id = result.fragment_face_id
        self.light_id = result.fragment_light_id
        self.fragment_id = result.fragment_id
        self.lit = result.fragment_lit
        self.area = result.fragment_area
        self.polygons = result.fragment_polygons

    def __len__(self):
        return len(self.face_id)

    def __repr__(self):
        return "<libshadow.Fragments: %d polygons>" % len(self)


def fragments(result):
    """result.fragments: the result's Fragments."""
    return Fragments(result)


_COLUMNS = ("face_id", "light_id", "area", "lit_area", "shadow_area", "lit_fraction", "faces_light",
            "lit_area_error_bound", "dropped_area", "fully_lit_area", "penumbra_area", "umbra_area")


def _to_pandas(result):
    """The per-(face, light) arrays as a pandas DataFrame, with the face's label and mesh and the
    light's name (and, for sun lights, its UTC time). Needs pandas (not a dependency of libshadow)."""
    try:
        import pandas as pd
    except ImportError as e:  # optional: say what to install
        raise ImportError("to_pandas() needs pandas (Debian: python3-pandas)") from e
    scene = result.scene
    data = {c: getattr(result, c) for c in _COLUMNS}
    face_id = data["face_id"]
    light_id = data["light_id"]
    meshes = [m.name for m in scene.meshes]
    face_mesh = scene.face_mesh
    data["face"] = [scene.face_label(int(f)) for f in face_id]
    data["mesh"] = [meshes[face_mesh[int(f)]] for f in face_id]
    names = [l.name for l in scene.lights]
    # A light given to ShadowEngine.compute_light need not be the scene's: named like report.json.
    data["light"] = [names[int(l)] if int(l) < len(names) else "light%d" % int(l) for l in light_id]
    if scene.sun_instants:
        time_of = {i.light_id: i.time for i in scene.sun_instants if i.light_id is not None}
        data["time"] = pd.to_datetime([time_of.get(int(l), None) for l in light_id], unit="s", utc=True)
    return pd.DataFrame(data)


def unique_face_labels(scene, face_ids):
    """Unique column names for faces: each face's label (``scene.face_label``: its name, or
    ``face_<id>``), and where several of the given faces share one (the pieces of one surface: a
    wall cut around its window and door, a CityJSON surface with a hole) ``<label>#1``,
    ``<label>#2``, ... in face order. A name that would still collide gets another ``#k``."""
    labels = [scene.face_label(int(f)) for f in face_ids]
    count = {}
    for label in labels:
        count[label] = count.get(label, 0) + 1
    taken = {label for label in labels if count[label] == 1}
    seen, out = {}, []
    for label in labels:
        if count[label] == 1:
            out.append(label)
            continue
        k = seen.get(label, 0)
        while True:
            k += 1
            name = "%s#%d" % (label, k)
            if name not in taken:
                break
        seen[label] = k
        taken.add(name)
        out.append(name)
    return out


def site_timezone(scene):
    """The fixed UTC offset of the scene's sun block (``utc_offset``, local standard time) as a
    ``datetime.timezone``: ``series.to_pandas().tz_convert(libshadow.site_timezone(scene))`` shows
    the UTC index in the site's local standard time. Raises ValueError when the scene has no sun."""
    import datetime
    period = scene.sun if isinstance(scene, Scene) else scene
    if period is None:
        raise ValueError("site_timezone: the scene has no sun block")
    offset = datetime.timedelta(hours=period.utc_offset_hours)
    minutes = int(round(period.utc_offset_hours * 60))
    sign = "+" if minutes >= 0 else "-"
    return datetime.timezone(offset, "UTC%s%02d:%02d" % (sign, abs(minutes) // 60, abs(minutes) % 60))


def _row_groups(series, by):
    """(labels, [row indices]) of a SeriesResult's rows grouped by mesh or by object."""
    scene = series.scene
    face_mesh = scene.face_mesh
    row_mesh = face_mesh[series.face_id.astype(_np.int64)] if len(series.face_id) else _np.zeros(0, dtype=_np.int64)
    objects = scene.objects(True, by == "mesh")
    labels, rows = [], []
    for o in objects:
        r = _np.flatnonzero(_np.isin(row_mesh, o.meshes))
        if len(r):
            labels.append(o.id)
            rows.append(r)
    return labels, rows


_SERIES_VALUES = ("lit_fraction", "lit_area", "lit_area_error_bound")
_SERIES_BY = ("face", "surface", "object", "mesh")


def _series_to_pandas(series, values="lit_fraction", by="face"):
    """A SeriesResult as a DataFrame: one row per instant, indexed by UTC time (tz-aware, named
    ``time``) for the scene's suns (by instant number otherwise); one column per

    - ``by="face"``: receiving face, named by ``unique_face_labels`` (the face's label, with
      ``#1``, ``#2``, ... for faces split from one surface);
    - ``by="surface"``: named surface (sunlit.csv's columns; faces sharing a name add up);
    - ``by="object"``: object (a CityJSON building with its parts, an EnergyPlus zone, any other
      mesh: sun_hours_by_object.csv's rows);
    - ``by="mesh"``: receiving mesh.

    ``values``: ``lit_fraction`` (of a group: its lit area over its area; a surface's as in
    sunlit.csv), ``lit_area`` (m2, summed over a group) or ``lit_area_error_bound`` (summed).
    Local time: ``df.tz_convert(libshadow.site_timezone(series.scene))``."""
    try:
        import pandas as pd
    except ImportError as e:
        raise ImportError("to_pandas() needs pandas (Debian: python3-pandas)") from e
    if values not in _SERIES_VALUES:
        raise ValueError("to_pandas: values must be one of %s, got %r" % (", ".join(_SERIES_VALUES), values))
    if by not in _SERIES_BY:
        raise ValueError("to_pandas: by must be one of %s, got %r" % (", ".join(_SERIES_BY), by))
    scene = series.scene
    if len(series.times) == series.instants:
        index = pd.DatetimeIndex(pd.to_datetime(_np.asarray(series.times, dtype=_np.int64), unit="s", utc=True),
                                 name="time")
    else:
        index = pd.RangeIndex(series.instants, name="instant")
    if by == "face":
        columns = unique_face_labels(scene, series.face_id)
        return pd.DataFrame(getattr(series, values).T, index=index, columns=columns)
    if by == "surface":
        weight = _libshadow.hours_per_instant(scene.sun) if scene.sun is not None else 1.0
        table = _libshadow._surface_series(series, weight)
        labels = table["labels"]
        if values == "lit_fraction":
            return pd.DataFrame(table["lit_fraction"].T, index=index, columns=labels)
        row_of = {int(f): r for r, f in enumerate(series.face_id)}
        rows = [[row_of[f] for f in s.faces if f in row_of] for s in table["surfaces"]]
    else:
        labels, rows = _row_groups(series, by)
    if values == "lit_fraction":
        lit, area = series.lit_area, series.area
        data = _np.zeros((len(rows), series.instants))
        for i, r in enumerate(rows):
            a = area[r].sum()
            if a > 0:
                data[i] = _np.minimum(1.0, lit[r].sum(axis=0) / a)
    else:
        table = getattr(series, values)
        data = _np.array([table[r].sum(axis=0) for r in rows]).reshape(len(rows), series.instants)
    return pd.DataFrame(data.T, index=index, columns=labels)


ShadowResult.fragments = property(fragments, doc=Fragments.__doc__)
ShadowResult.to_pandas = _to_pandas
SeriesResult.to_pandas = _series_to_pandas


# ---- the sun -------------------------------------------------------------------------------------

def solar_positions(site, times, north_axis=0.0, delta_t=69.0):
    """solar_position for many times (UTC seconds, ISO 8601 strings or aware datetimes): a dict of
    numpy arrays ``zenith``, ``elevation``, ``azimuth`` (degrees) and ``to_light`` (n, 3)."""
    positions = [solar_position(site, t, north_axis, delta_t) for t in times]
    return {
        "zenith": _np.array([p.zenith for p in positions], dtype=float),
        "elevation": _np.array([p.elevation for p in positions], dtype=float),
        "azimuth": _np.array([p.azimuth for p in positions], dtype=float),
        "to_light": _np.array([p.to_light for p in positions], dtype=float).reshape(-1, 3),
    }


def _hours_weight(weight):
    """hours_per_instant as given: a finite number >= 0 (a negative or NaN weight made negative or
    NaN sun hours); TypeError for what is not a number."""
    if isinstance(weight, (bool, _np.bool_)) or not isinstance(weight, (int, float, _np.integer, _np.floating)):
        raise TypeError("hours_per_instant: expected a number of hours, got %s" % type(weight).__name__)
    value = float(weight)
    if not _math.isfinite(value) or value < 0:
        raise ValueError("hours_per_instant must be a finite number of hours >= 0, got %r" % (value,))
    return value


def _series_weight(series, weight):
    if not isinstance(series, SeriesResult):
        raise TypeError("expected a libshadow.SeriesResult, got %s" % type(series).__name__)
    if weight is not None:
        return _hours_weight(weight)
    scene = series.scene
    if scene.sun is None:
        raise ValueError("sun_hours: the scene has no sun block; pass hours_per_instant")
    return _libshadow.hours_per_instant(scene.sun)


def surface_series(series, hours_per_instant=None):
    """A SeriesResult per named surface (faces sharing a name add up): a dict with ``labels``,
    ``surfaces`` (NamedSurface), ``area``, ``lit_fraction`` (surfaces x instants) and ``sun_hours``."""
    return _libshadow._surface_series(series, _series_weight(series, hours_per_instant))


def object_sun_hours(series, hours_per_instant=None, per_mesh=False):
    """Sun hours per object of a SeriesResult, as ``shadow series`` writes them to
    sun_hours_by_object.csv (docs/series.md): a dict of ``ids``, ``types`` (the CityJSON type,
    ``zone`` or ``mesh``), ``meshes`` (mesh indices per object), ``faces`` (receiving faces),
    ``area`` (m2), ``sun_hours`` (area-weighted mean, h) and ``sunlit_area_hours`` (m2 h).
    ``per_mesh=True``: one row per receiving mesh, parts not rolled up."""
    return _libshadow._object_sun_hours(series, _series_weight(series, hours_per_instant), per_mesh)


def sun_hours_by_object_csv(series):
    """sun_hours_by_object.csv's text for a SeriesResult of the scene's suns (the CLI's file)."""
    return _libshadow._sun_hours_by_object_csv(series)


def sun_hours_error_bound(series, hours_per_instant=None):
    """Per row of a SeriesResult: a bound on |sun hours - exact sun hours| (0 for exact)."""
    return _libshadow._series_sun_hours_error_bound(series, _series_weight(series, hours_per_instant))


def sun_hours(result, hours_per_instant=None, by="surface"):
    """Sun hours over the scene's sun period: for each receiving face (``by="face"``) or named
    surface (``by="surface"``, faces sharing a name, area-weighted), the sum over the period's
    instants of the lit fraction times the hours each instant stands for (its step: left-rectangle
    sums, docs/series.md). Instants with the sun below the horizon add nothing. The weight is
    hours_per_instant(scene.sun) (step_minutes / 60, or the median gap of explicit ``times``)
    unless ``hours_per_instant`` is given. ``result`` may be a ShadowResult (every sun light
    computed) or a SeriesResult (ShadowEngine.compute_series(), the faster route; by "face" or
    "surface"). compute_sun_hours_map gives the same totals per face
    (hour_area / area) together with the exact map of where on the face.

    ``by="mesh"`` gives one value per receiving mesh (area-weighted over its faces): one mesh per
    facade gives sun hours per facade. ``by="object"`` gives one per object (``Scene.objects()``:
    a CityJSON building with its BuildingParts rolled up, an EnergyPlus zone, any other mesh),
    area-weighted the same way: the numbers of ``shadow series``' sun_hours_by_object.csv
    (``object_sun_hours`` gives the whole table).

    Returns (labels, hours): a list of face, surface or mesh labels and a float64 array. The
    result must hold every sun light (compute without ``lights=``)."""
    if not isinstance(result, (ShadowResult, SeriesResult)):
        raise TypeError("sun_hours: expected a ShadowResult or a SeriesResult, got %s" % type(result).__name__)
    if not isinstance(by, str):
        raise TypeError('sun_hours: by must be "face", "surface" or "mesh", got %s' % type(by).__name__)
    if isinstance(result, SeriesResult):
        weight = _series_weight(result, hours_per_instant)
        if by == "face":
            return [result.scene.face_label(int(f)) for f in result.face_id], \
                _libshadow._series_sun_hours(result, weight)
        if by == "surface":
            table = _libshadow._surface_series(result, weight)
            return table["labels"], table["sun_hours"]
        if by in ("object", "mesh"):
            table = _libshadow._object_sun_hours(result, weight, by == "mesh")
            return table["ids"], table["sun_hours"]
        raise ValueError('sun_hours of a SeriesResult: by must be "face", "surface", "object" or "mesh", got %r' % (by,))
    scene = result.scene
    if scene.sun is None:
        raise ValueError("sun_hours: the scene has no sun block")
    if hours_per_instant is None:
        hours_per_instant = _libshadow.hours_per_instant(scene.sun)
    else:
        hours_per_instant = _hours_weight(hours_per_instant)
    sun_lights = _np.array(sorted(i.light_id for i in scene.sun_instants if i.light_id is not None), dtype=_np.uint64)
    face_id, light_id = result.face_id, result.light_id
    is_sun = _np.isin(light_id, sun_lights)
    present = set(_np.unique(light_id[is_sun]).tolist())
    if len(present) != len(sun_lights):
        raise ValueError("sun_hours: the result lacks %d of the %d sun lights (compute every light)"
                         % (len(sun_lights) - len(present), len(sun_lights)))
    n = scene.face_count
    lit = _np.bincount(face_id[is_sun].astype(_np.int64), weights=result.lit_area[is_sun], minlength=n)
    area = _np.zeros(n)
    area[face_id.astype(_np.int64)] = result.area
    if by == "face":
        faces = _np.unique(face_id)
        with _np.errstate(invalid="ignore", divide="ignore"):
            hours = _np.where(area[faces] > 0, lit[faces] / area[faces], 0.0) * hours_per_instant
        return [scene.face_label(int(f)) for f in faces], hours
    if by in ("mesh", "object"):
        meshes = scene.meshes
        groups = [(o.id, [f for m in o.meshes for f in range(meshes[m].first_face, meshes[m].first_face + meshes[m].face_count)])
                  for o in scene.objects(True, by == "mesh")]
        groups = [(label, faces) for label, faces in groups if faces]
    elif by == "surface":
        groups = [(s.label, s.faces) for s in scene.named_surfaces(True)]
    else:
        raise ValueError('sun_hours: by must be "face", "surface", "object" or "mesh", got %r' % (by,))
    labels, hours = [], []
    for label, faces in groups:
        a = area[faces].sum()
        labels.append(label)
        hours.append(lit[faces].sum() / a * hours_per_instant if a > 0 else 0.0)
    return labels, _np.array(hours, dtype=float)


# ---- irradiation over a weather year (docs/irradiance.md) -----------------------------------------

class IrradianceResult(dict):
    """What ``irradiance()`` returns: a dict of numpy arrays per receiving face (``face_id``,
    ``area``, ``sky_view_factor``, ``ground_view_factor``, ``direct``, ``sky_diffuse``,
    ``ground_reflected``, ``total`` in kWh/m2, ``monthly_total`` faces x 12, ...), with
    ``to_pandas()``."""

    def to_pandas(self):
        """One row per receiving face (index ``face_id``): the per-face columns and the twelve
        monthly totals (``jan`` .. ``dec``, kWh/m2)."""
        try:
            import pandas as pd
        except ImportError as e:  # pragma: no cover - depends on the machine
            raise ImportError("to_pandas() needs pandas (Debian: python3-pandas)") from e
        columns = ("area", "sky_view_factor", "ground_view_factor", "direct", "sky_diffuse", "ground_reflected", "total")
        data = {c: self[c] for c in columns}
        months = ("jan", "feb", "mar", "apr", "may", "jun", "jul", "aug", "sep", "oct", "nov", "dec")
        for m, name in enumerate(months):
            data[name] = self["monthly_total"][:, m]
        return pd.DataFrame(data, index=pd.Index(self["face_id"], name="face_id"))


def irradiance(scene, weather, *args, **kwargs):
    return IrradianceResult(_libshadow.irradiance(scene, weather, *args, **kwargs))


irradiance.__doc__ = _libshadow.irradiance.__doc__
