#!/usr/bin/env bash
# Counts what makes the source tree hard to work in, so that anyone can check the house rules
# (DEVELOPERS.md): functions over 100 lines (universal-ctags' function ends: Debian's
# `universal-ctags`), files over 500 lines, references to the project's own history in docs and
# code ("issue N", "session N"), PNG encoders compiled, quantile helpers defined, and the hdm
# includes a program needs to press a model (examples/consumer/press_model.cpp), and GoogleTest
# names that are not CamelCase (GoogleTest's own rule: no underscores in suite or test names).
# usage: bash scripts/house_counts.sh [--list]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
list=${1:-}
dirs=(src apps python bench include fuzz examples)
functions() {  # LENGTH FILE NAME of every C++ function definition
  ctags -R --languages=C++ --kinds-C++=f --fields=+ne -x --_xformat="%{end} %{line} %{input} %{name}" "${dirs[@]}" |
    awk '{print $1 - $2 + 1, $3, $4}'
}
command -v ctags >/dev/null || { echo "needs universal-ctags (apt-get install universal-ctags)" >&2; exit 2; }
long=$(functions | awk '$1 > 100' | sort -rn)
files=$(find "${dirs[@]}" tests \( -name '*.cpp' -o -name '*.h' \) -print0 | xargs -0 wc -l | awk '$1 > 500 && $2 != "total"')
history=$(grep -rniE '\b(issue|session) [0-9]+' docs README.md DEVELOPERS.md "${dirs[@]}" tests scripts \
  --exclude=house_counts.sh || true)
printf '%-40s %s\n' "functions over 100 lines" "$(printf '%s' "$long" | grep -c . || true)"
printf '%-40s %s\n' "functions over 80 lines" "$(functions | awk '$1 > 80' | wc -l)"
printf '%-40s %s\n' "files over 500 lines" "$(printf '%s' "$files" | grep -c . || true)"
printf '%-40s %s\n' "'issue N' / 'session N' references" "$(printf '%s' "$history" | grep -c . || true)"
printf '%-40s %s\n' "PNG encoders compiled" "$(grep -rl STB_IMAGE_WRITE_IMPLEMENTATION src apps | wc -l)"
printf '%-40s %s\n' "quantile helpers defined" \
  "$(grep -rE '^(template <class T>\s*)?[A-Za-z_:<> ]+ (percentile|p95|p99)\(' src apps bench include | wc -l)"
printf '%-40s %s\n' "hdm includes in press_model.cpp" "$(grep -c '#include <hdm' examples/consumer/press_model.cpp)"
printf '%-40s %s\n' "test names with underscores" \
  "$(grep -rhoE '^TEST(_F|_P)?\([A-Za-z0-9_]+, [A-Za-z0-9_]+\)' tests | grep -cE '\([A-Za-z0-9]*_|, [A-Za-z0-9]*_' || true)"
if [ "$list" = --list ]; then
  printf '\nfunctions over 100 lines:\n%s\n\nfiles over 500 lines:\n%s\n\nhistory references:\n%s\n' "$long" "$files" "$history"
fi
