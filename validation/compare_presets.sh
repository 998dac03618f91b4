#!/usr/bin/env bash
# Every preset run by two beadchain binaries, compared byte for byte: the snapshot files (both
# binaries are run through one symlink path with the same arguments, so the command line in the
# header is the same), and the `export` of all frames and of the event log. Extra arguments go to
# both runs (e.g. --rtol 1e-4). Both run with BEADCHAIN_NO_BUILD_COMMIT=1 (for byte comparisons
# across builds: the snapshot then holds no build commit; binaries older than the build commit
# ignore it), and the export's provenance comment lines (`#`, which older binaries do not write)
# are left out of the comparison.
# Usage: validation/compare_presets.sh OLD NEW [RUN ARGS...]; exit 1 if any preset differs.
set -euo pipefail
old=$(realpath "$1") new=$(realpath "$2")
shift 2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
status=0
export BEADCHAIN_NO_BUILD_COMMIT=1
cd "$tmp"
known=" $("$old" scenes | awk '{print $1}' | tr '\n' ' ') "
for p in $("$new" scenes | awk '{print $1}'); do
  # A preset the old binary does not have (added since) has nothing to compare against.
  [[ "$known" == *" $p "* ]] || { echo "$p: new preset (not in OLD), skipped"; continue; }
  fails=0
  for b in old new; do
    ln -sf "${!b}" "$tmp/beadchain"
    rm -f "$b.snap" "$b.txt" "$b.err"
    if ! "$tmp/beadchain" run "$p" -q --out run.snap "$@" >/dev/null 2>"$b.err"; then
      fails=$((fails + 1))
      continue
    fi
    mv run.snap "$b.snap"
    { "$tmp/beadchain" export "$b.snap"; "$tmp/beadchain" export "$b.snap" --events 2>/dev/null || true; } | grep -v '^#' >"$b.txt" || true
  done
  # A run both binaries refuse with the same message (e.g. a hard-contact preset with
  # --engine dense) is the same behaviour; one refusing alone is a difference.
  if [ "$fails" = 2 ] && cmp -s old.err new.err; then
    echo "$p: both refuse, same message: $(head -c 120 new.err)"
    continue
  elif [ "$fails" != 0 ]; then
    echo "$p: run failed ($fails of 2): $(head -c 200 old.err new.err 2>/dev/null | tr '\n' ' ')"
    status=1
    continue
  fi
  if cmp -s old.snap new.snap && cmp -s old.txt new.txt; then
    echo "$p: identical (snapshot bytes, frames, events)"
  else
    echo "$p: DIFFERS"; status=1
  fi
done
exit $status
