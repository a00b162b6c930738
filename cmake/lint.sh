#!/usr/bin/env bash
# The repository's habits, checked (CI runs this after the tests):
#   1. clang-format: every source is formatted as .clang-format says (fix: bash cmake/lint.sh --fix);
#   2. clang-tidy: the checks of .clang-tidy pass on every translation unit of the project's own
#      code (compile_commands.json of the build folder, default build/ci);
#   3. structure: no file over 800 lines, no function over 150 lines (cmake/check_sizes.sh).
# Tests, generated code (tests/hls/golden) and the vendor stand-ins (hls/compat) are exempt.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
BUILD_DIR="${PARALLAX_LINT_BUILD:-build/ci}"
JOBS="${PARALLAX_JOBS:-$(nproc)}"
fix=0
[ "${1:-}" = "--fix" ] && fix=1

mapfile -t sources < <(git ls-files '*.cpp' '*.hpp' '*.h' | grep -v -E '/golden/|^hls/compat/|node_modules')
status=0

echo "lint: clang-format on ${#sources[@]} files" >&2
if [ $fix -eq 1 ]; then
  clang-format -i "${sources[@]}"
else
  clang-format --dry-run --Werror "${sources[@]}" || status=1
fi

if [ ! -f "$BUILD_DIR/compile_commands.json" ]; then
  echo "lint: $BUILD_DIR/compile_commands.json is missing: configure first (cmake --preset ci)" >&2
  exit 2
fi
mapfile -t units < <(git ls-files '*.cpp' | grep -v -E '^tests/|/golden/|^hls/compat/')
echo "lint: clang-tidy on ${#units[@]} translation units ($JOBS jobs)" >&2
root=$(pwd)
abs_units=()
for u in "${units[@]}"; do abs_units+=("$root/$u"); done
# clang does not know some of GCC's flags (e.g. -fno-tree-loop-distribute-patterns): a copy of
# the compilation database without them.
tidy_db=$(mktemp -d)
sed -e 's/ -fno-tree-loop-distribute-patterns//g' "$BUILD_DIR/compile_commands.json" > "$tidy_db/compile_commands.json"
run-clang-tidy -quiet -j "$JOBS" -p "$tidy_db" "${abs_units[@]}" > /tmp/parallax-clang-tidy.$$ 2>&1 || status=1
grep -E "warning:|error:" /tmp/parallax-clang-tidy.$$ | sort -u || true
rm -rf /tmp/parallax-clang-tidy.$$ "$tidy_db"

echo "lint: sizes" >&2
bash cmake/check_sizes.sh || status=1
[ $status -eq 0 ] && echo "lint: clean" >&2
exit $status
