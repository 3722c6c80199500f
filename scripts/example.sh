#!/usr/bin/env bash
# Set up what is missing, then run the main job on the bundled fish: solve it and write the result,
# renders and (when the fabrication stage is present) STEP/3MF into OUT (default: out/).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
bash tools/install-deps.sh
OUT="${1:-out}"
mkdir -p "$OUT"
PY=/usr/bin/python3
$PY -m metamaterial_wb solve examples/fish.json --out "$OUT/fish-result.json"
if $PY -m metamaterial_wb --help | grep -q ' render'; then
  $PY -m metamaterial_wb render examples/fish.json --out "$OUT/fish.png"
fi
echo "wrote $(ls "$OUT" | tr '\n' ' ') to $OUT/"
