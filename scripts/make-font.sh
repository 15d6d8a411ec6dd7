#!/usr/bin/env bash
# Remakes crates/grasp-cli/assets/fonts/DejaVuSans-subset.ttf, the font the pictures are set
# in (shipped so PNGs need no system fonts and look the same everywhere): DejaVu Sans 2.37
# (Debian's fonts-dejavu-core; licence in LICENSE-DejaVu.txt beside it) cut to Latin,
# Greek, punctuation, arrows and mathematical operators with fontTools' pyftsubset.
set -euo pipefail
cd "$(dirname "$0")/.."
src=${1:-/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf}
venv=${GRASP_FONT_VENV:-$HOME/.cache/grasp-font-venv}
[ -x "$venv/bin/pyftsubset" ] || { python3 -m venv "$venv" && "$venv/bin/pip" install -q fonttools==4.55.3; }
"$venv/bin/pyftsubset" "$src" \
  --unicodes="U+0020-017F,U+0370-03FF,U+2000-206F,U+2190-21FF,U+2200-22FF" \
  --layout-features='kern,liga' \
  --output-file=crates/grasp-cli/assets/fonts/DejaVuSans-subset.ttf
