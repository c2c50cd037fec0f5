#!/usr/bin/env bash
# Seed corpus of orogen_fuzz_heightfield_image: small valid heightfield files of each format, each behind the
# byte that selects its extension (0 .png, 1 .exr, 2 .tif, 3 .r16). Needs oiiotool (openimageio-tools).
set -euo pipefail
out="$1"
mkdir -p "$out"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
oiiotool --pattern checker:width=2:height=2 8x8 1 -d uint16 -o "$tmp/a.png"
oiiotool --pattern fill:topleft=0:topright=1:bottomleft=0.5:bottomright=0.2 9x7 2 -d uint8 -o "$tmp/b.png"
oiiotool --pattern fill:top=0:bottom=1 8x8 1 -d float -o "$tmp/c.exr"
oiiotool --pattern checker 6x5 3 -d half -o "$tmp/d.exr"
oiiotool --pattern fill:left=0:right=1 8x8 1 -d float -o "$tmp/e.tif"
oiiotool --pattern checker 7x7 1 -d uint16 -o "$tmp/f.tif"
head -c 128 /dev/urandom > "$tmp/g.r16"  # 8x8 RAW16
seed() { { printf "\\x$1"; cat "$2"; } > "$out/$(basename "$2")"; }
seed 00 "$tmp/a.png"; seed 00 "$tmp/b.png"; seed 01 "$tmp/c.exr"; seed 01 "$tmp/d.exr"
seed 02 "$tmp/e.tif"; seed 02 "$tmp/f.tif"; seed 03 "$tmp/g.r16"
