#!/usr/bin/env bash
# The image quality of lancer builds at equal samples: for each BIN, renders SCENE with seeds
# 1..SEEDS (default 6) and prints each seed's relMSE against REF (`lancer bench scene
# --reference`) and their mean. A change that moves which random numbers a path reads (a
# sampler's dimensions, an order of draws) changes the error by the luck of the sequence as
# much as by any merit: compare the means over several seeds, and over several scenes, before
# calling it better (tools/ab_time.sh is the same for time). (bench scene's relMSE divides by
# B² + 0.01; ../shared/check/imgcmp.py, which the checks use, by B² + (0.1·mean B)²: the two
# rank builds alike but their values differ.)
#   tools/relmse_seeds.sh SCENE REF BIN [BIN...] [-- render flags...]
# The flags default to --spp 64 --threads 2; SEEDS overrides the count.
set -euo pipefail
[ $# -ge 3 ] || { sed -n 2,11p "$0" >&2; exit 2; }
scene=$(realpath "$1") ref=$(realpath "$2"); shift 2
bins=()
while [ $# -gt 0 ] && [ "$1" != -- ]; do bins+=("$(realpath "$1")"); shift; done
[ ${#bins[@]} -gt 0 ] || { echo "no BIN given before --" >&2; exit 2; }
[ $# -gt 0 ] && shift
flags=("$@"); [ ${#flags[@]} -gt 0 ] || flags=(--spp 64 --threads 2)
seeds=${SEEDS:-6}
cd "$(dirname "$scene")"
for bin in "${bins[@]}"; do
  all=()
  for seed in $(seq "$seeds"); do
    r=$("$bin" bench scene "$(basename "$scene")" --reference "$ref" --seed "$seed" "${flags[@]}" --json |
      sed -n 's/.*"relmse": *\([0-9.eE+-]*\).*/\1/p')
    [ -n "$r" ] || { echo "no relmse from $bin (seed $seed)" >&2; exit 1; }
    all+=("$r")
  done
  # awk, not bc: the JSON may write a small error as 1.5e-5.
  printf '%s\n' "${all[@]}" | awk -v bin="$bin" -v list="${all[*]}" \
    '{ s += $1; n++ } END { printf "%s: mean relmse %.6g over %d seeds (%s)\n", bin, s / n, n, list }'
done
