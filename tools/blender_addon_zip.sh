#!/usr/bin/env bash
# Makes the Blender add-on's zip, installable from Blender's Edit > Preferences > Add-ons >
# Install from Disk: target/lancer_blender.zip (or the path given), holding the package
# folder lancer_blender/ as Blender expects.
#   tools/blender_addon_zip.sh [OUT.zip]
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-target/lancer_blender.zip}
mkdir -p "$(dirname "$out")"
out=$(cd "$(dirname "$out")" && pwd)/$(basename "$out")
rm -f "$out"
(cd blender && python3 - "$out" <<'PY'
import os, sys, zipfile
with zipfile.ZipFile(sys.argv[1], "w", zipfile.ZIP_DEFLATED) as z:
    for root, dirs, files in os.walk("lancer_blender"):
        dirs[:] = [d for d in dirs if d != "__pycache__"]
        for f in sorted(files):
            if f.endswith(".py"):
                z.write(os.path.join(root, f))
PY
)
echo "$out"
