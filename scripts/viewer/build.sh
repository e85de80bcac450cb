#!/usr/bin/env bash
# Rebuilds geomcheck/report/templates/three.min.js from the npm packages package-lock.json pins:
# the three.js modules entry.js names (tree-shaken), minified into one classic script defining
# the global THREE, headed by three.js's MIT licence. The HTML report inlines it (no request
# leaves the file); tests/report/test_view3d.py checks the header and that the script cannot
# end its <script> element early.
set -euo pipefail
cd "$(dirname "$0")"
npm ci --no-audit --no-fund >/dev/null
version=$(node -p "JSON.parse(require('fs').readFileSync('node_modules/three/package.json')).version")
banner="/*! three.js ${version} (npm three@${version}), the subset scripts/viewer/entry.js names, bundled by scripts/viewer/build.sh
$(cat node_modules/three/LICENSE)
*/"
out=../../geomcheck/report/templates/three.min.js
npx esbuild entry.js --bundle --format=iife --global-name=THREE --minify --legal-comments=none \
  --target=es2020 --charset=utf8 --banner:js="$banner" --outfile="$out" --log-level=warning
if grep -qiE '</script|<!--' "$out"; then
  echo "error: $out holds text that would end its <script> element" >&2
  exit 1
fi
echo "wrote $out ($(wc -c <"$out") bytes)"
