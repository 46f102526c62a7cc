# shellcheck shell=bash
# Bash completion of `robotica node PACKAGE EXECUTABLE` (as `ros2 run` completes), sourced by
# scripts/env.sh: the names are those of `robotica node --list [PACKAGE]`.
_robotica_complete() {
  local cur=${COMP_WORDS[COMP_CWORD]} names
  COMPREPLY=()
  if [ "${COMP_WORDS[1]}" != node ] || [ "$COMP_CWORD" -lt 2 ] || [ "$COMP_CWORD" -gt 3 ]; then
    return
  fi
  case $cur in -*) return ;; esac
  if [ "$COMP_CWORD" -eq 2 ]; then
    names=$(python3 -m robotica_sim.cli.node 2>/dev/null)
  else
    names=$(python3 -m robotica_sim.cli.node "${COMP_WORDS[2]}" 2>/dev/null)
  fi
  mapfile -t COMPREPLY < <(compgen -W "$names" -- "$cur")
}
complete -o default -F _robotica_complete robotica
