#!/usr/bin/env bash
# Set up what is missing, then run the whole test suite (pure core, FreeCAD App, firmware, GUI under Xvfb).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
bash tools/install-deps.sh
export PYTHONDONTWRITEBYTECODE=1
rc=0
/usr/bin/python3 -m pytest -q -p no:cacheprovider tests "$@" || rc=$?
if [ -f tests/run_gui_pytest.py ]; then
  cfg="$(mktemp -d)/user.cfg"
  cp resources/test_user.cfg "$cfg"
  timeout 900 xvfb-run -a -s "-screen 0 1600x1000x24" freecad -u "$cfg" tests/run_gui_pytest.py -M "$PWD" || rc=$?
fi
exit $rc
