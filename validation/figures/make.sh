#!/usr/bin/env bash
# Regenerates the figures of validation/REPORT.md with `beadchain run` + `beadchain plot`
# (about 30 s; snapshots go to a scratch directory). Needs a TrueType font for the text
# (fonts-dejavu-core, or $BEADCHAIN_FONT).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$here/../.."
# $BEADCHAIN: an already built binary to use instead of building one
if [ -z "${BEADCHAIN:-}" ]; then
  cargo build --release -q --manifest-path "$root/Cargo.toml"
fi
bc="${BEADCHAIN:-$root/target/release/beadchain}"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
run() { "$bc" run "$1" --out "$tmp/$1.snap" "${@:2}" > /dev/null; }

# Interfaces (paper Figs. 4-6).
run interface_3.0_3.5 --every 100
"$bc" plot spacetime "$tmp/interface_3.0_3.5.snap" --scale log --out "$here/interface_3.0_3.5_spacetime_log.png"
"$bc" plot trace "$tmp/interface_3.0_3.5.snap" --beads 48,49,50,51 --t 5000:50000 --out "$here/interface_3.0_3.5_trace.png"
run interface_3.0_2.5 --every 10
"$bc" plot spacetime "$tmp/interface_3.0_2.5.snap" --out "$here/interface_3.0_2.5_spacetime.png"
"$bc" plot spacetime "$tmp/interface_3.0_2.5.snap" --scale log --out "$here/interface_3.0_2.5_spacetime_log.png"
"$bc" plot energy "$tmp/interface_3.0_2.5.snap" --from 90 --to 140 --log --out "$here/interface_3.0_2.5_energy.png"
# one fit per side of the interface at bead 50, never across it
"$bc" plot energy "$tmp/interface_3.0_2.5.snap" --interface 50 --log --out "$here/interface_3.0_2.5_energy_sides.png"
# side by side, one shared colour scale
run interface_3.0_3.5 --every 10
"$bc" plot spacetime "$tmp/interface_3.0_2.5.snap" "$tmp/interface_3.0_3.5.snap" --scale log --width 1200 \
  --title "Interfaces n = 3.0 | 2.5 and n = 3.0 | 3.5 (log colour scale)" --out "$here/interfaces_panels.png"
# a physical scene in SI units
run hertz_spheres_physical
"$bc" plot trace "$tmp/hertz_spheres_physical.snap" --beads 10,50,90 --units si --out "$here/hertz_spheres_physical_trace_si.png"

# Periodic chains (Figs. 10, 11, 13, 14).
for p in periodic_2.5_3.0 periodic_decay_2.5_2.555 periodic_breather_2.5_2.635 periodic_breather_4.0_5.0; do
  run "$p"
  "$bc" plot spacetime "$tmp/$p.snap" --out "$here/${p}_spacetime.png"
done
"$bc" plot energy "$tmp/periodic_decay_2.5_2.555.snap" --log --out "$here/periodic_decay_2.5_2.555_energy.png"

# Disorder: exponential decay of the leading wave (Fig. 20).
run disorder_2.5_0.04
"$bc" plot energy "$tmp/disorder_2.5_0.04.snap" --from 25 --log --out "$here/disorder_2.5_0.04_energy.png"

# Composite interfaces (Fig. 25) from the table of `paper_validation composite`.
# (y = log2(m2/m1), added as a column, so the log-spaced mass ratios are evenly spaced.)
awk -F, 'NR == 1 { print $0 ",log2_mass_ratio"; next } { print $0 "," log($2) / log(2) }' \
  "$here/../data/composite.csv" > "$tmp/composite.csv"
"$bc" plot map "$tmp/composite.csv" --x dn --y log2_mass_ratio --z e_refl --contour 0.01 \
  --title "Composite interfaces: reflected energy over (Δn, m2/m1)" \
  --xlabel "Δn = n2 − n1" --ylabel "log2(m2/m1)" --zlabel "E_refl / E_in" \
  --out "$here/composite_map.png"
echo "figures written to $here"
