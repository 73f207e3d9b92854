#!/usr/bin/env bash
# Records files that a tool of this project wrote into a stickslip results folder as the run's own: their names go
# into the folder's manifest (.stickslip-output), so the next `stickslip run --out DIR` replaces them with the rest
# of the folder instead of refusing to. Name exactly what the tool wrote: a folder ("snapshots") and each file in it
# ("snapshots/step-000010.png"); anything else in a claimed folder stays the user's, and the folder is then kept.
# A folder without a manifest (not a results folder) is left as it is.
# Usage: scripts/claim-results-files.sh RESULTS_DIR NAME...      (each NAME relative to RESULTS_DIR)
set -euo pipefail
if [ $# -lt 1 ] || [ "$1" = "--help" ] || [ "$1" = "-h" ]; then
  sed -n '2,7p' "$0" | sed 's/^# \{0,1\}//'
  [ $# -ge 1 ] && exit 0 || exit 2
fi
manifest="$1/.stickslip-output"
shift
# only a manifest that lists its files (it starts with its header; older stickslip wrote a bare marker)
[ -f "$manifest" ] && [ "$(head -c 1 "$manifest")" = "#" ] || exit 0
for name in "$@"; do
  grep -qxF -- "$name" "$manifest" || printf '%s\n' "$name" >>"$manifest"
done
