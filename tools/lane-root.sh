#!/usr/bin/env bash
# Make, or refresh, the Debian root of one FreeCAD lane:  tools/lane-root.sh SUITE DIR
# The root is a minimal Debian SUITE (mmdebstrap --variant=apt) with the packages of tools/lane-packages.txt
# (a line ending in "[suite,...]" is for those suites only). DIR/.metamaterial-lane records the suite and the
# package list. A root of the same suite whose list grew gets the missing packages with apt inside it; any
# other difference (or a failed install) rebuilds it into DIR.new, swapped in only when complete. A root is
# never deleted while anything is mounted inside it.
set -euo pipefail
suite="$1" dir="$2"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
mapfile -t pkgs < <(sed 's/#.*//' "$here/lane-packages.txt" | awk -v s="$suite" '
  NF == 0 { next }
  { only = ""; if (match($0, /\[[^]]*\]/)) only = substr($0, RSTART + 1, RLENGTH - 2) }
  only == "" || ("," only ",") ~ ("," s ",") { print $1 }')
want="$suite $(printf '%s\n' "${pkgs[@]}" | sort | tr '\n' ' ')"
stamp="$dir/.metamaterial-lane"
have="$(cat "$stamp" 2>/dev/null || true)"
[ "$have" = "$want" ] && exit 0
mounted_below() { findmnt -rn -o TARGET | awk -v d="$1" '$0 == d || index($0, d "/") == 1' ; }
aptopts=()
case "$suite" in
  # the testing/unstable Release files served here can be past their Valid-Until date
  forky|testing|sid|unstable) aptopts+=(-o 'Acquire::Check-Valid-Until=false') ;;
esac

if [ -n "$have" ] && [ "${have%% *}" = "$suite" ]; then   # same suite: add what is missing
  read -r -a old <<< "${have#* }"
  missing=($(comm -13 <(printf '%s\n' "${old[@]}" | sort) <(printf '%s\n' "${pkgs[@]}" | sort)))
  removed=($(comm -23 <(printf '%s\n' "${old[@]}" | sort) <(printf '%s\n' "${pkgs[@]}" | sort)))
  if [ ${#removed[@]} = 0 ] && [ ${#missing[@]} -gt 0 ] && [ -z "$(mounted_below "$dir")" ]; then
    echo "lane-root: adding ${missing[*]} to the $suite root" >&2
    . "$here/lane-mounts.sh"
    trap lane_unmount_all EXIT
    trap 'lane_unmount_all; exit 130' INT
    trap 'lane_unmount_all; exit 143' TERM
    lane_mount_proc "$dir"
    lane_bind "$dir" /dev /dev
    cp /etc/resolv.conf "$dir/etc/resolv.conf" 2>/dev/null || true
    if chroot "$dir" apt-get "${aptopts[@]}" update -qq >&2 &&
       DEBIAN_FRONTEND=noninteractive chroot "$dir" apt-get "${aptopts[@]}" install -y -qq "${missing[@]}" >&2; then
      chroot "$dir" apt-get clean
      echo "$want" > "$stamp"
      exit 0
    fi
    echo "lane-root: adding packages failed; rebuilding the root" >&2
    lane_unmount_all
    trap - EXIT INT TERM
  fi
fi

if [ -n "$(mounted_below "$dir")" ]; then
  echo "lane-root: $dir has mounts inside it; unmount them first:" >&2; mounted_below "$dir" >&2; exit 1
fi
if ! command -v mmdebstrap >/dev/null; then
  SUDO=""; [ "$(id -u)" = 0 ] || SUDO="sudo"
  $SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq mmdebstrap >&2
fi
opts=()
[ ${#aptopts[@]} = 0 ] || opts+=(--aptopt='Acquire::Check-Valid-Until "false"')
mkdir -p "$(dirname "$dir")"
tmp="$dir.new"
mm_pid=""
stop_mm() {  # timeout passes the signal to mmdebstrap's group, KILL after 30 s
  [ -n "$mm_pid" ] || return 0
  kill -TERM "$mm_pid" 2>/dev/null || return 0
  for _ in $(seq 400); do kill -0 "$mm_pid" 2>/dev/null || break; sleep 0.1; done
}
trap 'stop_mm; exit 130' INT
trap 'stop_mm; exit 143' TERM
for attempt in 1 2; do
  [ -z "$(mounted_below "$tmp")" ] || { echo "lane-root: $tmp has mounts inside it" >&2; exit 1; }
  rm -rf "$tmp"
  echo "lane-root: making the $suite root in $dir (attempt $attempt, takes 2-10 min)" >&2
  # timeout runs mmdebstrap in a process group of its own, which a TERM of ours misses: the traps pass it on
  timeout -k 30 1500 mmdebstrap --variant=apt "${opts[@]}" \
    --include="$(IFS=,; echo "${pkgs[*]}")" "$suite" "$tmp" > >(grep -v "^I: " >&2) 2>&1 &
  mm_pid=$!
  rc=0; wait "$mm_pid" || rc=$?     # (set -e: a failed attempt must not end the script)
  mm_pid=""
  if [ "$rc" = 0 ]; then
    echo "$want" > "$tmp/.metamaterial-lane"
    rm -rf "$dir"
    mv "$tmp" "$dir"
    exit 0
  fi
done
rm -rf "$tmp"
echo "lane-root: mmdebstrap could not make the $suite root" >&2
exit 1
