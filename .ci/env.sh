# Sourced by every project script. Debian's python3 must win over a pyenv one (rostest's scripts
# use `env python3`), and the workspace's devel space is sourced when it exists.
export PATH=/usr/sbin:/usr/bin:/sbin:/bin:$PATH
WS_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
export WS_ROOT
export ROS_PYTHON_VERSION=3
if [ -f "${DEVEL_DIR:-$WS_ROOT/devel}/setup.bash" ]; then
  # catkin's setup scripts read unset variables: allow that even under `set -u`.
  case $- in *u*) _ws_nounset=1; set +u ;; *) _ws_nounset= ;; esac
  # shellcheck disable=SC1091
  source "${DEVEL_DIR:-$WS_ROOT/devel}/setup.bash"
  [ -n "$_ws_nounset" ] && set -u
  unset _ws_nounset
fi
