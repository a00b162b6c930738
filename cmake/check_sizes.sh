#!/usr/bin/env bash
# Structure limits of the project's own code (docs/architecture.md): no source file over 800
# lines, no function over 150 lines. Tests, generated code and vendor stand-ins are exempt.
# Function extents come from universal-ctags (--fields=+ne). Prints every breach; exit 1 if any.
set -euo pipefail
cd "$(dirname "$0")/.."
max_file_lines=800
max_function_lines=150
status=0
files=$(git ls-files '*.cpp' '*.hpp' '*.h' | grep -v -E '^tests/|/golden/|^hls/compat/' || true)
for f in $files; do
  n=$(wc -l < "$f")
  if [ "$n" -gt "$max_file_lines" ]; then
    echo "$f: $n lines (limit $max_file_lines)"
    status=1
  fi
done
# shellcheck disable=SC2086
while IFS=$'\t' read -r name file start end; do
  len=$((end - start + 1))
  if [ "$len" -gt "$max_function_lines" ]; then
    echo "$file:$start: function $name is $len lines (limit $max_function_lines)"
    status=1
  fi
done < <(ctags -x --_xformat='%N	%F	%n	%e' --kinds-C++=f --fields=+ne --language-force=C++ $files 2>/dev/null)
exit $status
