#!/usr/bin/env bash
# Exact solitary waves (issue 35 part 1, docs/studies.md): runs tests/solitary.rs with its
# measurements printed, including the ignored `wide_validation` (300-bead travel for
# n = 2.1, 2.5, 3, 4, 6, 8 at v_m = 1e-3, 1, 1e3, and the hybrid engine), and writes them to
# validation/out_solitary.txt. About 30 s after the build on the 2-core development machine.
#   bash validation/solitary.sh
set -euo pipefail
cd "$(dirname "$0")/.."
out=validation/out_solitary.txt
cargo test --release --test solitary --no-run -q
cargo test --release --test solitary -- --include-ignored --nocapture --test-threads 1 2>&1 \
  | sed -E "s/^test [a-z_0-9]+ \.\.\. //" \
  | grep -E '^(n |  |head-on|hybrid|behind|test result)' | tee "$out"
echo "wrote $out"
