#!/usr/bin/env bash
# Run the test suite on the system this runs on (the host, or inside a lane root):
#   tools/run-suite.sh LANE [pytest args...]
# 1. pytest on tests/ with /usr/bin/python3 (pure core + FreeCAD App tests; firmware tests only on the host lane;
#    the whole suite on lane 1.0 leaves the pure-core tests to 0.20 and 1.1, the oldest and newest Python / numpy,
#    unless MM_LANE_PURE=1);
# 2. the GUI tests inside a real FreeCAD under Xvfb (tests/run_gui_pytest.py).
# Ends with one line 'LANE-RESULT <lane> <part> <passed> <failed> <skipped> <errors> <rc>' per part.
set -uo pipefail
lane="$1"; shift
cd "$(dirname "${BASH_SOURCE[0]}")/.."
export PYTHONDONTWRITEBYTECODE=1
py=/usr/bin/python3
args=(-q -p no:cacheprovider)
if [ "$lane" != 0.20 ]; then
  args+=(--ignore=tests/firmware)      # AVR toolchain and simavr live on the host lane
fi
logs="$(mktemp -d)"
trap 'rm -rf "$logs"' EXIT
if [ -z "${XDG_RUNTIME_DIR:-}" ]; then   # Qt wants one; a lane root's clean environment has none
  export XDG_RUNTIME_DIR="$logs/xdg-runtime"; mkdir -m 700 "$XDG_RUNTIME_DIR"
fi
bounded_pid=""
bounded() {  # bounded SECONDS LOG CMD...: CMD under timeout, its output to ours and to LOG. timeout runs CMD in a
             # process group of its own, which an INT / TERM of this script's group misses: the traps pass it on
  local secs="$1" log="$2" out teepid rc; shift 2
  exec {out}> >(tee "$log"); teepid=$!
  timeout -k 10 "$secs" "$@" >&"$out" 2>&1 &
  bounded_pid=$!
  exec {out}>&-
  wait "$bounded_pid"; rc=$?
  bounded_pid=""
  wait "$teepid" 2>/dev/null     # the log is complete before it is read
  return "$rc"
}
stop_bounded() {  # timeout passes the signal to its whole group (xvfb-run, Xvfb, FreeCAD), KILL after 10 s
  [ -n "$bounded_pid" ] || return 0
  kill -TERM "$bounded_pid" 2>/dev/null || return 0
  for _ in $(seq 120); do kill -0 "$bounded_pid" 2>/dev/null || break; sleep 0.1; done
}
trap 'stop_bounded; exit 130' INT
trap 'stop_bounded; exit 143' TERM
args+=(-rfEs)                           # failures, errors and the reason of every skip in the summary
count() {  # count WORD FILE: the number before WORD on pytest's closing line
  grep -E '^=*.* in [0-9.]+s' "$2" | tail -n1 | grep -oE "[0-9]+ $1" | awk '{print $1}' | head -n1
}
result() {  # result PART LOG RC
  local p f s e
  p=$(count passed "$2"); f=$(count failed "$2"); s=$(count skipped "$2"); e=$(count error "$2")
  echo "LANE-RESULT $lane $1 ${p:-0} ${f:-0} ${s:-0} ${e:-0} $3"
}
$py -c 'import sys; sys.path.append("/usr/lib/freecad-python3/lib"); import FreeCAD, numpy, scipy;
print("lane %s: FreeCAD %s, Python %s, numpy %s, scipy %s" % (sys.argv[1], ".".join(FreeCAD.Version()[:3]),
      sys.version.split()[0], numpy.__version__, scipy.__version__))' "$lane" || true
if [ -n "${MM_GUI_ONLY:-}" ]; then       # developers: the GUI part only (MM_GUI_PYTEST_ARGS selects tests)
  echo "MM_GUI_ONLY: app tests not run" > "$logs/app.log"; rc_app=0
else
  where=(tests)                         # test paths among the arguments replace the whole tests/ folder
  for a in "$@"; do [[ "$a" != -* && -e "${a%%::*}" ]] && where=(); done
  if [ "$lane" = 1.0 ] && [ $# -eq 0 ] && [ -z "${MM_LANE_PURE:-}" ]; then   # the whole suite, no selection
    args+=(-m "not pure")               # the pure-core tests run on 0.20 and 1.1 (docs/testing.md)
    echo "lane 1.0: the pure-core tests run on lanes 0.20 and 1.1 (MM_LANE_PURE=1 runs them here too)"
  fi
  args+=(--durations=20)                # the slowest tests, for the CI time budget
  $py -m pytest "${args[@]}" "${where[@]}" "$@" 2>&1 | tee "$logs/app.log"
  rc_app=${PIPESTATUS[0]}
fi
rc_gui=0
if [ -f tests/run_gui_pytest.py ] && [ -z "${MM_APP_ONLY:-}" ]; then   # MM_APP_ONLY=1: developers skip the GUI part
  cfgdir="$(mktemp -d)"; cp resources/test_user.cfg "$cfgdir/user.cfg"
  case "$lane" in 0.20) xn=99 ;; 1.0) xn=120 ;; *) xn=140 ;; esac   # lanes run at once; each root has its own /tmp,
  # so xvfb-run -a cannot see another lane's display: the numbers differ per lane
  bounded 1800 "$logs/gui.log" xvfb-run -a -n "$xn" -s "-screen 0 1600x1000x24" freecad -u "$cfgdir/user.cfg" \
    tests/run_gui_pytest.py -M "$PWD"
  rc_gui=$?
  rm -rf "$cfgdir"
  result gui "$logs/gui.log" "$rc_gui" > "$logs/gui.res"
fi
result app "$logs/app.log" "$rc_app"
[ -f "$logs/gui.res" ] && cat "$logs/gui.res"
[ "$rc_app" = 0 ] && [ "$rc_gui" = 0 ]
