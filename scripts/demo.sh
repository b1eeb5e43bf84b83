#!/usr/bin/env bash
# Installs what is missing, builds Release and renders the built-in demo scene to demo.png.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh release
./build/samples/tg-render/tg-render -o demo.png
echo "demo: wrote $(pwd)/demo.png"
