#!/usr/bin/env bash
# SciPy VODE (the paper's solver) vs beadchain's hybrid engine on the 1000-bead striker chain
# (n = 2.5, m = a = v0 = 1) to wave exit, measured in one invocation. Installs numpy and scipy
# from PyPI into validation/peers/.venv on first use. Prints a markdown table.
# Usage: bash validation/peers/run_vode.sh [N] [T_END]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
n=${1:-1000}
t_end=${2:-868}
if [ ! -x "$here/.venv/bin/python" ]; then
  python3 -m venv "$here/.venv"
  "$here/.venv/bin/pip" install -q numpy scipy
fi
cargo build --release --manifest-path "$root/Cargo.toml" -q
bin="$root/target/release/beadchain"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
printf '[chain]\nbeads = %s\n[initial]\nstriker = 1.0\n[run]\nuntil = %s\n' "$n" "$t_end" > "$tmp/s.toml"
echo "| solver | rtol | atol | wall time (s) | relative energy error |"
echo "|---|---|---|---|---|"
for tol in "1e-8 1e-10" "1e-10 1e-12" "1e-12 1e-14"; do
  set -- $tol
  "$here/.venv/bin/python" "$here/scipy_vode.py" "$n" "$t_end" "$1" "$2" |
    awk '{printf "| SciPy VODE (BDF, banded) | %s | %s | %s | %s |\n", $2, $3, $4, $5}'
done
for r in 1e-6 1e-7 1e-8 1e-9; do
  a=$(python3 -c "print('%g' % ($r/100))")
  out=$("$bin" run "$tmp/s.toml" --rtol "$r" --atol "$a" --out "$tmp/o.snap")
  secs=$(echo "$out" | sed -n 's/.* in \([0-9.]*\) s:.*/\1/p')
  err=$(echo "$out" | sed -n 's/.*relative change \([0-9.e+-]*\)).*/\1/p')
  echo "| beadchain hybrid (radau5) | $r | $a (scaled) | $secs | $err |"
done
