#!/usr/bin/env bash
# Renders every registered method at its quick knobs (`causticbench describe M --quick-knobs`) on every
# shipped scene it accepts, at a small resolution, into OUT/<method>/<scene>/. For refactors that must
# not change any output: run it before and after, then compare with `scripts/render_every_method.sh
# --compare BEFORE AFTER` (cmp of every caustic.exr). Scenes a method refuses (exit 2) are listed as such.
# Usage: scripts/render_every_method.sh OUT [causticbench binary]
#        scripts/render_every_method.sh --compare BEFORE AFTER
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "${1:-}" = "--compare" ]; then
  before=$2 after=$3 same=0 differ=0 missing=0
  while IFS= read -r file; do
    relative=${file#"$before"/}
    if [ ! -f "$after/$relative" ]; then echo "missing after: $relative"; missing=$((missing + 1));
    elif cmp -s "$file" "$after/$relative"; then same=$((same + 1));
    else echo "differs: $relative"; differ=$((differ + 1)); fi
  done < <(find "$before" -name caustic.exr | sort)
  echo "$same identical, $differ differ, $missing missing (of caustic.exr under $before)"
  [ "$differ" -eq 0 ] && [ "$missing" -eq 0 ]
  exit
fi
out=${1:?usage: scripts/render_every_method.sh OUT [binary]}
binary=${2:-build/apps/causticbench}
methods=$("$binary" list | awk '/^Methods/ {on = 1; next} on && NF == 0 {exit} on {print $1}')
for method in $methods; do
  # external runs a program of yours: it has no quick setting to render with.
  [ "$method" = external ] && continue
  knobs=()
  while IFS= read -r knob; do [ -n "$knob" ] && knobs+=(--set "$knob"); done < <("$binary" describe "$method" --quick-knobs)
  for scene in configs/scenes/*.yaml; do
    name=$(basename "$scene" .yaml)
    set +e
    "$binary" --quiet render "$scene" --method "$method" "${knobs[@]}" --resolution 48x36 --threads 2 \
      --out "$out/$method/$name" >"$out.log.tmp" 2>&1
    status=$?
    set -e
    case $status in
      0) echo "$method $name: rendered" ;;
      2) echo "$method $name: refused ($(tail -n 1 "$out.log.tmp" | cut -c1-120))"; rm -rf "${out:?}/$method/$name" ;;
      *) echo "$method $name: FAILED with exit $status"; cat "$out.log.tmp"; exit 1 ;;
    esac
  done
done
rm -f "$out.log.tmp"
