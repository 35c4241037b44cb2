"""Littoral from Python: wave surfaces, scene checks, runs, and every output as numpy arrays.

The work is done by the same C++ code as the `littoral` command (the compiled `_littoral`
module), so a run here writes the same files, byte for byte, as `littoral run`.

    import littoral
    surface = littoral.waves("pierson-moskowitz", wind=7, size=50, spacing=0.25, seed=1)
    surface.heights, surface.x, surface.y         # the height field (rows = y)
    surface.vertices, surface.triangles           # the facetized mesh
    surface.stats                                 # the statistics of `littoral waves --stats`
    print(littoral.check_scene("scene.yaml"))     # raises littoral.InputError with file:line:col
    littoral.run("scene.yaml", "out")             # build + render, with a progress bar
    littoral.sweep("scene.yaml", "study", vary={"sun.zenith_deg": [20, 40]})   # a grid of runs + index
    image = littoral.read_image("out/cam.img")    # data (bands, rows, cols), wavelengths, header
    probes = littoral.read_probes("out")          # probes.json as a list of dicts
    geo = littoral.read_layers("out/cam_geo.img") # {"latitude_deg": (rows, cols) float64, ...}
    truth = littoral.read_truth("out", "cam")     # material, surface, range, depth + the legend
    tif = littoral.read_raster("out/cam.tif")     # any image: channels, names, header attributes
    kd = littoral.read_kd("out")                  # kd.csv as columns
    det = littoral.read_detector("out", "cam")    # the detector's report (cam_detector.json)
"""
import csv
import json
import os

import numpy as np

from ._littoral import InputError, WaveSurface, check_scene, read_envi as _read_envi, read_exr as _read_exr
from ._littoral import read_raster as _read_raster
from ._littoral import run as _run
from ._littoral import sweep as _sweep
from ._littoral import waves as _waves

__all__ = ["InputError", "WaveSurface", "Image", "waves", "check_scene", "run", "sweep", "read_image",
           "read_probes", "read_products", "read_layers", "read_truth", "read_raster", "read_kd", "read_detector",
           "PRODUCTS"]

# The water-leaving products a sensor with `water_products: true` writes (docs/outputs.md).
PRODUCTS = ("water_leaving", "sky_reflected", "glint", "other", "ed0", "rrs")

WaveSurface.stats = property(lambda self: json.loads(self.stats_json),
                             doc="The wave statistics, as `littoral waves --stats` writes them")


def waves(model="beaufort", **options):
    """A wave surface with the options of `littoral waves` (wind=, wind_from=, size=, spacing=, seed=, ...)."""
    return _waves(model, **options)


def run(scene, out, *, sensor="", threads=0, progress=True):
    """Build and render a scene file into `out`, as `littoral run SCENE --out OUT`; returns the summary."""
    return _run(os.fspath(scene), os.fspath(out), sensor=sensor, threads=threads, progress=progress)


