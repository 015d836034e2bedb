#!/usr/bin/env bash
# Creates (or updates) the Python virtual environment the tests and tools use beside the Debian
# packages: .venv/ at the repository root (or $NEARFIELD_VENV), with the PyPI packages of
# scripts/python-requirements.txt (independent references such as Radiance, colour science, Ray).
# Idempotent: a venv whose requirements file is unchanged since the last install is left alone.
# Prints the venv's path on the last line. Needs python3-venv (scripts/setup.sh installs it).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
venv="${NEARFIELD_VENV:-$here/.venv}"
req="$here/scripts/python-requirements.txt"
stamp="$venv/.requirements.sha256"
want="$(sha256sum "$req" | cut -d' ' -f1)"
if [ ! -x "$venv/bin/python" ]; then
  echo "setup_python: creating $venv" >&2
  python3 -m venv "$venv"
fi
if [ ! -f "$stamp" ] || [ "$(cat "$stamp")" != "$want" ]; then
  echo "setup_python: installing $(grep -cv '^\s*\(#\|$\)' "$req" || true) packages from $req" >&2
  "$venv/bin/python" -m pip install --quiet --disable-pip-version-check --upgrade pip >&2
  if grep -qv '^\s*\(#\|$\)' "$req"; then
    "$venv/bin/python" -m pip install --quiet --disable-pip-version-check -r "$req" >&2
  fi
  echo "$want" >"$stamp"
fi
echo "$venv"
