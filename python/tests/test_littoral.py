"""The Python package against the command line: the same code, so the same bytes.

Runs from CTest (python.pytest) with BUILD/python on PYTHONPATH; LITTORAL_BINARY_DIR names the
build (for bin/littoral), LITTORAL_SOURCE_DIR the checkout.
"""
import csv
import json
import os
import subprocess
import sys

import numpy as np
import pytest

import littoral

BUILD = os.environ.get("LITTORAL_BINARY_DIR", "build")
SOURCE = os.environ.get("LITTORAL_SOURCE_DIR", ".")
CLI = os.path.join(BUILD, "bin", "littoral")

SCENE = """scene: {name: py, domain: {x: [-5, 5], y: [-5, 5]}}
sun: {zenith_deg: 30, irradiance: 1000}
sky: {radiance: 20}
water: {level_m: 0, optics: {preset: low}}
bathymetry: {type: planar_slope, z0_m: -2, material: sand}
materials: [{name: sand, reflectance: 0.3}]
sensors:
  - {name: cam, type: frame, elevation_deg: 70, azimuth_deg: 180, range_m: 20, gsd_m: 0.25, width: 8, height: 6,
     water_products: true}
probes:
  - {name: above, position: [0, 0, 1], quantities: [Ed, Rrs], samples: 256}
render: {bands: [[0.45, 0.5], [0.55, 0.6]], hemisphere_samples: 4, photons: {volume: 20000}, probe_batches: 4}
"""


