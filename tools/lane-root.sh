#!/usr/bin/env bash
# Make, or refresh, the Debian root of one FreeCAD lane:  tools/lane-root.sh SUITE DIR
# The root is a minimal Debian SUITE (mmdebstrap --variant=apt) with the packages of tools/lane-packages.txt.
# DIR/.metamaterial-lane records the suite and the package list; a root whose record differs is rebuilt into
# DIR.new and swapped in only when complete. Never deletes a root while anything is mounted inside it.
set -euo pipefail
suite="$1" dir="$2"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
mapfile -t pkgs < <(grep -v '^\s*#' "$here/lane-packages.txt" | awk 'NF{print $1}')
want="$suite $(printf '%s\n' "${pkgs[@]}" | sort | tr '\n' ' ')"
stamp="$dir/.metamaterial-lane"
if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$want" ]; then
  exit 0
fi
mounted_below() { findmnt -rn -o TARGET | awk -v d="$1" '$0 == d || index($0, d "/") == 1' ; }
if [ -n "$(mounted_below "$dir")" ]; then
  echo "lane-root: $dir has mounts inside it; unmount them first:" >&2; mounted_below "$dir" >&2; exit 1
fi
if ! command -v mmdebstrap >/dev/null; then
  SUDO=""; [ "$(id -u)" = 0 ] || SUDO="sudo"
  $SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq mmdebstrap >&2
fi
opts=()
case "$suite" in
  # the testing/unstable Release files served here can be past their Valid-Until date
  forky|testing|sid|unstable) opts+=(--aptopt='Acquire::Check-Valid-Until "false"') ;;
esac
mkdir -p "$(dirname "$dir")"
tmp="$dir.new"
for attempt in 1 2; do
  [ -z "$(mounted_below "$tmp")" ] || { echo "lane-root: $tmp has mounts inside it" >&2; exit 1; }
  rm -rf "$tmp"
  echo "lane-root: making the $suite root in $dir (attempt $attempt, takes 1-4 min)" >&2
  if timeout 1500 mmdebstrap --variant=apt "${opts[@]}" \
       --include="$(IFS=,; echo "${pkgs[*]}")" "$suite" "$tmp" 2>&1 | { grep -v "^I: " >&2 || true; }; then
    echo "$want" > "$tmp/.metamaterial-lane"
    rm -rf "$dir"
    mv "$tmp" "$dir"
    exit 0
  fi
done
rm -rf "$tmp"
echo "lane-root: mmdebstrap could not make the $suite root" >&2
exit 1
