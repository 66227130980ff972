#!/usr/bin/env bash
# Serves web/dist/ on http://localhost:${PORT:-8000}/ (build it first: bash web/build.sh).
# Any static file server will do; this one is node's (web/serve.mjs), or:
#   python3 -m http.server -d web/dist 8000
set -euo pipefail
web="$(cd "$(dirname "$0")" && pwd)"
exec node "$web/serve.mjs" "$web/dist" "${PORT:-8000}"
