#!/usr/bin/env bash
# check_isa_object.sh OBJECT: the fast engine's per-level object defines exactly one global
# symbol (parallax::fast::detail::isa_<level>()) and no dynamic initialiser.
set -euo pipefail
obj="$1"
globals=$(nm --defined-only "$obj" | awk '$2 ~ /^[A-Z]$/ && $2 != "R" && $2 != "D" && $2 != "B" {print $3}')
count=$(printf '%s\n' "$globals" | grep -c . || true)
if [ "$count" -ne 1 ] || ! printf '%s\n' "$globals" | grep -q '^_ZN8parallax4fast6detail[0-9]*isa_'; then
  echo "$obj: expected one global function isa_<level>, found:" >&2
  printf '  %s\n' $globals >&2
  exit 1
fi
if nm "$obj" | grep -q '_GLOBAL__sub_I'; then
  echo "$obj: has a dynamic initialiser (it would run this level's instructions at start-up)" >&2
  exit 1
fi
echo "$obj: one global ($globals), no initialiser"
