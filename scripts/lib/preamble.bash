# Sourced by the bash scripts in scripts/ (after `set -euo pipefail`):
#   source "$(dirname "${BASH_SOURCE[0]}")/lib/preamble.bash"
# root: the workspace; caller: the folder the script was called from (relative paths given to a
# script are the caller's); Debian's /usr/bin first on PATH (a pyenv python3 lacks catkin_pkg).
# shellcheck shell=bash
root="$(cd "$(dirname "${BASH_SOURCE[1]}")/.." && pwd)"
caller="$PWD"
export PATH="/usr/bin:/bin:$PATH"

# A path as the caller meant it.
absolute() { case "$1" in /*) echo "$1" ;; *) echo "$caller/$1" ;; esac; }

# The workspace's ROS environment (devel/, or AAR_DEVEL's); Debian's /etc/catkin/profile.d
# scripts read unset variables, so -u is off while it is sourced.
source_devel() {
  set +u
  # shellcheck disable=SC1090,SC1091
  source "$root/${AAR_DEVEL:-devel}/setup.bash"
  set -u
}
