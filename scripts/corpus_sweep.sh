#!/usr/bin/env bash
# Bakes every mesh of the given corpora (default: libcgal-demo assimp) at default settings, checks
# each with `hdm check` and writes one table per corpus into docs/figures.md, the set-aside third
# reported apart (scripts/corpus_sweep.py says how).
# Usage: HDM=build/bin/hdm [ONLY=regex] [PART=all|dev|held] [TIMEOUT=300] [OUT=dir] [WRITE=1] [REQUIRE_OK=1]
#        scripts/corpus_sweep.sh [libcgal-demo|assimp|FOLDER ...]
set -euo pipefail
exec python3 "$(dirname "${BASH_SOURCE[0]}")/corpus_sweep.py" "$@"
