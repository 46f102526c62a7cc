#!/usr/bin/env bash
# Set everything up (if needed) and run the whole test suite. CI runs exactly this (.ci/run).
#   scripts/test.sh                 all tests
#   scripts/test.sh -m "not slow"   skip the end-to-end runs; any pytest arguments pass through
#   scripts/test.sh -n 2 --dist loadgroup   two processes (pytest-xdist; conftest.py gives each its
#                                   own ROS domain ids): faster, but the 1 kHz arm run and the
#                                   real-time fault runs starve beside the other worker's tests
set -eo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
bash "$ROOT/scripts/setup.sh"
# shellcheck disable=SC1091
. "$ROOT/scripts/env.sh"
cd "$ROOT"
exec python -m pytest "$@"
