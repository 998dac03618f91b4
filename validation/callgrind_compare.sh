#!/usr/bin/env bash
# Instruction counts (valgrind --tool=callgrind, whole process) of two beadchain binaries on the
# scenes issue 34 names for "performance unchanged": striker, interface_3.0_2.5,
# periodic_decay_2.5_2.555 and disorder_2.5_0.04 (the last two shortened with --until so a
# callgrind run takes seconds, not minutes). Prints old, new and the relative change.
# Usage: validation/callgrind_compare.sh OLD NEW
set -euo pipefail
old=$(realpath "$1") new=$(realpath "$2")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp"
count() { # binary, run args...
  local b=$1
  shift
  valgrind --tool=callgrind --callgrind-out-file="$tmp/cg.out" "$b" run "$@" -q --out "$tmp/r.snap" \
    >/dev/null 2>"$tmp/vg.txt"
  grep -Eo 'Collected : [0-9]+' "$tmp/vg.txt" | awk '{print $3}'
}
printf '%-44s %14s %14s %9s\n' scene old new change
while read -r label args; do
  # shellcheck disable=SC2086
  a=$(count "$old" $args) b=$(count "$new" $args)
  printf '%-44s %14s %14s %+8.3f%%\n' "$label" "$a" "$b" "$(echo "scale=6; ($b - $a) * 100 / $a" | bc)"
done <<'SCENES'
striker striker
interface_3.0_2.5 interface_3.0_2.5
periodic_decay_2.5_2.555(until=2000) periodic_decay_2.5_2.555 --until 2000
disorder_2.5_0.04(until=3000) disorder_2.5_0.04 --until 3000
striker(radau5,1e-6) striker --method radau5 --rtol 1e-6
SCENES
