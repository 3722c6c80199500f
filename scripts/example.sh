#!/usr/bin/env bash
# Set up what is missing, then run the main job on the bundled fish (the seed's swimming fish with
# its skeleton of rotary axes): configure its joints, solve an actuated state, render it, and build
# the printable sheet and its modules as STEP + 3MF. Everything goes to OUT (default: out/).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
bash tools/install-deps.sh
OUT="${1:-out}"
mkdir -p "$OUT"
PY=/usr/bin/python3
run() { echo "+ $*" >&2; "$@"; }
run $PY -m metamaterial_wb design examples/fish_axes.json --out "$OUT/fish-configured.json"
run $PY -m metamaterial_wb solve "$OUT/fish-configured.json" --out "$OUT/fish-result.json" --set tail=0.9
run $PY -m metamaterial_wb render "$OUT/fish-configured.json" --set tail=0.9 --out "$OUT/fish-actuated.png"
run $PY -m metamaterial_wb render "$OUT/fish-configured.json" --global 1 --out "$OUT/fish-folded.png"
run $PY -m metamaterial_wb build "$OUT/fish-configured.json" --out "$OUT/fish-print" --step --3mf --modules
echo "done: $(cd "$OUT" && ls | tr '\n' ' ')" >&2
