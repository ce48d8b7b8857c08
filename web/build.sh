#!/usr/bin/env bash
# Builds the web client into OUT_DIR: index.html, the JavaScript loader (macroquad's bundle
# and the game's network plugin) and breakshot.wasm. Serve the directory with
# `breakshot-server --web OUT_DIR`, or publish it as a static site (README, "Play in a browser").
#
#   bash web/build.sh OUT_DIR
set -euo pipefail
if [ $# -ne 1 ]; then
  echo "usage: bash web/build.sh OUT_DIR" >&2
  exit 2
fi
out=$1
root=$(cd "$(dirname "$0")/.." && pwd)
target=wasm32-unknown-unknown

if command -v rustup >/dev/null 2>&1 && ! rustup target list --installed | grep -qx "$target"; then
  echo "adding the Rust target $target"
  rustup target add "$target"
fi

# The native build's line tables would only make the page's download larger.
CARGO_PROFILE_RELEASE_DEBUG=false CARGO_PROFILE_RELEASE_STRIP=debuginfo \
  cargo build --manifest-path "$root/Cargo.toml" --release --target "$target" \
  -p breakshot-client --no-default-features --features sound --bin breakshot

target_dir=$(cargo metadata --manifest-path "$root/Cargo.toml" --format-version 1 --no-deps |
  sed -n 's/.*"target_directory":"\([^"]*\)".*/\1/p')
macroquad_dir=$(cargo metadata --manifest-path "$root/Cargo.toml" --format-version 1 |
  grep -o '"manifest_path":"[^"]*/macroquad-[0-9][^"/]*/Cargo.toml"' | head -n 1 |
  sed 's/"manifest_path":"\(.*\)\/Cargo.toml"/\1/')
if [ -z "$macroquad_dir" ] || [ ! -f "$macroquad_dir/js/mq_js_bundle.js" ]; then
  echo "cannot find macroquad's js/mq_js_bundle.js" >&2
  exit 1
fi

mkdir -p "$out"
cp "$target_dir/$target/release/breakshot.wasm" "$out/breakshot.wasm"
cp "$macroquad_dir/js/mq_js_bundle.js" "$out/mq_js_bundle.js"
cp "$root/web/breakshot_net.js" "$root/web/index.html" "$out/"
echo "web client built in $out ($(du -sh "$out" | cut -f1))"
