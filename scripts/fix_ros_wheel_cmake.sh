#!/usr/bin/env bash
# The ros-jazzy-* wheels' CMake exports name the wheel build image's Python and NumPy include
# directories (/opt/python/cpXY-cpXY/...). Point them at this venv's, so that colcon can build
# robotica_msgs against the wheels. Idempotent. See shared/reference/ros2-pip-toolchain.md §2.
set -eo pipefail
: "${VIRTUAL_ENV:?activate the venv first}"
PYINC=$(python -c "import sysconfig; print(sysconfig.get_paths()['include'])")
NPINC=$(python -c "import numpy; print(numpy.get_include())")
TAG=$(python -c "import sys; v = sys.version_info; print(f'cp{v[0]}{v[1]}-cp{v[0]}{v[1]}')")
PYV=$(python -c "import sys; v = sys.version_info; print(f'python{v[0]}.{v[1]}')")
# grep exits 1 when everything is already fixed (a re-run): that is not an error.
{ grep -rlF "/opt/python/$TAG" "$VIRTUAL_ENV/share" --include='*.cmake' || true; } | while read -r f; do
  sed -i -e "s#/opt/python/$TAG/include/$PYV#$PYINC#g" \
         -e "s#/opt/python/$TAG/lib/$PYV/site-packages/numpy/_core/include#$NPINC#g" "$f"
done
