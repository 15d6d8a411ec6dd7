#!/usr/bin/env bash
# Installs the independent checkers the tests call: the `rerun` CLI from the Python package
# rerun-sdk==0.36.3 (same version as the Rust SDK we write with), in $HOME/.cache/grasp-venv.
set -euo pipefail
venv="$HOME/.cache/grasp-venv"
want="0.36.3"
if [ -x "$venv/bin/rerun" ] && CI=1 "$venv/bin/python" -c "import rerun, sys; sys.exit(0 if rerun.__version__ == '$want' else 1)" 2>/dev/null; then
  exit 0
fi
python3 -m venv "$venv"
"$venv/bin/pip" install --quiet --disable-pip-version-check "rerun-sdk==$want"
CI=1 "$venv/bin/rerun" --version
