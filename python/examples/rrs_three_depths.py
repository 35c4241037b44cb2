#!/usr/bin/env python3
"""Remote-sensing reflectance spectra of shallow water over sand at three depths.

The classic figure of shallow-water remote sensing (e.g. Lee et al. 1998, Fig. 1; Maritorena et
al. 1994): over a bright bottom, Rrs is high and bottom-shaped in shallow water and falls toward
the deep-water spectrum as the depth grows, first in the red (where water absorbs most), last in
the blue-green. Each depth is one Littoral run of a nadir sensor with `water_products: true`;
Rrs is the ratio of the image means of Lw and Ed(0+) (NAME_water_leaving.img, NAME_ed0.img).

    /usr/bin/python3 python/examples/rrs_three_depths.py --out out/rrs   [--quick]

Writes OUT/rrs_three_depths.csv (depth, wavelength, Rrs) and OUT/rrs_three_depths.png, and the
runs in OUT/depth_<d>m/. Needs the package on PYTHONPATH (BUILD/python) and python3-matplotlib.
"""
import argparse
import os

import numpy as np

import littoral

DEPTHS_M = (1.0, 3.0, 8.0)

# Sand brightening toward the red (reflectance 0.15-0.35), coastal water of 1 mg m^-3 chlorophyll,
# 0.5 g m^-3 sediment and CDOM (0.05 m^-1 at 440 nm) with pure sea water, sun 30 deg, the simple
# atmosphere.
SCENE = """scene: {{name: rrs-depth-{depth:g}, domain: {{x: [-10, 10], y: [-10, 10]}}}}
sun: {{zenith_deg: 30, azimuth_deg: 135}}
sky: {{model: simple, hemisphere_irradiance: 1500, sky_fraction: 0.2}}
water:
  level_m: 0
  horizontal: periodic
  optics: {{constituents: {{chlorophyll_mg_m3: 1, sediment_g_m3: 0.5, cdom_440_per_m: 0.05}}}}
bathymetry: {{type: planar_slope, z0_m: {z:g}, spacing_m: 5, material: sand}}
materials:
  - name: sand
    reflectance: {{wavelengths_um: [0.4, 0.5, 0.6, 0.7], values: [0.15, 0.22, 0.30, 0.35]}}
sensors:
  - {{name: nadir, type: frame, elevation_deg: 90, azimuth_deg: 0, range_m: 500, gsd_m: 0.5,
     width: {px}, height: {px}, samples_per_pixel: {spp}, water_products: true}}
render:
  bands: {{range_um: [0.4, 0.7], count: {bands}}}
  photons: {{volume: {photons}}}
  hemisphere_samples: {hemi}
"""


def rrs_spectrum(out, depth, quick):
    settings = dict(px=8, spp=1, bands=6, photons=100000, hemi=16) if quick else \
        dict(px=32, spp=4, bands=15, photons=2000000, hemi=64)
    run_dir = os.path.join(out, f"depth_{depth:g}m")
    os.makedirs(run_dir, exist_ok=True)
    scene = os.path.join(run_dir, "scene.yaml")
    with open(scene, "w", encoding="utf-8") as f:
        f.write(SCENE.format(depth=depth, z=-depth, **settings))
    littoral.run(scene, os.path.join(run_dir, "out"), progress=not quick)
    p = littoral.read_products(os.path.join(run_dir, "out"), "nadir")
    lw = p["water_leaving"].data.mean(axis=(1, 2))
    ed = p["ed0"].data.mean(axis=(1, 2))
    return p["water_leaving"].wavelengths_um, lw / ed


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="out/rrs_three_depths")
    ap.add_argument("--quick", action="store_true", help="small images and few photons (seconds, noisier)")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    spectra = {d: rrs_spectrum(args.out, d, args.quick) for d in DEPTHS_M}
    with open(os.path.join(args.out, "rrs_three_depths.csv"), "w", encoding="utf-8") as f:
        f.write("depth_m,wavelength_um,rrs_per_sr\n")
        for d, (wl, rrs) in spectra.items():
            for w, r in zip(wl, rrs):
                f.write(f"{d:g},{w:.4f},{r:.6e}\n")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.4, 4.2), dpi=120)
    for d, (wl, rrs) in spectra.items():
        ax.plot(1000 * wl, rrs, marker="o", ms=3, label=f"bottom at {d:g} m")
    ax.set_xlabel("wavelength (nm)")
    ax.set_ylabel(r"$R_{rs}$ (sr$^{-1}$)")
    ax.set_title("Shallow water over sand: Rrs at three depths (Littoral, nadir)")
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "rrs_three_depths.png"))
    print(f"wrote {args.out}/rrs_three_depths.csv and .png")


if __name__ == "__main__":
    main()
