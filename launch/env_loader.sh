#!/usr/bin/env bash
# env-loader for <machine> tags: the remote machine sources this workspace, then runs the command.
export PATH=/usr/sbin:/usr/bin:/sbin:/bin:$PATH
WS="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# shellcheck disable=SC1091
source "$WS/devel/setup.bash"
exec "$@"
