#!/usr/bin/env bash
# The "changed nothing" check of a refactor (issue 34): every preset run by the binary before
# and the binary after, compared byte for byte (snapshot files, frames, event log;
# validation/compare_presets.sh), at the default settings and across tolerances, engines and
# methods, and with an output selection. Runs both binaries refuse with the same message count
# as the same.
# Usage: validation/refactor_matrix.sh OLD NEW; exit 1 if any run differs. About 20 minutes
# on 2 cores.
set -euo pipefail
here=$(dirname "$(realpath "$0")")
status=0
while read -r args; do
  echo "== run args: ${args:-(defaults)}"
  # shellcheck disable=SC2086
  out=$("$here/compare_presets.sh" "$1" "$2" $args) || status=1
  echo "$out" | grep -v ": identical" || true
  echo "$(echo "$out" | grep -c ": identical") identical, $(echo "$out" | grep -c ": both refuse") refused by both"
done <<'ARGS'

--rtol 1e-4
--rtol 1e-10
--engine dense
--engine dense --rtol 1e-4
--method dop853
--method radau5 --rtol 1e-6
--method verlet --rtol 1e-3
--beads 0:3 --fields v
ARGS
exit $status
