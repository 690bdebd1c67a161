#!/bin/bash
# Two builds of WireNet side by side on the YADE punch (docs/examples/yade_punch.toml), one pinned
# to each core with taskset, the cores swapped every round: both see the same host at the same
# time, so a ratio of a few per cent is measurable where consecutive runs drift by 5 %.
#
#   tests/bench/ab_side_by_side.sh OLD_BUILD NEW_BUILD [ROUNDS] [TRAVEL]
#
# OLD_BUILD and NEW_BUILD hold bin/liggghts and bin/wirenet-gen (copies of build/bin of two
# commits). Prints the loop time per step of each (LIGGGHTS' "Loop time" lines summed) and
# new/old per round. Run from the repository root; work folders under ${TMPDIR:-/tmp}.
set -euo pipefail
old=$1 new=$2 rounds=${3:-4} travel=${4:-0.06}
work=${TMPDIR:-/tmp}/wirenet_ab
py=/usr/bin/python3

run() {  # label build core
  rm -rf "$work/$1"
  WIRENET_BUILD=$2 PYTHONPATH=$PWD taskset -c "$3" "$py" -P -m runner run docs/examples/yade_punch.toml \
    --np 1 --set punch.travel="$travel" --out "$work/$1" > "$work/$1.log" 2>&1
}
ms() { awk '/^Loop time/{t += $4; n += $9} END {printf "%.4f", 1000 * t / n}' "$work/$1/yade_punch/run/log.lammps"; }

mkdir -p "$work"
for r in $(seq 1 "$rounds"); do
  if [ $((r % 2)) = 1 ]; then co=0 cn=1; else co=1 cn=0; fi
  run old "$old" $co & run new "$new" $cn & wait
  o=$(ms old) n=$(ms new)
  echo "round $r: old $o ms, new $n ms per step, new/old $("$py" -c "print(f'{$n / $o:.3f}')")"
done
