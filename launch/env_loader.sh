#!/usr/bin/env bash
# env-loader for <machine> tags: the remote machine sources this workspace, then runs the command.
export PATH=/usr/sbin:/usr/bin:/sbin:/bin:$PATH
# -P: reached through the package link src/assistive_bringup, ".." must still be the workspace
WS="$(cd -P "$(dirname "${BASH_SOURCE[0]}")" && cd .. && pwd)"
# shellcheck disable=SC1091
source "$WS/devel/setup.bash"
exec "$@"
