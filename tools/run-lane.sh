#!/usr/bin/env bash
# Run one FreeCAD lane:  tools/run-lane.sh 0.20|1.0|1.1 [pytest args...]
#                        tools/run-lane.sh --prepare 1.0|1.1   only make (or refresh) the lane's root
#   0.20  the host (Debian 12's FreeCAD 0.20.2, Python 3.11, numpy 1.24)
#   1.0   a Debian 13 "trixie" root (FreeCAD 1.0, Python 3.13, numpy 2.x)
#   1.1   a Debian testing "forky" root (FreeCAD 1.1, Qt 6, Python 3.14, numpy 2.x)
# Roots live in $METAMATERIAL_LANE_ROOTS (default /var/cache/metamaterial-wb/roots) and are made by
# tools/lane-root.sh when missing or stale. The checkout, /proc, /dev, /dev/pts and /dev/shm are mounted into
# the root for the run and unmounted on every exit path. A root that cannot be made fails the lane.
set -euo pipefail
prepare=""
if [ "${1:-}" = "--prepare" ]; then prepare=1; shift; fi
lane="${1:-}"; [ $# -gt 0 ] && shift
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(dirname "$here")"
case "$lane" in
  0.20) [ -z "$prepare" ] || exit 0       # the host lane has no root
        exec bash "$here/run-suite.sh" 0.20 "$@" ;;
  1.0)  suite=trixie ;;
  1.1)  suite=forky ;;
  *) echo "run-lane: unknown lane '$lane' (allowed: 0.20, 1.0, 1.1)" >&2; exit 2 ;;
esac
[ "$(id -u)" = 0 ] || { echo "run-lane: lane $lane needs root (chroot, mount); run with sudo" >&2; exit 2; }
roots="${METAMATERIAL_LANE_ROOTS:-/var/cache/metamaterial-wb/roots}"
root="$roots/$suite"
mkdir -p "$roots"
exec 9>"$root.lock"          # one run per root at a time (a second waits): mounts and rebuilds never overlap
flock 9
if ! bash "$here/lane-root.sh" "$suite" "$root"; then
  [ -n "$prepare" ] || echo "LANE-RESULT $lane root 0 0 0 1 1"   # (--prepare: the lane run that follows says it)
  echo "run-lane: lane $lane FAILED: the $suite root could not be made" >&2
  exit 1
fi
[ -z "$prepare" ] || exit 0
. "$here/lane-mounts.sh"
child=""
stop_child() {   # end the run inside the root (its own process group) before the mounts go
  if [ -n "$child" ] && kill -0 "$child" 2>/dev/null; then
    kill -TERM -- "-$child" 2>/dev/null || true
    for _ in $(seq 50); do kill -0 "$child" 2>/dev/null || break; sleep 0.1; done
    kill -KILL -- "-$child" 2>/dev/null || true
  fi
}
trap lane_unmount_all EXIT
trap 'stop_child; lane_unmount_all; exit 130' INT
trap 'stop_child; lane_unmount_all; exit 143' TERM
lane_mount_proc "$root"
lane_bind "$root" /dev /dev
lane_bind "$root" /dev/pts /dev/pts
[ -d /dev/shm ] && lane_bind "$root" /dev/shm /dev/shm
lane_bind "$root" "$repo" "$repo"
set +e
setsid chroot "$root" /usr/bin/env -i HOME=/root LANG=C.UTF-8 TERM=dumb CI="${CI:-}" \
  MM_GUI_PYTEST_ARGS="${MM_GUI_PYTEST_ARGS:-}" MM_GUI_ONLY="${MM_GUI_ONLY:-}" MM_APP_ONLY="${MM_APP_ONLY:-}" \
  MM_LANE_PURE="${MM_LANE_PURE:-}" \
  PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin \
  /bin/bash "$repo/tools/run-suite.sh" "$lane" "$@" < /dev/null &
child=$!
wait "$child"
rc=$?
child=""
set -e
exit $rc
