#!/usr/bin/env bash
# Packs the files under FOLDER into one fuzz input (the container of fuzz/targets/fuzz_folder.h:
# a "--- PATH" line before each file's bytes, files separated by one "\n") and writes it to stdout.
#   fuzz/pack.sh out/ir > fuzz/corpus/ir_render/small
# Usage: fuzz/pack.sh FOLDER
set -euo pipefail
cd "$1"
first=1
while IFS= read -r f; do
  [ "$first" -eq 1 ] || printf '\n'
  first=0
  printf -- '--- %s\n' "${f#./}"
  cat -- "$f"
done < <(find . -type f | LC_ALL=C sort)
