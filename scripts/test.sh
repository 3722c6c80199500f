#!/usr/bin/env bash
# Set up what is missing, then run the whole test suite on every FreeCAD lane:
#   bash scripts/test.sh                  all lanes: 0.20 (this Debian 12 host), 1.0 (Debian 13 root), 1.1 (Debian testing root)
#   bash scripts/test.sh --lane 1.1 [...] one lane; further arguments go to pytest
# Each lane runs the pure-core and FreeCAD App tests and the GUI tests under Xvfb; firmware, slicer and
# emulator tests run on the host lane. One summary line per lane; a lane whose root cannot be made fails.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
SUDO=""
[ "$(id -u)" = 0 ] || SUDO="sudo"
lanes=(0.20 1.0 1.1)
if [ "${1:-}" = "--lane" ]; then
  [ $# -ge 2 ] || { echo "test.sh: --lane needs one of: ${lanes[*]}" >&2; exit 2; }
  case "$2" in 0.20|1.0|1.1) lanes=("$2") ;; *) echo "test.sh: unknown lane '$2' (allowed: 0.20, 1.0, 1.1)" >&2; exit 2 ;; esac
  shift 2
fi
bash tools/install-deps.sh
logdir="$(mktemp -d)"
trap 'rm -rf "$logdir"' EXIT
rc=0
for lane in "${lanes[@]}"; do
  echo "=== lane $lane ===" >&2
  start=$SECONDS
  lrc=0
  if [ "$lane" = 0.20 ]; then
    bash tools/run-lane.sh "$lane" "$@" 2>&1 | tee "$logdir/$lane.log" || lrc=$?
  else
    $SUDO bash tools/run-lane.sh "$lane" "$@" 2>&1 | tee "$logdir/$lane.log" || lrc=$?
  fi
  echo "$lrc $((SECONDS - start))" > "$logdir/$lane.rc"
  [ "$lrc" = 0 ] || rc=1
done
echo
echo "=== summary ==="
tp=0 tf=0 ts=0
for lane in "${lanes[@]}"; do
  read -r lrc secs < "$logdir/$lane.rc"
  info="$(grep -m1 "^lane $lane: FreeCAD" "$logdir/$lane.log" | sed "s/^lane $lane: //" || true)"
  parts=""
  while read -r _ _ part p f s e prc; do
    errs=""; [ "${e:-0}" = 0 ] || errs=" $e errors"          # shown only when pytest reported errors
    parts+=" $part $p passed $f failed $s skipped$errs;"
    tp=$((tp + p)); tf=$((tf + f + e)); ts=$((ts + s))
  done < <(grep '^LANE-RESULT ' "$logdir/$lane.log" || true)
  [ -n "$parts" ] || { parts=" no test ran;"; tf=$((tf + 1)); }
  verdict=PASS; [ "$lrc" = 0 ] || verdict=FAIL
  echo "lane $lane ${info:+($info)}:$parts ${secs} s: $verdict"
done
echo "total: $tp passed, $tf failed, $ts skipped"
exit $rc
