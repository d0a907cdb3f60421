#!/usr/bin/env bash
# Adds up a sharded `tetwalk paper` run: scripts/paper-merge.sh DIR writes DIR/paper.md (the tables)
# and DIR/paper.json from DIR/shard-*.json; `tetwalk paper merge` refuses a missing, doubled or
# foreign shard.
set -euo pipefail
dir=$1
tetwalk=${TETWALK:-target/release/tetwalk}
"$tetwalk" paper merge "$dir"/shard-*.json --out "$dir/paper.md" --json "$dir/paper.json" >/dev/null
echo "merged $(ls "$dir"/shard-*.json | wc -l) shards into $dir/paper.md"
