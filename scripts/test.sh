#!/usr/bin/env bash
# Set everything up (if needed) and run the whole test suite. CI runs exactly this (.ci/run).
#   scripts/test.sh                 all tests
#   scripts/test.sh -m "not slow"   skip the end-to-end runs; any pytest arguments pass through
#   scripts/test.sh -n 0            one process instead of two (pytest-xdist; conftest.py gives
#                                   each its own ROS domain ids)
set -eo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
bash "$ROOT/scripts/setup.sh"
# shellcheck disable=SC1091
. "$ROOT/scripts/env.sh"
cd "$ROOT"
exec python -m pytest -n 2 "$@"
