#!/usr/bin/env bash
# Install whatever the project needs and is missing (Debian 12, run as root or with sudo).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
SUDO=""
[ "$(id -u)" = 0 ] || SUDO="sudo"
mapfile -t pkgs < <(grep -v '^\s*#' "$here/apt-packages.txt" | awk 'NF{print $1}')
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing Debian packages: ${missing[*]}" >&2
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${missing[@]}" >&2
fi
mapfile -t pips < <(grep -v '^\s*#' "$here/pip-requirements.txt" | awk 'NF{print $1}')
if [ ${#pips[@]} -gt 0 ]; then
  need=()
  for spec in "${pips[@]}"; do
    mod="${spec%%[<>=!~]*}"
    /usr/bin/python3 -m pip show -q "$mod" >/dev/null 2>&1 || need+=("$spec")
  done
  if [ ${#need[@]} -gt 0 ]; then
    echo "installing PyPI packages: ${need[*]}" >&2
    $SUDO /usr/bin/python3 -m pip install -q --break-system-packages --root-user-action=ignore "${need[@]}" >&2
  fi
fi
# optional accelerators: best effort, never fatal
if [ "${METAMATERIAL_NO_OPTIONAL:-0}" != 1 ]; then
  mapfile -t opts < <(grep -v '^\s*#' "$here/pip-optional.txt" | awk 'NF{print $1}')
  for spec in "${opts[@]}"; do
    mod="${spec%%[<>=!~]*}"
    /usr/bin/python3 -m pip show -q "$mod" >/dev/null 2>&1 && continue
    mapfile -t odeps < <(grep -v '^\s*#' "$here/apt-optional.txt" | awk 'NF{print $1}')
    echo "installing optional $spec (failure is not fatal)" >&2
    { DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${odeps[@]}" >&2 &&
      $SUDO /usr/bin/python3 -m pip install -q --break-system-packages --root-user-action=ignore \
        --no-build-isolation "$spec" >&2; } || echo "warning: optional $spec not installed; falling back" >&2
  done
fi
