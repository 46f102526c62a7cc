# shellcheck shell=bash
# Source this before running anything of robotica:   . scripts/env.sh
#
# Every ROS process of this project must start with this environment:
# - ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST: DDS discovery stays on this machine (Fast DDS's
#   defaults multicast on the external interface). Users on a real robot network change this one
#   setting (and FASTRTPS_DEFAULT_PROFILES_FILE) after sourcing.
# - FASTRTPS_DEFAULT_PROFILES_FILE: loopback + shared-memory transports only, with fast initial
#   announcements (discovery in < 1 s instead of up to 2.7 s).
# - ROS_DOMAIN_ID: one per shell (a run's own unless already set), so parallel runs don't mix.
# - ROS_LOG_DIR inside the workspace, the venv and the colcon install overlay.
ROBOTICA_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]:-$0}")/.." && pwd)
export ROBOTICA_ROOT
if [ ! -f "$ROBOTICA_ROOT/ros2_ws/install/setup.bash" ]; then
  echo "robotica: not set up yet; run scripts/setup.sh first" >&2
  return 1 2>/dev/null || exit 1
fi
# shellcheck disable=SC1091
. "$ROBOTICA_ROOT/.venv/bin/activate"
case ":$PATH:" in *":$ROBOTICA_ROOT/bin:"*) ;; *) export PATH=$ROBOTICA_ROOT/bin:$PATH ;; esac
export AMENT_PREFIX_PATH=$VIRTUAL_ENV${AMENT_PREFIX_PATH:+:$AMENT_PREFIX_PATH}
export ROS_DISTRO=jazzy
unset ROS_LOCALHOST_ONLY   # deprecated; when set it overrides the discovery range
export ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST
export FASTRTPS_DEFAULT_PROFILES_FILE=$ROBOTICA_ROOT/config/fastdds_localhost.xml
export ROS_DOMAIN_ID=${ROS_DOMAIN_ID:-$((RANDOM % 100 + 1))}
# ROS 2 takes 0-232; above 101 the DDS ports enter Linux's ephemeral range (docs/scenarios.md).
case $ROS_DOMAIN_ID in
  *[!0-9]*) _robotica_domain=bad ;;
  *) if [ "${#ROS_DOMAIN_ID}" -gt 3 ] || [ "$ROS_DOMAIN_ID" -gt 232 ]; then _robotica_domain=bad
     elif [ "$ROS_DOMAIN_ID" -gt 101 ]; then _robotica_domain=high
     else _robotica_domain=ok; fi ;;
esac
if [ "$_robotica_domain" = bad ]; then
  echo "robotica: ROS_DOMAIN_ID must be an integer in 0-232, got '$ROS_DOMAIN_ID'" >&2
  unset _robotica_domain
  return 1 2>/dev/null || exit 1
elif [ "$_robotica_domain" = high ]; then
  echo "robotica: warning: ROS_DOMAIN_ID $ROS_DOMAIN_ID > 101: its DDS ports lie in the" \
    "ephemeral port range; use 0-101 if discovery fails (docs/scenarios.md)" >&2
fi
unset _robotica_domain
export ROS_LOG_DIR=${ROS_LOG_DIR:-$ROBOTICA_ROOT/ros2_ws/log/ros}
case $- in *u*) _robotica_nounset=1 ;; *) _robotica_nounset= ;; esac
set +u   # colcon's setup.bash reads unset variables
# shellcheck disable=SC1091
. "$ROBOTICA_ROOT/ros2_ws/install/setup.bash"
if [ -n "$_robotica_nounset" ]; then set -u; fi
unset _robotica_nounset
# Completion of `robotica node PACKAGE EXECUTABLE` (bash; other shells go without).
# shellcheck disable=SC1091
if [ -n "${BASH_VERSION:-}" ]; then . "$ROBOTICA_ROOT/scripts/completion.bash"; fi
