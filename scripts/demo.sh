#!/usr/bin/env bash
# Set everything up (if needed) and run the demo: a differential-drive robot follows a rounded
# square with pure pursuit, every node a separate process, the whole run recorded to a bag.
#   scripts/demo.sh                   the default scenario, lockstep (faster than real time)
#   scripts/demo.sh --pacing realtime any `robotica run` option passes through
set -eo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
bash "$ROOT/scripts/setup.sh"
# shellcheck disable=SC1091
. "$ROOT/scripts/env.sh"
cd "$ROOT"
exec robotica run demo "$@"
