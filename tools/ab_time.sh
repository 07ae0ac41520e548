#!/usr/bin/env bash
# Times two lancer builds against each other on one scene, alternately, so that the machine's
# drift and bursts fall on both: ROUNDS rounds (default 10), each running OLD then NEW in each
# mode, each run's time the median of 3 whole-process wall times (as ../shared/check/path.sh
# and spectral.sh time lancer). Prints each build's median, the ratio of medians, and the
# median and mean of the per-round ratios NEW/OLD (the paired figures are the ones to quote
# on a noisy machine: a burst that slows one round slows both builds' runs in it).
#   tools/ab_time.sh OLD_BIN NEW_BIN [SCENE] [-- render flags...]
# SCENE defaults to ../shared/scenes/pt/cbox.pbrt; the flags to --spp 64 --threads 2.
# MODES (default "--rgb --spectral") and ROUNDS override.
set -euo pipefail
[ $# -ge 2 ] || { sed -n 2,10p "$0" >&2; exit 2; }
old=$(realpath "$1") new=$(realpath "$2"); shift 2
root=$(cd "$(dirname "$0")/.." && pwd)
scene=$root/../shared/scenes/pt/cbox.pbrt
if [ $# -gt 0 ] && [ "$1" != -- ]; then scene=$(realpath "$1"); shift; fi
[ $# -gt 0 ] && [ "$1" = -- ] && shift
flags=("$@"); [ ${#flags[@]} -gt 0 ] || flags=(--spp 64 --threads 2)
rounds=${ROUNDS:-10} modes=${MODES:-"--rgb --spectral"}
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
median3() {
  local ts=() s e
  for _ in 1 2 3; do
    s=$(date +%s.%N)
    "$@" >/dev/null 2>&1 || { echo "failed: $*" >&2; exit 1; }
    e=$(date +%s.%N)
    ts+=("$(echo "$e - $s" | bc)")
  done
  printf '%s\n' "${ts[@]}" | sort -n | sed -n 2p
}
for r in $(seq "$rounds"); do
  for m in $modes; do
    for b in old new; do
      bin=$old; [ $b = new ] && bin=$new
      echo "$r $m $b $(median3 "$bin" render "$scene" -o "$tmp/out.exr" --quiet "$m" "${flags[@]}")"
    done
  done
done >"$tmp/times"
python3 - "$tmp/times" <<'EOF'
import statistics as st, sys
t = {}
for line in open(sys.argv[1]):
    r, m, b, s = line.split()
    t.setdefault(m, {}).setdefault(b, {})[r] = float(s)
for m, d in t.items():
    old, new = d["old"], d["new"]
    paired = [new[r] / old[r] for r in old]
    mo, mn = st.median(old.values()), st.median(new.values())
    print(f"{m}: old {mo:.3f} s, new {mn:.3f} s (medians of {len(old)} rounds), new/old {mn / mo:.3f}; "
          f"paired new/old median {st.median(paired):.3f}, mean {st.mean(paired):.3f}")
EOF
