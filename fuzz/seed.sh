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
# The image target's first byte picks the decoder: 0 PNG, 1 JPEG, 2 EXR.
mkdir -p corpus/image
for f in $(files '*.png') $(files '*.jpg') $(files '*.exr'); do
  [ "$(stat -c %s "$f")" -le $max ] || continue
  case "${f##*.}" in png) p='\x00' ;; jpg) p='\x01' ;; *) p='\x02' ;; esac
  { printf "$p"; cat "$f"; } > "corpus/image/$(name "$f")"
done
for d in corpus/*; do echo "$d: $(ls "$d" | wc -l) files"; done
