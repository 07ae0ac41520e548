#!/usr/bin/env bash
# Renders every scene under ../shared/scenes and scenes/ small, in both modes (spectral and
# --rgb), with a given lancer binary, and prints one line per render: "md5  scene mode". Two runs
# (an old build and a new one) compared with diff show whether a change kept every image's bytes.
#   tools/same_bytes.sh BIN > after.txt; diff before.txt after.txt
# SCENES_ROOTS overrides the folders searched; SPP (default 4) and RES (default 48x32) the size.
set -u
bin=$(realpath "$1")
spp=${SPP:-4} res=${RES:-48x32}
roots=${SCENES_ROOTS:-"$(cd "$(dirname "$0")/.." && pwd)/../shared/scenes $(cd "$(dirname "$0")/.." && pwd)/scenes"}
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
# shellcheck disable=SC2086
find $roots -name '*.pbrt' -o -name '*.pbrt.gz' | sort | while read -r scene; do
  for mode in spectral rgb; do
    flags=(--spp "$spp" --resolution "$res" --threads 2 --seed 1 --quiet)
    [ $mode = rgb ] && flags+=(--rgb)
    out=$tmp/out.exr; rm -f "$out"
    if (cd "$(dirname "$scene")" && timeout 120 "$bin" render "$(basename "$scene")" -o "$out" "${flags[@]}") >"$tmp/log" 2>&1; then
      # an EXR's renderTimeSeconds attribute (gbuffer and spectral films) is the one thing that
      # may differ between two runs: its value is zeroed before hashing
      sum=$(python3 -c 'import sys, hashlib; b = bytearray(open(sys.argv[1], "rb").read()); k = b"renderTimeSeconds\0float\0\x04\0\0\0"; i = b.find(k)
if i >= 0: b[i + len(k):i + len(k) + 4] = bytes(4)
print(hashlib.md5(b).hexdigest())' "$out")
    else
      sum="error:$(grep -a -m1 -i 'error' "$tmp/log" | md5sum | cut -c1-8)"
    fi
    echo "$sum  ${scene#*/scenes/} $mode"
  done
done
