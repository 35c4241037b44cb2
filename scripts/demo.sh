#!/usr/bin/env bash
# Fresh-machine command 1: install dependencies, build, and run `littoral demo` on the built-in
# default scene. Results go to out/demo/ (images, IR, statistics).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/scripts/build.sh"
"$root/build/bin/littoral" demo --out "$root/out/demo" "$@"
