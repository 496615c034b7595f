#!/bin/sh
# Refreshes crates/view/app/vendor/three/ from the npm package `three` pinned in
# tools/node/package.json (installed into tools/node/node_modules by `cargo xtask test`, or by
# `npm ci` in tools/node). The viewer embeds these files (crates/view/src/app.rs), so the page
# loads nothing from the internet. To move to another three.js version: change the pin in
# tools/node/package.json, run `npm install --package-lock-only` and `npm ci` in tools/node,
# then this script, and commit the result.
set -eu
root=$(cd "$(dirname "$0")/../../.." && pwd)
src="$root/tools/node/node_modules/three"
dst="$root/crates/view/app/vendor/three"
[ -f "$src/package.json" ] || { echo "no $src: run \`npm ci\` in tools/node first" >&2; exit 1; }
version=$(node -p "require('$src/package.json').version")
rm -rf "$dst"
mkdir -p "$dst/build" "$dst/addons/loaders" "$dst/addons/utils" "$dst/addons/controls" "$dst/addons/libs"
cp "$src/LICENSE" "$dst/LICENSE"
cp "$src/build/three.module.js" "$src/build/three.core.js" "$dst/build/"
for f in loaders/GLTFLoader.js utils/BufferGeometryUtils.js utils/SkeletonUtils.js \
         controls/OrbitControls.js libs/meshopt_decoder.module.js; do
    cp "$src/examples/jsm/$f" "$dst/addons/$f"
done
echo "$version" > "$dst/VERSION"
echo "three $version → $dst"
