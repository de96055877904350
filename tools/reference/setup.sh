#!/usr/bin/env bash
# Sets up the path-traced reference: a Python virtual environment in
# tools/reference/.venv with Mitsuba 3 and Pixar's usd-core (pinned in requirements.txt).
# Needs Python 3.11 or newer with its venv module (Debian: python3 python3-venv).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
python="${PYTHON:-python3}"
if [ ! -x "$here/.venv/bin/python" ]; then
    "$python" -m venv "$here/.venv"
fi
"$here/.venv/bin/python" -m pip install --quiet --disable-pip-version-check -r "$here/requirements.txt"
"$here/.venv/bin/python" -c "import mitsuba, pxr.Usd; print('reference renderer ready:', mitsuba.__version__)"
