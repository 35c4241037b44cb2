#!/usr/bin/env bash
# Issue 22's benchmark: the cost of spectral-response bands and of the sensor-model images on the
# coastal demo site (data_synthetic/coastal_site/, nadir simulation C, 450 x 300 px, its quick
# photon counts), measured side by side in one run of this script:
#   rect      the site as shipped: three rectangular bands 0.4-0.5, 0.5-0.6, 0.6-0.7 um
#   gaussian  three Gaussian bands (centres 0.47, 0.56, 0.65 um; FWHM 30, 30, 20 nm), which the
#             renderer renders as 5 nm sub-bands over 0.41-0.69 um and weights per band
#   products  rect plus a Gaussian PSF (FWHM 1.5 px) and a detector on the sensor
#   water     rect plus water_products: true (the radiance split at the sea surface, Ed(0+), Rrs)
# Prints each run's wall time (GNU time) and its ratio to rect.
# Usage: bench/sensor_products.sh [OUT_DIR]   (default out/bench-sensor-products; needs build/bin/littoral)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="${1:-$root/out/bench-sensor-products}"
rm -rf "$out"
mkdir -p "$out"
run() {  # name, sed expression applied to the scene file
    local site="$out/$1/site"
    mkdir -p "$out/$1"
    cp -r "$root/data_synthetic/coastal_site" "$site"
    sed -i "$2" "$site/scene.yaml"
    /usr/bin/time -f "%e" -o "$out/$1/wall.txt" "$root/build/bin/littoral" -q run "$site/scene.yaml" --out "$out/$1/render" \
        > "$out/$1/run.log" 2>&1 || { cat "$out/$1/run.log"; exit 1; }
    cat "$out/$1/wall.txt"
}
rect=$(run rect 's/^  bands: .*/  bands: {range_um: [0.4, 0.7], count: 3}/')
gauss=$(run gaussian 's/^  bands: .*/  bands: [{centre_um: 0.47, fwhm_um: 0.03}, {centre_um: 0.56, fwhm_um: 0.03}, {centre_um: 0.65, fwhm_um: 0.02}]/')
prod=$(run products 's/^     target: \[0, 0, 0\], width: 450, height: 300}/     target: [0, 0, 0], width: 450, height: 300, psf: {type: gaussian, fwhm_px: 1.5},\n     detector: {aperture_mm: 5, integration_ms: 1, quantum_efficiency: 0.6, read_noise_e: 20, full_well_e: 100000, bits: 12}}/')
water=$(run water 's/^     target: \[0, 0, 0\], width: 450, height: 300}/     target: [0, 0, 0], width: 450, height: 300, water_products: true}/')
grep -q "psf:" "$out/products/site/scene.yaml"
grep -q "water_products" "$out/water/site/scene.yaml"
cmp "$out/rect/render/sim-c-nadir.img" "$out/water/render/sim-c-nadir.img"  # the products leave the radiance as it was
printf "rect bands          %6.1f s  1\n" "$rect"
awk -v r="$rect" -v g="$gauss" -v p="$prod" -v w="$water" 'BEGIN {
    printf "gaussian bands      %6.1f s  %.2f\n", g, g / r
    printf "rect + psf+detector %6.1f s  %.3f\n", p, p / r
    printf "rect + water prods  %6.1f s  %.3f\n", w, w / r }'