def cli(*args):
    r = subprocess.run([CLI, "-q", *args], capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr
    return r


def test_wave_statistics_and_mesh_equal_the_command_byte_for_byte(tmp_path):
    cli("waves", "--model", "pierson-moskowitz", "--wind", "7", "--size", "24", "--spacing", "0.5", "--seed", "3",
        "--stats", str(tmp_path / "cli.json"), "--out", str(tmp_path / "cli.ply"))
    s = littoral.waves("pierson-moskowitz", wind=7, size=24, spacing=0.5, seed=3)
    # Every statistic equal (the JSON as written, but for the wall-clock timings it also holds).
    ours, theirs = s.stats, json.loads((tmp_path / "cli.json").read_text())
    assert ours.pop("timing_s") and theirs.pop("timing_s")
    assert ours == theirs
    s.write_mesh(str(tmp_path / "py.ply"))
    assert (tmp_path / "py.ply").read_bytes() == (tmp_path / "cli.ply").read_bytes()
    # The height field: a 49 x 49 grid over [-12, 12] m whose RMS is the statistics' own.
    assert s.heights.shape == (49, 49)
    assert s.x[0] == -12 and s.x[-1] == 12 and s.y.shape == (49,)
    h = s.heights[:-1, :-1] if s.stats["grid"]["periodic"] else s.heights  # (periodic: the last row and column repeat)
    rms = float(np.sqrt(np.mean((h - h.mean()) ** 2)))
    assert rms == pytest.approx(s.stats["grid_measured"]["rms_height"], rel=1e-6)
    assert s.vertices.shape[1] == 3 and s.triangles.shape[1] == 3
    assert int(s.triangles.max()) < s.vertices.shape[0]


def test_bad_options_and_scenes_raise_input_error_with_the_location(tmp_path):
    with pytest.raises(littoral.InputError, match="--model: unknown model 'beufort'.*did you mean 'beaufort'"):
        littoral.waves("beufort", wind=5)
    bad = tmp_path / "bad.yaml"
    bad.write_text(SCENE.replace("gsd_m: 0.25", "gsd_m: -1"))
    with pytest.raises(littoral.InputError, match=r"bad\.yaml:8:"):
        littoral.check_scene(str(bad))
    good = tmp_path / "good.yaml"
    good.write_text(SCENE)
    assert "1 sensor(s), 1 probe(s)" in littoral.check_scene(str(good))


def test_a_run_writes_what_the_command_writes(tmp_path):
    scene = tmp_path / "scene.yaml"
    scene.write_text(SCENE)
    cli("run", str(scene), "--out", str(tmp_path / "cli"))
    summary = littoral.run(scene, tmp_path / "py", progress=False)
    assert "rendered 1 sensor(s)" in summary
    # (The EXR header carries the time it was written, so its pixels are compared instead.)
    for name in ["cam.img", "cam.hdr", "cam_rrs.img", "cam_water_leaving.img", "cam_ed0.img", "probes.csv", "probes.json"]:
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    np.testing.assert_array_equal(littoral.read_image(tmp_path / "py" / "cam.exr").data,
                                  littoral.read_image(tmp_path / "cli" / "cam.exr").data)
    img = littoral.read_image(tmp_path / "py" / "cam.img")
    assert img.data.shape == (2, 6, 8) and img.data.dtype == np.float32
    np.testing.assert_allclose(img.wavelengths_um, [0.475, 0.575])
    assert img.units == "W m^-2 sr^-1 um^-1"
    exr = littoral.read_image(tmp_path / "py" / "cam.exr")
    np.testing.assert_array_equal(exr.data, img.data)
    p = littoral.read_products(tmp_path / "py", "cam")
    parts = p["water_leaving"].data + p["sky_reflected"].data + p["glint"].data + p["other"].data
    np.testing.assert_allclose(parts, img.data, rtol=1e-6)
    assert p["rrs"].units == "sr^-1" and p["ed0"].units == "W m^-2 um^-1"
    probes = {q["quantity"]: q for q in littoral.read_probes(tmp_path / "py")}
    assert probes["Rrs"]["units"] == "sr^-1" and probes["Rrs"]["value"].shape == (2,)
    # The probe 1 m up reads the open sky and sun: E cos 30 + pi L, within its standard error.
    assert probes["Ed"]["value"][0] == pytest.approx(1000 * np.cos(np.radians(30)) + np.pi * 20,
                                                     abs=4 * probes["Ed"]["stderr"][0] + 1e-3)


def test_a_sweep_runs_its_grid_and_indexes_it(tmp_path):
    scene = tmp_path / "scene.yaml"
    scene.write_text(SCENE)
    summary = littoral.sweep(scene, tmp_path / "study", vary={"sun.zenith_deg": [20, 40], "sky.radiance": [0, 20]},
                             progress=False)
    assert "sweep of 4 run(s)" in summary
    rows = list(csv.DictReader(open(tmp_path / "study" / "index.csv")))
    # The last key varies fastest.
    assert [(r["sun.zenith_deg"], r["sky.radiance"], r["status"]) for r in rows] == [
        ("20", "0", "done"), ("20", "20", "done"), ("40", "0", "done"), ("40", "20", "done")]
    # Run 0003 is the scene with both values set: the command's run of its own scene.yaml gives the same bytes.
    run = tmp_path / "study" / rows[3]["folder"]
    cli("run", str(run / "scene.yaml"), "--out", str(tmp_path / "single"))
    for name in ["cam.img", "probes.json"]:
        assert (run / name).read_bytes() == (tmp_path / "single" / name).read_bytes(), name
    # The sun at 40 degrees and the sky at 20 reach the probe 1 m up: E cos 40 + pi 20.
    ed = {q["quantity"]: q for q in littoral.read_probes(run)}["Ed"]
    assert ed["value"][0] == pytest.approx(1000 * np.cos(np.radians(40)) + np.pi * 20, abs=4 * ed["stderr"][0] + 1e-3)
    index = json.loads((tmp_path / "study" / "index.json").read_text())
    assert index["index"][3]["parameters"] == {"sun.zenith_deg": 40, "sky.radiance": 20}
    assert f"{rows[3]['folder']}/cam.img" in index["index"][3]["outputs"]


def test_a_failed_run_leaves_nothing(tmp_path):
    scene = tmp_path / "scene.yaml"
    scene.write_text(SCENE.replace("water_products: true", "water_products: true, medium: water"))
    with pytest.raises(littoral.InputError, match="water_products needs a sensor in the air"):
        littoral.run(scene, tmp_path / "out", progress=False)
    assert not (tmp_path / "out" / "cam.img").exists()


def test_the_example_runs_and_plots(tmp_path):
    example = os.path.join(SOURCE, "python", "examples", "rrs_three_depths.py")
    r = subprocess.run([sys.executable, example, "--quick", "--out", str(tmp_path)], capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr
    assert (tmp_path / "rrs_three_depths.png").stat().st_size > 10000
    csv = (tmp_path / "rrs_three_depths.csv").read_text().splitlines()
    assert csv[0] == "depth_m,wavelength_um,rrs_per_sr"
    rows = [tuple(map(float, line.split(","))) for line in csv[1:]]
    by_depth = {}
    for d, w, v in rows:
        by_depth.setdefault(d, []).append(v)
    # Over a bright sand bottom the shallow water is the brightest at every wavelength.
    depths = sorted(by_depth)
    assert len(depths) == 3
    assert all(a > b for a, b in zip(by_depth[depths[0]], by_depth[depths[-1]]))


OUTPUTS_SCENE = """scene: {name: pyall, origin: {latitude: 36.1833, longitude: -75.75}, domain: {x: [-5, 5], y: [-5, 5]}}
sun: {zenith_deg: 30, irradiance: 1000}
sky: {radiance: 20}
water: {level_m: 0, optics: {preset: low}}
bathymetry: {type: planar_slope, z0_m: -3, material: sand}
materials: [{name: sand, reflectance: 0.3}]
sensors:
  - {name: cam, type: frame, elevation_deg: 90, azimuth_deg: 0, range_m: 20, gsd_m: 0.5, width: 8, height: 6,
     samples_per_pixel: 4, psf: {type: gaussian, fwhm_px: 1.5},
     detector: {aperture_mm: 0.5, integration_ms: 1, quantum_efficiency: 0.5, read_noise_e: 20, full_well_e: 1000000,
                bits: 16}}
probes:
  - {name: prof, line: {from: [0, 0, -0.5], to: [0, 0, -2.0], count: 4}, quantities: [Ed], samples: 256}
render: {bands: [[0.45, 0.5], [0.55, 0.6]], hemisphere_samples: 4, photons: {volume: 20000}, probe_batches: 4}
"""


def test_every_output_reads_back_with_its_metadata(tmp_path):
    scene = tmp_path / "scene.yaml"
    scene.write_text(OUTPUTS_SCENE)
    out = tmp_path / "out"
    littoral.run(scene, out, progress=False)
    img = littoral.read_image(out / "cam.img")
    # The GeoTIFF holds the same radiance, band for band, as the ENVI image.
    tif = littoral.read_raster(out / "cam.tif")
    assert tif["data"].shape == img.data.shape and tif["data"].dtype == np.float32
    np.testing.assert_array_equal(tif["data"], img.data)
    # The PSF and detector images: the blur keeps the image's total; the noisy image is in the
    # radiance's units, its mean within a few per cent of the clean one (shot and read noise).
    psf = littoral.read_raster(out / "cam_psf.exr")
    noisy = littoral.read_raster(out / "cam_noisy.exr")
    assert psf["data"].shape == img.data.shape == noisy["data"].shape
    np.testing.assert_allclose(psf["data"].sum(axis=(1, 2)), img.data.sum(axis=(1, 2)), rtol=1e-4)
    det = littoral.read_detector(out, "cam")
    assert len(det["bands"]) == 2 and det["bits"] == 16 and all(b["snr"] > 0 for b in det["bands"])
    # The standard-error image (4 samples per pixel) is an ENVI image like the radiance.
    se = littoral.read_image(out / "cam_stderr.img")
    assert se.data.shape == img.data.shape and np.all(se.data >= 0)
    # The georeferencing layers: float64, the centre of the nadir view at the origin.
    geo = littoral.read_layers(out / "cam_geo.img")
    assert geo["latitude_deg"].dtype == np.float64 and geo["latitude_deg"].shape == (6, 8)
    assert set(geo) >= {"latitude_deg", "longitude_deg", "view_zenith_deg", "sun_zenith_deg"}
    # Pixel (4, 3)'s centre lies 0.25 m east and 0.25 m south of the origin.
    assert geo["latitude_deg"][3, 4] == pytest.approx(36.1833 - 0.25 / 111_000, abs=2e-7)
    assert geo["longitude_deg"][3, 4] == pytest.approx(-75.75 + 0.25 / (111_320 * np.cos(np.radians(36.1833))), abs=2e-7)
    np.testing.assert_allclose(geo["sun_zenith_deg"], 30.0)
    # Truth: every pixel sees the sand through the water, 3 m down, as the legend names it.
    truth = littoral.read_truth(out, "cam")
    assert truth["materialId"].shape == (6, 8)
    names = {int(row["id"]): row["material"] for row in truth["legend"]}
    assert {names[int(v)] for v in np.unique(truth["surfaceId"])} == {"sand"}
    np.testing.assert_allclose(truth["hitDepth"], 3.0, atol=1e-3)
    # K_d between the profile's consecutive probes: 3 pairs x 2 bands, positive.
    kd = littoral.read_kd(out)
    assert len(kd["kd_per_m"]) == 6 and np.all(kd["kd_per_m"] > 0)
