#!/usr/bin/env bash
# The Blender add-on's tests against real Blender: installs bpy (Blender as a Python module,
# from PyPI; about 400 MB, so not into CI's venv) with numpy and pytest into a virtualenv of its
# own, BLENDER_VENV (default ~/.cache/lancer-blender-venv; bpy needs the Python version its
# release was built for, e.g. 3.11 for Blender 4.x/5.0: PYTHON=python3.11), builds this
# checkout's Python module into it, and runs blender/tests (each light type and the Principled
# BSDF's inputs against Cycles, the factory scene, a refused scene).
#   tools/test_blender.sh [pytest options]
set -euo pipefail
cd "$(dirname "$0")/.."
venv=${BLENDER_VENV:-${XDG_CACHE_HOME:-$HOME/.cache}/lancer-blender-venv}
[ -x "$venv/bin/python" ] || "${PYTHON:-python3}" -m venv "$venv"
if ! "$venv/bin/python" -c "import bpy, numpy, pytest" 2>/dev/null || [ ! -x "$venv/bin/maturin" ]; then
  "$venv/bin/python" -m pip install --quiet bpy numpy pytest "maturin>=1.9.4,<2"
fi
(cd crates/lancer-py && VIRTUAL_ENV=$venv "$venv/bin/maturin" develop --profile dev --quiet)
"$venv/bin/python" -m pytest -q blender/tests "$@"
