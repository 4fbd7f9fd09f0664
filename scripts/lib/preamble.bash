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
# scripts read unset variables, so -u is off while it is sourced. --if-built: nothing when the
# workspace is not built yet (a script that builds it afterwards).
source_devel() {
  local setup="$root/${AAR_DEVEL:-devel}/setup.bash"
  [ "${1:-}" = --if-built ] && [ ! -f "$setup" ] && return 0
  set +u
  # shellcheck disable=SC1090,SC1091
  source "$setup"
  set -u
}

# Numeric arguments, checked before anything starts; each exits 2 naming the flag and the value.
#   nonnegative FLAG VALUE    a number >= 0 (e.g. a path time)
#   whole FLAG VALUE [MIN]    a whole number >= MIN (default 0), at most 9 digits
# Numbers: decimal, with an exponent if wanted (0.25, 2.5e-1). A number above 0 (a rate) is the
# Python scripts' only (scripts/campaign/arguments.py's positive).
refuse_argument() { echo "$(basename "$0"): $1 takes $2, not '$3'" >&2; exit 2; }
number_re='^([0-9]+\.?[0-9]*|\.[0-9]+)([eE][-+]?[0-9]+)?$'
nonnegative() {
  [[ "$2" =~ $number_re ]] || refuse_argument "$1" "a number of at least 0" "$2"
}
whole() {
  [[ "$2" =~ ^[0-9]{1,9}$ && "$2" -ge "${3:-0}" ]] ||
    refuse_argument "$1" "a whole number of at least ${3:-0}" "$2"
}
