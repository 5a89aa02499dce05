#!/usr/bin/env bash
# clang-format over every C++ source under src/: --check (default) or --fix.
set -euo pipefail
cd "$(dirname "$0")/.."
mapfile -t files < <(git ls-files --cached --others --exclude-standard 'src/*.cpp' 'src/*.h' 'src/*.hpp')
[[ ${#files[@]} -eq 0 ]] && exit 0
if [[ "${1:---check}" == "--fix" ]]; then
  clang-format -i "${files[@]}"
else
  clang-format --dry-run -Werror "${files[@]}"
  echo "clang-format: ${#files[@]} files clean"
fi
