#!/usr/bin/env bash
# Regenerates bunny.off from the npm package `bunny` (the Stanford bunny, Stanford Computer Graphics
# Laboratory), every coordinate rounded to the nearest f32 (printed exactly), then the scenes from it.
set -euo pipefail
cd "$(dirname "$0")"
tmp=$(mktemp -d)
(cd "$tmp" && npm pack --silent bunny@1.0.1 >/dev/null && tar xzf bunny-1.0.1.tgz)
node -e '
const b = require(process.argv[1] + "/package");
const out = ["OFF", `${b.positions.length} ${b.cells.length} 0`];
for (const p of b.positions) out.push(p.map(x => String(Math.fround(x))).join(" "));
for (const c of b.cells) out.push(`3 ${c.join(" ")}`);
require("fs").writeFileSync("bunny.off", out.join("\n") + "\n");
' "$tmp"
rm -rf "$tmp"
cargo run --release --quiet -- scene build bunny.off --out bunny-cdt
cargo run --release --quiet -- scene build bunny.off --quality --out bunny-quality
cargo run --release --quiet -- scene build bunny.off --offset 65536 --out bunny-far
cargo run --release --quiet -- scene build bunny.off --quality --offset 65536 --out bunny-quality-far
