#!/usr/bin/env bash
# Adds up a sharded `tetwalk paper` run: scripts/paper-merge.sh DIR writes DIR/paper.md (the tables)
# and DIR/paper.json from DIR/shard-*.json; `tetwalk paper merge` refuses a missing, doubled or
# foreign shard.
set -euo pipefail
dir=$1
# The program: scripts/tetwalk-bin.sh (TETWALK, else the release build where cargo puts it).
source "$(dirname "$0")/tetwalk-bin.sh"
"$tetwalk" paper merge "$dir"/shard-*.json --out "$dir/paper.md" --json "$dir/paper.json" >/dev/null
echo "merged $(ls "$dir"/shard-*.json | wc -l) shards into $dir/paper.md"
