#!/usr/bin/env bash
# One shard of `tetwalk paper`: scripts/paper-shard.sh I N OUT_DIR writes OUT_DIR/shard-I.json (the
# counts of views v with v % N == I; shard 0 also times the timed tables). What is run comes from
# PAPER_ARGS (default: the papers' size on the paper-scale bunny, `--scene bunny-paper --full`), the
# program from scripts/tetwalk-bin.sh (TETWALK, else the release build where cargo puts it). The GitHub workflow
# (.github/workflows/paper.yml), the GNU parallel line and the Slurm array (scripts/paper.slurm) of the
# user guide (docs/paper-scale.md) all run this.
set -euo pipefail
i=$1 n=$2 out=$3
source "$(dirname "$0")/tetwalk-bin.sh"
mkdir -p "$out"
start=$(date +%s)
# shellcheck disable=SC2086
"$tetwalk" paper ${PAPER_ARGS:---scene bunny-paper --full} --shard "$i/$n" --json "$out/shard-$i.json"
echo "shard $i/$n: $(( $(date +%s) - start )) s"
