#!/usr/bin/env bash
# Frames and event logs of every preset from two beadchain binaries, compared byte for byte
# (`export` of all frames and of the event log; the snapshot header also holds the command line,
# so whole files differ by the binary's path). Extra arguments go to both runs (e.g. --rtol 1e-4).
# Usage: validation/compare_presets.sh OLD NEW [RUN ARGS...]; exit 1 if any preset differs.
set -euo pipefail
old=$1 new=$2
shift 2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
status=0
for p in $("$new" scenes | awk '{print $1}'); do
  for b in old new; do
    bin=${!b}
    "$bin" run "$p" -q --out "$tmp/$b.snap" "$@" >/dev/null 2>&1 || { echo "$p: $b run failed"; status=1; continue 2; }
    { "$bin" export "$tmp/$b.snap"; "$bin" export "$tmp/$b.snap" --events 2>/dev/null || true; } >"$tmp/$b.txt"
  done
  if cmp -s "$tmp/old.txt" "$tmp/new.txt"; then echo "$p: identical"; else echo "$p: DIFFERS"; status=1; fi
done
exit $status
