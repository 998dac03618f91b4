#!/usr/bin/env bash
# The full paper reproduction (validation/REPORT.md): runs every experiment of
# benches/paper_validation.rs into validation/out_<name>.txt (data tables into validation/data/)
# and prints each one's wall time. 275 s on the idle 2-core development machine, plus the
# build (disorder N = 1000 is 172 s of it). The reduced version is `beadchain validate --quick` (seconds).
#   bash validation/regenerate.sh            # everything
#   bash validation/regenerate.sh grid timings   # only these (names as below)
set -euo pipefail
cd "$(dirname "$0")"
all=(interface grid impurity periodic disorder disorder_1000 wavelength timings impurity_examples
     appendix_a appendix_b periodic4 pairwise breathing transfer composite)
want=("$@")
[ ${#want[@]} -eq 0 ] && want=("${all[@]}")
cargo bench --bench paper_validation --no-run -q
total=0
for name in "${want[@]}"; do
  case "$name" in
    disorder) args=(disorder 300) ;;
    disorder_1000) args=(disorder 1000) ;;
    *) args=("$name") ;;
  esac
  start=$(date +%s%N)
  if ! cargo bench -q --bench paper_validation -- "${args[@]}" > "out_$name.txt.tmp" 2>&1; then
    rm -f "out_$name.txt.tmp"
    echo "regenerate: experiment '$name' failed" >&2
    exit 1
  fi
  mv "out_$name.txt.tmp" "out_$name.txt"
  ms=$(( ($(date +%s%N) - start) / 1000000 ))
  total=$(( total + ms ))
  printf '%-18s %6d.%01d s  -> validation/out_%s.txt\n' "$name" $((ms / 1000)) $((ms % 1000 / 100)) "$name"
done
printf '%-18s %6d.%01d s\n' total $((total / 1000)) $((total % 1000 / 100))
