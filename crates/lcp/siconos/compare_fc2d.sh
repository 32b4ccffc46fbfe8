#!/bin/sh
# Runs Siconos numerics' fc2d NSGS (compare_fc2d.c) and moreau-lcp's FC2D solver (the fc2d
# example) on the same files, one after the other in one run, and prints the table of the
# lcp README's "FC2D speed" section: per file and tolerance, each one's time per solve, its
# result, and the ratio Siconos / Moreau.
#
#   crates/lcp/siconos/compare_fc2d.sh [TOLERANCES [SOLVER [FILES...]]]
#
# from the workspace root. TOLERANCES defaults to "1e-4 1e-8", SOLVER (of the example) to
# auto, FILES to Siconos' collection in crates/lcp/tests/data/siconos/fc2d. Needs gcc,
# python3 and Siconos numerics (Debian: libsiconos-numerics-dev). Each solve is repeated
# until about a second has passed (once when one solve takes longer). Siconos' NSGS runs
# at most 100,000 sweeps: at 1e-8 it stalls on the granular files and takes minutes.
set -eu
tolerances=${1:-"1e-4 1e-8"}
solver=${2:-auto}
[ $# -ge 2 ] && shift 2 || shift $#
if [ $# -eq 0 ]; then
  set -- crates/lcp/tests/data/siconos/fc2d/*.dat
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cc -O2 -o "$work/compare_fc2d" crates/lcp/siconos/compare_fc2d.c -I/usr/include/siconos \
  -lsiconos_numerics -lm
cargo build --quiet --release -p moreau-lcp --example fc2d
moreau=target/release/examples/fc2d

# field KEY: reads one JSON object on stdin and prints the value at KEY (dotted path).
field() {
  python3 -c 'import json, sys
v = json.load(sys.stdin)
for k in sys.argv[1].split("."):
    v = v[k]
print(v)' "$1"
}

printf '%-42s %6s %5s | %-11s %9s %9s | %-13s %9s %9s %9s | %7s\n' file contacts tol \
  "siconos" "error" "s/solve" "moreau" "natural" "siconos" "s/solve" "ratio"
for tol in $tolerances; do
  for file in "$@"; do
    name=$(basename "$file")
    # One solve of each first, to size the repeats.
    once=$($moreau --solver "$solver" --tol "$tol" --repeat 1 "$file")
    t=$(echo "$once" | field seconds_per_solve)
    repeat=$(python3 -c "print(max(1, min(10000, int(1.0 / max($t, 1e-7)))))")
    json=$($moreau --solver "$solver" --tol "$tol" --repeat "$repeat" "$file")
    m_status=$(echo "$json" | field status)
    m_method=$(echo "$json" | field method)
    m_nat=$(echo "$json" | field residual.natural)
    m_sic=$(echo "$json" | field residual.siconos)
    m_time=$(echo "$json" | field seconds_per_solve)
    contacts=$(echo "$json" | field contacts)
    s_line=$("$work/compare_fc2d" nsgs "$tol" 1 "$file" 2>/dev/null | tail -n 1)
    s_repeat=$(echo "$s_line" | awk '{t = $12; r = (t > 0) ? int(1.0 / t) : 10000; if (r < 1) r = 1; if (r > 10000) r = 10000; print r}')
    if [ "$s_repeat" -gt 1 ]; then
      s_line=$("$work/compare_fc2d" nsgs "$tol" "$s_repeat" "$file" 2>/dev/null | tail -n 1)
    fi
    s_info=$(echo "$s_line" | awk '{print $6}')
    s_iter=$(echo "$s_line" | awk '{print $8}')
    s_err=$(echo "$s_line" | awk '{print $10}')
    s_time=$(echo "$s_line" | awk '{print $12}')
    ratio=$(python3 -c "t = $m_time; print('%.1f' % ($s_time / t) if t > 0 else '-')")
    printf '%-42s %6s %5s | %-11s %9.2e %9.2e | %-13s %9.2e %9.2e %9.2e | %7s\n' \
      "$name" "$contacts" "$tol" "info=$s_info/$s_iter" "$s_err" "$s_time" \
      "$m_status:$m_method" "$m_nat" "$m_sic" "$m_time" "$ratio"
  done
done
