#!/usr/bin/env bash
# Fills fuzz/corpus/<target>/ with the real files of ../shared/scenes (and the repo's own test
# data), the seed corpus each fuzz target starts from. Large files are left out: libFuzzer
# works best with inputs of a few hundred KiB at most (-max_len), and mutates them anyway.
set -euo pipefail
cd "$(dirname "$0")"
shared=${SHARED:-../../shared}
max=$((512 * 1024))
seed() { # seed TARGET FILE...
  local t=$1; shift
  mkdir -p "corpus/$t"
  for f in "$@"; do
    [ -f "$f" ] && [ "$(stat -c %s "$f")" -le $max ] && cp "$f" "corpus/$t/$(name "$f")"
  done
  return 0
}
# A corpus file name from a path, without leading ../ (which would hide it).
name() { echo "$1" | sed 's|^\(\.\./\)*||' | tr / _; }
files() { find "$shared/scenes" ../crates ../scenes -type f -iname "$1" 2>/dev/null; }
seed pbrt $(files '*.pbrt')
seed ply $(files '*.ply')
seed obj $(files '*.obj') $(files '*.mtl')
seed vox $(files '*.vox')
seed gltf $(files '*.glb') $(files '*.gltf')
seed nanovdb $(files '*.nvdb')
# The SDF language: every expression of the scenes, one per file.
mkdir -p corpus/sdf
i=0
for f in $(files '*.pbrt'); do
  grep -o '"string expr" *\[* *"[^"]*"' "$f" | sed 's/.*"\([^"]*\)"$/\1/' | while read -r e; do
    printf '%s' "$e" > "corpus/sdf/$(name "$f")-$RANDOM"
  done || true
done
printf '%s' 'smooth_union(sphere(0.6), translate([0, 0.5, 0], torus(0.7, 0.18)), 0.25)' > corpus/sdf/readme-1
printf '%s' 'difference(round_box([1, 0.5, 0.5], 0.1), repeat([0.4, 0.4, 0.4], [1, 1, 1], sphere(0.1)))' > corpus/sdf/readme-2
printf '%s' 'twist(1.5, rotate(30, [0, 1, 0], union(capsule([0, 0, 0], [0, 1, 0], 0.2), cone(0.5, 1), ellipsoid([1, 0.5, 0.3]), cylinder(0.5, 0.2))))' > corpus/sdf/readme-3
# The image target's first byte picks the decoder: 0 PNG, 1 JPEG, 2 EXR.
mkdir -p corpus/image
for f in $(files '*.png') $(files '*.jpg') $(files '*.exr'); do
  [ "$(stat -c %s "$f")" -le $max ] || continue
  case "${f##*.}" in png) p='\x00' ;; jpg) p='\x01' ;; *) p='\x02' ;; esac
  { printf "$p"; cat "$f"; } > "corpus/image/$(name "$f")"
done
for d in corpus/*; do echo "$d: $(ls "$d" | wc -l) files"; done
