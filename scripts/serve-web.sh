#!/usr/bin/env bash
# Serves build-web/ (scripts/build-web.sh) on http://127.0.0.1:PORT/ (default 8000) with the
# headers that make the page cross-origin isolated, so its tracer can use every core:
#   Cross-Origin-Opener-Policy: same-origin, Cross-Origin-Embedder-Policy: require-corp.
# RT_WEB_BIND=0.0.0.0 serves other machines too (they get the single-thread page unless they
# reach it as https or localhost, where browsers allow the isolation).
set -euo pipefail
cd "$(dirname "$0")/.."
port=${1:-8000}
if [ ! -f build-web/index.html ]; then
    echo "serve-web: no page in build-web/ (run scripts/build-web.sh)" >&2
    exit 1
fi
exec python3 tests/web/serve.py --dir build-web --bind "${RT_WEB_BIND:-127.0.0.1}" --port "$port"
