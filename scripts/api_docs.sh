#!/usr/bin/env bash
# Builds the API reference (Doxygen HTML of the public headers, include/hdm without detail/) into
# build/api/html. Any warning fails: an undocumented public symbol or parameter, or a broken
# doc command (docs/Doxyfile: WARN_AS_ERROR=FAIL_ON_WARNINGS; the log is checked too, so a
# Doxygen that ignores that setting still fails). Takes a few seconds.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$here"
command -v doxygen >/dev/null || { echo "api_docs: doxygen not found (bash scripts/setup.sh installs it)" >&2; exit 1; }
rm -rf build/api
mkdir -p build/api
status=0
doxygen docs/Doxyfile || status=$?
count=$(grep -cE "(warning|error):" build/api/warnings.log || true)
if [ "$status" != 0 ] || [ "$count" != 0 ]; then
  cat build/api/warnings.log >&2
  echo "api_docs: $count Doxygen warning(s) or error(s) in the public headers (build/api/warnings.log)" >&2
  exit 1
fi
echo "api_docs: 0 warnings, $here/build/api/html/index.html"