def _yaml_scalar(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    return str(v)


def sweep(scene, out, vary, *, threads=0, progress=True):
    """A grid of runs, as `littoral sweep SCENE --vary KEY=V1,V2 ... --out OUT` (docs/sweeps.md).

    `vary` maps each scene-file key (dotted, e.g. "water.surface.wind_speed") to its values; the
    last key varies fastest. Returns the summary; the runs and index.csv / index.json are in `out`.
    """
    options = [f"{key}={','.join(_yaml_scalar(v) for v in values)}" for key, values in vary.items()]
    return _sweep(os.fspath(scene), os.fspath(out), options, threads=threads, progress=progress)


def _read_envi_header(path):
    fields, key, value = {}, None, None
    with open(path, encoding="utf-8") as f:
        lines = f.read().splitlines()
    for line in lines[1:]:
        if key is not None:  # a braced value running over several lines
            value += "\n" + line
            if "}" in line:
                fields[key] = value.strip().strip("{}").strip()
                key = None
            continue
        if "=" not in line:
            continue
        k, v = line.split("=", 1)
        k, v = k.strip().lower(), v.strip()
        if v.startswith("{") and "}" not in v:
            key, value = k, v
        else:
            fields[k] = v.strip("{}").strip()
    return fields


class Image:
    """A multi-band image: `data` (bands, rows, cols) float32, its bands and, for ENVI, the header."""

    def __init__(self, path, film, header=None):
        self.path = os.fspath(path)
        self.data = np.asarray(film["data"])
        self.band_lo_um = np.asarray(film["band_lo_um"])
        self.band_hi_um = np.asarray(film["band_hi_um"])
        self.header = header or {}
        self.units = self.header.get("data units", "W m^-2 sr^-1 um^-1")

    @property
    def wavelengths_um(self):
        """Band centres (for a spectral response band: its nominal centre)."""
        return 0.5 * (self.band_lo_um + self.band_hi_um)

    @property
    def fwhm_um(self):
        return self.band_hi_um - self.band_lo_um

    def __repr__(self):
        b, h, w = self.data.shape
        return f"Image('{self.path}', {b} bands, {w} x {h} px, {self.units})"


def read_image(path):
    """Reads an ENVI image (.img, its .hdr beside it) or an OpenEXR radiance image (.exr)."""
    path = os.fspath(path)
    if path.lower().endswith(".exr"):
        return Image(path, _read_exr(path))
    header = _read_envi_header(os.path.splitext(path)[0] + ".hdr")
    return Image(path, _read_envi(path), header)


def read_products(out, sensor):
    """The water-leaving products of `sensor` in the output folder `out`, as {name: Image}."""
    return {p: read_image(os.path.join(os.fspath(out), f"{sensor}_{p}.img")) for p in PRODUCTS}


def read_probes(out):
    """probes.json of an output folder (or the file itself): a list of dicts, values as numpy arrays."""
    path = os.fspath(out)
    if os.path.isdir(path):
        path = os.path.join(path, "probes.json")
    with open(path, encoding="utf-8") as f:
        j = json.load(f)
    probes = []
    for p in j["probes"]:
        p = dict(p)
        p["value"] = np.asarray(p["value"], dtype=float)
        p["stderr"] = np.asarray(p["stderr"], dtype=float)
        p["band_lo_um"] = np.asarray([b["lo_um"] for b in j["bands"]])
        p["band_hi_um"] = np.asarray([b["hi_um"] for b in j["bands"]])
        probes.append(p)
    return probes


# ENVI data types of Littoral's outputs: 4 float32 (radiance, products, errors), 5 float64 (layers).
_ENVI_TYPES = {"4": np.float32, "5": np.float64}


def read_layers(path):
    """An ENVI image of named layers (NAME_geo.img: latitude, longitude, view and sun angles, float64)
    as {band name: (rows, cols) array}; the header's fields are under the key "header"."""
    path = os.fspath(path)
    h = _read_envi_header(os.path.splitext(path)[0] + ".hdr")
    if h.get("interleave", "bsq").lower() != "bsq" or h.get("data type") not in _ENVI_TYPES:
        raise InputError(f"{path}: not a band-sequential float32 or float64 ENVI image")
    rows, cols, bands = int(h["lines"]), int(h["samples"]), int(h["bands"])
    dtype = np.dtype(_ENVI_TYPES[h["data type"]]).newbyteorder(">" if h.get("byte order") == "1" else "<")
    data = np.fromfile(path, dtype=dtype, offset=int(h.get("header offset", "0")))
    if data.size != rows * cols * bands:
        raise InputError(f"{path}: {data.size} values, the header says {bands} x {rows} x {cols}")
    names = [n.strip() for n in h.get("band names", "").split(",")] if "band names" in h else \
        [f"band {k + 1}" for k in range(bands)]
    layers = {name: data[k * rows * cols:(k + 1) * rows * cols].reshape(rows, cols).astype(dtype.newbyteorder("="))
              for k, name in enumerate(names)}
    layers["header"] = h
    return layers


def read_raster(path):
    """Any image OpenImageIO reads (NAME.tif, NAME_truth.exr, NAME_psf.exr, NAME_noisy.exr, the PNGs):
    {"data": (channels, rows, cols), "channels": names, "attributes": the header's attributes}."""
    return _read_raster(os.fspath(path))


def read_truth(out, sensor):
    """The truth images of `sensor` (NAME_truth.exr) as {channel: (rows, cols)} (materialId and
    surfaceId as int, range and hitDepth in metres), with "legend": the rows of NAME_legend.csv."""
    out = os.fspath(out)
    r = _read_raster(os.path.join(out, f"{sensor}_truth.exr"))
    t = {}
    for k, name in enumerate(r["channels"]):
        plane = r["data"][k]
        t[name] = plane.astype(np.int64) if name.endswith("Id") else plane
    with open(os.path.join(out, f"{sensor}_legend.csv"), encoding="utf-8", newline="") as f:
        t["legend"] = list(csv.DictReader(f))
    return t


def read_kd(out):
    """kd.csv of an output folder (or the file itself) as {column: numpy array} (text columns as lists)."""
    path = os.fspath(out)
    if os.path.isdir(path):
        path = os.path.join(path, "kd.csv")
    with open(path, encoding="utf-8", newline="") as f:
        rows = list(csv.DictReader(f))
    columns = {}
    for key in (rows[0].keys() if rows else []):
        values = [row[key] for row in rows]
        try:
            columns[key] = np.asarray([float(v) for v in values])
        except ValueError:
            columns[key] = values
    return columns


def read_detector(out, sensor):
    """The detector report of `sensor` (NAME_detector.json): per band signal, noise, SNR, clipping."""
    with open(os.path.join(os.fspath(out), f"{sensor}_detector.json"), encoding="utf-8") as f:
        return json.load(f)
