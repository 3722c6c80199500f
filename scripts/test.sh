#!/usr/bin/env bash
# Set up what is missing, then run the whole test suite on every FreeCAD lane:
#   bash scripts/test.sh                  all lanes: 0.20 (this Debian 12 host), 1.0 (Debian 13 root), 1.1 (Debian testing root)
#   bash scripts/test.sh --lane 1.1 [...] one lane; further arguments go to pytest
# Each lane runs the FreeCAD App tests and the GUI tests under Xvfb; the pure-core tests run on 0.20 and 1.1 (the
# oldest and newest Python / numpy); firmware, slicer and emulator tests run on the host lane.
# All lanes, as root: two queues at once (a test process keeps about one core busy): the host lane, and the root
# lanes one after the other (the 1.1 root is made while 1.0 runs). MM_LANES_SERIAL=1 (or running as a user, with
# sudo) runs the lanes one after the other.
# The host lane's output streams; the root lanes' logs follow when they end. One summary line per lane; a lane
# whose root cannot be made fails.
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
groups=() tails=() shown=()
stop_jobs() {   # TERM every queue's process group (run-lane.sh stops its root's run and unmounts), wait until gone
  local p i
  for p in "${groups[@]}"; do kill -TERM -- "-$p" 2>/dev/null || true; done
  for p in "${groups[@]}"; do
    for i in $(seq 300); do pgrep -g "$p" >/dev/null 2>&1 || break; sleep 0.1; done
  done
}
stop_tails() {  # end the log followers (after a second: the last lines reach the output)
  local t
  [ "${1:-}" = now ] || sleep 1
  for t in "${tails[@]}"; do kill "$t" 2>/dev/null || true; done
  tails=()
}
finish() {      # on every exit: no tail left behind; the root lanes' logs are shown even after an interrupt
  local lane
  stop_tails now
  for lane in "${rooted[@]}"; do
    if [[ " ${shown[*]} " != *" $lane "* ]] && [ -s "$logdir/$lane.log" ]; then
      echo "=== lane $lane (log so far) ===" >&2
      cat "$logdir/$lane.log"
    fi
  done
  rm -rf "$logdir"
}
trap finish EXIT
trap 'stop_jobs; exit 130' INT
trap 'stop_jobs; exit 143' TERM

run_one() {  # run_one LANE [pytest args]: the lane's output to $logdir/LANE.log, "rc seconds" to LANE.rc
  local lane="$1"; shift
  local start=$SECONDS lrc=0
  if [ "$lane" = 0.20 ]; then
    bash tools/run-lane.sh "$lane" "$@" >> "$logdir/$lane.log" 2>&1 || lrc=$?
  else
    $SUDO bash tools/run-lane.sh "$lane" "$@" >> "$logdir/$lane.log" 2>&1 || lrc=$?
  fi
  echo "$lrc $((SECONDS - start))" > "$logdir/$lane.rc"
}

roots_queue() {  # the root lanes one after the other; the later roots are made meanwhile
  local lane i
  local -a prep=()
  for lane in "${rooted[@]:1}"; do
    $SUDO bash tools/run-lane.sh --prepare "$lane" > "$logdir/$lane.log" 2>&1 &
    prep+=($!)
  done
  i=0
  for lane in "${rooted[@]}"; do
    if [ "$i" -gt 0 ]; then wait "${prep[i-1]}" || true; fi   # a failed prepare: run-lane.sh tries again, and says so
    run_one "$lane" "$@"
    i=$((i + 1))
  done
}

follow() {  # follow LANE: stream the lane's log from its start
  : >> "$logdir/$1.log"
  tail -n +1 -f "$logdir/$1.log" & tails+=($!)
}

rooted=()
for lane in "${lanes[@]}"; do [ "$lane" = 0.20 ] || rooted+=("$lane"); done
# Two queues at once when every lane runs, as root (a sudo password prompt needs the terminal: as a user the
# lanes run one after the other). Each queue is a process group of its own: an interrupt stops both (stop_jobs).
if [ ${#lanes[@]} -gt 1 ] && [ "${MM_LANES_SERIAL:-0}" = 0 ] && [ -z "$SUDO" ] && [ ${#rooted[@]} -gt 0 ]; then
  echo "=== lanes ${rooted[*]} run in the background; their logs follow the host lane ===" >&2
  set -m
  roots_queue "$@" & groups+=($!)
  host=""
  if [[ " ${lanes[*]} " == *" 0.20 "* ]]; then
    echo "=== lane 0.20 ===" >&2
    follow 0.20
    run_one 0.20 "$@" & host=$!; groups+=($host)
  fi
  set +m
  [ -z "$host" ] || wait "$host" || true      # a trapped INT / TERM interrupts the wait at once
  shown+=(0.20)
  wait "${groups[0]}" || true
  groups=()
  stop_tails
  for lane in "${rooted[@]}"; do
    echo "=== lane $lane ===" >&2
    cat "$logdir/$lane.log"
    shown+=("$lane")
  done
else
  for lane in "${lanes[@]}"; do
    echo "=== lane $lane ===" >&2
    follow "$lane"
    run_one "$lane" "$@"
    shown+=("$lane")
    stop_tails
  done
fi

echo
echo "=== summary ==="
rc=0 tp=0 tf=0 ts=0
for lane in "${lanes[@]}"; do
  lrc=1 secs=0
  [ -f "$logdir/$lane.rc" ] && read -r lrc secs < "$logdir/$lane.rc"
  [ "$lrc" = 0 ] || rc=1
  info="$(grep -m1 "^lane $lane: FreeCAD" "$logdir/$lane.log" | sed "s/^lane $lane: //" || true)"
  parts=""
  while read -r _ _ part p f s e prc; do
    errs=""; [ "${e:-0}" = 0 ] || errs=" $e errors"          # shown only when pytest reported errors
    if [ "${prc:-0}" != 0 ] && [ $((f + e)) = 0 ]; then        # ended without a failed test: say how
      case "$prc" in 124) errs+=" (no result: timed out, exit 124)" ;; *) errs+=" (exit $prc)" ;; esac
      e=$((e + 1))
    fi
    parts+=" $part $p passed $f failed $s skipped$errs;"
    tp=$((tp + p)); tf=$((tf + f + e)); ts=$((ts + s))
  done < <(grep '^LANE-RESULT ' "$logdir/$lane.log" || true)
  [ -n "$parts" ] || { parts=" no test ran;"; tf=$((tf + 1)); }
  verdict=PASS; [ "$lrc" = 0 ] || verdict=FAIL
  echo "lane $lane ${info:+($info)}:$parts ${secs} s: $verdict"
done
echo "total: $tp passed, $tf failed, $ts skipped"
exit $rc
